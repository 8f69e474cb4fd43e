"""Item 2: repetition bombs. A move followed by thirty ``hamrepeatfromstart`` (or nested
``rpt_motion``, or nested MURML ``<repetition>``) expanded to 2³⁰ movements: MemoryError
after a minute, one such sign ended the whole ``mura sign`` run, and ``mura check`` said
OK. Expansion is now bounded by the number of resulting movements, the sign is refused
by name, and the batch goes on.
"""

from __future__ import annotations

import json

import pytest
from hostile_helpers import LIGHT, absolute_gesture, all_files, run_mura, utterance

from agent.cli import main
from mura.constraints import Arm, Dynamic, Parallel, Repetition, Segment, SegmentKind, Sequence, Static, Symmetrical, Symmetry
from mura.errors import SpecError
from mura.expansion import movement_count
from mura.hamnosys import hamnosys_string, parse_hamnosys
from mura.limits import Limits
from mura.values import HandShape

POSTURE = ["hamflathand", "hamextfingeru", "hampalml", "hamshoulders"]
MOVE = Dynamic("HandLocation", (Segment(SegmentKind.LINEAR),))
HOLD = Static("HandShape", HandShape("fist"))


def _repeated_move(repeats: int) -> list[str]:
    return POSTURE + ["hammoveo"] + ["hamrepeatfromstart"] * repeats


def _nested_brackets(depth: int) -> list[str]:
    return POSTURE + ["hamseqbegin"] * depth + ["hammoveo"] + ["hamrepeatcontinue", "hamseqend"] * depth


def _hns(gloss: str, names: list[str]) -> str:
    return f'<hns_sign gloss="{gloss}"><hamnosys_manual>{"".join(f"<{n}/>" for n in names)}</hamnosys_manual></hns_sign>'


def _gestural(gloss: str, depth: int) -> str:
    motion = '<directedmotion direction="o"/>'
    for _ in range(depth):
        motion = f'<rpt_motion repetition="continue">{motion}</rpt_motion>'
    return (f'<hamgestural_sign gloss="{gloss}"><sign_manual both_hands="false"><handconfig handshape="finger2"/>'
            f'<handconfig extfidir="u" palmor="l"/><location_bodyarm location="chest"/>{motion}</sign_manual></hamgestural_sign>')


@pytest.mark.parametrize(
    ("tree", "count"),
    [
        (MOVE, 1),
        (HOLD, 1),
        (Repetition(MOVE, 3), 3),
        (Repetition(HOLD, 5), 5),
        (Repetition(Sequence((MOVE, MOVE, HOLD)), 2), 6),
        (Repetition(Repetition(Parallel((MOVE, HOLD)), 2), 3), 12),
        (Symmetrical(Repetition(MOVE, 2), Arm.RIGHT, Symmetry(frozenset("S"), "SymMS")), 2),
        (Repetition(MOVE, 2 ** 40), 2 ** 40),
    ],
)
def test_movement_count_multiplies_through_repetitions(tree, count):
    assert movement_count(tree) == count


@pytest.mark.parametrize(
    ("names", "movements"),
    [(_repeated_move(30), 2 ** 30), (_repeated_move(11), 2 ** 11), (_nested_brackets(10), 2 ** 10)],
    ids=["30-repeats", "11-repeats", "nested-10"],
)
def test_hamnosys_bomb_is_refused_by_name(names, movements):
    with pytest.raises(SpecError) as caught:
        parse_hamnosys(hamnosys_string(names), gloss="BOMB")
    assert f"sign 'BOMB' expands to {movements} movements once its repetitions are performed, more than the limit of 1000" in str(caught.value)


def test_the_limit_is_raised_for_a_legitimate_sign():
    names = _nested_brackets(4)  # 16 movements
    with pytest.raises(SpecError, match="expands to 16 movements"):
        parse_hamnosys(hamnosys_string(names), gloss="S", limits=Limits(max_movements=8))
    assert parse_hamnosys(hamnosys_string(names), gloss="S", limits=Limits(max_movements=16)).gloss == "S"


@pytest.mark.timeout(60)
def test_sign_batch_renders_the_good_signs_and_reports_the_bombs(write, tmp_path):
    """One document: a good sign, a HamNoSys bomb, a gestural rpt_motion bomb; under an
    address-space limit the good sign renders and each bomb fails alone in the report."""
    document = write("signs.sigml", "<sigml>\n" + "\n".join([
        _hns("GOOD", POSTURE + ["hammoveo"]),
        _hns("REPEATS", _repeated_move(30)),
        _gestural("NESTED", 30),
    ]) + "\n</sigml>")  # fmt: skip
    out, report = tmp_path / "out", tmp_path / "report.json"
    signed = run_mura("sign", str(document), "-o", str(out), "--report", str(report), *LIGHT)
    assert signed.status == 1
    assert all_files(out) == ["GOOD.bvh", "GOOD.face.json", "GOOD.motion.js", "index.html"]
    records = {record["gloss"]: record for record in json.loads(report.read_text())["signs"]}
    assert records["GOOD"]["rendered"]
    assert records["REPEATS"]["reason"] == f"{document}:3:1: sign 'REPEATS' expands to 1073741824 movements once its repetitions are performed, more than the limit of 1000 (raise with --limit max_movements=N)"
    assert records["NESTED"]["reason"].startswith(f"{document}:4:1: sign 'NESTED' expands to 1073741824 movements")
    assert "1 of 3 signs rendered" in signed.out


def test_check_refuses_what_sign_refuses(write, capsys):
    document = write("signs.sigml", "<sigml>\n" + _hns("GOOD", POSTURE + ["hammoveo"]) + "\n" + _gestural("NESTED", 12) + "\n</sigml>")
    assert main(["check", str(document)]) == 1
    assert capsys.readouterr().out.strip() == (f"{document}:3:1: sign 'NESTED' expands to 4096 movements once its repetitions "
                                               "are performed, more than the limit of 1000 (raise with --limit max_movements=N)")


@pytest.mark.timeout(60)
def test_hamnosys_bomb_on_the_command_line_under_a_memory_limit(tmp_path):
    signed = run_mura("sign", "--hamnosys", hamnosys_string(_repeated_move(30)), "--gloss", "BOMB", "-o", str(tmp_path / "out"))
    assert signed.status == 1
    assert "--hamnosys: BOMB: --hamnosys:1:1: sign 'BOMB' expands to 1073741824 movements" in signed.out
    assert all_files(tmp_path / "out") == []


def _nested_repetition(depth: int, count: str = "2") -> str:
    tree = '<dynamic slot="HandLocation"><segment type="linear"><value type="direction" name="DirU"/><value type="distance" name="10cm"/></segment></dynamic>'
    for _ in range(depth):
        tree = f'<repetition count="{count}">{tree}</repetition>'
    return tree


@pytest.mark.parametrize(
    ("constraint", "message"),
    [
        (_nested_repetition(30), "gesture 'g1' expands to 1073741824 movements once its repetitions are performed, more than the limit of 1000"),
        (_nested_repetition(1, "1000000000"), "repetition count 1000000000 is more than the limit of 1000 movements"),
        (_nested_repetition(1, "9" * 5000), "repetition count 99999999999999999999 is more than the limit of 1000 movements"),
    ],
    ids=["nested-30", "count-1e9", "count-5000-digits"],
)
def test_murml_repetition_bombs_are_located(write, tmp_path, capsys, constraint, message):
    spec = write("rep.xml", utterance(behaviors=absolute_gesture("0.5", "1.5", constraint=constraint)))
    assert main(["check", str(spec)]) == 1
    checked = capsys.readouterr().out.strip()
    assert checked.startswith(f"{spec}:1:") and message in checked
    assert main(["render", str(spec), "-o", str(tmp_path / "out")]) == 1
    assert message in capsys.readouterr().err
    assert all_files(tmp_path / "out") == []
