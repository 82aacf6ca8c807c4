"""formats/pattern.schema.json describes exactly what pattern_to_dict writes."""

from __future__ import annotations

import copy
import dataclasses
import json
from pathlib import Path

import jsonschema
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from patternbridge.pattern.json import measurement_link_to_dict, pattern_from_dict, pattern_to_dict
from patternbridge.pattern.model import (
    GradeRuleTable,
    Notch,
    Pattern,
    Piece,
    Polyline,
    Quantity,
)
from patternbridge.testing import example_pattern

REPO = Path(__file__).resolve().parents[2]
SCHEMA_PATH = REPO / "formats" / "pattern.schema.json"
SHARED_AAMA = REPO / ".." / "shared" / "aama"


@pytest.fixture(scope="module")
def validator() -> jsonschema.Draft202012Validator:
    schema = json.loads(SCHEMA_PATH.read_text(encoding="utf-8"))
    jsonschema.Draft202012Validator.check_schema(schema)
    return jsonschema.Draft202012Validator(schema)


def _errors(validator, doc) -> list[str]:
    return [e.message for e in validator.iter_errors(doc)]


def test_example_with_bridge_data_is_valid(validator):
    doc = json.loads(json.dumps(pattern_to_dict(example_pattern())))
    assert doc["seams"] and doc["measurements"] and doc["pieces"][0]["placement"]
    assert _errors(validator, doc) == []
    doc["measurements"][0]["at_least"] = True
    assert _errors(validator, doc) == []
    doc["measurements"][0]["at_least"] = "yes"
    assert any("is not of type 'boolean'" in e for e in _errors(validator, doc))
    doc["measurements"][0]["at_least"] = True
    doc["measurements"][0]["proportional"] = "yes"
    assert any("is not of type 'boolean'" in e for e in _errors(validator, doc))


def test_schema_names_every_field_the_writer_emits(validator):
    """No field is missing from the schema and no schema field is stale."""
    schema = validator.schema
    doc = pattern_to_dict(example_pattern())
    fabric = {"fabric_class", "fabric_why"}  # written only when the fabric is stated or not woven
    assert set(doc) == set(schema["properties"]) - fabric
    front = doc["pieces"][0]
    optional = {"role", "role_confidence", "fabric_class"}  # written only for a piece whose role/fabric is known
    assert set(front) == set(schema["$defs"]["piece"]["properties"]) - optional
    pattern = example_pattern()
    with_role = dataclasses.replace(pattern.pieces[0], role="front", role_confidence=0.9, fabric_class="knit")
    typed = pattern_to_dict(
        dataclasses.replace(pattern, pieces=(with_role, *pattern.pieces[1:]), fabric_class="stretch_knit")
    )
    assert optional <= set(typed["pieces"][0]) and fabric <= set(typed)
    assert _errors(validator, json.loads(json.dumps(typed))) == []
    typed["fabric_class"] = "felt"
    assert any("'felt' is not one of" in e for e in _errors(validator, typed))
    notch = front["notches"][0]
    assert set(notch) == set(schema["$defs"]["notch"]["properties"]) - {
        "source_angle_deg"
    }
    assert set(doc["seams"][0]) == set(schema["$defs"]["seam"]["properties"])
    one_sided = dataclasses.replace(example_pattern().measurements[0], at_least=True, proportional=True)
    assert set(doc["measurements"][0]) | set(measurement_link_to_dict(one_sided)) == set(
        schema["$defs"]["measurement"]["properties"]
    )
    assert set(doc["provenance"]) == set(
        schema["properties"]["provenance"]["properties"]
    )


@pytest.mark.parametrize(
    "mutate, message",
    [
        (lambda d: d.pop("pieces"), "'pieces' is a required property"),
        (
            lambda d: d.update(format="something-else"),
            "'patternbridge.pattern' was expected",
        ),
        (lambda d: d.update(length_unit="mm"), "'cm' was expected"),
        (lambda d: d.update(units="IMPERIAL"), "is not one of"),
        (lambda d: d["pieces"][0].update(colour="red"), "Additional properties"),
        (lambda d: d["pieces"][0]["kinds"].__setitem__(0, "corner"), "is not one of"),
        (lambda d: d["pieces"][0]["notches"][0].update(type="W"), "is not one of"),
        (
            lambda d: d["pieces"][0]["outline"].__setitem__(0, [1.0, 2.0, 3.0]),
            ("is expected to be empty", "at most 2 items", "is too long"),
        ),
        (lambda d: d["pieces"][0].update(outline=[[0, 0], [1, 0]]), "is too short"),
        (lambda d: d["pieces"][0]["quantity"].update(left=-1), "less than the minimum"),
        (lambda d: d["seams"][0]["a"].update(copy="twice"), "is not one of"),
        (lambda d: d["measurements"][0].update(legs=[]), "should be non-empty"),
        (
            lambda d: d["pieces"][0]["placement"].update(body_part="tail"),
            "is not one of",
        ),
        (lambda d: d["rules"]["deltas"].update({"1": [[0.0]]}), "is too short"),
    ],
)
def test_schema_rejects_malformed_documents(validator, mutate, message):
    doc = json.loads(json.dumps(pattern_to_dict(example_pattern())))
    bad = copy.deepcopy(doc)
    mutate(bad)
    errors = _errors(validator, bad)
    assert errors, "the schema accepted a malformed document"
    options = (message,) if isinstance(message, str) else message
    assert any(m in e for e in errors for m in options), errors


coord = st.floats(min_value=-300, max_value=300, allow_nan=False, allow_infinity=False)


@st.composite
def patterns(draw) -> Pattern:
    n = draw(st.integers(3, 10))
    outline = draw(st.lists(st.tuples(coord, coord), min_size=n, max_size=n))
    kinds = draw(
        st.lists(st.sampled_from(["turn", "curve", "plain"]), min_size=n, max_size=n)
    )
    rules = [str(i) if k == "turn" else None for i, k in enumerate(kinds)]
    sizes = tuple(
        draw(
            st.lists(
                st.sampled_from(["XS", "S", "M", "L", "XL", "38", "40"]),
                min_size=1,
                max_size=4,
                unique=True,
            )
        )
    )
    piece = Piece(
        name=draw(st.text(min_size=1, max_size=12)),
        size=sizes[0],
        outline=outline,
        kinds=kinds,
        rules=rules,
        quantity=Quantity(right=draw(st.integers(0, 3)), left=draw(st.integers(0, 3))),
        notches=tuple(
            Notch(
                vertex=v,
                type=draw(st.sampled_from(["slit", "V", "T", "castle", "check", "U"])),
                source_angle_deg=draw(st.none() | st.floats(-360, 360)),
            )
            for v in draw(st.lists(st.integers(0, n - 1), max_size=3, unique=True))
        ),
        internal_lines=(
            Polyline(points=outline[:2], label=draw(st.none() | st.text(max_size=5))),
        ),
    )
    deltas = {
        r: draw(
            st.lists(st.tuples(coord, coord), min_size=len(sizes), max_size=len(sizes))
        )
        for r in rules
        if r is not None
    }
    return Pattern(
        style=draw(st.text(max_size=20)),
        pieces=(piece,),
        sample_size=sizes[0],
        sizes=sizes,
        rules=GradeRuleTable(sizes=sizes, sample_size=sizes[0], deltas=deltas),
        units=draw(st.sampled_from(["METRIC", "ENGLISH"])),
    )


@settings(max_examples=40, deadline=None)
@given(pattern=patterns())
def test_any_pattern_json_is_valid_and_round_trips(pattern):
    import jsonschema as js

    schema = json.loads(SCHEMA_PATH.read_text(encoding="utf-8"))
    doc = json.loads(json.dumps(pattern_to_dict(pattern)))
    assert [e.message for e in js.Draft202012Validator(schema).iter_errors(doc)] == []
    back = pattern_from_dict(doc)
    assert back == pattern
    np.testing.assert_array_equal(back.pieces[0].outline, pattern.pieces[0].outline)


@pytest.mark.shared
@pytest.mark.parametrize(
    "name", ["GLX4802S19_ASTM.DXF", "simple.DXF", "clo-pattern.dxf"]
)
def test_imported_real_files_are_valid(validator, name):
    from patternbridge.io.dxf_aama import read_dxf

    src = SHARED_AAMA / name
    if not src.is_file():
        pytest.skip("../shared/aama is not beside the checkout")
    pattern, _ = read_dxf(src)
    doc = json.loads(json.dumps(pattern_to_dict(pattern)))
    assert _errors(validator, doc) == []


def test_library_garments_are_valid(validator):
    try:
        from patternbridge.library import garment_names, load_garment
    except ImportError:
        pytest.skip("the garment library is not available")
    names = list(garment_names())
    if not names:
        pytest.skip("the garment library is empty")
    for name in names:
        doc = json.loads(json.dumps(pattern_to_dict(load_garment(name))))
        assert _errors(validator, doc) == [], name
