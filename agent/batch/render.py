"""Rendering corpus items to their files, each alone, whatever happens to it.

:func:`render_chunk` turns a chunk of consecutive items (signs or utterances) into their
files in the output folder and returns one :class:`ItemResult` each; it never raises for
an item's sake: a sign that cannot be planned, an utterance that does not read, an
exception deep in the motor core, a ``MemoryError`` or running past the time limit all
become a ``failed`` result with the reason, and the chunk's other items go on. The signs
of a chunk are planned together (always the whole chunk, so a plan never depends on
which items were still to do); each item is realized and written on its own — a fresh
scheduler per utterance — so its files depend only on the chunk it belongs to and the
options, never on which process rendered it; the files of an item appear together, when
all are complete, or not at all.

Files of a sign: ``NAME.bvh``, ``NAME.face.json`` (the non-manuals' morph weights per
frame) and ``NAME.motion.js`` (for the corpus index), with ``pages`` ``NAME.html`` and
with ``glb`` ``NAME.glb``. Of an utterance: also ``NAME.wav`` and ``NAME.timeline.json``.
"""

from __future__ import annotations

import ctypes
import hashlib
import json
import threading
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import asdict, dataclass
from functools import lru_cache
from pathlib import Path

from agent.agent import Agent
from agent.batch.items import SIGN, CorpusItem
from agent.batch.report import summarize_warnings
from agent.export.bvh import bvh_text, write_bvh
from agent.export.corpus_index import write_motion_script
from agent.export.face import face_json, page_face_json
from agent.export.gltf import motion_model, write_motion_glb
from agent.export.html import write_html
from agent.export.page_model import page_model
from agent.export.staging import Staging
from motor.body.avatar import Avatar, load_avatar
from motor.body.conventions import DEFAULT_AVATAR
from motor.motion import Motion
from motor.signing.plan import SignPlan, SignPlanningError
from motor.signing.planning import plan_signs
from motor.signing.sequence import PreparedSigns, SignedMotion, prepare_signs, realize_prepared
from mura.errors import SpecError
from mura.lexicon import load_lexicons
from mura.limits import DEFAULT_LIMITS, Limits
from mura.signs import Sign
from tts.wav import write_wav

RENDERED = "rendered"
FAILED = "failed"
#: Frames per second of signs and of utterances when the options do not say.
SIGN_FPS = 25.0
UTTERANCE_FPS = 60.0
#: Longest time one item may take, seconds, unless the options say otherwise.
DEFAULT_TIME_LIMIT = 120.0


@dataclass(frozen=True)
class RenderOptions:
    """How items are rendered (and so what their files hold).

    ``fps`` None means :data:`SIGN_FPS` for signs and :data:`UTTERANCE_FPS` for
    utterances; ``lexicons`` are layered over the bundled one for utterances;
    ``limits`` are ``--limit NAME=VALUE`` overrides of the input limits; ``time_limit`` is
    seconds per item.
    """

    avatar: str = DEFAULT_AVATAR
    fps: float | None = None
    glb: bool = False
    pages: bool = False
    tts: str = "fake"
    lexicons: tuple[str, ...] = ()
    time_limit: float = DEFAULT_TIME_LIMIT
    limits: tuple[str, ...] = ()

    def input_limits(self) -> Limits:
        """The input limits these options ask for (raises :class:`~mura.limits.LimitError`)."""
        return DEFAULT_LIMITS.with_overrides(self.limits) if self.limits else DEFAULT_LIMITS

    def key(self) -> str:
        """A hash of everything that changes an item's files (not the time limit)."""
        fields = asdict(self)
        fields.pop("time_limit")
        return hashlib.sha256(json.dumps(fields, sort_keys=True).encode()).hexdigest()


@dataclass(frozen=True)
class OutputFile:
    """One file an item wrote: its name in the output folder, SHA-256 and size in bytes."""

    name: str
    sha256: str
    size: int


@dataclass(frozen=True)
class ItemResult:
    """What became of one item."""

    index: int
    name: str
    status: str
    reason: str | None = None
    duration: float | None = None
    files: tuple[OutputFile, ...] = ()
    warnings: tuple[str, ...] = ()

    @property
    def rendered(self) -> bool:
        return self.status == RENDERED


class ItemTimeLimit(Exception):
    """An item ran past its time limit."""


def render_item(item: CorpusItem, options: RenderOptions, output: str | Path) -> ItemResult:
    """Render ``item`` into ``output`` (module docstring); never raises for the item's sake."""
    (result,) = render_chunk([item], options, output)
    return result


def render_chunk(items: Sequence[CorpusItem], options: RenderOptions, output: str | Path, done: frozenset[int] = frozenset()) -> list[ItemResult]:
    """Render a chunk of consecutive items, skipping the indices in ``done``.

    The chunk's signs are planned together (the reach of all their wrist positions is
    checked in one vectorized pass, several times faster than sign by sign), every sign of
    the chunk whether done or not, so that an item's plan never depends on which others
    were left to do; should planning them together fail, each is planned alone. The
    transitions from rest into each sign and back are then found together too
    (:func:`motor.signing.sequence.prepare_signs`: each the same as alone), and each item
    realized and written on its own, under its own time limit.
    """
    folder = Path(output)
    plans = _plans(items, options)
    prepared = _prepared({index: plan for index, plan in plans.items() if index not in done}, options)
    results = []
    for item in items:
        if item.index in done:
            continue
        results.append(guarded(item, options, lambda item=item: _render_one(item, options, folder, plans.get(item.index), prepared.get(item.index))))
    return results


def guarded(item: CorpusItem, options: RenderOptions, render: Callable[[], ItemResult]) -> ItemResult:
    """``render()``, with every way it can fail turned into a failed result."""
    if item.error is not None:
        return ItemResult(item.index, item.name, FAILED, item.error)
    try:
        with time_limit(options.time_limit):
            return render()
    except ItemTimeLimit:
        return ItemResult(item.index, item.name, FAILED, f"{item.source}: {item.label}: ran past the time limit of {options.time_limit:g} s")
    except MemoryError:
        return ItemResult(item.index, item.name, FAILED, f"{item.source}: {item.label}: ran out of memory")
    except RecursionError:
        return ItemResult(item.index, item.name, FAILED, f"{item.source}: {item.label}: nested too deeply to render (recursion limit)")
    except Exception as error:  # noqa: BLE001 - one item's failure, whatever it is, must not stop the batch
        return ItemResult(item.index, item.name, FAILED, _reason(item, error))


def _plans(items: Sequence[CorpusItem], options: RenderOptions) -> dict[int, SignPlan | SignPlanningError]:
    """The plans of the chunk's signs by item index: together, or one by one if that fails."""
    signs = [item for item in items if item.kind == SIGN and item.sign is not None]
    if not signs:
        return {}
    avatar = _avatar(options.avatar)
    try:
        with time_limit(options.time_limit * len(signs)):
            return dict(zip((item.index for item in signs), plan_signs(avatar, [item.sign for item in signs])))
    except Exception:  # noqa: BLE001 - planned again one by one, where each failure stays with its sign
        return {}


def _prepared(plans: dict[int, SignPlan | SignPlanningError], options: RenderOptions) -> dict[int, PreparedSigns]:
    """Each planned sign prepared as a sequence of its own, by item index: together, or
    none (each then alone) if that fails. A sign's preparation is the same whichever
    others share the batch."""
    planned = {index: plan for index, plan in plans.items() if isinstance(plan, SignPlan)}
    if not planned:
        return {}
    try:
        with time_limit(options.time_limit * len(planned)):
            return dict(zip(planned, prepare_signs(_avatar(options.avatar), [[plan] for plan in planned.values()])))
    except Exception:  # noqa: BLE001 - prepared again one by one, where each failure stays with its sign
        return {}


def _render_one(
    item: CorpusItem, options: RenderOptions, folder: Path, plan: SignPlan | SignPlanningError | None, prepared: PreparedSigns | None
) -> ItemResult:
    if item.kind != SIGN:
        return _render_utterance(item, options, folder)
    if plan is None:
        (plan,) = plan_signs(_avatar(options.avatar), [item.sign])
    return _render_sign(item, options, folder, plan, prepared)


def _reason(item: CorpusItem, error: BaseException) -> str:
    """The failure as one line: a spec error names its place; anything else the item."""
    if isinstance(error, SpecError):
        return str(error).replace("\n", "; ")
    return f"{item.source}: {item.label}: {type(error).__name__}: {error}"


@contextmanager
def time_limit(seconds: float) -> Iterator[None]:
    """Raise :class:`ItemTimeLimit` in this thread if the block runs longer than ``seconds``.

    A timer thread sets the exception asynchronously in the rendering thread (it is
    raised at the next Python instruction, so a numpy call in progress finishes first);
    leaving the block in time cancels the timer and any exception still pending.
    """
    target = ctypes.c_ulong(threading.get_ident())
    lock = threading.Lock()
    armed = [True]

    def expire() -> None:
        with lock:
            if armed[0]:
                ctypes.pythonapi.PyThreadState_SetAsyncExc(target, ctypes.py_object(ItemTimeLimit))

    timer = threading.Timer(seconds, expire)
    timer.daemon = True
    timer.start()
    try:
        yield
    finally:
        with lock:
            armed[0] = False
            timer.cancel()
            ctypes.pythonapi.PyThreadState_SetAsyncExc(target, None)


@lru_cache(maxsize=4)
def _avatar(name: str) -> Avatar:
    return load_avatar(name)


@lru_cache(maxsize=4)
def _agent(avatar: str, tts: str, fps: float, lexicons: tuple[str, ...], limits: tuple[str, ...]) -> Agent:
    input_limits = DEFAULT_LIMITS.with_overrides(limits) if limits else DEFAULT_LIMITS
    return Agent(avatar=_avatar(avatar), tts=tts, fps=fps, lexicon=load_lexicons(lexicons) if lexicons else None, limits=input_limits)


def _render_sign(item: CorpusItem, options: RenderOptions, folder: Path, plan: SignPlan | SignPlanningError, prepared: PreparedSigns | None) -> ItemResult:
    assert item.sign is not None
    avatar = _avatar(options.avatar)
    if isinstance(plan, SignPlanningError):
        return ItemResult(item.index, item.name, FAILED, planning_reason(item.sign, plan))
    if prepared is None:
        (prepared,) = prepare_signs(avatar, [[plan]])
    signed = realize_prepared(avatar, prepared, options.fps or SIGN_FPS)
    timeline = timeline_of(signed, item.label)
    writers: dict[str, Callable[[Path], None]] = {
        f"{item.name}.bvh": lambda path: write_bvh(signed.motion, path),
        f"{item.name}.face.json": lambda path: path.write_text(face_json(signed.motion), encoding="ascii"),
        f"{item.name}.motion.js": lambda path: write_motion_script(path, item.name, signed.motion, timeline),
    }
    _add_extras(writers, item.name, signed.motion, timeline, avatar, options, wav=None)
    files = _write_together(folder, writers)
    return ItemResult(item.index, item.name, RENDERED, None, round(signed.duration, 4), files, summarize_warnings(signed.warnings))


def _render_utterance(item: CorpusItem, options: RenderOptions, folder: Path) -> ItemResult:
    agent = _agent(options.avatar, options.tts, options.fps or UTTERANCE_FPS, options.lexicons, options.limits)
    performance = agent.render(item.source, name=item.name)
    timeline = dict(performance.timeline, motion_start_time=performance.motion.start_time)
    track, rate = performance.soundtrack()
    writers: dict[str, Callable[[Path], None]] = {
        f"{item.name}.wav": lambda path: write_wav(path, track, rate),
        f"{item.name}.bvh": lambda path: write_bvh(performance.motion, path),
        f"{item.name}.timeline.json": lambda path: path.write_text(json.dumps(timeline, indent=1), encoding="utf-8"),
        f"{item.name}.face.json": lambda path: path.write_text(face_json(performance.motion), encoding="ascii"),
        f"{item.name}.motion.js": lambda path: write_motion_script(path, item.name, performance.motion, timeline),
    }
    _add_extras(writers, item.name, performance.motion, timeline, agent.avatar, options, wav=f"{item.name}.wav")
    files = _write_together(folder, writers)
    return ItemResult(item.index, item.name, RENDERED, None, round(performance.duration, 4), files, summarize_warnings(performance.warnings))


def _add_extras(
    writers: dict[str, Callable[[Path], None]], name: str, motion: Motion, timeline: dict, avatar: Avatar, options: RenderOptions, wav: str | None
) -> None:
    if options.pages:
        model = page_model(avatar)
        writers[f"{name}.html"] = lambda path: write_html(path, name=name, bvh_text=bvh_text(motion), timeline=timeline, wav_filename=wav, model=model,
                                                          face_json=page_face_json(motion))
    if options.glb:
        writers[f"{name}.glb"] = lambda path: write_motion_glb(motion, path, motion_model(avatar), avatar.root_height)


def _write_together(folder: Path, writers: dict[str, Callable[[Path], None]]) -> tuple[OutputFile, ...]:
    """Write every file under a temporary name, then publish them all (or none)."""
    folder.mkdir(parents=True, exist_ok=True)
    staging = Staging(folder)
    written = []
    try:
        for name, write in writers.items():
            temporary = staging.temporary(folder / name)
            write(temporary)
            data = temporary.read_bytes()
            written.append(OutputFile(name, hashlib.sha256(data).hexdigest(), len(data)))
    except BaseException:
        staging.discard()
        raise
    staging.publish()
    return tuple(written)


def planning_reason(sign: Sign, error: SignPlanningError) -> str:
    """Why a sign could not be planned, at the sign's place (an error the motor raised
    without knowing the file says ``<input>:0:0:``, which is dropped)."""
    message = str(error).replace("<input>:0:0: ", "")
    return f"{sign.where}: {message}" if sign.where is not None else message


def timeline_of(signed: SignedMotion, name: str) -> dict:
    """The avatar page's timeline of realized signs: one behaviour per sign with its phases."""
    arms = ["right_arm", "left_arm"]
    behaviors = [
        {
            "id": timing.gloss, "chunk": 0, "arms": arms,
            "phases": {
                "start": timing.start, "ready": timing.ready, "stroke_start": timing.ready,
                "stroke": 0.5 * (timing.ready + timing.end), "stroke_end": timing.end, "relax": timing.end, "end": timing.end,
            },
        }
        for timing in signed.timings
    ]  # fmt: skip
    return {
        "version": 1, "name": name, "duration": signed.duration, "fps": signed.motion.fps, "chunks": [],
        "behaviors": behaviors, "words": [], "phonemes": [], "time_tags": {},
    }  # fmt: skip
