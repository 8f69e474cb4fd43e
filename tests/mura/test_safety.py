"""Reading specs is safe: no network, no external DTD, no entity bombs, bounded size."""

import pytest

from mura.errors import SpecError
from mura.murml import parse_utterance
from mura.xml_source import XmlSource

SIMPLE = "<utterance><specification>Hello there.</specification></utterance>"


def test_external_doctype_is_ignored_not_fetched():
    text = '<?xml version="1.0"?>\n<!DOCTYPE definition SYSTEM "http://127.0.0.1:9/utterances.dtd">\n' + SIMPLE
    utterance = parse_utterance(text)
    assert utterance.chunks[0].text == "Hello there."


def test_external_entity_is_refused():
    text = '<!DOCTYPE u [<!ENTITY ext SYSTEM "file:///etc/passwd">]><utterance><specification>&ext;</specification></utterance>'
    with pytest.raises(SpecError, match="entity declarations are not allowed"):
        parse_utterance(text, file="ext.xml")


def test_oversized_input_is_refused():
    with pytest.raises(SpecError, match="more than the limit of 100"):
        XmlSource.from_bytes(SIMPLE.encode() + b" " * 200, "big.xml", max_bytes=100)


def test_empty_input_is_refused():
    with pytest.raises(SpecError, match="empty document") as caught:
        parse_utterance("   ", file="empty.xml")
    assert str(caught.value) == "empty.xml:1:1: empty document"


def test_missing_file_is_a_spec_error(tmp_path):
    with pytest.raises(SpecError, match="cannot read file"):
        XmlSource.from_path(tmp_path / "nope.xml")


def test_attribute_position_is_exact():
    source = XmlSource.from_bytes(b'<a>\n  <b x="1"\n     y="2"/>\n</a>', "pos.xml")
    b = source.root[0]
    assert (source.where(b).line, source.where(b).column) == (2, 3)
    assert (source.where(b, "y").line, source.where(b, "y").column) == (3, 6)
