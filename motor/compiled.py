"""Loading the motor core's compiled kernels before the first frame is due.

numba compiles each kernel (:mod:`motor.quaternion`'s products, :mod:`motor.body.distance`'s
signed distances, :mod:`motor.arm.clearance`'s arm-against-body loop,
:mod:`motor.arm.swivel`'s value tables) once per checkout and caches it on disk (``__pycache__``); a process
then loads each on its first call: about 0.2 s for the first (numba's own start), a few
milliseconds for each further one, and several seconds the very first time, while they
compile. A live realizer calls :func:`warm_up` when it starts, so that no utterance's
first frame waits for it; the benches call it before they time anything.
"""

from __future__ import annotations

import time

from motor import quaternion
from motor.arm import clearance, swivel
from motor.body import distance


def warm_up() -> float:
    """Load (compiling where no cache holds them) every compiled kernel; returns the
    seconds it took."""
    started = time.perf_counter()
    for module in (quaternion, distance, clearance, swivel):
        module.load_kernels()
    return time.perf_counter() - started
