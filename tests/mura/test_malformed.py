"""Each malformed spec gets the precise error its case expects: place and message."""

from pathlib import Path

import pytest

from mura.errors import SpecError
from mura.murml import load_utterances

MALFORMED = Path(__file__).parent / "malformed"

CASES = [
    ("affiliate_crosses_chunks.xml", 5, 29, "behaviour 'g1': affiliate from 't1' (chunk 1) to 't3' (chunk 2) crosses a chunk border"),
    ("affiliate_reversed.xml", 5, 29, "behaviour 'g1': affiliate ends at 't1', before its onset 't2'"),
    ("bad_distance.xml", 11, 36, "a distance is one number or one of DistShort, DistNorm, DistFar, DistFFar, not 'far'"),
    ("bad_unit.xml", 1, 1, "Invalid attribute unit for element definition"),
    ("duplicate_time_tag.xml", 2, 50, "time tag 't1' is defined twice"),
    ("empty_utterance.xml", 2, 3, "utterance has neither spoken text nor behaviours"),
    ("entity_bomb.xml", 3, 3, "entity declarations are not allowed in specs"),
    ("missing_function_param.xml", 6, 7, "function 'refer_to_loc' needs parameter 'refloc'"),
    ("not_well_formed.xml", 4, 13, "malformed XML: Opening and ending tag mismatch: behaviorspec line 3 and utterance"),
    ("schema_violation.xml", 6, 7, "does not fit the MURML schema: Did not expect element wobble there"),
    ("segment_without_path.xml", 8, 11, "a HandLocation segment needs an end, a direction and a distance, or a start to hold"),
    ("slot_value_mismatch.xml", 7, 40, "PalmOrientation: unknown palm orientation 'BSflat'"),
    ("time_tag_inside_word.xml", 2, 25, "time tag 't1' stands inside a word; put it between words"),
    ("timing_end_before_onset.xml", 5, 29, "timing of 'behavior_1' ends at 1.0 s, not after its onset 3.0 s"),
    ("unknown_function.xml", 6, 17, "unknown gesture function 'juggle'"),
    ("unknown_handshape.xml", 7, 34, "HandShape: unknown hand shape 'BSclaw'"),
    ("unknown_location_name.xml", 7, 37, "HandLocation: unknown location name 'LocMiddle' in 'LocShoulder LocMiddle LocNorm'"),
    ("unknown_place.xml", 6, 7, "unknown place $Loc-Moon"),
    ("unknown_slot.xml", 7, 17, "unknown slot 'ElbowColour'"),
    ("unknown_symmetry.xml", 7, 43, "unknown symmetry 'SymMX'"),
    ("unknown_time_tag.xml", 5, 29, "behaviour 'g1': end names unknown time tag 't9' (known: t1, t2)"),
    ("zero_direction.xml", 10, 37, "direction '0 0 0' has zero length"),
]


def test_every_malformed_file_has_a_case():
    assert sorted(path.name for path in MALFORMED.glob("*.xml")) == sorted(case[0] for case in CASES)


@pytest.mark.parametrize(("name", "line", "column", "message"), CASES)
def test_malformed_spec_error(name, line, column, message):
    with pytest.raises(SpecError) as caught:
        load_utterances(MALFORMED / name)
    error = caught.value
    assert error.file.endswith(name)
    assert (error.line, error.column) == (line, column)
    assert message in error.message
    assert str(error).startswith(f"{error.file}:{line}:{column}: ")
