"""A sign's hands laid out before their plan, and their wrists placed, many signs at once.

The sign compiler (:mod:`motor.signing.sign_compiler`) compiles each sign into a :class:`Layout`:
its hands' first postures and, per move, the palm path with the wrist-to-palm offsets of
the move's first and last postures. :func:`placed` turns the palm paths of all the layouts
of a collection into wrist paths and eases every wrist position out of the torso in one
pass, each row's arithmetic that of a move alone.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from motor.body.avatar import Avatar
from motor.body.collision import kept_out_of_torso
from motor.signing.plan import HandPose
from motor.signing.reach import arc_fractions_of_paths, split_runs


@dataclass(frozen=True, eq=False)
class Layout:
    """A sign's hands before their plan: first postures, and per hand and move the palm
    path ``(m, 3)`` with the wrist-to-palm offsets ``(3,)`` of its first and last postures
    (metres); once placed (:func:`placed`), ``wrists`` holds each move's wrist path."""

    first: dict[str, HandPose]
    palms: dict[str, list[tuple[np.ndarray, np.ndarray, np.ndarray]]]
    wrists: dict[str, list[np.ndarray]] | None = None


def placed(avatar: Avatar, layouts: Sequence[Layout]) -> list[Layout]:
    """The layouts with their wrist paths — each palm path less the offset to the palm,
    blended from the first posture's to the last's by the fraction of the way
    (:func:`motor.signing.reach.arc_fractions`) — and every wrist position, first postures
    too, eased out of the torso (:func:`kept_out_of_torso`, continuous in the position); all the moves of all the layouts
    in one pass, each row's arithmetic that of a move alone."""
    moves = [move for layout in layouts for palms in layout.palms.values() for move in palms]
    points = [pose.wrist[None] for layout in layouts for pose in layout.first.values()]
    if moves:
        counts = [len(palm) for palm, _, _ in moves]
        fractions = arc_fractions_of_paths([palm for palm, _, _ in moves])[:, None]
        start = np.repeat(np.array([offset for _, offset, _ in moves]), counts, axis=0)
        end = np.repeat(np.array([offset for _, _, offset in moves]), counts, axis=0)
        wrists = np.concatenate([palm for palm, _, _ in moves]) - ((1.0 - fractions) * start + fractions * end)
        points.append(wrists)
    if not points:
        return list(layouts)
    eased = kept_out_of_torso(avatar, np.concatenate(points))
    hands = iter(eased[: len(points) - bool(moves)])
    paths = iter(split_runs(eased[len(points) - bool(moves) :], counts) if moves else ())
    return [
        Layout(
            {arm: HandPose(next(hands), pose.rotation, pose.shape) for arm, pose in layout.first.items()},
            layout.palms,
            {arm: [next(paths) for _ in palms] for arm, palms in layout.palms.items()},
        )
        for layout in layouts
    ]
