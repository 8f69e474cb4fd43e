"""Arm-continuity figures over the example utterances, the published MURML files and a
sample of real signs (not a test: prints a table; the tests assert the properties).

Run from the repository root: ``python tests/arm_continuity/measure.py [--signs N]
[--avatar NAME ...]`` (by default on ``max`` and on the default avatar, ``makehuman``).
Every input is rendered at 60 fps (utterances with fake speech through the agent, each
sign alone as ``mura sign`` renders it) and measured with :mod:`checks`.
"""

from __future__ import annotations

import argparse
import re
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from checks import TURN_LIMIT_DEG, figures  # noqa: E402

REPO = Path(__file__).resolve().parents[2]
SHARED = REPO.parent / "shared"
FPS = 60.0
_TIMING = re.compile(r'<timing onset="([0-9.]+)" end="([0-9.]+)"')
_SIGN = re.compile(rb"<(hns_sign|hamgestural_sign)\b.*?</\1>", re.DOTALL)


def utterance_motions(avatar: str):
    """(name, avatar, motion) of every example utterance and published MURML file; a
    published file whose absolute timing is too early for the preparation is retried 1 s later."""
    from agent.agent import Agent

    agent = Agent(avatar=avatar, tts="fake", fps=FPS)
    paths = sorted((REPO / "specs" / "utterances").glob("*.xml")) + sorted((SHARED / "corpora" / "murml").glob("*.us"))
    for path in paths:
        for delay in (0.0, 1.0):
            source = path if delay == 0.0 else _TIMING.sub(lambda m: f'<timing onset="{float(m[1]) + delay:g}" end="{float(m[2]) + delay:g}"', path.read_text()).encode()
            try:
                yield path.stem, agent.avatar, agent.render(source, name=path.stem).motion
                break
            except Exception as error:  # noqa: BLE001 - reported, the batch goes on
                if delay:
                    print(f"  {path.name}: not rendered: {error}", file=sys.stderr)


def sign_sample(count: int):
    from mura.sigml import parse_sigml

    signs = []
    for name in ("German_SL_DGS.sigml", "Indian_SL.sigml"):
        elements = [m.group(0) for m in _SIGN.finditer((SHARED / "corpora" / "sigml" / name).read_bytes())]
        step = max(1, len(elements) // (count // 2))
        chosen = elements[::step][: count // 2]
        signs.extend(parse_sigml(b"<sigml>" + b"".join(chosen) + b"</sigml>", file=name).signs)
    return signs


def sign_motions(avatar_name: str, count: int):
    from motor.body.avatar import load_avatar
    from motor.signing.plan import SignPlan
    from motor.signing.planning import plan_signs
    from motor.signing.sequence import realize_signs

    avatar = load_avatar(avatar_name)
    signs = sign_sample(count)
    for sign, plan in zip(signs, plan_signs(avatar, signs)):
        if isinstance(plan, SignPlan):
            yield sign.gloss, avatar, realize_signs(avatar, [plan], FPS).motion


def summary(label: str, rows: list) -> None:
    n = len(rows)
    if not n:
        return
    popped = sum(1 for _, f in rows if f.pop_frames)
    turned = sum(1 for _, f in rows if f.turns_over_limit)
    wrapped = sum(1 for _, f in rows if f.twist_wraps)
    deep = sum(1 for _, f in rows if f.torso_depth > 0.01)
    crossed = sum(1 for _, f in rows if f.arm_depth > 0.01)
    print(f"{label}: {n} motions, {sum(f.frames for _, f in rows)} frames")
    print(f"  elbow pops: {popped}/{n} motions ({100 * popped / n:.0f} %), {sum(f.pop_frames for _, f in rows)} frames; fastest elbow {max(f.max_elbow_speed for _, f in rows):.2f} m/s")
    print(f"  largest arm-joint turn: {max(f.max_turn_deg for _, f in rows):.1f} deg/frame; motions with a turn > {TURN_LIMIT_DEG:g} deg: {turned}")
    print(f"  torso depth (arm surface): max {100 * max(f.torso_depth for _, f in rows):.1f} cm, median {100 * np.median([f.torso_depth for _, f in rows]):.1f} cm; motions > 1 cm: {deep}")
    print(f"  arm-arm depth: max {100 * max(f.arm_depth for _, f in rows):.1f} cm; motions > 1 cm: {crossed}")
    print(f"  twist wraps: {sum(f.twist_wraps for _, f in rows)} frames in {wrapped} motions")
    print(f"  smallest palm gap (midlines minus palm thickness): {100 * min(f.palm_gap for _, f in rows):.1f} cm")


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--signs", type=int, default=100)
    parser.add_argument("--avatar", action="append", help="avatar to measure (repeatable; default: max and the default avatar)")
    parser.add_argument("--verbose", action="store_true")
    args = parser.parse_args()
    from motor.body.avatar import DEFAULT_AVATAR

    for avatar in args.avatar or ["max", DEFAULT_AVATAR]:
        for label, source in (("utterances (examples + published MURML)", utterance_motions(avatar)), (f"signs (sample of {args.signs})", sign_motions(avatar, args.signs))):
            started = time.perf_counter()
            rows = [(name, figures(body, motion)) for name, body, motion in source]
            if args.verbose:
                for name, f in rows:
                    print(f"  {name}: {f}")
            summary(f"{avatar}, {label}", rows)
            print(f"  ({time.perf_counter() - started:.1f} s)")


if __name__ == "__main__":
    main()
