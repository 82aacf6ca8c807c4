"""The fabric read off a pattern: negative ease makes a knit, fabric words are hints, the sidecar keeps it."""

from __future__ import annotations

import dataclasses
import json

import pytest

from patternbridge.bridge import infer_bridge
from patternbridge.bridge.fabric import infer_fabric, pullover_neck_cm, word_fabric
from patternbridge.bridge.sidecar import inference_sidecar
from patternbridge.errors import InputError
from patternbridge.io.dxf_aama import read_dxf
from patternbridge.library.sidecar import apply_sidecar, sidecar_dict
from patternbridge.pattern.json import pattern_from_dict, pattern_to_dict
from patternbridge.pattern.model import FabricClass, MeasurementLink, Pattern, Piece
from patternbridge.testing import assert_patterns_equal

# file -> (garment fabric, pieces of another fabric): the leggings are drafted 15.6 % under the calf, the
# relaxed tank 3.8 % under the bust, the crew-neck top 2.8 % under the hips at its hem; the polo's collar and
# cuffs are written "1XRIB" on a body whose fabric the file does not say; the classic tee's crew neck (51.9 cm)
# does not go over a man's head (57 cm) unless it stretches
EXPECTED = {
    "MEN CLASSIC TEE.DXF": (FabricClass.KNIT, {}),
    "GLX4802S19_AAMA.DXF": (FabricClass.STRETCH_KNIT, {}),
    "WM LOOSE SHAPE TANK.DXF": (FabricClass.KNIT, {}),
    "GMH1004F15-2.DXF": (FabricClass.KNIT, {}),
    "GMX1016S18_AAMA.DXF": (FabricClass.WOVEN, {"GMX1016S18CO": FabricClass.KNIT, "GMX1016S18CU": FabricClass.KNIT}),
    "clo-pattern.dxf": (FabricClass.WOVEN, {}),
    "simple.DXF": (FabricClass.WOVEN, {}),
}


@pytest.fixture(scope="module", params=sorted(EXPECTED))
def inferred(request, aama_dir):
    pattern, _ = read_dxf(aama_dir / request.param)
    return request.param, pattern, inference_sidecar(pattern, infer_bridge(pattern))


@pytest.mark.shared
def test_the_fabric_of_the_real_files(inferred):
    name, _, sidecar = inferred
    fabric, pieces = EXPECTED[name]
    assert sidecar["fabric_class"] == fabric.value, sidecar["fabric_why"]
    assert {p["name"]: p["fabric_class"] for p in sidecar["pieces"] if "fabric_class" in p} == {
        k: v.value for k, v in pieces.items()
    }
    assert sidecar["fabric_why"]


@pytest.mark.shared
def test_the_inferred_fabric_applies_and_survives_the_json_round_trip(inferred, tmp_path):
    name, pattern, sidecar = inferred
    path = tmp_path / "g.seams.json"
    path.write_text(json.dumps(sidecar))
    applied = apply_sidecar(pattern, path)
    assert applied.fabric_class is EXPECTED[name][0]
    assert {p.name: p.fabric_class for p in applied.pieces if p.fabric_class} == EXPECTED[name][1]
    back = pattern_from_dict(json.loads(json.dumps(pattern_to_dict(applied))))
    assert (back.fabric_class, back.fabric_why) == (applied.fabric_class, applied.fabric_why)
    assert_patterns_equal(back, applied)
    # and through a sidecar written from the applied pattern
    again = tmp_path / "again.seams.json"
    again.write_text(json.dumps(sidecar_dict(applied)))
    plain = dataclasses.replace(applied, fabric_class=FabricClass.WOVEN, fabric_why="")
    assert apply_sidecar(plain, again).fabric_class is applied.fabric_class


@pytest.mark.shared
def test_an_old_sidecar_without_a_fabric_loads_woven_and_a_wrong_one_is_refused(aama_dir, tmp_path):
    pattern, _ = read_dxf(aama_dir / "GLX4802S19_AAMA.DXF")
    data = inference_sidecar(pattern, infer_bridge(pattern))
    old = {k: v for k, v in data.items() if not k.startswith("fabric")} | {"format_version": "1.1"}
    (tmp_path / "old.seams.json").write_text(json.dumps(old))
    assert apply_sidecar(pattern, tmp_path / "old.seams.json").fabric_class is FabricClass.WOVEN
    (tmp_path / "bad.seams.json").write_text(json.dumps({**data, "fabric_class": "felt"}))
    with pytest.raises(InputError, match="fabric_class 'felt'"):
        apply_sidecar(pattern, tmp_path / "bad.seams.json")


def _piece(name: str, **kw) -> Piece:
    return Piece(name=name, outline=[[0, 0], [10, 0], [10, 10], [0, 10]], **kw)


def _link(measurement: str, ease_cm: float) -> MeasurementLink:
    return MeasurementLink(measurement=measurement, legs=(), ease_cm=ease_cm)


def _roles(*names: str, role: str = "front") -> dict:
    from patternbridge.bridge.model import Role, RoleGuess

    return {n: RoleGuess(role=Role(role), confidence=1.0, why="") for n in names}


def test_negative_ease_makes_a_knit_and_more_than_a_knit_takes_a_stretch_knit():
    pattern = Pattern(style="s", pieces=(_piece("fr"),))
    body = {"chest_girth": 100.0, "calf_girth_right": 34.0}
    infer = lambda *links: infer_fabric(pattern, _roles("fr"), ("fr",), links, body)  # noqa: E731
    assert infer(_link("chest_girth", 4.0)).fabric is FabricClass.WOVEN
    # within the size chart's own uncertainty (half a size step): says nothing
    assert infer(_link("chest_girth", -2.0)).fabric is FabricClass.WOVEN
    assert infer(_link("chest_girth", -4.0)).fabric is FabricClass.KNIT
    leggings = infer(_link("chest_girth", 1.0), _link("calf_girth_right", -5.3))
    assert leggings.fabric is FabricClass.STRETCH_KNIT and "calf_girth_right" in leggings.why
    # a scoop neckline kept in proportion to the chest (its "ease" is its length against the chest) is no girth
    neckline = dataclasses.replace(_link("chest_girth", -30.0), id="neckline", proportional=True)
    assert infer(neckline).fabric is FabricClass.WOVEN
    # a girth drafted under the body follows it in proportion (as links.py writes it) and still counts
    calf = dataclasses.replace(_link("calf_girth_right", -5.3), id="calf_girth", proportional=True)
    assert infer(neckline, calf).fabric is FabricClass.STRETCH_KNIT


def test_fabric_words_are_hints_on_the_body_and_name_a_trims_own_fabric():
    pieces = (_piece("fr", annotation="1X JERSEY"), _piece("co", category="COLLAR", annotation="1XRIB"))
    pattern = Pattern(style="s", pieces=pieces)
    roles = {**_roles("fr"), **_roles("co", role="collar")}
    got = infer_fabric(pattern, roles, ("fr", "co"), (), {})
    assert got.fabric is FabricClass.KNIT and "JERSEY" in got.why and dict(got.pieces) == {}
    woven = Pattern(style="s", pieces=(_piece("fr", category="DENIM FRONT"), pieces[1]))
    got = infer_fabric(woven, roles, ("fr", "co"), (), {})
    assert got.fabric is FabricClass.WOVEN and dict(got.pieces) == {"co": FabricClass.KNIT}
    # negative ease overrides a woven word: the garment could not go on
    got = infer_fabric(woven, roles, ("fr", "co"), (_link("chest_girth", -8.0),), {"chest_girth": 100.0})
    assert got.fabric is FabricClass.KNIT
    assert word_fabric(_piece("x", annotation="1XFABRIC")) is None
    assert word_fabric(_piece("x", category="LEGGING", annotation="LYCRA")) == (FabricClass.STRETCH_KNIT, "LYCRA")


def test_a_pullover_neck_smaller_than_the_head_makes_a_knit():
    pattern = Pattern(style="s", pieces=(_piece("fr", category="POPLIN FRONT"),))
    body = {"head_girth": 57.0}
    infer = lambda neck: infer_fabric(pattern, _roles("fr"), ("fr",), (), body, neck_cm=neck)  # noqa: E731
    # 54 cm stretched the woven's 5 % is 56.7 cm, under the head: it must be a knit, whatever the words say
    assert infer(54.0).fabric is FabricClass.KNIT and "57 cm" in infer(54.0).why
    # 54.3 cm stretched 5 % reaches 57.0 cm: a woven goes over the head
    assert infer(54.3).fabric is FabricClass.WOVEN
    assert infer(None).fabric is FabricClass.WOVEN  # a garment that opens
    assert infer_fabric(pattern, _roles("fr"), ("fr",), (), {}, neck_cm=40.0).fabric is FabricClass.WOVEN


# file -> the neck opening of a pullover (cm, both halves of the fold counted) or None for one that opens:
# the tees' crew necks, the CLO shirt's centre fronts sewn to each other, the polo's placket
PULLOVER_NECKS = {
    "MEN CLASSIC TEE.DXF": 51.9,
    "GMH1004F15-2.DXF": 48.7,
    "clo-pattern.dxf": 57.3,
    "WM LOOSE SHAPE TANK.DXF": 61.1,
    "GMX1016S18_AAMA.DXF": None,
    "annotation.DXF": None,
    "GLX4802S19_AAMA.DXF": None,
}


@pytest.mark.shared
@pytest.mark.parametrize("name", sorted(PULLOVER_NECKS))
def test_the_neck_opening_of_the_real_pullovers(aama_dir, name):
    pattern, _ = read_dxf(aama_dir / name)
    got = pullover_neck_cm(pattern, infer_bridge(pattern))
    want = PULLOVER_NECKS[name]
    assert got is None if want is None else got == pytest.approx(want, abs=0.1)
