"""Where a viewer sees a stroke begin, and how far it leads the affiliate's acoustic onset.

The landmark (issue 12, item 7) is found on the rendered wrist path of each arm a
behaviour moves (:mod:`bench.motion_audit.movement`):

* a stroke is **dynamic** when the wrist travels more than :data:`DYNAMIC_PATH` during
  the planned stroke phase, else **static** (a held pointing or placing);
* a static stroke begins where the hand *arrives*: the first frame of a hold;
* a dynamic stroke begins where the hand *departs* from a post-preparation hold (its
  last frame) or at a speed **valley** between the preparation and the stroke — or,
  when the wrist is still over the stroke's first :data:`STILL_SPAN` (moving less than
  :data:`STILL_PATH`: the stroke opens with the hand's shape or orientation, and the
  wrist's travel comes later), where the hand *arrives*, as for a static stroke;
* of the landmarks of the right kind between the behaviour's start and its stroke end,
  the one nearest the planned ``stroke_start`` is the stroke onset, if it lies within
  :data:`MATCH_WINDOW` of it (a landmark further off than the whole nominal lead belongs
  to another movement); otherwise the stroke shows **no landmark** (it flows from
  its preparation without a hold or a valley a viewer could see).

The timeline says only where to look; the onset is the landmark's time on the motion.
The **lead** is the affiliate's acoustic onset (:mod:`bench.motion_audit.audio`) minus
the stroke onset; the target is :data:`TARGET_LEAD` (seed 004) within one frame.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from bench.motion_audit.audio import AcousticOnset
from bench.motion_audit.movement import Segmentation
from bench.motion_audit.timeline import Behaviour

DYNAMIC_PATH = 0.03
STILL_SPAN = 0.1
STILL_PATH = 0.005
MATCH_WINDOW = 0.2
TARGET_LEAD = 0.2


@dataclass(frozen=True)
class StrokeOnset:
    """One arm's stroke: its landmark (``kind``: ``arrival``, ``departure``, ``valley`` or
    None) and time, the acoustic onset it is measured against and the lead (seconds)."""

    behaviour: str
    side: str
    dynamic: bool
    planned: float
    landmark: str | None
    onset: float | None
    acoustic: AcousticOnset | None
    file: str = ""

    @property
    def lead(self) -> float | None:
        if self.onset is None or self.acoustic is None:
            return None
        return self.acoustic.onset - self.onset

    def as_json(self) -> dict:
        return {
            "file": self.file,
            "behaviour": self.behaviour,
            "side": self.side,
            "dynamic": self.dynamic,
            "planned_onset": round(self.planned, 4),
            "landmark": self.landmark,
            "onset": None if self.onset is None else round(self.onset, 4),
            "affiliate_word": None if self.acoustic is None else self.acoustic.word,
            "word_event": None if self.acoustic is None else round(self.acoustic.event, 4),
            "acoustic_onset": None if self.acoustic is None else round(self.acoustic.onset, 4),
            "refined_on_audio": None if self.acoustic is None else self.acoustic.refined,
            "lead": None if self.lead is None else round(self.lead, 4),
        }


def path_length(path: np.ndarray) -> float:
    return float(np.linalg.norm(np.diff(path, axis=0), axis=1).sum()) if path.shape[0] > 1 else 0.0


def landmarks(segmentation: Segmentation, dynamic: bool, fps: float, start: float, opens_still: bool = False) -> list[tuple[str, float]]:
    """Landmarks of the kind a stroke of this sort shows: ``(kind, time)``; ``start`` is
    the time of frame 0; ``opens_still``: a dynamic stroke whose wrist is still at first
    shows arrivals too."""
    arrivals = [("arrival", start + hold.first / fps) for hold in segmentation.holds if hold.first > 0]
    if not dynamic:
        return arrivals
    found = [("departure", start + hold.last / fps) for hold in segmentation.holds]
    return found + [("valley", start + valley.at / fps) for valley in segmentation.valleys] + (arrivals if opens_still else [])


def _frame(time: float, fps: float, start: float, frames: int) -> int:
    return int(np.clip(round((time - start) * fps), 0, frames - 1))


def stroke_onset(
    behaviour: Behaviour,
    side: str,
    path: np.ndarray,
    segmentation: Segmentation,
    fps: float,
    start: float,
    acoustic: AcousticOnset | None,
) -> StrokeOnset:
    """The stroke onset of ``behaviour`` on arm ``side`` (``path`` the whole wrist track)."""
    phases = behaviour.phases
    first, last = (_frame(phases[name], fps, start, path.shape[0]) for name in ("stroke_start", "stroke_end"))
    dynamic = path_length(path[first : last + 1]) > DYNAMIC_PATH
    opens_still = path_length(path[first : min(last, first + int(round(STILL_SPAN * fps))) + 1]) < STILL_PATH
    planned = phases["stroke_start"]
    candidates = [
        (kind, time)
        for kind, time in landmarks(segmentation, dynamic, fps, start, opens_still)
        if phases["start"] <= time <= phases["stroke_end"] and abs(time - planned) <= MATCH_WINDOW
    ]
    if not candidates:
        return StrokeOnset(behaviour.id, side, dynamic, planned, None, None, acoustic)
    kind, time = min(candidates, key=lambda candidate: abs(candidate[1] - planned))
    return StrokeOnset(behaviour.id, side, dynamic, planned, kind, time, acoustic)
