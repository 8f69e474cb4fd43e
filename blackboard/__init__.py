"""The chunk blackboard and scheduler (seed 004, section 5): chunks run through
InPrep → Pending → Lurking → InExec → Subsiding → Completed, planning of the next chunk
interleaved with the execution of the current one, speech and gesture synchronized within
each chunk by a simple temporal network that relaxes before it refuses."""

from blackboard.board import Blackboard, PlannedGesture
from blackboard.chunk import TRANSITIONS, ChunkState, ChunkStateMachine, Transition
from blackboard.clock import Clock, VirtualClock, WallClock
from blackboard.errors import (
    BehaviorError,
    IllegalTransition,
    OverlappingGestures,
    ScheduleError,
    TimingConflict,
)
from blackboard.events import (
    BehaviorFeedback,
    ChunkStateChanged,
    EventBus,
    FramesReady,
    SpeechEnded,
    SpeechStarted,
)
from blackboard.planning import (
    PEG_NAMES,
    GestureDemands,
    MotorControl,
    MotorProgramLike,
    TimePegs,
)
from blackboard.anchors import TagAnchor, acoustic_anchors
from blackboard.chunk_timing import (
    ChunkTiming,
    GestureRequest,
    GestureTiming,
    PauseStretch,
    TimingConfig,
    time_chunk,
)
from blackboard.config import SchedulerConfig
from blackboard.job import ScheduledUtterance
from blackboard.relaxation import RELAXATION_ORDER, Relaxation, RelaxationStep
from blackboard.scheduler import LiveHandle, Scheduler
from blackboard.timeline import Timeline
from blackboard.timing import Give, TemporalNetwork
from blackboard.validation import validate

__all__ = [
    "PEG_NAMES", "RELAXATION_ORDER", "TRANSITIONS", "Give", "Relaxation", "RelaxationStep", "TagAnchor", "acoustic_anchors", "BehaviorError", "BehaviorFeedback", "Blackboard", "ChunkState",
    "ChunkStateChanged", "ChunkStateMachine", "ChunkTiming", "Clock", "EventBus", "FramesReady",
    "GestureDemands", "GestureRequest", "GestureTiming", "IllegalTransition", "LiveHandle", "MotorControl",
    "MotorProgramLike", "OverlappingGestures", "PauseStretch", "PlannedGesture", "ScheduleError",
    "ScheduledUtterance", "Scheduler", "SchedulerConfig", "SpeechEnded", "SpeechStarted", "TemporalNetwork",
    "TimePegs", "Timeline", "TimingConfig", "TimingConflict", "Transition", "VirtualClock", "WallClock",
    "time_chunk", "validate",
]
