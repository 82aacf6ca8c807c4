"""Bridge-data sidecars: round trip, re-matching by position, and every InputError path."""

from __future__ import annotations

import json
from dataclasses import replace

import numpy as np
import pytest

from patternbridge.errors import InputError
from patternbridge.library import load_garment
from patternbridge.library.sidecar import (
    apply_sidecar,
    read_sidecar,
    sidecar_dict,
    write_sidecar,
)
from patternbridge.testing import assert_patterns_equal


def _bare(pattern):
    """The pattern as a DXF without bridge data would give it."""
    pieces = tuple(
        replace(p, marks={}, landmarks={}, placement=None) for p in pattern.pieces
    )
    return replace(pattern, pieces=pieces, seams=(), measurements=(), description="")


def test_round_trip_restores_all_bridge_data(tmp_path):
    shirt = load_garment("shirt")
    path = write_sidecar(shirt, tmp_path / "shirt.seams.json")
    back = apply_sidecar(_bare(shirt), path)
    assert_patterns_equal(shirt, back)


def test_marks_are_rematched_by_position_when_the_outline_is_rotated(tmp_path):
    trousers = load_garment("trousers")
    path = write_sidecar(trousers, tmp_path / "t.seams.json")
    bare = _bare(trousers)
    front = bare.piece("front")
    shift = 5
    rotated = replace(front, outline=np.roll(front.outline, -shift, axis=0))
    bare = replace(
        bare, pieces=tuple(rotated if p.name == "front" else p for p in bare.pieces)
    )
    back = apply_sidecar(bare, path)
    n = front.n_vertices
    for name, i in trousers.piece("front").marks.items():
        assert back.piece("front").marks[name] == (i - shift) % n


def test_confirmed_only_drops_proposals(tmp_path):
    skirt = load_garment("skirt")
    proposal = {
        "id": "guess",
        "status": "proposed",
        "confidence": 0.5,
        "a": {"piece": "front", "start": "cf_hem", "end": "side_hem_left"},
        "b": {"piece": "back", "start": "cb_hem", "end": "side_hem"},
    }
    path = write_sidecar(skirt, tmp_path / "s.json", proposals=[proposal])
    assert len(apply_sidecar(skirt, path).seams) == len(skirt.seams) + 1
    assert len(apply_sidecar(skirt, path, confirmed_only=True).seams) == len(
        skirt.seams
    )


def _write(tmp_path, data) -> str:
    p = tmp_path / "bad.seams.json"
    p.write_text(data if isinstance(data, str) else json.dumps(data))
    return str(p)


@pytest.mark.parametrize(
    "mutate, message",
    [
        (lambda d: "{not json", "not valid JSON"),
        (lambda d: {**d, "format": "something.else"}, "not a bridge-data sidecar"),
        (lambda d: [1, 2], "not a bridge-data sidecar"),
        (
            lambda d: {**d, "pieces": d["pieces"] + [{"name": "cape", "marks": {}}]},
            "piece 'cape'",
        ),
        (
            lambda d: {
                **d,
                "seams": [
                    {**d["seams"][0], "a": {**d["seams"][0]["a"], "start": "nowhere"}}
                ],
            },
            "mark 'nowhere'",
        ),
        (
            lambda d: {
                **d,
                "seams": [
                    {**d["seams"][0], "b": {**d["seams"][0]["b"], "piece": "cape"}}
                ],
            },
            "piece 'cape'",
        ),
        (lambda d: {**d, "seams": [{"id": "x"}]}, "malformed sidecar"),
        (
            lambda d: {
                **d,
                "measurements": [
                    {
                        **d["measurements"][0],
                        "legs": [
                            {"piece": "front", "start": "cf_waist", "end": "moon"}
                        ],
                    }
                ],
            },
            "measurement",
        ),
    ],
)
def test_bad_sidecars_raise_one_line_input_errors(tmp_path, mutate, message):
    trousers = load_garment("trousers")
    data = mutate(sidecar_dict(trousers))
    with pytest.raises(InputError, match=message) as info:
        apply_sidecar(trousers, _write(tmp_path, data))
    assert "\n" not in str(info.value)


def test_a_mark_off_the_outline_is_an_error(tmp_path):
    trousers = load_garment("trousers")
    data = sidecar_dict(trousers)
    data["pieces"][0]["marks"]["cf_waist"]["xy"] = [500.0, 500.0]
    with pytest.raises(InputError, match="from the nearest outline vertex"):
        apply_sidecar(trousers, _write(tmp_path, data))
    data["pieces"][0]["marks"]["cf_waist"] = {"vertex": 9999}
    with pytest.raises(InputError, match="vertex 9999"):
        apply_sidecar(trousers, _write(tmp_path, data))


def test_missing_sidecar_file(tmp_path):
    with pytest.raises(InputError, match="no such sidecar"):
        read_sidecar(tmp_path / "absent.json")
