"""Indicating verbs (seed 001): cross-validated model errors and how the avatar performs them.

Not a test: prints figures. ``run(quick)`` reads the shipped SYNTHETIC recording session
(``specs/verbs/recordings_synthetic.json``; made by a generator, not motion capture):

* **cross-validation**: leave-one-arrangement-out errors of the point, vector and
  uninflected models, mean over the eight verbs (location cm, movement direction °, hand
  orientation °), and per verb (``quick``: the first 6 of the 42 arrangements per verb);
* **on the avatar** (``max``, 25 fps): every verb inflected by the point model for a set of
  arrangements, rendered as a sign; per rendered keyframe, how far the hand's rotation is
  from the model's (the IK's wrist limits) — measured on the exported BVH with the clip's
  own kinematics — how far keyframe wrists were moved to be reachable, and per frame the
  worst upper-arm depth in the torso and NaN (:func:`motor.signing.sequence.frame_faults`).
"""

from __future__ import annotations

import time

import numpy as np
from scipy.spatial.transform import Rotation

from agent.export.bvh import bvh_text
from motor.body.avatar import load_avatar
from motor.signing.sequence import frame_faults, realize_signs
from motor.verbs.capture import global_transforms
from motor.verbs.evaluation import cross_validate
from motor.verbs.model import MODEL_KINDS
from motor.verbs.plan import on_avatar, verb_plan
from motor.verbs.shipped import RECORDINGS_PATH, shipped_models
from mura.bvh import parse_bvh
from mura.recordings import read_recordings
from mura.verb_lexicon import load_verb_lexicon

FPS = 25.0
#: Arrangements rendered on the avatar (subject, object).
RENDERED = ((-1.0, 1.0), (1.0, -1.0), (-0.6, 0.9), (0.9, -0.6), (0.3, -0.3), (0.0, 0.6), (-0.3, -1.0))


def run(quick: bool) -> dict:
    lexicon = load_verb_lexicon()
    session = read_recordings(RECORDINGS_PATH)
    started = time.perf_counter()
    scores = [s for verb in session.verbs for s in cross_validate(lexicon.entry(verb), session.of(verb), lexicon, 6 if quick else None)]
    seconds = time.perf_counter() - started
    result: dict = {"synthetic_training_data": session.synthetic, "cross_validation_seconds": round(seconds, 2)}
    for kind in MODEL_KINDS:
        rows = [s for s in scores if s.model == kind]
        result[kind] = {
            "location_cm": round(float(np.mean([s.location_cm for s in rows])), 2),
            "direction_deg": round(float(np.mean([s.direction_deg for s in rows])), 2),
            "orientation_deg": round(float(np.mean([s.orientation_deg for s in rows])), 2),
            "per_verb_location_cm": {s.verb: round(s.location_cm, 2) for s in rows},
        }
    result["on_avatar"] = _on_avatar(lexicon, RENDERED[:3] if quick else RENDERED)
    return result


def _on_avatar(lexicon, arrangements) -> dict:
    avatar = load_avatar("max")
    models = shipped_models()
    turns, moved, depth, nan, frames = [], [], 0.0, 0, 0
    for verb, model in models.items():
        for subject, obj in arrangements:
            form = model.predict("point", subject, obj)
            plan = verb_plan(avatar, lexicon.entry(verb), form)
            signed = realize_signs(avatar, [plan], FPS)
            faults = frame_faults(avatar, signed)
            depth = max(depth, float(np.max(faults["upper_arm_depth"], initial=0.0)))
            nan += int(faults["non_finite"].sum())
            frames += signed.motion.frame_count
            clip = parse_bvh(bvh_text(signed.motion))
            timing = signed.timings[0]
            for hand in model.hands:
                wanted = [plan.first[hand].rotation] + [m.values[-1] for m in plan.moves[(hand, "hand_rotation")]]
                times = [timing.ready] + [timing.ready + m.end * (timing.end - timing.ready) / plan.duration for m in plan.moves[(hand, "hand_rotation")]]
                index = np.round((np.array(times) - signed.motion.start_time) * FPS).astype(int)
                rotations, _ = global_transforms(clip, index, root_fixed=False)
                achieved = rotations[clip.names.index(f"{hand[0]}_wrist")]
                turns.extend(np.degrees((achieved * Rotation.from_quat(wanted).inv()).magnitude()).tolist())
                keyframes = np.stack([plan.first[hand].wrist] + [m.values[-1] for m in plan.moves[(hand, "wrist_position")]])
                moved.extend((100.0 * np.linalg.norm(keyframes - on_avatar(avatar, form.locations[hand]), axis=1)).tolist())
    return {
        "verbs_rendered": len(models) * len(arrangements),
        "hand_rotation_error_deg_mean": round(float(np.mean(turns)), 2),
        "hand_rotation_error_deg_p95": round(float(np.percentile(turns, 95)), 2),
        "keyframe_moved_for_reach_cm_mean": round(float(np.mean(moved)), 2),
        "keyframe_moved_for_reach_cm_max": round(float(np.max(moved)), 2),
        "upper_arm_depth_in_torso_cm_max": round(100.0 * depth, 2),
        "frames": frames,
        "nan_frames": nan,
    }


if __name__ == "__main__":
    import json
    import sys

    print(json.dumps(run("--quick" in sys.argv), indent=1))
