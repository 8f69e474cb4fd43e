"""SiGML sequences with placed entities: items in document order, failures one by one."""

import pytest

from mura.errors import SpecError
from mura.sigml_space import parse_signed_sequence
from mura.signs import Sign
from mura.space import IndicatingVerbSign, PointingSign


def test_items_in_order_with_entities_resolved():
    sequence = parse_signed_sequence(open("specs/verbs/ask_sequence.sigml", "rb").read(), "ask.sigml")
    kinds = [type(item) for item in sequence.items]
    assert kinds == [PointingSign, IndicatingVerbSign, PointingSign, Sign]
    verb = sequence.items[1]
    assert (verb.subject.arc, verb.object.arc) == (0.9, -0.6)
    assert sequence.failures == ()


@pytest.mark.parametrize(
    ("body", "message"),
    [
        ('<sign verb="ASK" subject="x" object="0.1"/>', "neither an arc position"),
        ('<sign point="1.5"/>', "outside [-1, 1]"),
        ("<hns_sign gloss='X'><hamnosys_manual><hamnothing/></hamnosys_manual></hns_sign>", "unknown HamNoSys symbol"),
    ],
)
def test_bad_item_fails_alone_with_its_place(body, message):
    sequence = parse_signed_sequence(f'<sigml>\n<sign point="0.3"/>\n{body}\n<sign point="-0.3"/>\n</sigml>', "s.sigml")
    assert len(sequence.items) == 2 and len(sequence.failures) == 1
    failure = sequence.failures[0]
    assert failure.index == 1 and message in failure.error.message and failure.error.line == 3


def test_wrong_root_is_one_error():
    with pytest.raises(SpecError, match="not <sigml>"):
        parse_signed_sequence("<utterance/>", "x.sigml")
