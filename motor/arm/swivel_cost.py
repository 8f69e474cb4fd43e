"""What a swivel costs: how natural, comfortable for the wrist and clear of the body it is.

Candidate swivels are the whole circle in steps of :data:`SWIVEL_STEP`
(:data:`CANDIDATES`). Each candidate's cost sums

* its distance from the natural swivel (Soechting & Flanders, :mod:`motor.arm.chain`):
  quadratic, and steeply beyond :data:`SWIVEL_RANGE` where the shoulder leaves its
  comfortable range;
* the wrist's load (seed 000: spare the wrist): flexion and — weighted more — radial/ulnar
  deviation as fractions of their limits, and the hand rotation the limits leave
  unachieved, saturating (a hand rotation no swivel comes near does not drag the elbow
  around);
* the arm's clearance from the body and the other arm (:mod:`motor.arm.clearance`).

Only the candidates within :data:`WINDOW` steps of the natural swivel are measured; the
others cost their distance from it plus :data:`OUTSIDE` (a swivel track adds what they pay
for going into the body, :func:`beyond_penalties`). Everything is computed on
coordinate arrays ``(n, K)`` (contiguous per coordinate); the wrist state and the costs
of each frame's candidates are compiled loops (:func:`_wrist_rows`, :func:`_cost_rows`),
held to the numpy arithmetic they replaced by ``tests/perf_equivalence``.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from motor.arm.chain import ArmPlacement
from motor.arm.clearance import CLEARANCE, ArmSegments, arm_capsules, clearance, penetration_penalty, segment_table
from motor.arm.other_arm_clearance import near_frames, other_arm_window
from motor.body.avatar import Avatar
from motor.body.distance import Components
from motor.kernel_types import READ1, READ2, WRITE2

#: Candidate swivels (radians): the whole circle in steps of :data:`SWIVEL_STEP`.
SWIVEL_STEP = float(np.deg2rad(10.0))
CANDIDATES = np.arange(-np.pi, np.pi - 1e-9, SWIVEL_STEP)
#: Cost weights: distance from the natural swivel (per radian), wrist deviation and
#: flexion as fractions of their limits, unachieved hand rotation (per radian squared,
#: saturating beyond :data:`RESIDUAL_SATURATION` radians).
SWIVEL_SCALE = 0.7
DEVIATION_WEIGHT = 1.5
FLEXION_WEIGHT = 0.4
RESIDUAL_WEIGHT = 5000.0
RESIDUAL_SATURATION = 0.25
#: Farther than this from the natural swivel (radians) the elbow is forced, e.g. straight
#: up, the shoulder leaves its comfortable range: the cost then grows by
#: :data:`RANGE_WEIGHT` per radian squared beyond it.
SWIVEL_RANGE = float(np.radians(100.0))
RANGE_WEIGHT = 300.0
#: Candidates measured on each side of the natural swivel, and the cost added to those
#: not measured (farther than the comfortable range anyway).
WINDOW = int(round(SWIVEL_RANGE / SWIVEL_STEP))
OUTSIDE = 1000.0
_CELLS = np.arange(-WINDOW, WINDOW + 1, dtype=float)
#: The cells beyond the window, as steps from its first cell.
_BEYOND = np.arange(2 * WINDOW + 1, len(CANDIDATES), dtype=float)
_TINY = 1e-12
#: Frames measured in one pass: their ``(frames, candidates)`` arrays stay in the CPU's
#: cache, which makes the elementwise arithmetic several times faster than one pass over
#: tens of thousands of frames. Every frame's costs are its own (the arithmetic is the
#: same whatever the batch), so this changes no number. 384 frames (8,000 candidates, 64 kB
#: per array) measured about a quarter faster per frame than 1,024 on the bench machine.
CHUNK_FRAMES = 384


def candidate_costs(
    avatar: Avatar,
    placement: ArmPlacement,
    natural: np.ndarray,
    other: ArmSegments | None = None,
    own: bool = True,
    nearby: np.ndarray | None = None,
) -> np.ndarray:
    """Costs ``(n, K)`` of the candidates (module docstring) for an arm placed at
    ``placement`` with natural swivels ``natural (n,)``, keeping clear of the ``other``
    arm's capsules too; with ``own`` False, only that: the penalty of coming near the
    other arm (0 outside the window). ``nearby (n, K)``: each candidate's clearance
    penalty at instants around each one (:func:`body_penalties`), which it pays where it
    is more than its own (the other arm's penalty alone is measured in one pass: only in
    the frames near it, by a compiled loop)."""
    if not own:
        return _other_arm_costs(avatar, placement, natural, other)
    if len(natural) > CHUNK_FRAMES:
        return np.concatenate([
            candidate_costs(avatar, placement.take(rows), natural[rows], None if other is None else other.take(rows), own, None if nearby is None else nearby[rows])
            for rows in (slice(start, start + CHUNK_FRAMES) for start in range(0, len(natural), CHUNK_FRAMES))
        ])  # fmt: skip
    cells, psi = measured_window(natural)
    elbow, radial = candidate_elbows(placement, np.cos(psi), np.sin(psi))
    circle = placement.circle
    penalty, _ = clearance(avatar, placement.chain.side, circle.shoulder, circle.wrist, elbow, placement.body_frame, other, carried_frames=placement.carried_frames)
    return _window_costs(placement, natural, cells, psi, penalty, elbow, radial, nearby)


def body_penalties(avatar: Avatar, placement: ArmPlacement, natural: np.ndarray) -> np.ndarray:
    """The clearance penalty from the body ``(n, K)`` of the candidates within the window
    about the natural swivels ``natural (n,)`` (0 for the others, which are not measured)."""
    count = len(CANDIDATES)
    cells, psi = measured_window(natural)
    elbow, _ = candidate_elbows(placement, np.cos(psi), np.sin(psi))
    circle = placement.circle
    penalty, _ = clearance(avatar, placement.chain.side, circle.shoulder, circle.wrist, elbow, placement.body_frame, carried_frames=placement.carried_frames)
    penalties = np.zeros((len(natural), count))
    np.put_along_axis(penalties, cells.astype(np.int64) % count, penalty, axis=1)
    return penalties


def beyond_penalties(avatar: Avatar, placement: ArmPlacement, natural: np.ndarray) -> np.ndarray:
    """What the candidates beyond the window about the natural swivels ``natural (n,)``
    pay for going into the body ``(n, K)``, which :func:`candidate_costs` does not measure:
    the penetration's penalty beyond :data:`motor.arm.clearance.TOLERATED_DEPTH`
    (:func:`motor.arm.clearance.penetration_penalty`; 0 for the window's candidates and
    wherever the arm goes no deeper). A swivel track adds them
    (:func:`motor.arm.ik.track_costs`): carried beyond the window by its continuity, it
    took those candidates for clear, and an upper arm stayed 12 cm inside the chest for
    seconds, paying :data:`OUTSIDE` where the window's candidates there paid their depth.
    The single-posture search (:func:`cheapest_swivels`) has no such blind spot: it
    measures the depth where its choice puts the arm."""
    count = len(CANDIDATES)
    cells, _ = measured_window(natural)
    beyond = cells[:, :1] + _BEYOND
    swivels = CANDIDATES[0] + beyond * SWIVEL_STEP
    elbow, _ = candidate_elbows(placement, np.cos(swivels), np.sin(swivels))
    circle = placement.circle
    _, depth = clearance(avatar, placement.chain.side, circle.shoulder, circle.wrist, elbow, placement.body_frame, carried_frames=placement.carried_frames)
    penalties = np.zeros((len(natural), count))
    np.put_along_axis(penalties, beyond.astype(np.int64) % count, penetration_penalty(depth), axis=1)
    return penalties


def _other_arm_costs(avatar: Avatar, placement: ArmPlacement, natural: np.ndarray, other: ArmSegments) -> np.ndarray:
    """Only the penalty of coming near the other arm, measured in the frames whose arm —
    bounded by its shoulder, wrist and whole elbow circle — may reach the other's capsules
    (:func:`motor.arm.other_arm_clearance.near_frames`), by a compiled loop over those
    frames (:func:`motor.arm.other_arm_clearance.other_arm_window`)."""
    count = len(CANDIDATES)
    costs = np.zeros((len(natural), count))
    circle = placement.circle
    rows = lambda value: np.ascontiguousarray(value, dtype=float)
    own = arm_capsules(avatar, placement.chain.side)
    ends, radii = other.table()
    margins = np.array([max(other.radii), max(own.upper_radius, own.fore_radius), CLEARANCE])
    shoulder, wrist, center, radius = rows(circle.shoulder), rows(circle.wrist), rows(circle.center), rows(circle.radius)
    near = np.empty(len(natural), dtype=np.bool_)
    near_frames(shoulder, wrist, center, radius, margins, ends, radii, near)
    if not np.any(near):
        return costs
    measured = np.flatnonzero(near)
    cells, psi = measured_window(natural[measured])
    other_arm_window(
        measured, shoulder, wrist, center, rows(circle.down), rows(circle.out), radius, np.cos(psi), np.sin(psi),
        cells.astype(np.int64) % count, segment_table(own), ends, radii, costs,
    )  # fmt: skip
    return costs


def measured_window(natural: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The candidates measured about the natural swivels ``natural (n,)``: their cells
    ``(n, 2 WINDOW + 1)`` (unwrapped steps from the first candidate, as floats; modulo
    ``K`` the candidate's index) and swivels (radians)."""
    cells = np.rint((natural - CANDIDATES[0]) / SWIVEL_STEP)[:, None] + _CELLS
    return cells, CANDIDATES[0] + cells * SWIVEL_STEP


def candidate_elbows(placement: ArmPlacement, cos: np.ndarray, sin: np.ndarray) -> tuple[Components, Components]:
    """Elbow positions at swivels with cosines and sines ``(n, K)`` and their directions
    from the circle's centre, as coordinate arrays."""
    circle = placement.circle
    radial = tuple(circle.down[:, i : i + 1] * cos + circle.out[:, i : i + 1] * sin for i in range(3))
    radius = circle.radius[:, None]
    return tuple(circle.center[:, i : i + 1] + radius * radial[i] for i in range(3)), radial


def _window_costs(
    placement: ArmPlacement,
    natural: np.ndarray,
    cells: np.ndarray,
    psi: np.ndarray,
    penalty: np.ndarray,
    elbow: Components,
    radial: Components,
    nearby: np.ndarray | None,
) -> np.ndarray:
    """Every candidate's cost ``(n, K)`` (module docstring) from the measured window's
    cells and swivels ``(n, W)`` (:func:`measured_window`), its clearance ``penalty``, the
    ``nearby`` penalties (:func:`body_penalties`) it pays where they are more, and — where
    the hand's rotation is given — the wrist's load: its flexion and deviation as
    fractions of their limits, and the rotation the limits leave unachieved, saturating.
    Compiled (:func:`_cost_rows`)."""
    chain, circle = placement.chain, placement.circle
    rows = lambda value: np.ascontiguousarray(value, dtype=float)
    hands = np.zeros((0, 4)) if placement.hands is None else rows(placement.hands)
    limits = np.array([*chain.wrist_flexion, *chain.wrist_deviation, *chain.twist_range], dtype=float)
    costs = np.empty((len(natural), len(CANDIDATES)))
    _cost_rows(
        rows(natural), rows(cells), rows(psi), rows(penalty), np.zeros((0, 0)) if nearby is None else rows(nearby),
        hands, rows(circle.wrist), rows(circle.axis), *map(rows, elbow), *map(rows, radial),
        wrist_constant_row(chain), limits, CANDIDATES, costs,
    )  # fmt: skip
    return costs


def wrist_state(placement: ArmPlacement, elbow: Components, radial: Components) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Wrist flexion and deviation, forearm twist (all radians, unclamped) and the swing
    between forearm and hand (radians) that the hand rotation ``placement.hands`` asks for
    with elbows at ``elbow`` (directions ``radial`` from the circle's centre), each of the
    broadcast shape of ``elbow`` and ``radial`` (``(n, K)``).

    The same quantities :func:`motor.arm.ik.solve_arm` computes, from vectors alone: the
    wrist's swing is the rotation taking the forearm's axis, seen from the hand, onto the
    hand's long axis (its rotation vector gives flexion and deviation); the forearm twist
    is what turns the elbow's hinge onto where the hand, swung back, wants it (Rodrigues'
    formula for the swing of a fixed vector). Compiled (:func:`_wrist_rows`)."""
    chain, circle = placement.chain, placement.circle
    shape = np.broadcast_shapes(*(c.shape for c in (*elbow, *radial)))
    rows = lambda c: np.ascontiguousarray(np.broadcast_to(c, shape), dtype=float)
    constants = wrist_constant_row(chain)
    out = tuple(np.empty(shape) for _ in range(4))
    _wrist_rows(
        np.ascontiguousarray(placement.hands, dtype=float), np.ascontiguousarray(circle.wrist, dtype=float),
        np.ascontiguousarray(circle.axis, dtype=float), *map(rows, elbow), *map(rows, radial), constants, *out,
    )  # fmt: skip
    return out


def wrist_constant_row(chain) -> np.ndarray:  # noqa: ANN001
    """The constants of :func:`wrist_angles` for an arm (:class:`motor.arm.chain.ArmChain`)."""
    a = np.asarray(chain.fore_rest, dtype=float)
    return np.array([
        1.0 / chain.fore, *a, *_cross(a, chain.flexion_axis), *_cross(a, chain.deviation_axis),
        *np.asarray(chain.hinge_rest, dtype=float), float(chain.pronation_axis @ chain.fore_rest),
    ], dtype=float)  # fmt: skip


def _cross(u: np.ndarray, v: np.ndarray) -> tuple[float, float, float]:
    return (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])


@numba.njit(cache=True, error_model="numpy", inline="always")
def hand_matrix(hands, i):  # noqa: ANN001, ANN202
    """The rotation matrix of the hand quaternion ``hands[i]``, row by row."""
    x, y, z, w = hands[i, 0], hands[i, 1], hands[i, 2], hands[i, 3]
    return (
        1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w),
        2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w),
        2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y),
    )  # fmt: skip


@numba.njit(cache=True, error_model="numpy", inline="always")
def wrist_angles(m, c, wrist, elbow, radial, constants):  # noqa: ANN001, ANN202
    """:func:`wrist_state` of one candidate: flexion, deviation, twist and swing (radians),
    from the hand's matrix ``m``, the circle's axis ``c``, the wrist, the candidate's elbow
    and its direction from the circle's centre ``radial`` (3-tuples). The forearm seen
    from the hand, its swing onto the rest forearm ``a`` (flexion and deviation along
    ``a`` × the wrist's axes), the hinge swung back and the twist that turns the elbow's
    hinge onto it. ``constants``: 1 / forearm length, ``a``, ``a`` × flexion axis, ``a`` ×
    deviation axis, the rest hinge, the pronation sign."""
    m00, m01, m02, m10, m11, m12, m20, m21, m22 = m
    inverse_fore, a0, a1, a2, fa0, fa1, fa2, da0, da1, da2, h0, h1, h2, sign = constants
    f0 = (wrist[0] - elbow[0]) * inverse_fore
    f1 = (wrist[1] - elbow[1]) * inverse_fore
    f2 = (wrist[2] - elbow[2]) * inverse_fore
    s0 = m00 * f0 + m10 * f1 + m20 * f2
    s1 = m01 * f0 + m11 * f1 + m21 * f2
    s2 = m02 * f0 + m12 * f1 + m22 * f2
    x0, x1, x2 = s1 * a2 - s2 * a1, s2 * a0 - s0 * a2, s0 * a1 - s1 * a0
    sine = math.sqrt(x0 * x0 + x1 * x1 + x2 * x2)
    cosine = s0 * a0 + s1 * a1 + s2 * a2
    angle = math.atan2(sine, cosine)
    scale = angle / max(sine, _TINY)
    flexion = scale * (s0 * fa0 + s1 * fa1 + s2 * fa2)
    deviation = scale * (s0 * da0 + s1 * da1 + s2 * da2)
    along = (x0 * h0 + x1 * h1 + x2 * h2) / max(1.0 + cosine, _TINY)
    w0 = h0 * cosine - (x1 * h2 - x2 * h1) + x0 * along
    w1 = h1 * cosine - (x2 * h0 - x0 * h2) + x1 * along
    w2 = h2 * cosine - (x0 * h1 - x1 * h0) + x2 * along
    t0 = m00 * w0 + m01 * w1 + m02 * w2
    t1 = m10 * w0 + m11 * w1 + m12 * w2
    t2 = m20 * w0 + m21 * w1 + m22 * w2
    g0 = radial[1] * c[2] - radial[2] * c[1]
    g1 = radial[2] * c[0] - radial[0] * c[2]
    g2 = radial[0] * c[1] - radial[1] * c[0]
    u0, u1, u2 = g1 * t2 - g2 * t1, g2 * t0 - g0 * t2, g0 * t1 - g1 * t0
    twist = math.atan2(sign * (u0 * f0 + u1 * f1 + u2 * f2), g0 * t0 + g1 * t1 + g2 * t2)
    return flexion, deviation, twist, angle


@numba.njit(cache=True, error_model="numpy", inline="always")
def wrist_constants(constants):  # noqa: ANN001, ANN202
    """The 14 constants of :func:`wrist_angles` as a tuple (held in registers in the loops)."""
    return (constants[0], constants[1], constants[2], constants[3], constants[4], constants[5], constants[6],
            constants[7], constants[8], constants[9], constants[10], constants[11], constants[12], constants[13])  # fmt: skip


@numba.njit([numba.void(*(READ2,) * 9, READ1, *(WRITE2,) * 4)], cache=True, error_model="numpy")
def _wrist_rows(hands, wrist, circle_axis, ex, ey, ez, rx, ry, rz, constants, flexion, deviation, twist, swing):  # noqa: ANN001, ANN202
    """:func:`wrist_state` per frame ``i`` and candidate ``k`` (:func:`wrist_angles`)."""
    fixed = wrist_constants(constants)
    for i in range(ex.shape[0]):
        m = hand_matrix(hands, i)
        c = (circle_axis[i, 0], circle_axis[i, 1], circle_axis[i, 2])
        w = (wrist[i, 0], wrist[i, 1], wrist[i, 2])
        for k in range(ex.shape[1]):
            flexion[i, k], deviation[i, k], twist[i, k], swing[i, k] = wrist_angles(
                m, c, w, (ex[i, k], ey[i, k], ez[i, k]), (rx[i, k], ry[i, k], rz[i, k]), fixed
            )


@numba.njit(cache=True, error_model="numpy", inline="always")
def turn_remainder(x):  # noqa: ANN001, ANN202
    """``x % 2π`` as numpy computes it (the floored remainder), without its ``fmod`` where
    ``x`` lies within one turn of [0, 2π): there the remainder is ``x``, ``x − 2π`` (exact,
    as ``fmod``'s is) or ``x + 2π`` (the addition numpy makes too)."""
    turn = 2.0 * np.pi
    if 0.0 <= x < turn:
        return x + 0.0  # numpy's remainder of -0.0 is +0.0
    if turn <= x < 2.0 * turn:
        return x - turn
    if -turn < x < 0.0:
        return x + turn
    return x % turn


@numba.njit(cache=True, error_model="numpy", inline="always")
def natural_cost(away):  # noqa: ANN001, ANN202
    """The cost of being ``away`` radians (in [-π, π]) from the natural swivel: quadratic,
    and steeply beyond :data:`SWIVEL_RANGE`."""
    beyond = max(abs(away) - SWIVEL_RANGE, 0.0)
    return away * away * (1.0 / SWIVEL_SCALE**2) + RANGE_WEIGHT * beyond * beyond


@numba.njit(cache=True, error_model="numpy", inline="always")
def wrist_load(flexion, deviation, twist, limits):  # noqa: ANN001, ANN202
    """The wrist's load (module docstring) of one candidate's wrist state; ``limits``:
    flexion, deviation and twist limits, low and high (radians)."""
    excess_flexion = flexion - min(max(flexion, limits[0]), limits[1])
    excess_deviation = deviation - min(max(deviation, limits[2]), limits[3])
    excess_twist = twist - min(max(twist, limits[4]), limits[5])
    unreached = excess_flexion * excess_flexion + excess_deviation * excess_deviation + excess_twist * excess_twist
    deviation = deviation / (limits[3] if deviation >= 0 else -limits[2])
    flexion = flexion / (limits[1] if flexion >= 0 else -limits[0])
    return DEVIATION_WEIGHT * deviation * deviation + FLEXION_WEIGHT * flexion * flexion + RESIDUAL_WEIGHT * unreached / (1.0 + unreached / RESIDUAL_SATURATION**2)


@numba.njit(cache=True, error_model="numpy", inline="always")
def _paid(penalty, nearby, i, k, cell):  # noqa: ANN001, ANN202
    """The clearance penalty candidate ``k`` of frame ``i`` pays: its own, or the nearby one
    of its ``cell`` where that is more."""
    return penalty[i, k] if nearby.shape[0] == 0 else max(penalty[i, k], nearby[i, cell])


@numba.njit(
    [numba.void(READ1, *(READ2,) * 5, *(READ2,) * 2, *(READ2,) * 6, READ1, READ1, READ1, WRITE2)],
    cache=True,
    error_model="numpy",
)
def _cost_rows(natural, cells, psi, penalty, nearby, hands, wrist, circle_axis, ex, ey, ez, rx, ry, rz, constants, limits, candidates, costs):  # noqa: ANN001, ANN202, E501
    """:func:`_window_costs` per frame ``i``: every candidate at its distance from the
    natural swivel plus :data:`OUTSIDE`, then the measured window's candidates at their
    distance, clearance penalty (or the nearby one, where more) and wrist load — the
    arithmetic of the numpy version (``tests/perf_equivalence/plain_costs.py``), element
    by element, the wrist state within numba's ``atan2``."""
    count = candidates.size
    fixed = wrist_constants(constants)
    for i in range(cells.shape[0]):
        for j in range(count):
            costs[i, j] = natural_cost(turn_remainder(candidates[j] - natural[i] + np.pi) - np.pi) + OUTSIDE
        cell = int(cells[i, 0]) % count - 1
        if hands.shape[0] == 0:
            for k in range(cells.shape[1]):
                # the window's cells are consecutive: the next candidate round the circle
                cell = cell + 1 if cell + 1 < count else 0
                costs[i, cell] = natural_cost(psi[i, k] - natural[i]) + _paid(penalty, nearby, i, k, cell)
            continue
        m = hand_matrix(hands, i)
        c = (circle_axis[i, 0], circle_axis[i, 1], circle_axis[i, 2])
        w = (wrist[i, 0], wrist[i, 1], wrist[i, 2])
        for k in range(cells.shape[1]):
            cell = cell + 1 if cell + 1 < count else 0
            flexion, deviation, twist, _ = wrist_angles(m, c, w, (ex[i, k], ey[i, k], ez[i, k]), (rx[i, k], ry[i, k], rz[i, k]), fixed)
            measured = natural_cost(psi[i, k] - natural[i]) + _paid(penalty, nearby, i, k, cell)
            costs[i, cell] = measured + wrist_load(flexion, deviation, twist, limits)


def parabola_offset(left: np.ndarray, middle: np.ndarray, right: np.ndarray) -> np.ndarray:
    """Where (in steps, within ±½) the parabola through three evenly spaced costs is lowest."""
    curvature = left - 2.0 * middle + right
    step = 0.5 * (left - right) / np.where(curvature > 1e-12, curvature, 1.0)
    return np.where(curvature > 1e-12, np.minimum(np.maximum(step, -0.5), 0.5), 0.0)


def load_kernels() -> None:
    """Run this module's compiled loops once (they load when it is imported):
    :func:`motor.compiled.warm_up`."""
    hands, points, cells = np.array([[0.0, 0.0, 0.0, 1.0]]), np.zeros((1, 3)), np.zeros((1, 1))
    constants, limits = np.ones(14), np.array([-1.0, 1.0, -1.0, 1.0, -1.0, 1.0])
    _wrist_rows(hands, points, points, *(cells,) * 6, constants, *(np.empty((1, 1)) for _ in range(4)))
    _cost_rows(np.zeros(1), *(cells,) * 3, np.zeros((0, 0)), hands, points, points, *(cells,) * 6, constants, limits, CANDIDATES, np.empty((1, CANDIDATES.size)))
