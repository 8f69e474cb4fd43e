"""Head, gaze and face measured on what is rendered, with kinematics of their own.

Not a pass/fail test: ``run(quick)`` renders utterances through :class:`agent.agent.Agent`
and measures the output only — the WAV, the face weights of the frames and the joint
rotations — never the plans:

* **Lip-sync**: for every example utterance with speech, spoken by espeak-ng, Pearson's r
  between each frame's ``jawOpen`` weight and the audio's energy envelope (the RMS of the
  samples within :data:`ENVELOPE_WINDOW` centred on the frame); and the largest
  ``jawOpen`` inside every pause of the audio (a run of at least :data:`PAUSE` seconds
  whose envelope stays below :data:`SILENCE` of its peak): from a quarter into it to a
  quarter, or :data:`LEAD_IN` seconds if longer, before its end — in the last tenth of a
  second the mouth rightly begins the next word. The fake
  backend's r is given beside it (its audio is a buzz only as loud as vowel or consonant).
* **Gaze**: for behaviours whose target is known (:data:`GAZE_CASES`), the angle between
  each eye's line of sight and the line from that eye to the target, at the behaviour's
  stroke; the eyes' poses come from :func:`joint_frames`, a forward kinematics written
  with scipy's ``Rotation`` that shares no code with the motor side. Targets: scene places
  from the lexicon, the listener (1.2 m ahead of the eyes at rest, as the spec names it),
  the right palm (halfway from the wrist to the middle finger's base, by the same forward
  kinematics).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy.spatial.transform import Rotation

from motor.motion import Motion

EXAMPLES = Path(__file__).resolve().parents[1] / "specs" / "utterances"
#: Width of the energy envelope's window, seconds (about a 10 Hz low-pass).
ENVELOPE_WINDOW = 0.05
#: A pause: at least this long, seconds, with the envelope below SILENCE of its peak.
PAUSE = 0.2
SILENCE = 0.02
#: The end of a pause left out of its interior: the mouth's lead into the next word, seconds.
LEAD_IN = 0.1
FPS = 60.0
#: The listener as the specs name it: this far straight ahead of the eyes at rest, metres.
LISTENER_DISTANCE = 1.2


@dataclass(frozen=True)
class GazeCase:
    """A behaviour of an example whose gaze target is known: a scene place, ``listener``
    or ``right_palm``."""

    utterance: str
    behavior: str
    target: str


GAZE_CASES: tuple[GazeCase, ...] = (
    GazeCase("look_and_nod", "look_at_bar", "Loc-Bar_2"),
    GazeCase("look_and_nod", "agree", "listener"),
    GazeCase("fig2_take_this_bar", "gesture_1", "Loc-Bar_1"),
    GazeCase("stack_height", "look_at_user", "Loc-User"),
    GazeCase("circle_wheel", "draw_wheel", "right_palm"),
)


def joint_frames(motion: Motion, frames: np.ndarray) -> tuple[np.ndarray, list[Rotation]]:
    """World positions ``(k, J, 3)`` (root at the origin) and orientations (one scipy
    ``Rotation`` of ``k`` per joint) of ``frames`` of ``motion``."""
    count = len(motion.joint_names)
    positions = np.zeros((len(frames), count, 3))
    orientations: list[Rotation] = []
    for joint in range(count):
        local = Rotation.from_quat(np.asarray(motion.rotations)[frames, joint])
        parent = motion.parents[joint]
        if parent < 0:
            positions[:, joint] = np.asarray(motion.offsets[joint])
            orientations.append(local)
        else:
            positions[:, joint] = positions[:, parent] + orientations[parent].apply(np.array(motion.offsets[joint], dtype=float))
            orientations.append(orientations[parent] * local)
    return positions, orientations


def gaze_errors(motion: Motion, time: float, target: str, places: dict[str, np.ndarray]) -> dict[str, float]:
    """Degrees between each eye's line of sight and the line to ``target`` at ``time``
    (seconds on the motion's clock)."""
    frame = int(round((time - motion.start_time) * motion.fps))
    frames = np.array([frame, 0])
    positions, orientations = joint_frames(motion, frames)
    names = motion.joint_names
    eyes = [names.index(n) for n in ("l_eyeball_joint", "r_eyeball_joint")]
    if target == "listener":
        rest_eyes = 0.5 * (positions[1, eyes[0]] + positions[1, eyes[1]])
        point = rest_eyes + np.array([0.0, 0.0, LISTENER_DISTANCE])
    elif target == "right_palm":
        point = 0.5 * (positions[0, names.index("r_wrist")] + positions[0, names.index("r_middle1")])
    else:
        point = places[target]
    errors = {}
    for name, eye in zip(("left", "right"), eyes):
        sight = orientations[eye][0].apply([0.0, 0.0, 1.0])
        wanted = point - positions[0, eye]
        cosine = sight @ wanted / np.linalg.norm(wanted)
        errors[name] = float(np.degrees(np.arccos(np.clip(cosine, -1.0, 1.0))))
    return errors


def energy_envelope(audio: np.ndarray, rate: int, times: np.ndarray, window: float = ENVELOPE_WINDOW) -> np.ndarray:
    """RMS of ``audio`` within ``window`` seconds centred on each of ``times`` (seconds)."""
    samples = np.asarray(audio, dtype=np.float64)
    squares = np.concatenate([[0.0], np.cumsum(samples * samples)])
    half = int(round(0.5 * window * rate))
    centre = np.round(np.asarray(times) * rate).astype(int)
    lo = np.clip(centre - half, 0, samples.size)
    hi = np.clip(centre + half, 0, samples.size)
    return np.sqrt((squares[hi] - squares[lo]) / np.maximum(hi - lo, 1))


def pause_middles(envelope: np.ndarray, fps: float) -> list[np.ndarray]:
    """Frame indices of the interior of every pause of the envelope (module docstring)."""
    quiet = envelope < SILENCE * float(np.max(envelope, initial=0.0))
    edges = np.diff(np.concatenate([[0], quiet.astype(int), [0]]))
    starts, ends = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)
    middles = []
    for start, end in zip(starts, ends):
        if (end - start) / fps >= PAUSE:
            quarter = (end - start) // 4
            middles.append(np.arange(start + quarter, end - max(quarter, int(round(LEAD_IN * fps)))))
    return middles


def mouth_against_audio(performance) -> dict[str, float]:
    """r between jawOpen and the energy envelope, and the largest jawOpen in pauses, of a
    rendered performance (its soundtrack and its frames)."""
    motion = performance.motion
    track, rate = performance.soundtrack()
    jaw = np.asarray(motion.face_weights)[:, list(motion.face_names).index("jawOpen")]
    envelope = energy_envelope(track, rate, motion.times)
    middles = pause_middles(envelope, motion.fps)
    in_pauses = max((float(jaw[m].max()) for m in middles if m.size), default=0.0)
    return {"r": float(np.corrcoef(jaw, envelope)[0, 1]), "pause_jaw_max": in_pauses, "pauses": len(middles)}


def run(quick: bool) -> dict:
    from agent.agent import Agent
    from mura.lexicon import load_lexicon
    from tts import make_synthesizer

    spoken = [p for p in sorted(EXAMPLES.glob("*.xml")) if "<specification>" in p.read_text()]
    if quick:
        spoken = spoken[:3]
    lipsync: dict[str, dict] = {}
    espeak = make_synthesizer("espeak")
    if espeak.available():
        agent = Agent(avatar="max", tts=espeak, fps=FPS)
        lipsync = {p.stem: mouth_against_audio(agent.render(p)) for p in spoken}
    fake = Agent(avatar="max", tts="fake", fps=FPS)
    fake_r = {p.stem: mouth_against_audio(fake.render(p))["r"] for p in spoken}
    lexicon = load_lexicon()
    places = {name: _place(lexicon, name) for name in lexicon.scene}
    gaze: dict[str, dict] = {}
    for avatar in ("max",) if quick else ("max", "makehuman"):
        agent = Agent(avatar=avatar, tts="fake", fps=FPS)
        rendered: dict[str, object] = {}
        for case in GAZE_CASES:
            performance = rendered.setdefault(case.utterance, agent.render(EXAMPLES / f"{case.utterance}.xml"))
            stroke = next(b for b in performance.timeline["behaviors"] if b["id"] == case.behavior)["phases"]["stroke"]
            gaze[f"{avatar}: {case.utterance}/{case.behavior} → {case.target}"] = gaze_errors(performance.motion, stroke, case.target, places)
    figures = {
        "lipsync": lipsync,
        "lipsync_fake_r": fake_r,
        "gaze_error_deg": gaze,
        "gaze_error_max_deg": max(max(e.values()) for e in gaze.values()),
    }
    if lipsync:
        figures["lipsync_r_min"] = min(v["r"] for v in lipsync.values())
        figures["pause_jaw_max"] = max(v["pause_jaw_max"] for v in lipsync.values())
    else:
        figures["lipsync_r_min"] = {"status": "not measured", "reason": "espeak-ng is not available"}
    return figures


def _place(lexicon, name: str) -> np.ndarray:
    from mura.lexicon import SceneLocation

    place: SceneLocation = lexicon.scene[name]
    scale = {"mm": 0.001, "cm": 0.01, "m": 1.0}[place.unit]
    return np.array([float(v) for v in place.text.split()]) * scale if place.is_position else np.full(3, np.nan)
