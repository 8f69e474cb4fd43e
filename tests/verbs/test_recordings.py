"""Recording tables: both forms read back what was written; bad performances are refused by
file and row, and the others kept."""

import json

import numpy as np
import pytest

from motor.verbs.synthetic import synthetic_session
from mura.errors import SpecError
from mura.recordings import (
    parse_recordings_csv,
    parse_recordings_json,
    read_recordings,
    recordings_csv,
    recordings_json,
)


@pytest.fixture(scope="module")
def few():
    """Three GIVE and three TELL performances (synthetic)."""
    performances = synthetic_session(verbs=("GIVE", "TELL"))
    return [p for p in performances if p.verb == "GIVE"][:3] + [p for p in performances if p.verb == "TELL"][:3]


def _same(first, second):
    assert [p.id for p in first] == [p.id for p in second]
    for a, b in zip(first, second):
        assert (a.verb, a.signer, a.subject, a.object) == (b.verb, b.signer, b.subject, b.object)
        assert np.allclose(a.times, b.times, atol=1e-5)
        for hand in a.hands:
            assert np.allclose(a.hands[hand].location, b.hands[hand].location, atol=1e-5)
            assert np.allclose(np.abs(np.sum(a.hands[hand].orientation * b.hands[hand].orientation, axis=1)), 1.0, atol=1e-6)


@pytest.mark.parametrize("form", ["csv", "json"])
def test_round_trip(few, form, tmp_path):
    path = tmp_path / f"session.{form}"
    path.write_text(recordings_csv(few) if form == "csv" else recordings_json(few, True, "test"))
    session = read_recordings(path)
    assert session.refused == ()
    _same(few, session.performances)
    assert session.verbs == ("GIVE", "TELL")


def _csv_lines(few):
    return recordings_csv(few).splitlines()


# (what to change in the CSV, line to change (1 = header; 0: every row of the first
# performance), the message fragment)
CSV_CASES = [
    ("subject", 0, "-1.5", "outside [-1, 1]"),
    ("object", 0, "1.2", "outside [-1, 1]"),
    ("object", 3, "0.5", "differs from its first row"),
    ("x", 3, "nan", "is nan"),
    ("qw", 2, "abc", "qw 'abc' is not a number"),
    ("hand", 2, "middle", "hand 'middle' is not right or left"),
    ("keyframe", 2, "x", "is not a whole number"),
]


@pytest.mark.parametrize(("column", "line", "value", "message"), CSV_CASES)
def test_bad_csv_row_is_refused_by_line(few, column, line, value, message):
    lines = _csv_lines(few)
    header = lines[0].split(",")
    rows = [i + 1 for i, l in enumerate(lines) if l.startswith(few[0].id + ",")] if line == 0 else [line]
    for row in rows:
        cells = lines[row - 1].split(",")
        cells[header.index(column)] = value
        lines[row - 1] = ",".join(cells)
    session = parse_recordings_csv("\n".join(lines) + "\n", "bad.csv")
    assert len(session.refused) == 1
    error = session.refused[0]
    assert error.file == "bad.csv" and message in error.message
    assert error.line in (2, line)  # the performance's first row, or the bad row itself
    assert len(session.performances) == len(few) - 1


def test_missing_hand_at_a_keyframe_is_refused(few):
    lines = _csv_lines(few)
    dropped = [i for i, l in enumerate(lines) if l.startswith(few[0].id + ",") and ",left," in l][-1]
    del lines[dropped]
    session = parse_recordings_csv("\n".join(lines) + "\n", "bad.csv")
    assert "left hand is missing at keyframe" in session.refused[0].message
    assert session.refused[0].line == 2


def test_one_handed_where_the_verb_is_two_handed_is_refused_by_its_row(few):
    lines = _csv_lines(few)
    second = few[1].id + ","
    kept = [l for l in lines if not (l.startswith(second) and ",left," in l)]
    session = parse_recordings_csv("\n".join(kept) + "\n", "bad.csv")
    assert len(session.refused) == 1
    assert few[1].id in session.refused[0].message and "first performance" in session.refused[0].message
    assert session.refused[0].line == next(i for i, l in enumerate(kept, 1) if l.startswith(second))


def _json_document(few):
    return json.loads(recordings_json(few, True, "test"))


def _mutations():
    def nan_location(p):
        p["hands"]["right"]["location"][0][1] = float("nan")

    def no_right(p):
        del p["hands"]["right"]

    def far_subject(p):
        p["subject"] = 3.0

    def one_keyframe(p):
        p["times"] = p["times"][:1]
        for hand in p["hands"].values():
            hand["location"], hand["orientation"] = hand["location"][:1], hand["orientation"][:1]

    def zero_quaternion(p):
        p["hands"]["right"]["orientation"][1] = [0.0, 0.0, 0.0, 0.0]

    def backwards(p):
        p["times"] = p["times"][::-1]

    return [
        (nan_location, "NaN or infinite"),
        (no_right, "has no right hand"),
        (far_subject, "outside [-1, 1]"),
        (one_keyframe, "at least 2"),
        (zero_quaternion, "zero quaternion"),
        (backwards, "do not increase"),
    ]


@pytest.mark.parametrize(("mutate", "message"), _mutations())
@pytest.mark.parametrize("index", [0, 4])
def test_bad_json_performance_is_refused_by_line(few, mutate, message, index):
    document = _json_document(few)
    mutate(document["performances"][index])
    text = "{" + json.dumps({k: v for k, v in document.items() if k != "performances"})[1:-1] + ', "performances": [\n'
    text += ",\n".join(json.dumps(p) for p in document["performances"]) + "\n]}"
    session = parse_recordings_json(text.replace("NaN", "NaN"), "bad.json")
    assert len(session.refused) == 1, session.refused
    error = session.refused[0]
    assert message in error.message and error.file == "bad.json"
    assert error.line == 2 + index  # one performance per line after the head
    assert len(session.performances) == len(few) - 1


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("{}", "not a recording table"),
        ('{"format": "mura verb recordings", "version": 2, "performances": []}', "unknown version"),
        ("{not json", "not JSON"),
    ],
)
def test_unusable_json_file_is_one_error(text, message):
    with pytest.raises(SpecError, match=message):
        parse_recordings_json(text, "bad.json")


def test_csv_without_the_columns_is_one_error():
    with pytest.raises(SpecError, match="header lacks the column"):
        parse_recordings_csv("performance,verb\n", "bad.csv")
