"""Loading the motor core's compiled kernels before the first frame is due.

numba compiles each kernel (:mod:`motor.quaternion`'s products, :mod:`motor.body.distance`'s
signed distances) once per checkout and caches it on disk (``__pycache__``); a process
then loads each on its first call: about 0.2 s for the first (numba's own start), a few
milliseconds for each further one, and several seconds the very first time, while they
compile. A live realizer calls :func:`warm_up` when it starts, so that no utterance's
first frame waits for it; the benches call it before they time anything.
"""

from __future__ import annotations

import time

import numpy as np

from motor import quaternion as quat
from motor.body import distance
from motor.body.volumes import Capsule, Ellipsoid, EllipticCylinder

_POINTS = np.zeros((1, 3))
_VOLUMES = (
    Capsule("capsule", "root", np.zeros(3), np.ones(3), 0.1),
    Ellipsoid("ellipsoid", "root", np.zeros(3), np.ones(3)),
    EllipticCylinder("cylinder", "root", np.zeros(3), 1.0, 1.0, 0.0, 1.0),
)


def warm_up() -> float:
    """Load (compiling where no cache holds them) every compiled kernel; returns the
    seconds it took."""
    started = time.perf_counter()
    rotation = quat.normalize(np.ones((1, 4)))
    quat.multiply(rotation, rotation)
    quat.rotate(rotation, _POINTS)
    quat.cross(_POINTS, _POINTS)
    distance.closest_parameters(_POINTS, _POINTS, _POINTS, _POINTS)
    distance.segment_distance(_POINTS, _POINTS, _POINTS, _POINTS)
    distance.point_segment_distance(_POINTS, _POINTS, _POINTS)
    for volume in _VOLUMES:
        distance.capsule_distance(volume, _POINTS, _POINTS, 0.0)
    return time.perf_counter() - started
