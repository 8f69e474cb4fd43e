"""A swivel track carried beyond the measured window keeps the arm out of the body.

The candidates farther than the window from the natural swivel cost their distance and
``OUTSIDE``; before they paid for going into the body too, a track that continuity had
carried there took them for clear: in the Indian SL corpus, 'wash' after 'was' held the right
upper arm 12 cm inside the chest (the motion audit's figure) for over a second."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from motor.arm.chain import natural_swivel, place_arm
from motor.arm.ik import track_costs
from motor.arm.swivel_cost import CANDIDATES, beyond_penalties, candidate_costs, measured_window
from motor.body.kinematics import forward_kinematics
from motor.signing.plan import SignPlan
from motor.signing.planning import plan_signs
from motor.signing.sequence import realize_signs, upper_arm_depths
from mura.sigml import parse_sigml

#: Signs in a row, in a corpus, whose arm the track once took through the body.
ROWS = [("Indian_SL.sigml", ("was", "wash"))]


def signs_named(path: Path, glosses: tuple[str, ...]):  # noqa: ANN201
    """The corpus's signs of these glosses, in the order given."""
    data = path.read_bytes()
    found = {}
    for match in re.finditer(rb"<hns_sign\b[^>]*gloss=\"([^\"]+)\".*?</hns_sign>", data, re.DOTALL):
        gloss = match.group(1).decode()
        if gloss in glosses and gloss not in found:
            found[gloss] = match.group(0)
    result = parse_sigml(b"<sigml>" + b"".join(found[gloss] for gloss in glosses) + b"</sigml>", file=path.name)
    return result.signs


@pytest.mark.parametrize(("corpus", "glosses"), ROWS, ids=["-".join(g) for _, g in ROWS])
def test_the_upper_arm_stays_out_of_the_chest(avatar, shared, corpus, glosses):
    plans = plan_signs(avatar, signs_named(shared / "corpora" / "sigml" / corpus, glosses))
    assert all(isinstance(plan, SignPlan) for plan in plans)
    signed = realize_signs(avatar, plans, 25.0)
    depths = upper_arm_depths(avatar, forward_kinematics(avatar, signed.motion.rotations))
    assert max(float(np.max(depth)) for depth in depths.values()) < 0.01


def test_the_track_pays_for_candidates_beyond_the_window_in_the_body(avatar):
    """The hand held in front of the chest ('wash'): some candidates beyond the window put
    the elbow in the chest; the track's costs charge them their depth (thousands), the
    window's and the clear ones nothing more than the single-posture costs."""
    targets = np.array([[-0.02, 0.43, 0.175], [-0.02, 0.43, 0.175], [-0.051, 0.342, 0.159]])
    hands = np.array([[0.567, -0.567, 0.423, -0.423], [0.567, -0.567, 0.423, -0.423], [0.44, -0.44, 0.44, -0.648]])
    hands = hands / np.linalg.norm(hands, axis=1, keepdims=True)
    track = track_costs(avatar, "r", targets, hands)
    placement = place_arm(avatar, "r", targets[1:], hands[1:])
    natural = natural_swivel(placement.chain, placement.circle, placement.targets, placement.torso_q)
    extra = track.costs - candidate_costs(avatar, placement, natural)
    window = measured_window(natural)[0].astype(int) % len(CANDIDATES)
    assert np.all(np.take_along_axis(extra, window, axis=1) == 0.0)
    assert np.all(extra >= 0.0)
    assert np.all(np.max(extra, axis=1) > 1000.0)
    assert np.allclose(extra, beyond_penalties(avatar, placement, natural), rtol=1e-12, atol=1e-9)
