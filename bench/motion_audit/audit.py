"""The audit of one rendered motion (``NAME.bvh`` with its timeline and audio when present).

:func:`audit_file` reads the BVH with the audit's own reader, finds the avatar it was
rendered for (its skeleton must match one avatar file's, see
:mod:`bench.motion_audit.avatar_file`), runs the audit's forward kinematics and measures
every figure of :class:`FileAudit`. Strokes come from the timeline's behaviours
(``NAME.timeline.json``, or the data island of ``NAME.html`` for signs); the affiliates'
acoustic onsets from its words and ``NAME.wav``. A file without a timeline gets every
per-frame figure and the starts from rest, but no strokes.

An arm takes part in a behaviour when its wrist moves during it (:data:`ARM_MOVES`); a
stroke's jerk ratios are those of the movement units whose middle lies in its planned
stroke phase (a repeated stroke is several units); its power law is fitted over the
stroke phase; its onset is the landmark of :mod:`bench.motion_audit.stroke_onset`.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from bench.motion_audit import audio, continuity, penetration, speed_laws, stroke_onset, twist
from bench.motion_audit.audio import AudioError
from bench.motion_audit.avatar_file import AvatarError, AvatarFile, match_avatar
from bench.motion_audit.bvh_reader import BvhError, read_bvh
from bench.motion_audit.findings import EventCount, Failure, Worst
from bench.motion_audit.kinematics import Kinematics, forward_kinematics
from bench.motion_audit.movement import Segmentation, Unit, segment
from bench.motion_audit.timeline import Behaviour, Timeline, TimelineError, timeline_for
from bench.motion_audit.volumes import audit_volumes

SIDES = ("l", "r")
#: The joints every audited skeleton must have (H-Anim names).
REQUIRED_JOINTS = tuple(f"{side}_{joint}" for side in SIDES for joint in ("shoulder", "elbow", "wrist"))
#: An arm takes part in a behaviour when its wrist travels at least this far (metres)
#: between the behaviour's start and its stroke end.
ARM_MOVES = 0.03


@dataclass
class FileAudit:
    """Every figure of one render; ``Worst.file`` is ``file`` throughout."""

    file: str
    avatar: str
    frames: int
    fps: float
    elbow_pops: dict[str, EventCount]
    wrist_steps: dict[str, EventCount]
    joint_turns: continuity.JointTurns
    penetrations: dict[str, penetration.Penetration]
    peak_speed: Worst
    peak_acceleration: Worst
    twist: dict[str, twist.TwistPinning]
    power_laws: list[speed_laws.PowerLawFit] = field(default_factory=list)
    jerk_strokes: list[Worst] = field(default_factory=list)
    jerk_starts: list[Worst] = field(default_factory=list)
    onsets: list[stroke_onset.StrokeOnset] = field(default_factory=list)
    has_timeline: bool = False

    def as_json(self) -> dict:
        return {
            "file": self.file,
            "avatar": self.avatar,
            "frames": self.frames,
            "fps": self.fps,
            "elbow_pops": {side: count.as_json() for side, count in self.elbow_pops.items()},
            "wrist_steps": {side: count.as_json() for side, count in self.wrist_steps.items()},
            "joint_turns": self.joint_turns.as_json(),
            "penetration": {group: found.as_json() for group, found in self.penetrations.items()},
            "peak_wrist_speed": self.peak_speed.as_json(),
            "peak_wrist_acceleration": self.peak_acceleration.as_json(),
            "twist": {side: {"gesture_frames": t.gesture_frames, "pinned_frames": t.pinned_frames, "worst": t.worst.as_json() if t.worst else None} for side, t in self.twist.items()},
            "power_law": [fit.as_json() for fit in self.power_laws],
            "jerk_strokes": [worst.as_json() for worst in self.jerk_strokes],
            "jerk_starts_from_rest": [worst.as_json() for worst in self.jerk_starts],
            "stroke_onsets": [onset.as_json() for onset in self.onsets],
            "has_timeline": self.has_timeline,
        }


def _in_file(worst: Worst | None, file: str) -> Worst | None:
    return None if worst is None else worst.in_file(file)


def _wrist_peaks(kinematics: Kinematics, start: float, file: str) -> tuple[Worst, Worst]:
    speeds, accelerations = [], []
    for side in SIDES:
        path = kinematics.positions[:, kinematics.index(f"{side}_wrist")]
        speed, frame = speed_laws.peak_speed(path, kinematics.fps)
        speeds.append(Worst(speed, start + frame / kinematics.fps, f"{side}_wrist", file))
        acceleration, frame = speed_laws.peak_acceleration(path, kinematics.fps)
        accelerations.append(Worst(acceleration, start + frame / kinematics.fps, f"{side}_wrist", file))
    return max(speeds, key=lambda w: w.value), max(accelerations, key=lambda w: w.value)


def _frame(time: float, kinematics: Kinematics, start: float) -> int:
    return int(np.clip(round((time - start) * kinematics.fps), 0, kinematics.frame_count - 1))


def _arm_moves(path: np.ndarray, behaviour: Behaviour, kinematics: Kinematics, start: float) -> bool:
    first, last = _frame(behaviour.phases["start"], kinematics, start), _frame(behaviour.phases["stroke_end"], kinematics, start)
    return stroke_onset.path_length(path[first : last + 1]) >= ARM_MOVES


def _unit_label(side: str, unit: Unit, kinematics: Kinematics, start: float, behaviour: str | None) -> str:
    span = f"{start + unit.first / kinematics.fps:.2f}–{start + unit.last / kinematics.fps:.2f} s"
    return f"{side}_wrist {span}" + (f" ({behaviour})" if behaviour else "")


def _strokes_of_side(
    audit: FileAudit, kinematics: Kinematics, timeline: Timeline | None, side: str, sound: audio.Audio | None
) -> None:
    """Power laws, jerk ratios and stroke onsets of one arm, appended to ``audit``."""
    fps, start = kinematics.fps, timeline.motion_start if timeline else 0.0
    path = kinematics.positions[:, kinematics.index(f"{side}_wrist")]
    segmentation: Segmentation = segment(path, fps)
    behaviours = [b for b in (timeline.behaviours if timeline else ()) if side in b.sides and _arm_moves(path, b, kinematics, start)]
    for unit in segmentation.units:
        middle = start + 0.5 * (unit.first + unit.last) / fps
        owner = next((b.id for b in behaviours if b.phases["stroke_start"] <= middle <= b.phases["stroke_end"]), None)
        ratio = speed_laws.jerk_ratio(path, unit, fps)
        if ratio is None:
            continue
        worst = Worst(ratio, start + unit.first / fps, _unit_label(side, unit, kinematics, start, owner), audit.file)
        if owner is not None:
            audit.jerk_strokes.append(worst)
        if unit.from_rest:
            audit.jerk_starts.append(worst)
    for behaviour in behaviours:
        first, last = (_frame(behaviour.phases[name], kinematics, start) for name in ("stroke_start", "stroke_end"))
        fit = speed_laws.power_law(path, fps, first, last, f"{side}_wrist ({behaviour.id})", behaviour.phases["stroke_start"])
        if fit is not None:
            audit.power_laws.append(replace(fit, file=audit.file))
        acoustic = None
        if timeline and behaviour.affiliate_onset is not None and not behaviour.absolute and timeline.words:
            word = audio.affiliate_word(timeline.words, behaviour.affiliate_onset, behaviour.affiliate_end)
            acoustic = None if word is None else audio.acoustic_onset(sound, word)
        onset = stroke_onset.stroke_onset(behaviour, side, path, segmentation, fps, start, acoustic)
        audit.onsets.append(replace(onset, file=audit.file))


def audit_file(path: Path, name: str, avatars: list[AvatarFile]) -> FileAudit:
    """Audit the render ``path`` (shown as ``name``) for the first of ``avatars`` it matches.

    Raises the reader's errors (:class:`~bench.motion_audit.bvh_reader.BvhError`,
    ``AvatarError``, ``TimelineError``, ``AudioError``), each naming the file.
    """
    motion = read_bvh(path)
    missing = [name for name in REQUIRED_JOINTS if name not in motion.joint_names]
    if missing:
        raise BvhError(f"{path}: no joint {', '.join(missing)}: the audit needs the H-Anim arm joints {', '.join(REQUIRED_JOINTS)}")
    avatar, scale = match_avatar(motion, avatars)
    kinematics = forward_kinematics(motion, scale)
    timeline = timeline_for(path)
    start = timeline.motion_start if timeline else 0.0
    volumes = audit_volumes(avatar, kinematics)
    speed, acceleration = _wrist_peaks(kinematics, start, name)
    audit = FileAudit(
        file=name,
        avatar=avatar.name,
        frames=kinematics.frame_count,
        fps=kinematics.fps,
        elbow_pops={side: _count_in(continuity.elbow_pops(kinematics, side, start), name) for side in SIDES},
        wrist_steps={side: _count_in(continuity.wrist_steps(kinematics, side, start), name) for side in SIDES},
        joint_turns=_turns_in(continuity.joint_turns(kinematics, start), name),
        penetrations={group: penetration.Penetration(found.frames_over, _in_file(found.worst, name)) for group, found in penetration.penetrations(kinematics, volumes, start).items()},
        peak_speed=speed,
        peak_acceleration=acceleration,
        twist={side: _twist_in(twist.twist_pinning(kinematics, side, avatar.twist_limit(side), start), name) for side in SIDES},
        has_timeline=timeline is not None,
    )
    needs_audio = timeline is not None and bool(timeline.words) and any(b.affiliate_onset is not None and not b.absolute for b in timeline.behaviours)
    wav = path.with_suffix(".wav")
    sound = audio.read_wav(wav) if needs_audio and wav.is_file() else None
    for side in SIDES:
        _strokes_of_side(audit, kinematics, timeline, side, sound)
    return audit


def _count_in(count: EventCount, file: str) -> EventCount:
    return EventCount(count.frames, count.events, _in_file(count.worst, file))


def _turns_in(turns: continuity.JointTurns, file: str) -> continuity.JointTurns:
    return continuity.JointTurns(_in_file(turns.largest, file), turns.frames_over, turns.joints_over)


def _twist_in(pinning: twist.TwistPinning, file: str) -> twist.TwistPinning:
    return twist.TwistPinning(pinning.gesture_frames, pinning.pinned_frames, _in_file(pinning.worst, file))


#: Errors that fail one file of a folder, never the audit: the readers' own (BvhError,
#: AvatarError, TimelineError, AudioError are ValueErrors naming the file) and any other
#: ValueError or lookup error a strange file may cause, reported with its type.
FILE_ERRORS = (ValueError, LookupError)


def audit_folder(
    folder: Path, avatars: list[AvatarFile], progress: Callable[[str], None] | None = None
) -> tuple[list[FileAudit], list[Failure]]:
    """Audit every ``*.bvh`` under ``folder`` (names relative to it, sorted); a file that
    cannot be audited is a :class:`~bench.motion_audit.findings.Failure` with its reason."""
    audits, failures = [], []
    for path in sorted(folder.rglob("*.bvh")):
        name = path.relative_to(folder).as_posix()
        if progress is not None:
            progress(name)
        try:
            audits.append(audit_file(path, name, avatars))
        except (BvhError, AvatarError, TimelineError, AudioError) as error:
            failures.append(Failure(name, str(error)))
        except FILE_ERRORS as error:
            failures.append(Failure(name, f"{type(error).__name__}: {error}"))
    return audits, failures
