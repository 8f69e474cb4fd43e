"""Where a sign's hand goes, and where its parts then are: the hand-placement half of
compiling a sign (:class:`motor.signing.sign_compiler.SignCompiler` holds one
:class:`HandPlacement` and asks it).

A location names where the *palm centre* goes (the avatar's ``palm`` site of that hand),
or the part of the hand its contact bracket names (``hamchin [hamtouch hamthumb
hamfingertip]``: the thumb's tip); the wrist is placed so that it gets there with the hand
in its orientation and shape. Locations come from
:func:`motor.body.locations.resolve_location`: body sites with their proximity and side,
the signing-space grid, and sites on the other arm or hand, read from that arm's posture
at the time (forward kinematics). A sign without a location is made in neutral space,
:data:`NEUTRAL_LOCATION` (mirrored for the left hand). Site names the resolver does not
know are read as documented in :data:`motor.signing.sites.SITE_ALIASES` and
:data:`~motor.signing.sites.PROXIMITY_ALIASES`; the bare ``contact`` site keeps the hand
where it is.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace

import numpy as np

from motor import quaternion as quat
from motor.body.conventions import AVATAR_SIDE
from motor.body.kinematics import Pose
from motor.body.locations import resolve_location
from motor.signing.hand_geometry import HandGeometry, key_bytes
from motor.signing.plan import HandPose
from motor.signing.sites import is_hand_site, normalized, on_other_hand
from mura.signs import HandPosture
from mura.values import BetweenLocation, BodySite, GridLocation, HandShape, Location, PalmOrientation

#: Neutral signing space of the right hand (mirrored for the left).
NEUTRAL_LOCATION = GridLocation("LocLowerChest", "LocCCenterRight", "LocNorm")
#: Extended-finger direction and palm of a hand whose sign leaves them open.
NEUTRAL_FINGERS = (0.0, 0.0, 1.0)
_NEUTRAL_LEFT = replace(NEUTRAL_LOCATION, lateral="LocCCenterLeft")
PALM = BodySite("palm", proximity="touch")


@dataclass(eq=False, slots=True)
class PlannedHand:
    """A hand's state while planning: palm-centre location, EFD and palm vectors, shape;
    ``rotations`` holds its global rotation by side once a memoizing compiler has asked for
    it (:meth:`HandPlacement.rotation`), shared with the copies that keep its fingers and palm.
    Unchanged once made, though not frozen: frozen, one took 4× as long (~27,000 a collection)."""

    location: np.ndarray
    fingers: np.ndarray
    palm: np.ndarray
    shape: HandShape
    params: np.ndarray
    rotations: dict[str, np.ndarray]

    def at(self, location: np.ndarray) -> PlannedHand:
        """The same hand with its palm centre at ``location`` (``dataclasses.replace``
        without its overhead: planning moves hands tens of thousands of times)."""
        return PlannedHand(location, self.fingers, self.palm, self.shape, self.params, self.rotations)

    def turned(self, fingers: np.ndarray, palm: np.ndarray) -> PlannedHand:
        """The same hand with its extended fingers and palm along ``fingers``, ``palm`` (as :meth:`at`)."""
        return PlannedHand(self.location, fingers, palm, self.shape, self.params, {})

    def shaped(self, shape: HandShape, params: np.ndarray) -> PlannedHand:
        """The same hand in another shape, ``params`` its joint parameters (as :meth:`at`)."""
        return PlannedHand(self.location, self.fingers, self.palm, shape, params, self.rotations)


class HandPlacement:
    """A sign's hands placed and measured (module docstring): where a posture puts the palm
    centre, the hand's global rotation, the offsets from the wrist to its sites — each
    offset asked once per sign and posture (:meth:`offset_request`), so that a collection
    compiled in rounds computes them all at once (:class:`HandGeometry`).

    ``hands`` are the sign's hands as compiled so far (a site on the other hand is read
    from it), ``note`` records a warning about the sign."""

    def __init__(self, geometry: HandGeometry, hands: dict[str, PlannedHand], note: Callable[[str], None]) -> None:
        self.geometry = geometry
        self.avatar = geometry.avatar
        self.hands = hands
        self.note = note
        self._offsets: dict[tuple, tuple[str, BodySite, np.ndarray, np.ndarray]] = {}
        self._asked: dict[tuple, tuple[str, BodySite, np.ndarray, np.ndarray]] = {}

    def hand_from(self, arm: str, posture: HandPosture, other: PlannedHand | None) -> PlannedHand:
        shape = posture.shape or HandShape("flathand")
        fingers = np.asarray(posture.ext_finger.vector if posture.ext_finger else NEUTRAL_FINGERS, dtype=float)
        palm = self.palm_vector(arm, fingers, posture.palm)
        params = self.geometry.params(shape)
        hand = PlannedHand(np.zeros(3), fingers, palm, shape, params, {})
        return hand.at(self.locate(arm, posture.location, hand, other) + self.part_to_palm(arm, hand, posture.location))

    def palm_vector(self, arm: str, fingers: np.ndarray, palm: PalmOrientation | None) -> np.ndarray:
        if palm is None:
            inward = np.array([1.0 if arm == "right" else -1.0, 0.0, 0.0])
            return inward
        direction = np.asarray(palm.direction, dtype=float)
        if palm.relative:
            direction = quat.rotate(quat.between_vectors(np.array([0.0, 0.0, 1.0]), fingers / np.linalg.norm(fingers)), direction)
        return direction

    def neutral(self, arm: str) -> np.ndarray:
        return self.geometry.location(NEUTRAL_LOCATION if arm == "right" else _NEUTRAL_LEFT, AVATAR_SIDE[arm])

    def locate(self, arm: str, location: Location | None, hand: PlannedHand, other: PlannedHand | None, here: np.ndarray | None = None) -> np.ndarray:
        """Palm-centre point ``(3,)`` for ``location`` (see the module docstring)."""
        if location is None:
            return self.neutral(arm) if here is None else here
        if isinstance(location, BetweenLocation):
            first = self.locate(arm, location.first, hand, other, here)
            second = self.locate(arm, location.second, hand, other, here)
            return (1.0 - location.fraction) * first + location.fraction * second
        if not isinstance(location, BodySite):
            return self.geometry.location(location, AVATAR_SIDE[arm])
        site = normalized(location)
        if site.site == "contact":
            return self.neutral(arm) if here is None else here
        if site.site == "neutralspace":
            return self.neutral(arm)
        if on_other_hand(site):
            other_arm = "left" if arm == "right" else "right"
            other_hand = other or self.hands.get(other_arm)
            if other_hand is None:
                self.note(f"location {location.site!r} on the other hand, which takes no part; neutral space")
                return self.neutral(arm) if here is None else here
            pose = self.arm_pose(other_arm, other_hand)
            return resolve_location(self.avatar, site, AVATAR_SIDE[arm], pose)
        return self.geometry.location(site, AVATAR_SIDE[arm])

    def rotation(self, arm: str, hand: PlannedHand) -> np.ndarray:
        """The hand's global rotation ``(4,)`` (:meth:`HandGeometry.rotation`); when
        memoizing, kept on the hand, which a sign asks about again and again."""
        side = AVATAR_SIDE[arm]
        known = hand.rotations.get(side)
        if known is None:
            known = self.geometry.rotation(side, hand.fingers, hand.palm)
            if self.geometry.memoize:
                hand.rotations[side] = known
        return known

    def offset(self, arm: str, hand: PlannedHand, site: BodySite) -> np.ndarray:
        """From the wrist to a site of this hand ``(3,)``, for its rotation and shape."""
        return self.offset_of(arm, self.rotation(arm, hand), hand.params, site)

    def expect_offsets(self, wanted: Sequence[tuple[str, PlannedHand, BodySite]]) -> None:
        """Note the :meth:`offset` of each ``(arm, hand, site)`` the sign is about to ask
        for, in the order it will (:meth:`offset_request`), so that a sign compiled in
        rounds waits one round for all of them (:meth:`HandGeometry.expect_site_offsets`)."""
        self.geometry.expect_site_offsets([self.offset_request(arm, self.rotation(arm, hand), hand.params, site) for arm, hand, site in wanted])

    def part_to_palm(self, arm: str, hand: PlannedHand, location: Location | None) -> np.ndarray:
        """From the part of the hand a location puts at its site (``hand_part``: HamNoSys'
        contact by the fingertip, the pinky side …) to the palm centre ``(3,)`` that
        locations place, for the hand's rotation and shape; zeros without a named part."""
        part = location.hand_part if isinstance(location, BodySite) else None
        if part is None or not is_hand_site(part) or part.site == PALM.site:
            return np.zeros(3)
        site = replace(normalized(part), proximity=PALM.proximity)
        self.expect_offsets([(arm, hand, PALM), (arm, hand, site)])
        return self.offset(arm, hand, PALM) - self.offset(arm, hand, site)

    def arm_pose(self, arm: str, hand: PlannedHand) -> Pose:
        """The whole body with this arm in the hand's posture (rest elsewhere), one frame:
        :meth:`HandGeometry.palm_pose` of the wrist under the palm."""
        rotation = self.rotation(arm, hand)
        offset = self.offset_request(arm, rotation, hand.params, PALM)
        return self.geometry.palm_pose(AVATAR_SIDE[arm], hand.location, offset, rotation, hand.params)

    def pose(self, arm: str, hand: PlannedHand, palm_offset: np.ndarray) -> HandPose:
        """The hand's posture with the wrist at its palm centre less ``palm_offset`` ``(3,)``."""
        return HandPose(hand.location - palm_offset, self.rotation(arm, hand).copy(), hand.params.copy())

    def offset_of(self, arm: str, rotation: np.ndarray, params: np.ndarray, site: BodySite) -> np.ndarray:
        return self.geometry.site_offset(*self.offset_request(arm, rotation, params, site))

    def offset_request(self, arm: str, rotation: np.ndarray, params: np.ndarray, site: BodySite) -> tuple[str, BodySite, np.ndarray, np.ndarray]:
        """The offset this sign takes for a hand posture: that of the first posture it asked for within
        1e-9 of it (rounded to 9 decimals); the exact key of :data:`PALM` itself, most asked, omits the site."""
        exact = (arm, key_bytes(rotation), key_bytes(params)) if site is PALM else (arm, site, key_bytes(rotation), key_bytes(params))
        known = self._asked.get(exact)
        if known is None:  # else asked for these very values before: the same answer
            key = (arm, site, "q", np.asarray(rotation).round(9).tobytes(), np.asarray(params).round(9).tobytes())
            known = self._asked[exact] = self._offsets.setdefault(key, (AVATAR_SIDE[arm], site, rotation, params))
        return known
