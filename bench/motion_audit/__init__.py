"""An independent audit of rendered motion: what a viewer (and a motion scientist) sees.

The audit reads rendered BVH files with a reader and forward kinematics of its own
(:mod:`~bench.motion_audit.bvh_reader`, :mod:`~bench.motion_audit.kinematics`; nothing is
imported from ``motor/``, ``blackboard/`` or ``agent/export/``), the avatar file as plain
JSON (:mod:`~bench.motion_audit.avatar_file`, :mod:`~bench.motion_audit.volumes`), the
render's timeline and WAV, and measures per render (:mod:`~bench.motion_audit.audit`):

* elbow pops, wrist speed steps, the largest per-frame joint rotation
  (:mod:`~bench.motion_audit.continuity`);
* penetration of the arm segments into the torso and into each other
  (:mod:`~bench.motion_audit.penetration`, :mod:`~bench.motion_audit.distance`);
* peak wrist speed and acceleration, β of the power law on curved strokes, jerk against
  minimum jerk (:mod:`~bench.motion_audit.speed_laws`, :mod:`~bench.motion_audit.movement`);
* forearm twist pinned at its limit (:mod:`~bench.motion_audit.twist`);
* the stroke onset's landmark and its lead on the affiliate's acoustic onset
  (:mod:`~bench.motion_audit.stroke_onset`, :mod:`~bench.motion_audit.audio`).

``python -m bench.motion_audit DIR`` audits any folder of renders;
``python -m bench.motion_audit --corpus`` renders the visible inputs first
(:mod:`~bench.motion_audit.corpus`); ``mura bench`` runs :func:`run`.
"""

from __future__ import annotations

from bench.motion_audit.corpus import audit_corpus

#: The summary figures ``mura bench`` reports at the top level of its section.
HEADLINE = (
    "elbow_pop_events",
    "elbow_pop_frames",
    "wrist_step_events",
    "largest_joint_turn_deg",
    "torso_penetration_cm",
    "forearm_penetration_cm",
    "hand_penetration_cm",
    "peak_wrist_speed",
    "peak_wrist_acceleration",
    "power_law_beta_median",
    "curved_strokes_fitted",
    "jerk_ratio_stroke_median",
    "jerk_ratio_start_median",
    "twist_pinned_percent",
    "stroke_landmark_percent",
)


def run(quick: bool) -> dict:
    """The ``mura bench`` section: render the corpus (a subset when ``quick``), audit it."""
    result = audit_corpus(quick)
    overall, speech = result["overall"], result["speech"]
    figures = {key: overall[key] for key in HEADLINE}
    figures["stroke_onset_error_max_frames"] = speech["stroke_onset_error_max_frames"]
    figures["stroke_lead_median_ms"] = speech["stroke_lead_median_ms"]
    figures["items_rendered"] = f"{result['rendered']} of {result['items']}"
    return {**figures, "corpus": result}
