"""The realizer server's protocol: JSON envelopes in, BML feedback out as JSON.

Every message is one JSON object with a ``type``. A client sends:

==========================================  ===============================================
``{"type": "bml", "xml": "<bml …>"}``         perform a BML 1.0 block (its composition says
                                             how it joins what plays)
``{"type": "murml", "xml": "<utterance …>",`` perform a MURML utterance; ``id`` names it in
``"id": "u1"}``                               the feedback (default ``utterance-N``)
``{"type": "interrupt"}``                    end every block playing or queued gracefully;
``{"type": "interrupt", "block": "bml1"}``   or only that one
``{"type": "observe", "frames": true}``      receive every block's feedback (and the
                                             avatar's skeleton and frames when ``frames``)
``{"type": "ping"}``                         answered by ``{"type": "pong"}``
==========================================  ===============================================

Any message may carry a ``"request"`` value; the answer to it (``accepted``, ``error``,
``interrupted``, ``pong``) carries it back. The server sends (times in seconds; ``time``
on the block clock, ``globalTime`` on the server's session clock):

* ``{"type": "hello", "protocol": 1, "page": URL}`` on connecting;
* ``{"type": "accepted", "block": id}`` once a block is read and queued;
* ``{"type": "error", "message": …, "where": "FILE:LINE:COL", "line": L, "column": C}`` for a
  message that cannot be performed (malformed JSON or XML, invalid BML); the connection
  stays open;
* BML feedback for the blocks the client sent (observers get every block's):
  ``{"type": "prediction", "block", "chunk", "behaviors": {id: {sync: time}}, "globalStart",
  "globalEnd", "bml": "<bml …>"}`` (BML's ``<predictionFeedback>`` content: the block with
  every sync point at its planned time), ``{"type": "blockProgress", "id": "bml1:start",
  "block", "point", "time", "globalTime", "status"}`` (``status`` ``DONE``, ``INTERRUPTED``
  or ``FAILED`` at the end), ``{"type": "syncPointProgress", "id": "bml1:g1:stroke",
  "block", "behavior", "sync", "time", "globalTime"}``, ``{"type": "warning", "block",
  "kind", "message", "where"}``;
* to observers with frames: ``{"skeleton": …}`` then ``{"frame", "time", "rotations",
  "root"}`` per frame (the live page's stream format, ``viewer/src/live.js``).
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass

from lxml import etree

from blackboard.feedback import BlockProgress, BmlFeedback, PredictionFeedback, SyncPointProgress, WarningFeedback
from mura.bml import BML_NAMESPACE
from mura.errors import SpecError, SpecErrors

PROTOCOL_VERSION = 1
#: Largest message a client may send, bytes (the connection is closed beyond it).
MAX_MESSAGE_BYTES = 1 << 20
REQUEST_TYPES = ("bml", "murml", "interrupt", "observe", "ping")


@dataclass(frozen=True)
class Request:
    """One client message, checked: its ``type`` and fields, and the ``request`` tag to echo."""

    type: str
    fields: dict
    tag: object = None


class ProtocolError(ValueError):
    """A message that is not a valid envelope; ``line`` and ``column`` locate it in the JSON text."""

    def __init__(self, message: str, line: int = 0, column: int = 0) -> None:
        super().__init__(message)
        self.line = line
        self.column = column


def read_request(text: str | bytes) -> Request:
    """The request a client message holds; :class:`ProtocolError` says what is wrong with it."""
    if isinstance(text, bytes):
        try:
            text = text.decode("utf-8")
        except UnicodeDecodeError as error:
            raise ProtocolError(f"message is not UTF-8 text: {error.reason} at byte {error.start}") from None
    try:
        message = json.loads(text)
    except json.JSONDecodeError as error:
        raise ProtocolError(f"message is not JSON: {error.msg}", error.lineno, error.colno) from None
    if not isinstance(message, dict):
        raise ProtocolError(f"message must be a JSON object with a type, not {type(message).__name__}", 1, 1)
    kind = message.get("type")
    if kind not in REQUEST_TYPES:
        raise ProtocolError(f"unknown message type {kind!r} (expected one of {', '.join(REQUEST_TYPES)})", 1, 1)
    if kind in ("bml", "murml") and not isinstance(message.get("xml"), str):
        raise ProtocolError(f"a {kind} message needs its document as a string in \"xml\"", 1, 1)
    for key in ("block", "id"):
        if key in message and not isinstance(message[key], str):
            raise ProtocolError(f"\"{key}\" must be a string", 1, 1)
    return Request(kind, message, message.get("request"))


def error_message(error: Exception, tag: object = None) -> dict:
    """The ``error`` answer for a failed request, located when the failure says where."""
    out: dict = {"type": "error", "message": str(error)}
    if isinstance(error, SpecError):
        where = error.where
        out.update(message=error.message, where=str(where), line=where.line, column=where.column)
        if isinstance(error, SpecErrors):
            out["errors"] = [{"message": e.message, "where": str(e.where), "line": e.line, "column": e.column} for e in error.errors]
    elif isinstance(error, ProtocolError):
        out.update(line=error.line, column=error.column)
    if tag is not None:
        out["request"] = tag
    return out


def feedback_message(feedback: BmlFeedback) -> dict:
    """A BML feedback event as its JSON message."""
    if isinstance(feedback, BlockProgress):
        return {"type": "blockProgress", "id": feedback.id, "block": feedback.block, "point": feedback.point,
                "time": _time(feedback.time), "globalTime": _time(feedback.global_time), "status": feedback.status,
                "characterId": feedback.character}
    if isinstance(feedback, SyncPointProgress):
        return {"type": "syncPointProgress", "id": feedback.id, "block": feedback.block, "behavior": feedback.behavior,
                "sync": feedback.sync, "time": _time(feedback.time), "globalTime": _time(feedback.global_time),
                "characterId": feedback.character}
    if isinstance(feedback, PredictionFeedback):
        behaviors = {b: {sync: _time(t) for sync, t in syncs.items()} for b, syncs in feedback.behaviors.items()}
        return {"type": "prediction", "block": feedback.block, "chunk": feedback.chunk, "behaviors": behaviors,
                "globalStart": _time(feedback.global_start), "globalEnd": _time(feedback.global_end),
                "characterId": feedback.character, "bml": predicted_bml(feedback)}
    if isinstance(feedback, WarningFeedback):
        return {"type": "warning", "block": feedback.block, "kind": feedback.kind, "message": feedback.message, "where": feedback.where}
    raise TypeError(f"not BML feedback: {feedback!r}")


def predicted_bml(feedback: PredictionFeedback) -> str:
    """The block as BML's prediction feedback gives it: each behaviour with its sync points at
    their planned times (seconds on the block clock), ``globalStart``/``globalEnd`` on the block."""
    block = etree.Element(f"{{{BML_NAMESPACE}}}bml", nsmap={None: BML_NAMESPACE})
    block.set("id", feedback.block)
    block.set("globalStart", f"{feedback.global_start:.4f}")
    block.set("globalEnd", f"{feedback.global_end:.4f}")
    if feedback.character is not None:
        block.set("characterId", feedback.character)
    for behavior, syncs in feedback.behaviors.items():
        kind = feedback.kinds.get(behavior) or "behavior"
        element = etree.SubElement(block, f"{{{BML_NAMESPACE}}}{kind}", id=behavior)
        for sync, time in syncs.items():
            if kind == "speech" and sync not in ("start", "end"):
                continue
            element.set(sync, f"{time:.4f}")
        if kind == "speech":
            for sync, time in syncs.items():
                if sync not in ("start", "end"):
                    etree.SubElement(element, f"{{{BML_NAMESPACE}}}sync", id=sync, time=f"{time:.4f}")
    return etree.tostring(block, encoding="unicode")


def _time(value: float) -> float:
    return round(value, 6) if math.isfinite(value) else 0.0
