"""Fixtures for the fast sign-planning paths: the avatar, and a sample of the real corpora."""

from __future__ import annotations

from pathlib import Path

import pytest

from motor.body.avatar import Avatar, load_avatar
from mura.hamnosys import hamnosys_string, parse_hamnosys
from mura.sigml import parse_sigml
from mura.signs import Sign

CORPORA = ("German_SL_DGS.sigml", "Indian_SL.sigml")
#: Every how many signs of each corpus the sample takes.
STRIDE = 40
#: How many signs with a hand constellation of each corpus the sample adds.
CONSTELLATIONS = 4

#: Signs written for these tests (HamNoSys symbol names): one and two hands, symmetry,
#: hands on the other hand and arm (arm poses), hand constellations, repetitions, circles,
#: arcs, local movements, changes of shape and orientation, and a sign with an unknown site.
WRITTEN: dict[str, str] = {
    "static": "hamfist hamextfingeru hampalml hamchin",
    "circle": "hamflathand hamextfingeru hampalml hamchest hamcircleo hamclocku hamclockd hamlargemod hamfast",
    "arc to touch": "hamfinger2 hamextfingeru hampalml hamchest hammoveu hamarcl hamchin hamtouch",
    "sequence": "hamfist hamextfingero hampalmd hamseqbegin hammoveu hammoved hamseqend hamtense",
    "parallel": "hamflathand hamextfingero hampalmd hamchest hamparbegin hammoved hamplus hammoveu hamsmallmod hamparend",
    "replace": "hamfist hamextfingero hampalmd hamchest hamreplace hamflathand hampalmu",
    "repeat from start": "hamflathand hamextfingero hampalmd hamchest hammoveu hamrepeatfromstart",
    "repeat reverse": "hamflathand hamextfingero hampalmd hamchest hammoveu hamrepeatreverse",
    "symmetric alternating": "hamsymmlr hamalternatingmotion hamflathand hamextfingero hampalmd hammoveu",
    "symmetric parallel": "hamsymmpar hamflathand hamextfingero hampalmd hammover",
    "two postures": "hamparbegin hamflathand hamextfingerol hampalmd hamplus hamfist hamextfingeror hampalmu hamparend hamchest",
    "on the other palm": "hamfinger2 hamextfingero hampalmd hampalm hamtouch",
    "to the other palm": "hamfinger2 hamextfingero hampalmd hamchest hammoved hampalm hamtouch",
    "on the other elbow": "hamflathand hamextfingeru hampalml hamelbow",
    "between sites": "hamflathand hamextfingeru hampalml hambetween hampalmul hamshoulders hambetween hamchest hamtouch",
    "nondominant": "hamnondominant hamflathand hamextfingeru hampalml hamchest hammoved",
    "nodding": "hamflathand hamextfingero hampalmd hamchest hamnodding",
    "fingerplay": "hamfinger2345 hamextfingeru hampalml hamchest hamfingerplay",
}


@pytest.fixture(scope="session")
def avatar() -> Avatar:
    return load_avatar("max")


@pytest.fixture(scope="session")
def written_signs() -> list[Sign]:
    return [parse_hamnosys(hamnosys_string(symbols.split()), gloss=gloss) for gloss, symbols in WRITTEN.items()]


@pytest.fixture(scope="session")
def corpus_sample(shared: Path) -> list[Sign]:
    """Every :data:`STRIDE`-th parsed sign of both SiGML corpora (real signs), and the
    first :data:`CONSTELLATIONS` signs of each with a hand constellation."""
    signs: list[Sign] = []
    for name in CORPORA:
        parsed = parse_sigml((shared / "corpora" / "sigml" / name).read_bytes(), file=name).signs
        signs.extend(parsed[::STRIDE])
        signs.extend([sign for sign in parsed if sign.constellation is not None][:CONSTELLATIONS])
    return signs
