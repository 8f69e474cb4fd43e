"""A sign's non-manual tiers realized with the same temporal trajectories as its hands (seed 000).

HamNoSys/SiGML writes non-manuals in tiers — shoulders, body, head, eye gaze, facial
expression (eyebrows, eyelids, nose) and mouth (mouth gestures, mouth pictures) — each
item a two-letter code (``hnm_head tag="NO"``, gestural ``<head_movement
movement="NO"/>``) or, for mouth pictures, a SAMPA string. Seed 000 gives each an
attack, a sustain and a release: here the attack runs during the sign's transition (from
its ``start`` to ``ready``, when the hands reach the first posture), the sustain over the
sign's movement (``ready`` to ``end``), the release after it. The items go to the neck
(:mod:`motor.neck`: head lexemes, gaze, torso and shoulders) and the face
(:mod:`motor.face`: expressions, blinks, mouthings):

* head: swings (``NO``, ``SH``) fill the movement, at their own pace when it is shorter;
  held postures (``TL``, ``SR``, ``NF`` …) rise during the transition;
* eye gaze: ``AD`` the addressee, ``FR`` far ahead, ``UP``/``DN``/``LE``/``RI`` up,
  down, left, right, ``HD``/``HN``/``HB`` the dominant, the non-dominant or both hands,
  ``NO`` no target (rest); the eyes arrive by ``ready`` and return to rest after the sign;
* eyebrows, eyelids, nose, mouth gestures: :mod:`motor.face.expressions` (``BB`` is one
  blink at ``ready``);
* mouth pictures: the SAMPA segments spread over the sign's movement (over their own
  length from ``ready`` when the movement is shorter), coarticulated like speech.

An unknown tag, code or SAMPA character is reported with the sign, the place in the
file and the code, and left out; the rest of the sign is performed.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, replace

import numpy as np

from motor.body.avatar import Avatar
from motor.face.blinks import BlinkLMP
from motor.face.expressions import UnknownExpression, expression, hamnosys_face
from motor.face.lipsync import mouth_picture
from motor.face.planning import mouthing_duration
from motor.neck.gaze import UnknownGazeTarget, gaze, gaze_target, rest
from motor.neck.lexemes import UnknownHeadLexeme, head_lexeme, natural_duration
from motor.neck.trunk import UnknownTrunkCode, trunk_movement
from motor.trajectory.envelope import Envelope
from mura.errors import SourceLocation
from mura.signs import NonmanualItem

#: SiGML non-manual element → (tier, attribute holding its code); ``hnm_…`` in
#: ``<hns_sign>``, the others in ``<hamgestural_sign>``.
ITEMS: dict[str, tuple[str, str]] = {
    "hnm_shoulder": ("shoulder", "tag"), "shoulder_movement": ("shoulder", "movement"),
    "hnm_body": ("body", "tag"), "body_movement": ("body", "movement"),
    "hnm_head": ("head", "tag"), "head_movement": ("head", "movement"),
    "hnm_eyegaze": ("eyegaze", "tag"), "eye_gaze": ("eyegaze", "direction"),
    "hnm_eyebrows": ("eyebrows", "tag"), "eye_brows": ("eyebrows", "movement"),
    "hnm_eyelids": ("eyelids", "tag"), "eye_lids": ("eyelids", "movement"),
    "hnm_nose": ("nose", "tag"), "nose": ("nose", "movement"),
    "hnm_mouthgesture": ("mouthgesture", "tag"), "mouth_gesture": ("mouthgesture", "movement"),
    "hnm_mouthpicture": ("mouthpicture", "picture"), "mouth_picture": ("mouthpicture", "picture"),
    "hnm_extra": ("extra", "tag"), "extra_movement": ("extra", "movement"),
}  # fmt: skip
#: HamNoSys eye-gaze codes → gaze target names of :mod:`motor.neck.gaze`.
EYE_GAZE: dict[str, str] = {
    "AD": "listener", "FR": "ahead", "NO": "rest", "UP": "up", "DN": "down", "LE": "left", "RI": "right",
    "HD": "dominanthand", "HN": "nondominant", "HB": "hands",
}  # fmt: skip
#: Release of every non-manual after the sign's movement, seconds.
RELEASE = 0.25


@dataclass
class NonmanualPlan:
    """The neck LMPs and face tracks of one sign's non-manual tiers, and the notes."""

    lmps: list = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)


def plan_nonmanuals(
    avatar: Avatar, gloss: str, tiers: Mapping[str, Sequence[NonmanualItem]], start: float, ready: float, end: float,
    hands: Callable[[str, np.ndarray], np.ndarray] | None = None, dominant: str = "right", where: SourceLocation | None = None,
) -> NonmanualPlan:  # fmt: skip
    """The non-manuals of sign ``gloss`` whose transition starts at ``start``, reaches its
    first posture at ``ready`` and whose movement ends at ``end`` (seconds; module docstring).
    ``hands(arm, times)`` gives palm centres for gaze at the hands."""
    plan = NonmanualPlan()
    reader = _Reader(avatar, gloss, start, max(ready, start), max(end, ready, start), hands, dominant, where, plan)
    for items in tiers.values():
        for item in items:
            reader.item(item)
    return plan


@dataclass
class _Reader:
    avatar: Avatar
    gloss: str
    start: float
    ready: float
    end: float
    hands: Callable[[str, np.ndarray], np.ndarray] | None
    dominant: str
    where: SourceLocation | None
    plan: NonmanualPlan
    gazed: bool = False

    @property
    def attack(self) -> float:
        return max(self.ready - self.start, 0.1)

    def warn(self, item: NonmanualItem, message: str) -> None:
        place = item.where or self.where
        self.plan.warnings.append(f"sign {self.gloss!r} ({place if place is not None else 'unknown place'}): {message}")

    def item(self, item: NonmanualItem) -> None:
        attributes = dict(item.attributes)
        known = ITEMS.get(item.tag)
        if known is None:
            if attributes:
                self.warn(item, f"non-manual <{item.tag}> is not one mura reads; left out")
            return
        tier, attribute = known
        code = attributes.get(attribute, "").strip()
        if not code:
            self.warn(item, f"<{item.tag}> has no {attribute}; left out")
            return
        read = getattr(self, f"_{tier}", None)
        if read is None:
            self.warn(item, f"{tier} {code!r} is not realized (mura reads shoulder, body, head, eye gaze, facial and mouth tiers)")
            return
        read(item, code)

    def _head(self, item: NonmanualItem, code: str) -> None:
        if code.upper() == "LI":
            self.warn(item, "head linked to the eye gaze (LI): the eye–head split of the gaze already turns the head")
            return
        try:
            probe = head_lexeme(code, self.ready)
        except UnknownHeadLexeme as error:
            self.warn(item, f"{error}; the head does not move for it")
            return
        if probe.lexeme.held:
            self.plan.lmps.append(replace(head_lexeme(code, self.ready, self.end), attack=self.attack, release=RELEASE))
        else:
            self.plan.lmps.append(head_lexeme(code, self.ready, max(self.end, self.ready + natural_duration(probe.lexeme))))

    def _eyegaze(self, item: NonmanualItem, code: str) -> None:
        name = EYE_GAZE.get(code.upper())
        if name is None:
            self.warn(item, f"unknown eye gaze code {code!r} (known: {', '.join(sorted(EYE_GAZE))}); the eyes stay where they are")
            return
        if name == "dominanthand":
            name = f"{self.dominant}hand"
        elif name == "nondominant":
            name = "lefthand" if self.dominant == "right" else "righthand"
        try:
            target = rest(self.avatar) if name == "rest" else gaze_target(self.avatar, name, self.hands)
        except UnknownGazeTarget as error:
            self.warn(item, f"{error}; the eyes stay where they are")
            return
        self.plan.lmps.append(gaze(self.avatar, target, self.start, self.end))
        if not self.gazed:
            self.plan.lmps.append(gaze(self.avatar, rest(self.avatar), self.end, self.end + RELEASE, returning=True))
            self.gazed = True

    def _body(self, item: NonmanualItem, code: str) -> None:
        self._trunk(item, code)

    def _shoulder(self, item: NonmanualItem, code: str) -> None:
        self._trunk(item, code)

    def _trunk(self, item: NonmanualItem, code: str) -> None:
        try:
            lmp = trunk_movement(code, self.ready, self.end)
        except UnknownTrunkCode as error:
            self.warn(item, f"{error}; left out")
            return
        self.plan.lmps.append(replace(lmp, attack=self.attack, release=RELEASE))

    def _face(self, item: NonmanualItem, tier: str, code: str) -> None:
        if tier == "eyelids" and code.upper() == "BB":
            self.plan.lmps.append(BlinkLMP(self.ready))
            return
        try:
            weights, note = hamnosys_face(tier, code)
        except UnknownExpression as error:
            self.warn(item, f"{error}; left out")
            return
        if note is not None:
            self.warn(item, note)
        self.plan.lmps.append(expression(weights, Envelope.around(self.ready, self.end, self.attack, RELEASE), 1.0, f"{tier} {code}"))

    def _eyebrows(self, item: NonmanualItem, code: str) -> None:
        self._face(item, "eyebrows", code)

    def _eyelids(self, item: NonmanualItem, code: str) -> None:
        self._face(item, "eyelids", code)

    def _nose(self, item: NonmanualItem, code: str) -> None:
        self._face(item, "nose", code)

    def _mouthgesture(self, item: NonmanualItem, code: str) -> None:
        self._face(item, "mouthgesture", code)

    def _mouthpicture(self, item: NonmanualItem, code: str) -> None:
        end = max(self.end, self.ready + mouthing_duration(code))
        articulation, skipped = mouth_picture(code, self.ready, end)
        for position, char in skipped:
            self.warn(item, f"mouth picture {code!r}: unknown SAMPA symbol {char!r} at position {position}; left out")
        if articulation is not None:
            self.plan.lmps.append(articulation)

