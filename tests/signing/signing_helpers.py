"""Helpers for the signing tests: write a one-sign SiGML document or a HamNoSys string."""

from __future__ import annotations

from mura.hamnosys import hamnosys_string, parse_hamnosys
from mura.signs import Sign


def hns_document(gloss: str, symbols: str, nonmanual: str = "") -> str:
    """A one-sign SiGML document with the space-separated ``symbols`` as ``ham…`` tags."""
    tags = "".join(f"<{name}/>" for name in symbols.split())
    return (
        f'<sigml><hns_sign gloss="{gloss}">'
        f"<hamnosys_nonmanual>{nonmanual}</hamnosys_nonmanual>"
        f"<hamnosys_manual>{tags}</hamnosys_manual></hns_sign></sigml>"
    )


def sign_of(symbols: str, gloss: str = "test") -> Sign:
    """Parse space-separated symbol names as a HamNoSys 4 Unicode string."""
    return parse_hamnosys(hamnosys_string(symbols.split()), gloss=gloss)

#: The SiGML corpora in ``../shared/corpora/sigml``.
CORPORA = ("German_SL_DGS.sigml", "Indian_SL.sigml")
