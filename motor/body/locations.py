"""Where a named location is on a particular avatar.

Resolves the location values of :mod:`mura.values` to a point in the avatar frame (metres,
root joint at the origin at hip level, y up, +x the avatar's left, +z forward):

* :class:`~mura.values.GridLocation`: the avatar's scaled MURML/ACE grid — lateral from
  the mid-sagittal plane, height above the hip level, distance in front of the chest
  surface (see :class:`motor.body.avatar.Grid`);
* :class:`~mura.values.BodySite`: a HamNoSys site on the body, the arm or the hand, taken
  from the avatar's site table in the current posture (rest if none is given), then moved
  off the surface along the site's normal by the proximity, and sideways by ``lrat`` /
  ``lrbeside``. Paired body sites (ear, cheek, …) are the ones on the moving hand's side;
  arm and hand sites are on the *other* arm, the one the moving hand refers to;
* :class:`~mura.values.PointLocation`: as given;
* :class:`~mura.values.BetweenLocation`: linear interpolation of its two ends.

Proximities and sideways shifts are proportions of the avatar's arm length (shoulder to
wrist), seed 000's suggestion for making "far" avatar-specific: touch 0, close 0.05,
near (also ``medium`` and the default) 0.12, far 0.3; lrat 0.08, lrbeside 0.2.
"""

from __future__ import annotations

import numpy as np

from motor import quaternion as quat
from motor.body.avatar import Avatar, Site, check_side
from motor.body.kinematics import Pose
from mura.errors import SpecError
from mura.murml_vocabulary import GRID_ALIASES
from mura.values import (
    FINGERS,
    BetweenLocation,
    BodySite,
    GridLocation,
    Location,
    PointLocation,
)

#: Sites on the head and trunk without a side.
CENTRAL_SITES: tuple[str, ...] = (
    "head", "headtop", "forehead", "eyebrows", "eyes", "nose", "nostrils", "lips", "tongue", "teeth",
    "chin", "underchin", "neck", "shoulders", "chest", "stomach", "belowstomach",
)  # fmt: skip
#: Sites on the head and trunk that come in pairs; the moving hand's side is meant.
PAIRED_SITES: tuple[str, ...] = ("ear", "earlobe", "cheek", "shouldertop")
#: Sites on the other arm and hand.
ARM_SITES: tuple[str, ...] = (
    "upperarm", "elbow", "elbowinside", "lowerarm", "wristback", "wristpulse",
    "thumbball", "palm", "handback", "thumbside", "pinkyside",
)  # fmt: skip
#: Sites on a finger of the other hand; the index finger unless one is named.
FINGER_SITES: tuple[str, ...] = ("fingertip", "fingernail", "fingerpad", "fingermidjoint", "fingerbase", "fingerside")

PROXIMITIES: dict[str, float] = {"touch": 0.0, "close": 0.05, "near": 0.12, "medium": 0.12, "far": 0.3}
SIDEWAYS: dict[str, float] = {"lrat": 0.08, "lrbeside": 0.2}
DEFAULT_PROXIMITY = "near"


def resolve_location(avatar: Avatar, location: Location, side: str, pose: Pose | None = None) -> np.ndarray:
    """The point ``(3,)`` a location names, for the hand on ``side`` (``"l"``/``"r"``).

    ``pose`` (frame 0 is used) places sites on moving bones; the rest pose if None.
    Raises SpecError naming an unknown symbol.
    """
    check_side(side)
    if isinstance(location, PointLocation):
        return np.array(location.position, dtype=float)
    if isinstance(location, GridLocation):
        return _grid_point(avatar, location)
    if isinstance(location, BodySite):
        return _site_point(avatar, location, side, pose)
    if isinstance(location, BetweenLocation):
        first = resolve_location(avatar, location.first, side, pose)
        second = resolve_location(avatar, location.second, side, pose)
        return (1.0 - location.fraction) * first + location.fraction * second
    raise SpecError(f"not a location: {location!r}")


def _grid_point(avatar: Avatar, location: GridLocation) -> np.ndarray:
    grid = avatar.grid
    values = []
    for name, table, axis in (
        (location.lateral, grid.laterals, "lateral position"),
        (location.height, grid.heights, "height"),
        (location.distance, grid.distances, "distance"),
    ):
        canonical = GRID_ALIASES.get(name, name)
        if canonical not in table:
            raise SpecError(f"unknown grid {axis} {name!r} (expected one of {', '.join(table)})")
        values.append(table[canonical])
    lateral, height, distance = values
    return np.array([lateral, height, grid.front + distance])


def site_name(location: BodySite, side: str) -> str:
    """The avatar's site-table key for a HamNoSys site seen from the hand on ``side``."""
    site = location.site.removeprefix("ham")
    other = "r" if side == "l" else "l"
    if site in CENTRAL_SITES:
        return site
    if site in PAIRED_SITES:
        return f"{side}_{site}"
    if site in ARM_SITES:
        return f"{other}_{site}"
    if site in FINGER_SITES or site == "thumb":
        finger = "thumb" if site == "thumb" else (location.finger or "index")
        if finger not in FINGERS:
            raise SpecError(f"unknown finger {finger!r} for body location {location.site!r}")
        return f"{other}_{finger}_{'fingertip' if site == 'thumb' else site}"
    known = CENTRAL_SITES + PAIRED_SITES + ARM_SITES + FINGER_SITES
    raise SpecError(f"unknown body location {location.site!r} (expected one of {', '.join(known)})")


def _site_point(avatar: Avatar, location: BodySite, side: str, pose: Pose | None) -> np.ndarray:
    site = _site(avatar, location, side)
    if pose is None:
        origin, normal = avatar.rest_positions[site.bone] + site.offset, site.normal
    else:
        orientation = pose.orientations[0, site.bone]
        origin = pose.positions[0, site.bone] + quat.rotate(orientation, site.offset)
        normal = quat.rotate(orientation, site.normal)
    return _off_surface(avatar, location, side, origin, normal)


def site_points(avatar: Avatar, location: BodySite, side: str, pose: Pose) -> np.ndarray:
    """The point a body site names in every frame of ``pose`` ``(n, 3)``, each as
    :func:`resolve_location` gives it for a one-frame pose; raises SpecError likewise."""
    site = _site(avatar, location, side)
    orientation = pose.orientations[:, site.bone]
    origin = pose.positions[:, site.bone] + quat.rotate(orientation, site.offset)
    return _off_surface(avatar, location, side, origin, quat.rotate(orientation, site.normal))


def _site(avatar: Avatar, location: BodySite, side: str) -> Site:
    name = site_name(location, side)
    if name not in avatar.sites:
        raise SpecError(f"avatar {avatar.name!r} does not define body location {name!r}")
    return avatar.sites[name]


def _off_surface(avatar: Avatar, location: BodySite, side: str, origin: np.ndarray, normal: np.ndarray) -> np.ndarray:
    """The site's surface point(s) moved along the normal by the proximity, and sideways."""
    proximity = location.proximity or DEFAULT_PROXIMITY
    if proximity not in PROXIMITIES:
        raise SpecError(f"unknown proximity {proximity!r} at {location.site!r} (expected one of {', '.join(PROXIMITIES)})")
    arm = avatar.arm_length(side)
    point = origin + normal * PROXIMITIES[proximity] * arm
    if location.side is not None:
        if location.side not in SIDEWAYS:
            raise SpecError(f"unknown side {location.side!r} at {location.site!r} (expected lrat or lrbeside)")
        point = point + np.array([1.0 if side == "l" else -1.0, 0.0, 0.0]) * SIDEWAYS[location.side] * arm
    return point
