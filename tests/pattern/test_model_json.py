"""The canonical model is immutable and its JSON form round-trips exactly."""

from __future__ import annotations

import json

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from patternbridge.errors import InputError
from patternbridge.io.pattern_json import dumps_pattern, load_pattern_json, save_pattern_json
from patternbridge.pattern import (
    EdgeRange,
    GradeRuleTable,
    Leg,
    MeasurementLink,
    Notch,
    Pattern,
    Piece,
    Placement,
    Quantity,
    Seam,
)
from patternbridge.pattern.json import pattern_from_dict, pattern_to_dict

coord = st.floats(min_value=-500, max_value=500, allow_nan=False, allow_infinity=False)


def _pattern(outline, deltas) -> Pattern:
    n = len(outline)
    piece = Piece(
        name="front",
        size="M",
        outline=outline,
        rules=["1"] + [None] * (n - 1),
        quantity=Quantity(right=1, left=1),
        notches=(Notch(vertex=n - 1, type="T", depth_cm=0.4),),
        marks={"a": 0, "b": n - 1},
        landmarks={"waist_side_right": "a"},
        placement=Placement(body_part="torso", side="front", anchor="waist_side_right", anchor_mark="a"),
    )
    return Pattern(
        style="S1",
        pieces=(piece,),
        sample_size="M",
        sizes=("S", "M", "L"),
        rules=GradeRuleTable(sizes=("S", "M", "L"), sample_size="M", deltas={"1": deltas}),
        seams=(
            Seam(
                id="s",
                a=EdgeRange(piece="front", start="a", end="b"),
                b=EdgeRange(piece="front", start="b", end="a", copy="mirror"),
            ),
        ),
        measurements=(
            MeasurementLink(
                measurement="waist_girth", ease_cm=2, legs=(Leg(piece="front", start="a", end="b", factor=2),)
            ),
            MeasurementLink(
                measurement="hip_girth", ease_cm=4, at_least=True, legs=(Leg(piece="front", start="b", end="a"),)
            ),
        ),
    )


@settings(max_examples=40, deadline=None)
@given(
    outline=st.lists(st.tuples(coord, coord), min_size=3, max_size=12),
    deltas=st.lists(st.tuples(coord, coord), min_size=3, max_size=3),
)
def test_json_round_trip_is_exact(outline, deltas):
    pattern = _pattern(outline, deltas)
    text = json.dumps(pattern_to_dict(pattern))
    back = pattern_from_dict(json.loads(text))
    assert back == pattern
    np.testing.assert_array_equal(back.pieces[0].outline, np.asarray(outline, dtype=float))


def test_model_arrays_are_read_only():
    pattern = _pattern([(0, 0), (1, 0), (0, 1)], [(0, 0)] * 3)
    with pytest.raises(ValueError):
        pattern.pieces[0].outline[0, 0] = 5.0


def test_model_rejects_inconsistent_input():
    with pytest.raises(ValueError, match="marks outside"):
        Piece(name="p", outline=[(0, 0), (1, 0), (0, 1)], marks={"x": 3})
    with pytest.raises(ValueError, match="unknown marks"):
        Piece(name="p", outline=[(0, 0), (1, 0), (0, 1)], landmarks={"crotch_point": "nope"})
    with pytest.raises(ValueError, match="expected shape"):
        Piece(name="p", outline=[(0, 0, 0), (1, 0, 0), (0, 1, 0)])
    piece = Piece(name="p", outline=[(0, 0), (1, 0), (0, 1)])
    with pytest.raises(ValueError, match="duplicate piece"):
        Pattern(style="x", pieces=(piece, piece))


def test_quantity_total_splits_like_accumark():
    assert Quantity.from_total(2) == Quantity(right=1, left=1)
    assert Quantity.from_total(1) == Quantity(right=1, left=0)
    assert Quantity.from_total(3).total == 3


def test_json_file_round_trip_and_bad_files(tmp_path):
    pattern = _pattern([(0, 0), (4, 0), (4, 3)], [(0, 0), (0, 0), (1, 1)])
    path = save_pattern_json(pattern, tmp_path / "p.json")
    assert load_pattern_json(path) == pattern
    assert dumps_pattern(load_pattern_json(path)) == path.read_text()
    bad = tmp_path / "bad.json"
    bad.write_text("{not json")
    with pytest.raises(InputError, match="not valid JSON"):
        load_pattern_json(bad)
    other = tmp_path / "other.json"
    other.write_text('{"format": "something"}')
    with pytest.raises(InputError, match="not a valid PatternBridge pattern"):
        load_pattern_json(other)
    yes = tmp_path / "yes.json"
    doc = json.loads(path.read_text())
    doc["measurements"][1]["at_least"] = "yes"
    yes.write_text(json.dumps(doc))
    with pytest.raises(InputError, match="at_least: expected true or false, got a string 'yes'"):
        load_pattern_json(yes)
    doc["measurements"][1]["at_least"] = True
    doc["measurements"][1]["proportional"] = "yes"
    yes.write_text(json.dumps(doc))
    with pytest.raises(InputError, match="proportional must be true or false, got 'yes'"):
        load_pattern_json(yes)
