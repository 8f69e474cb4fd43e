"""How the sign planner reads the sites a sign names (seed 000, section 4.1): the names
and proximities the resolver (:func:`motor.body.locations.resolve_location`) does not know,
which sites lie on the other hand or arm, and the site a hand constellation puts in
contact.
"""

from __future__ import annotations

from dataclasses import replace
from functools import lru_cache

from motor.body.locations import ARM_SITES, FINGER_SITES
from mura.constraints import Dynamic, Static
from mura.values import BetweenLocation, BodySite, Location

#: Sites the parser writes that the resolver does not name, read as the nearest it does.
SITE_ALIASES: dict[str, str] = {"finger": "fingerpad", "thumb": "thumb"}
#: Proximities outside the resolver's table: at arm's length is far; behind the body is
#: read as near; crossing and interlocking fingers are contact.
PROXIMITY_ALIASES: dict[str, str] = {"armextended": "far", "behind": "near", "brushing": "touch", "cross": "touch", "interlock": "touch"}


@lru_cache(maxsize=4096)
def normalized(site: BodySite) -> BodySite:
    """``site`` with its name and proximity as the resolver knows them."""
    name = site.site.split(":")[0]
    name = SITE_ALIASES.get(name, name)
    proximity = PROXIMITY_ALIASES.get(site.proximity or "", site.proximity)
    return replace(site, site=name, proximity=proximity)


def on_other_hand(location: Location | None) -> bool:
    """Whether ``location`` (or either end of a location between two) is on a hand or arm."""
    if isinstance(location, BetweenLocation):
        return on_other_hand(location.first) or on_other_hand(location.second)
    if not isinstance(location, BodySite):
        return False
    return is_hand_site(normalized(location))


def leaf_location(leaf: Static | Dynamic) -> Location | None:
    """The location a HandLocation leaf moves to, if it names one."""
    if leaf.slot != "HandLocation":
        return None
    if isinstance(leaf, Static):
        return leaf.value if isinstance(leaf.value, (BodySite, BetweenLocation)) else None
    return next((s.end for s in leaf.segments if isinstance(s.end, (BodySite, BetweenLocation))), None)


def is_hand_site(site: BodySite) -> bool:
    """Whether a resolver's site lies on a hand or arm."""
    return site.site in ARM_SITES or site.site in FINGER_SITES or site.site == "thumb"


def hand_site(location: Location | None, contact: str | None) -> BodySite:
    """A constellation's site of one hand (the palm when none is named), at the contact."""
    proximity = {"touch": "touch", "close": "close", "interlock": "touch", "cross": "touch"}.get(contact or "", "close")
    if isinstance(location, BodySite):
        return replace(normalized(location), proximity=proximity)
    return BodySite("palm", proximity=proximity)


def touches(location: Location) -> bool:
    """Whether ``location`` is in contact with its site."""
    return isinstance(location, BodySite) and location.proximity in ("touch", "interlock", "cross")
