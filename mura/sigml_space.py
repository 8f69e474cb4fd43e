"""SiGML sequences with placed entities, pointing signs and indicating verbs.

A ``<sigml>`` document read as one signed sequence, in document order, may hold beside its
``<hns_sign>`` and ``<hamgestural_sign>`` signs the spatial markup of :mod:`mura.space`::

    <sigml>
      <space><place entity="john" arc="0.9"/><place entity="mary" arc="-0.6"/></space>
      <hns_sign gloss="JOHN">…</hns_sign>
      <sign point="john"/>
      <sign verb="ASK" subject="john" object="mary"/>
    </sigml>

A ``<space>`` places entities for the signs after it. Every item that cannot be read fails
alone (its gloss, its index and the error, as :class:`mura.signs.SignFailure`); the others
stay in order. ``mura verbs sequence`` performs such a document.
"""

from __future__ import annotations

from dataclasses import dataclass

from mura.errors import SpecError
from mura.signs import Sign, SignFailure
from mura.limits import DEFAULT_LIMITS, Limits
from mura.sigml import ROOTS, read_sign_element
from mura.space import SpatialReference, SpatialSign
from mura.space_markup import is_spatial_sign, read_space, read_spatial_sign
from mura.xml_source import XmlSource


@dataclass(frozen=True)
class SignedSequence:
    """The items of a SiGML sequence in order (signs, pointing signs, indicating verbs),
    the entities placed, and the items that could not be read."""

    items: tuple[Sign | SpatialSign, ...]
    space: tuple[SpatialReference, ...]
    failures: tuple[SignFailure, ...]
    source: str


def parse_signed_sequence(data: str | bytes, file: str = "<input>", limits: Limits = DEFAULT_LIMITS) -> SignedSequence:
    """Read a SiGML sequence (module docstring) within ``limits``; :class:`SpecError` only
    when the document as a whole cannot be read."""
    raw = data.encode("utf-8") if isinstance(data, str) else data
    source = XmlSource.from_bytes(raw, file, limits=limits)
    root = source.root
    if root.tag not in ROOTS:
        raise SpecError(f"root element <{root.tag}> is not <sigml> or <sigml_collection>", source.where(root))
    placed: dict[str, SpatialReference] = {}
    items: list[Sign | SpatialSign] = []
    failures: list[SignFailure] = []
    for index, element in enumerate(e for e in root if isinstance(e.tag, str)):
        gloss = element.get("gloss") or element.get("verb") or (f"POINT-{element.get('point')}" if element.get("point") else f"#{index}")
        try:
            if element.tag == "space":
                read_space(source, element, placed)
            elif element.tag == "sign" and is_spatial_sign(element):
                items.append(read_spatial_sign(source, element, gloss, placed))
            else:
                items.append(read_sign_element(element, gloss, source.where, limits))
        except SpecError as error:
            failures.append(SignFailure(gloss, index, error))
    return SignedSequence(tuple(items), tuple(placed.values()), tuple(failures), file)
