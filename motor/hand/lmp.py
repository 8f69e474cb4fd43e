"""The hand-shape LMP: hand parameter vectors (:mod:`motor.hand.shape`) through keys."""

from __future__ import annotations

import numpy as np

from motor.program.lmp import TimePegs, VectorKeyframeLMP
from motor.trajectory.biocontrol import TimeProfile, minimum_jerk


class HandShapeLMP(VectorKeyframeLMP):
    """Interpolation of hand parameter vectors ``(m, P)`` on ``(side, "handshape")``."""

    def __init__(
        self,
        side: str,
        pegs: TimePegs,
        shapes: np.ndarray,
        key_times: np.ndarray | None = None,
        time_profile: TimeProfile | str | None = None,
    ) -> None:
        super().__init__((side, "handshape"), pegs, shapes, key_times, time_profile or minimum_jerk())

