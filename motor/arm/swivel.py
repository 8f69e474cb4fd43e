"""The swivel LMP: the elbow's angle about the shoulder–wrist axis (radians) through keys.

The swivel is the arm's one redundant degree of freedom once the wrist is placed
(seed 004's IK); an LMP on ``(side, "swivel")`` overrides the natural swivel.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from motor.program.lmp import TimePegs, VectorKeyframeLMP
from motor.trajectory.biocontrol import TimeProfile, minimum_jerk


class SwivelLMP(VectorKeyframeLMP):
    """Interpolation of the arm's swivel angle (radians) on ``(side, "swivel")``."""

    def __init__(
        self,
        side: str,
        pegs: TimePegs,
        angles: np.ndarray | Sequence[float],
        key_times: np.ndarray | None = None,
        time_profile: TimeProfile | str | None = None,
    ) -> None:
        super().__init__((side, "swivel"), pegs, np.asarray(angles, dtype=float), key_times, time_profile or minimum_jerk())

