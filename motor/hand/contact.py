"""How close two hands may come: the palm's thickness.

Hands that meet touch; they never overlap. A hand's palm surface lies half a palm
thickness from the wrist's axis, so two wrists whose palms face each other are at least
one palm thickness apart. The thickness is read from the avatar: twice the depth of its
palm site (``r_palm``) along the site's outward normal, i.e. how far the palm's surface
lies from the wrist bone; an avatar without a palm site uses
:data:`DEFAULT_PALM_THICKNESS`. This is the one place the planners read it from.
"""

from __future__ import annotations

import numpy as np

from motor.body.avatar import Avatar

#: Palm thickness (m) of an avatar that does not give one (an adult hand: about 3 cm).
DEFAULT_PALM_THICKNESS = 0.03


def palm_thickness(avatar: Avatar) -> float:
    """The avatar's palm thickness, metres (module docstring)."""
    site = avatar.sites.get("r_palm")
    if site is None:
        return DEFAULT_PALM_THICKNESS
    depth = abs(float(np.asarray(site.offset, dtype=float) @ np.asarray(site.normal, dtype=float)))
    return 2.0 * depth if depth > 0.0 else DEFAULT_PALM_THICKNESS
