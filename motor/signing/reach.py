"""Sign paths kept within the arm's reach and out of the body (seed 000, section 4.4).

Every wrist position a sign plan passes through is kept with its hand out of the torso
(:mod:`motor.signing.hand_clearance`) and checked with the arm IK: positions out
of reach are pulled in, positions too near the shoulder step around its front, positions
so far across the body that no swivel keeps the upper arm out of the torso step back to
the arm's own side; chords between moved neighbours are refined with checked midpoints.
All positions are metres in the avatar frame; checks run in one vectorized IK call per
arm and round.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import replace

import numba
import numpy as np

from motor import quaternion as quat
from motor.arm.ik import ArmReach, arm_reach
from motor.body.avatar import Avatar
from motor.body.conventions import ARMS, AVATAR_SIDE
from motor.body.collision import outside_torso
from motor.kernel_types import READ2, READ_INTS2, WRITE1
from motor.signing.hand_clearance import hands_clear_of_torso
from motor.signing.lmp import Move
from motor.signing.plan import HandPose, SignPlan, SignPlanningError
from motor.signing.reach_steps import reach_probes, reach_step
from motor.signing.repeats import first_of_repeats
from motor.signing.spreading import any_coordinate, spread_along_chains

#: Shortest path length that counts as a movement, metres.
_SAME = 1e-6

#: How far (m) the IK may fall short before a position is moved within reach, and the
#: margin inside the reach limit that positions keep.
REACH_TOLERANCE = 1e-3


REACH_MARGIN = 0.03


#: Upper-arm penetration (m, IK diagnostics) that moves a position back from across the
#: body, in steps of CROSS_STEP metres, at most CROSS_STEPS of them.
PENETRATION_TOLERANCE = 1e-3


CROSS_STEP = 0.02


CROSS_STEPS = 16


#: Longest chord (m) between a path's checked points (see :func:`clear_paths`).
REFINE_SPACING = 0.03


#: Rounds of sharing a displacement along a chain (see :func:`clear_paths`).
SPREAD_ROUNDS = 8


#: Rows per IK call when checking many positions: the cost per row of the vectorized IK
#: is lowest around a few thousand rows (measured: ~16 µs at 1,000–4,000, ~25 µs at
#: 30,000 on the bench machine), as its temporaries then stay in the processor's caches.
IK_CHUNK = 2048


#: A path moved by more than this (m) is named in the plan's warnings, with the amount.
REACH_NOTE_THRESHOLD = 0.01


def within_reach_all(avatar: Avatar, drafts: list[SignPlan | SignPlanningError]) -> list[SignPlan | SignPlanningError]:
    """Plans with every wrist position moved within reach (:func:`within_reach`); a
    path the check leaves as it was, bit for bit, keeps its move."""
    plans = [draft for draft in drafts if isinstance(draft, SignPlan)]
    fixed: dict[int, dict] = {id(plan): {"first": dict(plan.first), "moves": dict(plan.moves), "notes": []} for plan in plans}
    for arm in ARMS:
        points, keys, owners = [], [], []
        for plan in plans:
            if arm not in plan.first:
                continue
            first = plan.first[arm]
            points.append(first.wrist[None])
            keys.append(first.rotation[None])
            for move, turn in zip(plan.moves[(arm, "wrist_position")], plan.moves[(arm, "hand_rotation")]):
                points.append(move.values)
                keys.append(turn.values)
            owners.append((plan, 1 + len(plan.moves[(arm, "wrist_position")])))
        if not points:
            continue
        counts = [count for _, count in owners]
        lengths = np.array([len(path) for path in points])
        original = np.concatenate(points, dtype=float)
        # a hand's first posture and moves in one sign are one chain: they still meet once cleared
        chains = np.repeat(np.arange(len(owners)), counts)
        cleared, cleared_lengths, _ = _cleared_runs(avatar, arm, original, rotations_along_paths(keys, points), lengths, chains=chains)
        changed = _changed_runs(cleared, cleared_lengths, original, lengths)
        ends = np.cumsum(cleared_lengths)
        # each changed path its own array; a path the check left as it was, bit for bit, keeps its move
        pieces = {
            index: cleared[end - size : end].copy()
            for index, end, size in zip(np.flatnonzero(changed).tolist(), ends[changed].tolist(), cleared_lengths[changed].tolist())
        }
        shifts = np.zeros(len(points))
        shifts[changed] = path_shifts(list(pieces.values()), [points[index] for index in pieces])
        starts = np.cumsum(counts) - counts
        noted = shifts > REACH_NOTE_THRESHOLD
        for (plan, count), start, notes, largest in zip(
            owners, starts.tolist(), np.add.reduceat(noted, starts).tolist(), np.maximum.reduceat(shifts, starts).tolist()
        ):
            record = fixed[id(plan)]
            if notes:
                record["notes"].append(
                    f"{plan.gloss}: {notes} path(s) of the {arm} hand moved within reach or out of the body, "
                    f"by up to {100.0 * largest:.1f} cm"
                )
            if start in pieces:
                first = plan.first[arm]
                record["first"][arm] = HandPose(pieces[start][0], first.rotation, first.shape)
            record["moves"][(arm, "wrist_position")] = tuple(
                Move(m.start, m.end, m.manner, pieces[index]) if index in pieces else m
                for index, m in enumerate(plan.moves[(arm, "wrist_position")], start + 1)
            )
    return [
        draft if not isinstance(draft, SignPlan) else replace(
            draft, first=fixed[id(draft)]["first"], moves=fixed[id(draft)]["moves"],
            warnings=draft.warnings + tuple(fixed[id(draft)]["notes"]),
        )
        for draft in drafts
    ]  # fmt: skip


def within_reach(
    avatar: Avatar, arm: str, points: np.ndarray, rotations: np.ndarray | None = None, unique: bool = True, across: bool = True
) -> tuple[np.ndarray, int, float]:
    """Wrist positions ``(n, 3)`` the arm reaches, with its upper arm out of the torso.

    Positions out of reach, or within :data:`REACH_MARGIN` of its limit (interpolation
    between two reachable positions can leave the reachable shell, whose shoulder moves
    with the clavicle), are pulled in to that margin; positions too near the shoulder
    for the elbow's flexion step away from it and forward (around the shoulder's front,
    where the hand passes) by what they lack, at least :data:`CROSS_STEP`; positions so far across the body
    that no swivel keeps the upper arm out of the torso (the IK reports penetration) step
    back toward the arm's own side and forward by :data:`CROSS_STEP` until it does. Also returns how
    many positions moved and the largest shortfall (m). ``rotations`` ``(n, 4)`` are the
    hand's global rotations there, which change the swivel the IK picks. With ``across``
    False the step back from across the body is left out.

    Each position is moved on its own (the IK solves every row apart), so with ``unique``
    a position that occurs again with the same rotation, bit for bit, is solved once (a
    collection of signs repeats many postures); ``unique=False`` solves every row."""
    points = np.asarray(points, dtype=float).reshape(-1, 3)
    if not unique or len(points) < 2:
        fixed, moved, worst = _within_reach(avatar, arm, points, rotations, across)
        return fixed, int(moved.sum()), worst
    rows = points if rotations is None else np.concatenate([points, np.asarray(rotations, dtype=float)], axis=1)
    first, inverse = first_of_repeats(rows)
    turns = None if rotations is None else np.asarray(rotations, dtype=float)[first]
    fixed, moved, worst = _within_reach(avatar, arm, points[first], turns, across)
    return fixed[inverse], int(moved[inverse].sum()), worst


def _within_reach(
    avatar: Avatar, arm: str, points: np.ndarray, rotations: np.ndarray | None, across: bool = True
) -> tuple[np.ndarray, np.ndarray, float]:
    """:func:`within_reach` of every row: positions, which moved, the largest shortfall.
    Each step probes the open rows and moves them in compiled passes
    (:mod:`motor.signing.reach_steps`)."""
    side = AVATAR_SIDE[arm]
    shoulder = avatar.rest_positions[avatar.joint_index(f"{side}_shoulder")]
    outward = np.array([-1.0 if arm == "right" else 1.0, 0.0, 1.0]) * CROSS_STEP
    ahead = np.array([0.0, 0.0, CROSS_STEP]) / CROSS_STEP
    limits = np.array([REACH_MARGIN, REACH_TOLERANCE, PENETRATION_TOLERANCE, CROSS_STEP, 0.5 * avatar.arm_length(side)])
    fixed = np.array(points, dtype=float)
    moved = np.zeros(len(fixed), dtype=bool)
    open_ = np.arange(len(fixed))
    worst = 0.0
    for _ in range(CROSS_STEPS):
        if open_.size == 0:
            break
        away, targets = reach_probes(fixed, open_, shoulder, REACH_MARGIN)
        turns = None if rotations is None else np.asarray(rotations)[open_]
        # beyond and short of each position, in the same IK calls; the depth only where it is read
        probed = _solve_in_chunks(avatar, side, targets, None if turns is None else np.concatenate([turns, turns]), across)
        worst = max(worst, float(np.max(probed.shortfall[: open_.size] - REACH_MARGIN, initial=0.0)))
        bad = reach_step(fixed, open_, away, probed, shoulder, limits, outward, ahead, across)
        moved[open_[bad]] = True
        open_ = open_[bad]
    return fixed, moved, max(worst, 0.0)


def _solve_in_chunks(avatar: Avatar, side: str, targets: np.ndarray, turns: np.ndarray | None, with_depth: bool = True) -> ArmReach:
    """The arm IK's reach (:func:`motor.arm.ik.arm_reach`, the body's depth only
    ``with_depth``) for many wrist positions, :data:`IK_CHUNK` rows per call (the IK
    solves every row apart; its cost per row grows for very long calls)."""
    chunks = (slice(start, start + IK_CHUNK) for start in range(0, len(targets), IK_CHUNK))
    parts = [arm_reach(avatar, side, targets[rows], None if turns is None else turns[rows], with_depth) for rows in chunks]
    if len(parts) == 1:
        return parts[0]
    return ArmReach(*(np.concatenate(column) for column in zip(*parts)))


def clear_paths(
    avatar: Avatar,
    arm: str,
    paths: list[np.ndarray],
    rotations: list[np.ndarray],
    keep_ends: bool = False,
    chains: np.ndarray | None = None,
    across: bool = True,
) -> tuple[list[np.ndarray], int]:
    """Wrist paths ``(m, 3)`` (with the hand's rotations ``(m, 4)`` along them) kept
    outside the torso, the hand in those rotations too, and within reach
    (:func:`outside_torso`, :func:`motor.signing.hand_clearance.hands_clear_of_torso`,
    :func:`within_reach`); with
    ``keep_ends`` the first and last points stay. Also returns how many points moved.

    Each path first gets evenly spaced points inserted wherever neighbours lie more than
    :data:`REFINE_SPACING` apart (a chord between checked points could cut the torso or
    the unreachable core around the shoulder). Points are not moved one by one — a path
    whose points each stepped aside on their own would zigzag, and the hand would jerk
    along it — but by a displacement that varies smoothly along the path: what each
    point needs is spread over its neighbours within ``SPREAD`` metres of arc
    (:func:`motor.signing.spreading.spread_along_chains`), for :data:`SPREAD_ROUNDS` rounds, each checking only the points
    that moved; a last check moves whatever still needs it. A short path whose points all
    need about the same thus moves whole, keeping its shape. Paths of one ``chains``
    number ``(len(paths),)``, in order, are one hand's consecutive moves (each starting
    where the one before ends): they share one displacement along their joined arc, so
    they still meet. With ``across`` False no point is stepped back from across the body
    (:func:`within_reach`): a transition between two postures already checked keeps to
    the torso and the reach only. All paths are handled as one array of points (each
    round is a few vectorized passes over the collection)."""
    if not paths:
        return [], 0
    points, turns = (np.concatenate(rows, dtype=float).reshape(-1, width) for rows, width in ((paths, 3), (rotations, 4)))
    points, lengths, total = _cleared_runs(avatar, arm, points, turns, np.array([len(path) for path in paths]), keep_ends, chains, across)
    return [piece.copy() for piece in split_runs(points, lengths)], total  # each path its own array


def _cleared_runs(
    avatar: Avatar,
    arm: str,
    points: np.ndarray,
    turns: np.ndarray,
    lengths: np.ndarray,
    keep_ends: bool = False,
    chains: np.ndarray | None = None,
    across: bool = True,
) -> tuple[np.ndarray, np.ndarray, int]:
    """:func:`clear_paths` of paths laid end to end: points ``(n, 3)`` and rotations
    ``(n, 4)`` in runs ``lengths (k,)`` long. The cleared points laid end to end, the
    runs' new lengths and how many points moved."""
    points, turns, lengths = _refined(points, turns, lengths)
    owner = np.repeat(np.arange(len(lengths)), lengths)
    chain = (np.arange(len(lengths)) if chains is None else np.asarray(chains))[owner]
    mask = np.ones(len(points), dtype=bool)
    if keep_ends:
        ends = np.cumsum(lengths)[lengths > 0]
        mask[ends - lengths[lengths > 0]] = False
        mask[ends - 1] = False
    original = points
    arc = _chain_arc(points, owner, chain)
    checked = mask.copy()
    for _ in range(SPREAD_ROUNDS):
        cleared, moved, _ = _clear_points(avatar, arm, points, turns, checked, across)
        if not moved.any():
            break
        shift = spread_along_chains(cleared - points, arc, chain, ~mask) * mask[:, None]
        points = points + shift
        checked = mask & any_coordinate(np.abs(shift) > 1e-12)
    points = _clear_points(avatar, arm, points, turns, checked, across)[0]
    return points, lengths, int(any_coordinate(np.abs(points - original) > 1e-9).sum())


def _refined(points: np.ndarray, turns: np.ndarray, lengths: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Paths ``lengths`` long (concatenated points ``(n, 3)``, rotations ``(n, 4)``) with
    evenly spaced points inserted on every chord longer than :data:`REFINE_SPACING` (the
    rotations slerped), so that no chord is longer."""
    owner = np.repeat(np.arange(len(lengths)), lengths)
    gap = np.linalg.norm(np.diff(points, axis=0), axis=1)
    pieces = np.where(owner[1:] == owner[:-1], np.ceil(gap / REFINE_SPACING - 1e-9), 1).astype(int)
    pieces = np.maximum(pieces, 1)
    if np.all(pieces == 1):
        return points, turns, lengths
    # each point i < n − 1 becomes pieces[i] points: itself and pieces[i] − 1 along its chord
    chord = np.repeat(np.arange(len(points) - 1), pieces)
    step = np.arange(chord.size) - np.repeat(np.cumsum(pieces) - pieces, pieces)
    fraction = step / np.repeat(pieces, pieces)
    refined = np.concatenate([points[chord] + fraction[:, None] * (points[chord + 1] - points[chord]), points[-1:]])
    refined_turns = np.concatenate([quat.slerp(turns[chord], turns[chord + 1], fraction), turns[-1:]])
    inserted = np.bincount(owner[:-1], weights=pieces - 1, minlength=len(lengths)).astype(int)
    return refined, refined_turns, lengths + inserted


def _chain_arc(points: np.ndarray, owner: np.ndarray, chain: np.ndarray) -> np.ndarray:
    """Arc length (m) of every point from the start of its chain: a path continues its
    chain's arc from where the path before it ends. Summed chain by chain (a row of a
    table each), so that a chain's arc does not depend on the chains before it."""
    step = np.concatenate([[0.0], np.linalg.norm(np.diff(points, axis=0), axis=1)])
    step[np.concatenate([[True], owner[1:] != owner[:-1]])] = 0.0
    first = np.flatnonzero(np.concatenate([[True], chain[1:] != chain[:-1]]))
    sizes = np.diff(np.append(first, len(points)))
    row = np.repeat(np.arange(len(first)), sizes)
    column = np.arange(len(points)) - first[row]
    table = np.zeros((len(first), int(sizes.max())))
    table[row, column] = step
    return np.cumsum(table, axis=1)[row, column]


def _clear_points(
    avatar: Avatar, arm: str, points: np.ndarray, turns: np.ndarray, mask: np.ndarray, across: bool = True
) -> tuple[np.ndarray, np.ndarray, int]:
    """The masked points ``(n, 3)`` checked at once; which points moved."""
    chosen = points[mask]
    if chosen.size == 0:
        return points, np.zeros(len(points), dtype=bool), 0
    clear = hands_clear_of_torso(avatar, AVATAR_SIDE[arm], outside_torso(avatar, chosen), turns[mask])
    fixed = within_reach(avatar, arm, clear, turns[mask], across=across)[0]
    changed = any_coordinate(np.abs(fixed - chosen) > 1e-9)
    points = points.copy()
    points[mask] = fixed
    moved = np.zeros(len(points), dtype=bool)
    moved[mask] = changed
    return points, moved, int(changed.sum())


def path_shifts(moved: list[np.ndarray], original: list[np.ndarray]) -> np.ndarray:
    """:func:`path_shift` of every pair of paths ``(m_k, 3)``, ``(n_k, 3)`` ``(k,)``, m, in
    one compiled pass over every moved point and every chord of its original path (tens of
    thousands per corpus), each value with :func:`path_shift`'s arithmetic (its dot
    products summed as ``np.einsum`` sums three terms: the first and last, then the
    middle). A one-point original is a chord from the point to itself, whose nearest point
    is it."""
    if not moved:
        return np.zeros(0)
    points = np.ascontiguousarray(np.concatenate(moved), dtype=float)
    polylines = np.ascontiguousarray(np.concatenate(original), dtype=float)
    counts = np.array([[len(a), len(b)] for a, b in zip(moved, original)], dtype=np.int64)
    shifts = np.empty(len(moved))
    _shift_rows(points, polylines, counts, shifts)
    return shifts


@numba.njit(cache=True, error_model="numpy", inline="always")
def _dot(x0, x1, x2, y0, y1, y2):  # noqa: ANN001, ANN202
    """A dot product of three terms as ``np.einsum`` sums them."""
    return (x0 * y0 + x2 * y2) + x1 * y1


@numba.njit(
    [numba.void(READ2, READ2, READ_INTS2, WRITE1)],
    cache=True,
    error_model="numpy",
)
def _shift_rows(points, polylines, counts, shifts):  # noqa: ANN001, ANN202
    """Into ``shifts``: per pair ``k`` of a moved path (``counts[k, 0]`` rows of ``points``)
    and its original (``counts[k, 1]`` rows of ``polylines``), the farthest of the moved
    points from the nearest chord."""
    point, vertex = 0, 0
    for k in range(counts.shape[0]):
        size, corners = counts[k, 0], counts[k, 1]
        chords = max(corners - 1, 1)
        worst = 0.0
        for p in range(point, point + size):
            nearest = 0.0
            for c in range(chords):
                a = vertex + c
                b = a if corners == 1 else a + 1
                ax, ay, az = polylines[a, 0], polylines[a, 1], polylines[a, 2]
                lx, ly, lz = polylines[b, 0] - ax, polylines[b, 1] - ay, polylines[b, 2] - az
                length = max(_dot(lx, ly, lz, lx, ly, lz), 1e-18)
                t = min(max(_dot(points[p, 0] - ax, points[p, 1] - ay, points[p, 2] - az, lx, ly, lz) / length, 0.0), 1.0)
                gx, gy, gz = points[p, 0] - (ax + t * lx), points[p, 1] - (ay + t * ly), points[p, 2] - (az + t * lz)
                distance = math.sqrt((gx * gx + gy * gy) + gz * gz)
                nearest = distance if c == 0 else min(nearest, distance)
            worst = nearest if p == point else max(worst, nearest)
        shifts[k] = worst
        point += size
        vertex += corners


def path_shift(moved: np.ndarray, original: np.ndarray) -> float:
    """How far (m) a path was moved: the largest distance of a point of ``moved`` ``(m, 3)``
    from the polyline ``original`` ``(n, 3)`` (midpoints may have been inserted)."""
    if len(original) == 1:
        return float(np.max(np.linalg.norm(moved - original[0], axis=1)))
    a, b = original[:-1], original[1:]
    chord = b - a
    lengths = np.maximum(np.einsum("ij,ij->i", chord, chord), 1e-18)
    t = np.clip(np.einsum("mij,ij->mi", moved[:, None, :] - a[None], chord) / lengths, 0.0, 1.0)
    nearest = a[None] + t[..., None] * chord[None]
    return float(np.max(np.min(np.linalg.norm(moved[:, None, :] - nearest, axis=2), axis=1)))


def rotations_along(keys: np.ndarray, fractions: np.ndarray) -> np.ndarray:
    """Rotations ``(n, 4)`` at fractions of the way through evenly spaced keys ``(m, 4)``."""
    position = np.clip(fractions, 0.0, 1.0) * (len(keys) - 1)
    index = np.minimum(position.astype(int), len(keys) - 2)
    return quat.slerp(keys[index], keys[index + 1], position - index)


def rotations_along_paths(keys: list[np.ndarray], paths: list[np.ndarray]) -> np.ndarray:
    """For every path ``(n_k, 3)``: the rotations ``(n_k, 4)`` at its points' fractions of
    the way (:func:`arc_fractions`) through its evenly spaced keys ``(m_k, 4)``
    (:func:`rotations_along`); a path of one point takes its only key. Concatenated
    ``(sum n_k, 4)``, as :func:`arc_fractions_of_paths`; all paths in a few vectorized
    passes, each row computed as those functions compute it."""
    counts = np.array([len(path) for path in paths])
    key_counts = np.array([len(key) for key in keys])
    flat_keys = np.concatenate(keys)
    single = np.repeat(key_counts == 1, counts)
    spans = np.repeat(key_counts, counts)
    base = np.repeat(np.cumsum(key_counts) - key_counts, counts)
    fractions = arc_fractions_of_paths(paths)
    position = np.clip(fractions, 0.0, 1.0) * (spans - 1)
    index = np.where(single, 0, np.minimum(position.astype(int), spans - 2))
    following = np.where(single, 0, index + 1)
    turns = quat.slerp(flat_keys[base + index], flat_keys[base + following], position - index)
    turns[single] = flat_keys[base[single]]
    return turns


def arc_fractions_of_paths(paths: list[np.ndarray]) -> np.ndarray:
    """:func:`arc_fractions` of every path, concatenated ``(sum n_k,)``, in vectorized passes."""
    counts = np.array([len(path) for path in paths])
    points = np.concatenate(paths)
    starts = np.cumsum(counts) - counts
    owner = np.repeat(np.arange(len(paths)), counts)
    column = np.arange(len(points)) - starts[owner]
    steps = np.linalg.norm(np.diff(points, axis=0), axis=1)
    within = column[1:] > 0
    table = np.zeros((len(paths), int(counts.max())))
    table[owner[1:][within], column[1:][within]] = steps[within]
    travelled = np.cumsum(table, axis=1)
    lengths = travelled[owner, column]
    totals = travelled[np.arange(len(paths)), counts - 1]
    fractions = lengths / np.where(totals > _SAME, totals, 1.0)[owner]
    # a path that does not move: evenly spaced, as np.linspace(0, 1, n) computes them
    still = (totals <= _SAME)[owner]
    step = 1.0 / np.maximum(counts - 1, 1)
    fractions[still] = column[still] * step[owner[still]] + 0.0
    last = starts + counts - 1
    fractions[last[(totals <= _SAME) & (counts > 1)]] = 1.0
    return fractions


def split_runs(rows: np.ndarray, counts: Sequence[int] | np.ndarray) -> list[np.ndarray]:
    """``rows`` cut into consecutive runs of ``counts`` rows, views (as :func:`numpy.split`
    at the cumulative counts gives them, without its overhead per piece)."""
    ends = np.cumsum(counts).tolist()
    return [rows[start:end] for start, end in zip([0, *ends[:-1]], ends)]


def _changed_runs(paths: np.ndarray, lengths: np.ndarray, originals: np.ndarray, original_lengths: np.ndarray) -> np.ndarray:
    """Which paths laid end to end in ``paths (n, 3)``, runs ``lengths (k,)`` long, differ
    from the originals laid end to end ``(m, 3)`` in runs ``original_lengths`` ``(k,)``:
    in length (points were inserted) or in any coordinate, bit for bit (a zero that
    changed its sign counts: a path found the same is kept as it was)."""
    changed = lengths != original_lengths
    same = ~changed
    new, old = (rows[np.repeat(same, runs)].view(np.int64) for rows, runs in ((paths, lengths), (originals, original_lengths)))
    differs = any_coordinate(new != old)
    counts = lengths[same]
    kept = np.flatnonzero(same)[counts > 0]
    if kept.size:
        changed[kept] = np.logical_or.reduceat(differs, (np.cumsum(counts) - counts)[counts > 0])
    return changed


def arc_fractions(points: np.ndarray) -> np.ndarray:
    lengths = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(points, axis=0), axis=1))])
    return lengths / lengths[-1] if lengths[-1] > _SAME else np.linspace(0.0, 1.0, len(points))


def load_kernels() -> None:
    """Run this module's compiled loop once (it loads when the module is imported):
    :func:`motor.compiled.warm_up`."""
    path_shifts([np.zeros((1, 3))], [np.zeros((2, 3))])
