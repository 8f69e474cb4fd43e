"""The face motor module (seed 004): visemes, expressions and blinks as named morph weights.

Face motion is a set of ARKit-named morph weights per frame (:mod:`motor.face.arkit`).

* :mod:`motor.face.visemes` — the viseme set as morph weights, and dominance;
* :mod:`motor.face.phonemes` — phoneme → viseme tables per alphabet (espeak-ng, the fake
  backend, SAMPA for mouth pictures);
* :mod:`motor.face.lipsync` — coarticulated lip-sync from ``SpeechTiming``, word-level
  fallback, mouth pictures;
* :mod:`motor.face.expressions` — face lexemes and the HamNoSys facial tiers;
* :mod:`motor.face.blinks` — spontaneous and boundary blinks, deterministic per seed;
* :mod:`motor.face.planning` — MURML ``FaceExpression`` and ``Mouth`` slots;
* :mod:`motor.face.control` — the activated tracks sampled per frame, and a chunk's
  speech turned into lip-sync, accent brows and a boundary blink.

For a realizer (BML ``<faceLexeme>``, ``<faceFacs>``-like needs): build tracks with
:func:`motor.face.expressions.face_lexeme` (``face_lexeme("RAISE_BROWS", start, end,
amount=0.6)``), :func:`motor.face.expressions.expression` (any ARKit weights under an
:class:`motor.trajectory.envelope.Envelope`), :class:`motor.face.blinks.BlinkLMP` and
:func:`motor.face.lipsync.mouth_picture`, and hand them to
:meth:`motor.control.MotorControl.activate` in a program's ``lmps`` (their channels
start with ``"face"``).
"""
