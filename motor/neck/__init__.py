"""The neck motor module (seed 004): head, gaze, torso and shoulders.

* :mod:`motor.neck.lexemes` — head lexemes (nod, shake, tilts, turns, chin up/down,
  pushes) as LMPs with seed 000's temporal profiles;
* :mod:`motor.neck.gaze` — gaze targets and the coordinated eye–head shift;
* :mod:`motor.neck.trunk` — the HamNoSys body and shoulder tiers;
* :mod:`motor.neck.planning` — MURML ``GazeDirection``, ``Neck``, ``HeadDirection``,
  ``Torso``, ``Shoulders`` slots (and deictic gaze) on a gesture's time pegs;
* :mod:`motor.neck.control` — the activated LMPs applied to frames (torso, clavicles,
  ``vc7``/``vc4``/``skullbase``, eyeball joints).

For a realizer (BML ``<head>``, ``<gaze>``): build LMPs with
:func:`motor.neck.lexemes.head_lexeme` (``head_lexeme("NOD", start, end, amount=0.5,
repetitions=2)``), :func:`motor.neck.gaze.gaze_target` / :func:`~motor.neck.gaze.point` /
:func:`~motor.neck.gaze.direction` and :func:`motor.neck.gaze.gaze` (``gaze(avatar,
target, start, hold_until)``; add a :func:`~motor.neck.gaze.rest` gaze with
``returning=True`` to look back), :func:`motor.neck.trunk.trunk_movement`, and hand them
to :meth:`motor.control.MotorControl.activate` in a program's ``lmps`` (their channels
start with ``"neck"``).
"""
