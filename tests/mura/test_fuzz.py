"""Mutated specs never raise anything but SpecError."""

from pathlib import Path

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from mura.errors import SpecError
from mura.murml import parse_utterance

EXAMPLES = sorted((Path(__file__).resolve().parents[2] / "specs" / "utterances").glob("*.xml"))
SEEDS = [path.read_text(encoding="utf-8") for path in EXAMPLES]
FRAGMENTS = ["<", ">", "/>", '"', "&", "&amp;", "$", "Loc", "Dir", "BS", "(", ")", " ", "0", "-1", "1e9", "nan",
             "t1", "t9", "chunkborder", '="true"', "<time id=\"t1\"/>", "</gesture>", "<segment>", "Sym", "right_arm"]


def _mutate(text: str, position: int, cut: int, insert: str) -> str:
    position %= len(text) + 1
    return text[:position] + insert + text[position + cut:]


@settings(max_examples=300, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow])
@given(
    seed=st.sampled_from(SEEDS),
    edits=st.lists(
        st.tuples(st.integers(0, 4000), st.integers(0, 12), st.sampled_from(FRAGMENTS) | st.text(max_size=6)),
        min_size=1,
        max_size=4,
    ),
)
def test_only_spec_errors_escape(seed, edits):
    text = seed
    for position, cut, insert in edits:
        text = _mutate(text, position, cut, insert)
    try:
        parse_utterance(text, file="mutant.xml")
    except SpecError as error:
        assert error.file == "mutant.xml"
        assert error.line >= 0 and error.column >= 0
