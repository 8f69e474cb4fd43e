"""The harness on tiny fake bench modules: figures, error entries, targets, README."""

import json
import sys
import textwrap

import pytest

from bench import runner
from bench.memory import long_utterance
from mura.murml import parse_utterance


@pytest.fixture
def fake_modules(tmp_path, monkeypatch):
    package = tmp_path / "fakebench"
    package.mkdir()
    (package / "__init__.py").write_text("")
    (package / "fine.py").write_text(textwrap.dedent('''
        def run(quick):
            return {"frames_per_s": 200000.0 if quick else 100000.0, "nested": {"ms": 12.5}}
    '''))
    (package / "broken.py").write_text("def run(quick):\n    raise RuntimeError('no avatar here')\n")
    (package / "wrong.py").write_text("def run(quick):\n    return [1, 2]\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    yield ("fakebench.fine", "fakebench.broken", "fakebench.wrong", "fakebench.absent")
    for name in [m for m in sys.modules if m.startswith("fakebench")]:
        del sys.modules[name]


TARGETS = (
    runner.Target("speed", "≥ 150,000", ("fakebench.fine", "frames_per_s"), "min", 150_000, "frames/s"),
    runner.Target("latency", "≤ 20 ms", ("fakebench.fine", "nested", "ms"), "max", 20.0, "ms"),
    runner.Target("missing", "≤ 1", ("fakebench.fine", "other"), "max", 1.0),
    runner.Target("broken", "0", ("fakebench.broken", "x"), "max", 0.0),
)


def test_every_module_runs_and_failures_are_entries(fake_modules):
    report = runner.run_bench(fake_modules, quick=True, command="mura bench --quick")
    results = report["results"]
    assert results["fakebench.fine"]["frames_per_s"] == 200000.0
    assert "RuntimeError: no avatar here" in results["fakebench.broken"]["error"]
    assert "returned list" in results["fakebench.wrong"]["error"]
    assert "ModuleNotFoundError" in results["fakebench.absent"]["error"]
    assert report["machine"]["python"] and report["machine"]["cores"] >= 1
    json.dumps(report)  # JSON-ready


@pytest.mark.parametrize("quick, speed_status", [(True, "met"), (False, "missed")])
def test_targets_are_judged(fake_modules, quick, speed_status):
    rows = runner.judge(runner.run_bench(fake_modules[:2], quick=quick)["results"], TARGETS)
    status = {row["what"]: (row["status"], row["note"]) for row in rows}
    assert status["speed"][0] == speed_status
    assert status["latency"] == ("met", "")
    assert status["missing"] == ("not measured", "no figure 'other'")
    assert status["broken"][0] == "not measured" and "no avatar here" in status["broken"][1]


@pytest.mark.parametrize(
    "kind, bound, tolerance, figure, met",
    [("min", 1.0, 0, 1.0, True), ("max", 1.0, 0, 1.1, False), ("below", 500, 0, 500, False), ("within", 1 / 3, 0.05, 0.38, True), ("within", 1 / 3, 0.05, 0.39, False)],
)
def test_target_kinds(kind, bound, tolerance, figure, met):
    assert runner.Target("x", "", ("m",), kind, bound, tolerance=tolerance).met(figure) is met


def test_table_and_readme_section(fake_modules, tmp_path):
    report = runner.run_bench(fake_modules[:2], quick=True, command="mura bench --quick")
    table = runner.format_table(report, TARGETS)
    assert "fakebench.fine:" in table and "machine:" in table and "no figure 'other'" in table
    readme = tmp_path / "README.md"
    readme.write_text(f"# mura\n\ntext\n{runner.README_START}\nold figures\n{runner.README_END}\nafter\n")
    runner.update_readme(readme, runner.readme_section(report, TARGETS))
    text = readme.read_text()
    assert "old figures" not in text and "mura bench --quick" in text and text.endswith(f"{runner.README_END}\nafter\n")
    assert "| speed | 200,000 frames/s | ≥ 150,000 | yes |" in text and "| latency | 12.5 ms | ≤ 20 ms | yes |" in text


def test_readme_without_markers_is_refused(tmp_path):
    readme = tmp_path / "README.md"
    readme.write_text("# mura\n")
    with pytest.raises(ValueError, match="bench:start"):
        runner.update_readme(readme, "section")


def test_default_targets_name_real_rows():
    names = [t.what for t in runner.TARGETS]
    assert len(names) == len(set(names))
    assert all(t.path[0] in runner.MODULES for t in runner.TARGETS)


@pytest.mark.parametrize("seconds, repeats", [(3.0, 1), (20.0, 6)])
def test_long_utterance_parses_into_repeated_chunks(seconds, repeats):
    utterance = parse_utterance(long_utterance(seconds))
    assert len(utterance.chunks) == 2 * repeats
    assert len(utterance.behaviors) == 2 * repeats


def test_mura_bench_command(fake_modules, tmp_path, monkeypatch, capsys):
    from agent.cli import main
    from agent.commands import bench as command

    monkeypatch.setattr(command, "run_bench", lambda **kw: runner.run_bench(fake_modules[:2], **kw))
    out = tmp_path / "figures.json"
    assert main(["bench", "--quick", "--json", str(out)]) == 0
    written = json.loads(out.read_text())
    assert written["command"] == "mura bench --quick" and "fakebench.broken" in written["results"]
    assert "fakebench.fine:" in capsys.readouterr().out
