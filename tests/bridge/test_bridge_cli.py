"""``patternbridge bridge infer``, the inferred sidecar, and the pattern ``fit`` gets from a garment argument."""

from __future__ import annotations

import json
import shutil

import pytest

from patternbridge.bridge import infer_bridge
from patternbridge.bridge.fit_input import pattern_for_fit
from patternbridge.bridge.model import is_band
from patternbridge.bridge.sidecar import inference_sidecar
from patternbridge.cli.main import main
from patternbridge.io.dxf_aama import read_dxf
from patternbridge.library.catalogue import LIBRARY_DIR
from patternbridge.library.seams import check_seams
from patternbridge.library.sidecar import apply_sidecar
from patternbridge.pattern.json import pattern_from_dict, pattern_to_dict
from patternbridge.pattern.model import Role

TANK = "GLX0926S16.DXF"


@pytest.mark.shared
def test_bridge_infer_writes_a_sidecar_that_applies_and_a_picture(aama_dir, tmp_path, capsys):
    out, png = tmp_path / "tank.seams.json", tmp_path / "tank.png"
    assert main(["bridge", "infer", str(aama_dir / TANK), "-o", str(out), "--png", str(png)]) == 0
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    data = json.loads(out.read_text())
    assert data["format_version"] == "1.2"
    roles = {p["name"]: p["role"] for p in data["pieces"]}
    assert roles == {
        "GLX0926S16SBK": "back",
        "GLX0926S16SFR": "front",
        "GLX0926S16SBIN": "neck_binding",
        "GLX0926S16SBIA": "armhole_binding",
    }
    pattern, _ = read_dxf(aama_dir / TANK)
    applied = apply_sidecar(pattern, out)
    assert applied.piece("GLX0926S16SFR").role is Role.FRONT
    # the one-to-one seams sew in every one of the 14 sizes; a band's parts, marked in proportion to the
    # opening's ranges in the sample size, sew there (the file grades front and back armholes differently)
    results = check_seams(applied)
    assert results and len(results) == 14 * len(applied.seams)
    banded = {s.id for s in applied.seams if is_band(applied.piece(s.b.piece).role) and s.a.piece != s.b.piece}
    assert banded
    body = [r for r in results if r.seam not in banded]
    assert sum(r.ok for r in body) >= 0.95 * len(body)
    assert all(r.ok for r in results if r.seam in banded and r.size == pattern.sample_size)
    assert "GLX0926S16" in capsys.readouterr().out


@pytest.mark.shared
def test_unknown_piece_in_pieces_is_an_input_error(aama_dir, capsys):
    assert main(["bridge", "infer", str(aama_dir / TANK), "--pieces", "NOPE"]) == 2
    assert "no piece 'NOPE'" in capsys.readouterr().err


def test_old_sidecars_without_roles_still_load():
    dxf = LIBRARY_DIR / "tshirt" / "tshirt_aama.dxf"
    pattern, _ = read_dxf(dxf)
    applied = apply_sidecar(pattern, LIBRARY_DIR / "tshirt" / "tshirt.seams.json")
    assert all(p.role is None for p in applied.pieces)
    assert len(applied.seams) == 15


def test_role_round_trips_through_the_pattern_json():
    pattern, _ = read_dxf(LIBRARY_DIR / "tshirt" / "tshirt_aama.dxf")
    data = inference_sidecar(pattern, infer_bridge(pattern))
    assert {p["name"]: p["role"] for p in data["pieces"]}["sleeve"] == "sleeve"
    roled = pattern.pieces[2].__class__(name="x", outline=[[0, 0], [1, 0], [0, 1]], role="sleeve", role_confidence=0.9)
    back = pattern_from_dict(pattern_to_dict(type(pattern)(style="s", pieces=(roled,))))
    assert back.pieces[0].role is Role.SLEEVE and back.pieces[0].role_confidence == 0.9


def test_pattern_for_fit_uses_the_sidecar_beside_a_dxf_and_infers_without_one(tmp_path):
    beside = pattern_for_fit(LIBRARY_DIR / "tshirt" / "tshirt_aama.dxf", tmp_path / "out1")
    assert beside.sidecar is not None and beside.sidecar.name == "tshirt.seams.json"
    assert beside.pattern.measurements and beside.summary is None
    lone = tmp_path / "tee.dxf"
    shutil.copy(LIBRARY_DIR / "tshirt" / "tshirt_aama.dxf", lone)
    inferred = pattern_for_fit(lone, tmp_path / "out2")
    assert inferred.sidecar == tmp_path / "out2" / "tee.seams.json" and inferred.sidecar.is_file()
    assert inferred.picture is not None and inferred.picture.is_file()
    assert inferred.pattern.seams and "lowest confidence" in inferred.summary
    assert pattern_for_fit("tshirt", tmp_path / "out3").sidecar is None


def test_chest_link_read_off_the_pattern_matches_the_library_drafts(tmp_path):
    """The inferred chest girth of the T-shirt and the shirt equals the drafted chest + ease (104 and 108 cm)."""
    from patternbridge.bridge.links import REFERENCE_BODY_CM
    from patternbridge.library.seams import link_lengths

    for name, drafted in (("tshirt", 104.0), ("shirt", 108.0)):
        pattern, _ = read_dxf(LIBRARY_DIR / name / f"{name}_aama.dxf")
        path = tmp_path / f"{name}.seams.json"
        path.write_text(json.dumps(inference_sidecar(pattern, infer_bridge(pattern))))
        applied = apply_sidecar(pattern, path)
        chest = next(m for m in applied.measurements if m.measurement == "chest_girth")
        assert link_lengths(applied)["chest_girth"][0] == pytest.approx(drafted, abs=0.5)
        assert chest.ease_cm == pytest.approx(drafted - REFERENCE_BODY_CM["chest_girth"], abs=0.5)


@pytest.mark.shared
def test_fit_input_of_a_tee_is_one_garment_placed_on_both_body_sides(aama_dir, tmp_path):
    """The T-shirt's default garment only; its left-drawn halves meet the sleeve's mirror copy, on both sides."""
    fit = pattern_for_fit(aama_dir / "MEN CLASSIC TEE.DXF", tmp_path)
    data = json.loads(fit.sidecar.read_text())
    assert sorted(p.name for p in fit.pattern.pieces) == sorted(data["garment_pieces"])
    assert all(p.placement is not None for p in fit.pattern.pieces)
    roles = {p["name"]: p["role"] for p in data["pieces"]}
    to_sleeve = [
        s
        for s in data["seams"]
        if s["status"] != "band"
        and {roles[s["a"]["piece"]], roles[s["b"]["piece"]]} == {"front", "sleeve"}
        and s["a"]["piece"] in data["garment_pieces"]
        and s["b"]["piece"] in data["garment_pieces"]
    ]
    # the front is drawn as the left half, the sleeve as the right one: one seam per body side
    assert sorted((s["a"]["copy"], s["b"]["copy"]) for s in to_sleeve) == [("mirror", "primary"), ("primary", "mirror")]
    front = next(p for p in data["pieces"] if p["role"] == "front")
    assert "shoulder_point_left" in front["landmarks"]


@pytest.mark.shared
def test_upright_pattern_stands_a_sideways_accumark_tank_up(aama_dir, tmp_path):
    """The tank is drawn sideways; stood up for the drape, its neck is above its hem and its centre on x = 0."""
    from patternbridge.bridge.upright import upright_pattern

    fit = pattern_for_fit(aama_dir / "WM LOOSE SHAPE TANK.DXF", tmp_path)
    up = upright_pattern(fit.pattern, fit.sidecar)
    for piece in up.pieces:
        neck, hem = piece.outline[piece.marks["centre_neck"]], piece.outline[piece.marks["centre_hem"]]
        assert neck[1] - hem[1] > 50.0  # a body length up the +y axis
        assert abs(neck[0]) < 0.5 and abs(hem[0]) < 0.5
        assert abs(piece.grain_line.points[1] - piece.grain_line.points[0])[0] < 0.5  # grain along y
