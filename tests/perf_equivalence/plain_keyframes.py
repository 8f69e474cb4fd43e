"""The numpy sampling of keyframe realizations and wrist splines as it stood before it was
compiled (issue 19): :meth:`motor.program.lmp.VectorKeyframes.sample`,
:meth:`motor.program.lmp.RotationKeyframes.sample`,
:meth:`motor.trajectory.spline.WristTrajectory.position` and
:meth:`motor.trajectory.biocontrol.TimeProfile.fraction`. The plain path the compiled
loops (:mod:`motor.program.keyframe_sampling`, :mod:`motor.trajectory.spline_positions`)
are held to bit for bit by ``test_keyframe_sampling.py``. Not used by mura itself."""

from __future__ import annotations

import numpy as np

from motor import quaternion as quat


def fraction(fractions: np.ndarray, u: np.ndarray) -> np.ndarray:
    """A time profile's path fraction at time fractions ``u``."""
    grid = np.linspace(0.0, 1.0, fractions.size)
    return np.interp(np.clip(u, 0.0, 1.0), grid, fractions)


def _locate(knots: np.ndarray, times: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    t = np.asarray(times, dtype=float)
    segment = np.clip(np.searchsorted(knots, t, side="right") - 1, 0, knots.size - 2)
    length = knots[segment + 1] - knots[segment]
    return segment, np.clip((t - knots[segment]) / length, 0.0, 1.0)


def _blend(times: np.ndarray, start: float, window: float) -> np.ndarray:
    tau = np.clip(np.asarray(times, dtype=float) - start, 0.0, window)
    s = tau / window
    return tau * (1.0 - s) ** 2


def vector_keyframes(knots: np.ndarray, values: np.ndarray, incoming: np.ndarray, fractions: np.ndarray, times: np.ndarray) -> np.ndarray:
    segment, u = _locate(knots, times)
    s = fraction(fractions, u)[:, None]
    weight = _blend(times, knots[0], knots[1] - knots[0])
    return values[segment] + s * (values[segment + 1] - values[segment]) + weight[:, None] * incoming


def rotation_keyframes(knots: np.ndarray, keys: np.ndarray, steps: np.ndarray, incoming: np.ndarray, fractions: np.ndarray, times: np.ndarray) -> np.ndarray:
    segment, u = _locate(knots, times)
    s = fraction(fractions, u)[:, None]
    planned = quat.multiply(keys[segment], quat.from_rotation_vector(s * steps[segment]))
    weight = _blend(times, knots[0], knots[1] - knots[0])
    return quat.multiply(quat.from_rotation_vector(weight[:, None] * incoming), planned)


def spline_position(knots: np.ndarray, coefficients: np.ndarray, times: np.ndarray) -> np.ndarray:
    t = np.asarray(times, dtype=float)
    clipped = np.clip(t, knots[0], knots[-1])
    index = np.clip(np.searchsorted(knots, clipped, side="right") - 1, 0, len(knots) - 2)
    u = ((clipped - knots[index]) / (knots[index + 1] - knots[index]))[:, None]
    c = coefficients[index]
    return c[:, 0] + u * (c[:, 1] + u * (c[:, 2] + u * (c[:, 3] + u * (c[:, 4] + u * c[:, 5]))))
