"""``mura verbs fit|render|evaluate|synthesize``: the indicating-verb models of seed 001.

- ``fit RECORDINGS... -o MODEL``: fit every verb of the recordings (CSV/JSON keyframe
  tables, BVH clips with their sidecar JSON, or folders of them) and write a model file;
  refused rows and verbs that cannot be fitted are listed, the others still fitted.
- ``render VERB --subject S --object O [--model point|vector|uninflected] -o DIR``: the
  inflected verb on an avatar, as BVH and an avatar page.
- ``evaluate [RECORDINGS...] [--plot FILE.png]``: leave-one-arrangement-out
  cross-validation of the point, vector and uninflected models; prints the table, and the
  top view of the predicted paths over the arc with ``--plot``. Without recordings, the
  shipped synthetic session.
- ``sequence FILE.sigml -o DIR``: a SiGML sequence whose signs may place entities, point
  and use indicating verbs (:mod:`mura.sigml_space`), performed in order as one
  performance; each item that cannot be read or planned fails alone.
- ``synthesize -o FILE``: write the synthetic recording session (labelled synthetic).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from agent.commands.sign import safe_stem, timeline_of
from agent.commands.table import SUMMARIES
from agent.export.bvh import bvh_text, write_bvh
from agent.export.html import write_html
from agent.export.staging import staged_text
from motor.body.avatar import load_avatar
from motor.signing.plan import SignPlan, SignPlanningError
from motor.signing.planning import plan_sign
from motor.signing.sequence import realize_signs
from motor.verbs.behavior import spatial_plan
from motor.verbs.capture import read_capture
from motor.verbs.evaluation import cross_validate, scores_table
from motor.verbs.fitting import fit_session
from motor.verbs.model import MODEL_KINDS, ModelFileError, models_json
from motor.verbs.plan import verb_plan
from motor.verbs.shipped import MODELS_PATH, RECORDINGS_PATH, shipped_models
from motor.verbs.synthetic import SEED, synthetic_session_json
from mura.errors import SpecError
from mura.recordings import RecordingSession, read_recordings
from mura.sigml_space import parse_signed_sequence
from mura.signs import Sign
from mura.verb_lexicon import load_verb_lexicon

#: File kinds a recordings folder is searched for.
RECORDING_SUFFIXES = (".csv", ".json", ".bvh")


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser(
        "verbs",
        help=SUMMARIES["verbs"],
        description="Indicating verbs (seed 001): point, vector and uninflected models of eight ASL verbs.",
    )
    commands = parser.add_subparsers(dest="verbs_command", required=True, metavar="VERBS_COMMAND")
    fit = commands.add_parser("fit", help="fit verb models from recordings")
    fit.add_argument("recordings", nargs="+", metavar="RECORDINGS", help="CSV/JSON keyframe tables, BVH clips (with sidecar JSON), or folders")
    fit.add_argument("-o", "--output", required=True, metavar="MODEL", help="the model file to write (JSON)")
    fit.set_defaults(func=run_fit)
    render = commands.add_parser("render", help="render an inflected verb to BVH and an avatar page")
    render.add_argument("verb", metavar="VERB")
    render.add_argument("--subject", type=float, default=0.0, help="subject's arc position in [-1, 1] (default 0)")
    render.add_argument("--object", type=float, required=True, help="object's arc position in [-1, 1]")
    render.add_argument("--model", choices=MODEL_KINDS, default="point", help="which model inflects the verb (default: point)")
    render.add_argument("--models", type=Path, default=MODELS_PATH, help="model file (default: the shipped models, fitted from synthetic recordings)")
    render.add_argument("-o", "--output", required=True, metavar="DIR", help="output folder (created if missing)")
    render.add_argument("--avatar", default="max", help="avatar name or file (default: max)")
    render.add_argument("--fps", type=float, default=25.0, help="frames per second (default: 25)")
    render.set_defaults(func=run_render)
    evaluate = commands.add_parser("evaluate", help="cross-validate the models and print the table")
    evaluate.add_argument("recordings", nargs="*", metavar="RECORDINGS", help="recordings (default: the shipped synthetic session)")
    evaluate.add_argument("--plot", type=Path, metavar="FILE.png", help="write the top view of predicted paths")
    evaluate.add_argument("--folds", type=int, default=None, help="hold out only the first N arrangements of each verb")
    evaluate.set_defaults(func=run_evaluate)
    sequence = commands.add_parser("sequence", help="perform a SiGML sequence with placed entities, pointing and indicating verbs")
    sequence.add_argument("file", type=Path, metavar="FILE.sigml")
    sequence.add_argument("-o", "--output", required=True, type=Path, metavar="DIR", help="output folder (created if missing)")
    sequence.add_argument("--avatar", default="max", help="avatar name or file (default: max)")
    sequence.add_argument("--fps", type=float, default=25.0, help="frames per second (default: 25)")
    sequence.set_defaults(func=run_sequence)
    synthesize = commands.add_parser("synthesize", help="write the SYNTHETIC recording session")
    synthesize.add_argument("-o", "--output", required=True, type=Path, metavar="FILE.json")
    synthesize.add_argument("--seed", type=int, default=SEED, help=f"generator seed (default {SEED}, the shipped session)")
    synthesize.set_defaults(func=run_synthesize)


def read_sources(paths: list[str]) -> RecordingSession:
    """Every recording of the given files and folders in one session; unreadable files are
    refused like bad rows."""
    files: list[Path] = []
    for name in paths:
        path = Path(name)
        if path.is_dir():
            files.extend(sorted(p for p in path.iterdir() if p.suffix.lower() in RECORDING_SUFFIXES and not _is_sidecar(p)))
        else:
            files.append(path)
    session = RecordingSession(())
    for path in files:
        try:
            part = read_capture(path) if path.suffix.lower() == ".bvh" else read_recordings(path)
        except SpecError as error:
            part = RecordingSession((), (error,))
        session = session.merged(part)
    return session


def _is_sidecar(path: Path) -> bool:
    return path.suffix.lower() == ".json" and path.with_suffix(".bvh").exists()


def run_fit(args: argparse.Namespace) -> int:
    session = read_sources(args.recordings)
    for error in session.refused:
        print(f"refused: {error}", file=sys.stderr)
    if not session.performances:
        print("mura verbs fit: no usable performances", file=sys.stderr)
        return 2
    fitted = fit_session(session, load_verb_lexicon())
    for error in fitted.failures:
        print(f"not fitted: {error}", file=sys.stderr)
    if not fitted.models:
        return 2
    output = Path(args.output)
    output.parent.mkdir(parents=True, exist_ok=True)
    description = ("SYNTHETIC training data: " if session.synthetic else "") + (session.description or "recordings")
    with staged_text(output) as stream:
        stream.write(models_json(fitted.models, description))
    counts = ", ".join(f"{verb} ({model.performances})" for verb, model in fitted.models.items())
    print(f"fitted {len(fitted.models)} verb(s) from {len(session.performances)} performance(s): {counts} -> {output}")
    if session.synthetic:
        print("note: the training data are synthetic (made by a generator, not motion capture)")
    return 0 if not session.refused and not fitted.failures else 1


def run_render(args: argparse.Namespace) -> int:
    for name, value in (("--subject", args.subject), ("--object", args.object)):
        if not -1.0 <= value <= 1.0:
            print(f"mura verbs render: {name} {value} is outside the arc [-1, 1]", file=sys.stderr)
            return 2
    if not args.fps > 0:
        print(f"mura verbs render: --fps must be positive, got {args.fps}", file=sys.stderr)
        return 2
    try:
        avatar = load_avatar(args.avatar)
        entry = load_verb_lexicon().entry(args.verb)
        models = shipped_models(args.models)
    except (OSError, ValueError) as error:
        print(f"mura verbs render: {error}", file=sys.stderr)
        return 2
    model = models.get(entry.gloss)
    if model is None:
        print(f"mura verbs render: {args.models} has no model of {entry.gloss} (it has: {', '.join(models)})", file=sys.stderr)
        return 2
    form = model.predict(args.model, args.subject, args.object)
    name = f"{entry.gloss}_{args.model}_s{args.subject:+.2f}_o{args.object:+.2f}"
    try:
        signed = realize_signs(avatar, [verb_plan(avatar, entry, form)], args.fps)
    except (SignPlanningError, ValueError, FloatingPointError) as error:
        print(f"mura verbs render: {entry.gloss}: {error}", file=sys.stderr)
        return 1
    output = Path(args.output)
    output.mkdir(parents=True, exist_ok=True)
    stem = safe_stem(name, set())
    write_bvh(signed.motion, output / f"{stem}.bvh")
    write_html(output / f"{stem}.html", name=name, bvh_text=bvh_text(signed.motion), timeline=timeline_of(signed, name), wav_filename=None)
    for warning in signed.warnings:
        print(f"warning: {warning}", file=sys.stderr)
    note = " (model fitted from SYNTHETIC recordings)" if model.synthetic else ""
    print(f"{entry.gloss} with subject {args.subject:+.2f}, object {args.object:+.2f}, {args.model} model{note} -> {output / (stem + '.html')}")
    return 0


def run_evaluate(args: argparse.Namespace) -> int:
    session = read_sources(args.recordings or [str(RECORDINGS_PATH)])
    for error in session.refused:
        print(f"refused: {error}", file=sys.stderr)
    lexicon = load_verb_lexicon()
    scores, failures = [], 0
    for verb in session.verbs:
        try:
            scores.extend(cross_validate(lexicon.entry(verb), session.of(verb), lexicon, args.folds))
        except SpecError as error:
            failures += 1
            print(f"not evaluated: {error}", file=sys.stderr)
    if not scores:
        print("mura verbs evaluate: nothing to evaluate", file=sys.stderr)
        return 2
    if session.synthetic:
        print("Training and test data: SYNTHETIC recordings (made by motor.verbs.synthetic, not motion capture).")
    folds = max(s.folds for s in scores)
    print(f"Leave-one-arrangement-out cross-validation, {folds} arrangements per verb, {len(session.performances)} performances.\n")
    print(scores_table(scores))
    if args.plot is not None:
        from agent.verb_plots import plot_verb_paths

        try:
            plot_verb_paths(session, lexicon, args.plot)
        except (OSError, ModelFileError) as error:
            print(f"mura verbs evaluate: cannot write the plot: {error}", file=sys.stderr)
            return 1
        print(f"\ntop view of predicted paths -> {args.plot}")
    return 0 if not failures and not session.refused else 1


def run_sequence(args: argparse.Namespace) -> int:
    if not args.fps > 0:
        print(f"mura verbs sequence: --fps must be positive, got {args.fps}", file=sys.stderr)
        return 2
    try:
        avatar = load_avatar(args.avatar)
        sequence = parse_signed_sequence(args.file.read_bytes(), str(args.file))
    except (OSError, ValueError) as error:
        print(f"mura verbs sequence: {error}", file=sys.stderr)
        return 2
    failures = [f"{failure.gloss}: {failure.error}" for failure in sequence.failures]
    plans: list[SignPlan] = []
    for item in sequence.items:
        try:
            plans.append(plan_sign(avatar, item) if isinstance(item, Sign) else spatial_plan(avatar, item))
        except (SignPlanningError, SpecError, ValueError) as error:
            failures.append(f"{item.gloss}: {error}")
    for failure in failures:
        print(f"failed: {failure}", file=sys.stderr)
    if not plans:
        print("mura verbs sequence: nothing to perform", file=sys.stderr)
        return 1
    try:
        signed = realize_signs(avatar, plans, args.fps)
    except (SignPlanningError, ValueError, FloatingPointError) as error:
        print(f"mura verbs sequence: {error}", file=sys.stderr)
        return 1
    args.output.mkdir(parents=True, exist_ok=True)
    stem = safe_stem(args.file.stem, set())
    write_bvh(signed.motion, args.output / f"{stem}.bvh")
    write_html(args.output / f"{stem}.html", name=stem, bvh_text=bvh_text(signed.motion), timeline=timeline_of(signed, stem), wav_filename=None)
    placed = ", ".join(f"{r.entity} at {r.arc:+.2f}" for r in sequence.space) or "none"
    print(f"{len(plans)} of {len(plans) + len(failures)} signs performed (entities placed: {placed}) -> {args.output / (stem + '.html')}")
    return 0 if not failures else 1


def run_synthesize(args: argparse.Namespace) -> int:
    args.output.parent.mkdir(parents=True, exist_ok=True)
    with staged_text(args.output) as stream:
        stream.write(synthetic_session_json(args.seed))
    print(f"SYNTHETIC recording session (seed {args.seed}) -> {args.output}")
    return 0
