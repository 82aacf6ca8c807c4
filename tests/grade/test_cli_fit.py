"""``patternbridge fit`` on a measurements JSON and a pattern JSON: outputs and bad input."""

from __future__ import annotations

import json
import os

import numpy as np
import pytest
from grade_fixtures import skirt_pattern, write_skirt_inputs

from patternbridge.cli.main import main
from patternbridge.io.dxf_aama import read_dxf
from patternbridge.io.dxf_aama.sizes import is_cad_size
from patternbridge.io.pattern_json import load_pattern_json, save_pattern_json


@pytest.fixture
def inputs(tmp_path):
    return write_skirt_inputs(tmp_path)


def test_fit_writes_every_output(inputs, tmp_path, capsys):
    pattern_path, body_path = inputs
    out = tmp_path / "out"
    code = main(["fit", str(body_path), "--garment", str(pattern_path), "-o", str(out),
                 "--seed", "1", "--pop-size", "20", "--generations", "10"])
    assert code == 0
    names = {p.name for p in out.iterdir()}
    assert {"measurements.json", "fit_report.json", "pattern.png", "pareto.png",
            "skirt_aama.dxf", "skirt_aama.rul", "skirt_astm.dxf", "skirt_astm.rul", "skirt_hero.json"} <= names
    assert not [n for n in names if n.startswith(".")]  # no temporary leftovers
    rep = json.loads((out / "fit_report.json").read_text())
    assert rep["mean_error_cm"] <= 0.5 and rep["max_seam_mm"] <= 1.0
    assert "baseline" in rep and "seconds" in rep and "shape_error" in rep
    graded = load_pattern_json(out / "skirt_hero.json")
    assert graded.sample_size == "hero" and [p.name for p in graded.pieces] == ["front", "back"]
    # the RUL carries the original size plus the character, in size names CAD takes (a character among
    # numeric sizes gets a numeric code, named by a layer-15 note in the DXF); the import gives it back
    rul = (out / "skirt_aama.rul").read_text(errors="replace")
    size_list = next(line for line in rul.splitlines() if line.startswith("SIZE LIST:")).split(":")[1].split()
    assert len(size_list) == 2 and all(is_cad_size(s) for s in size_list)
    assert read_dxf(out / "skirt_aama.dxf")[0].sizes[-1] == "hero"
    err = capsys.readouterr()
    assert "[grade]" in err.err and "wrote" in err.out
    # files get the mode a plain open() gives under the umask (not mkstemp's 0600)
    umask = os.umask(0)
    os.umask(umask)
    for f in out.iterdir():
        assert f.stat().st_mode & 0o777 == 0o666 & ~umask, f.name
    # the final step keeps the skirt's straight hem straight
    for piece in graded.pieces:
        assert np.ptp(piece.outline[[0, 1, 2], 1]) < 0.01


def test_fit_pattern_without_links_exits_2(inputs, tmp_path, capsys):
    _, body_path = inputs
    bare = tmp_path / "bare.json"
    save_pattern_json(skirt_pattern(links=False), bare)
    code = main(["fit", str(body_path), "--garment", str(bare), "-o", str(tmp_path / "o")])
    assert code == 2
    assert "seams infer" in capsys.readouterr().err
    assert not (tmp_path / "o").exists()


def test_fit_lists_missing_measurements(inputs, tmp_path, capsys):
    pattern_path, _ = inputs
    body = tmp_path / "thin.json"
    body.write_text(json.dumps({"waist_girth": 70.0}))
    code = main(["fit", str(body), "--garment", str(pattern_path), "-o", str(tmp_path / "o")])
    assert code == 2
    err = capsys.readouterr().err
    assert "hip_girth" in err and "waist_to_knee" in err


def test_fit_missing_character_file(inputs, tmp_path, capsys):
    pattern_path, _ = inputs
    code = main(["fit", str(tmp_path / "nobody.obj"), "--garment", str(pattern_path), "-o", str(tmp_path / "o")])
    assert code == 2
    assert "no such character file" in capsys.readouterr().err


def test_fit_deformation_option_reaches_the_grader(inputs, tmp_path):
    pattern_path, body_path = inputs
    out = tmp_path / "cubic"
    code = main(["fit", str(body_path), "--garment", str(pattern_path), "-o", str(out), "-q",
                 "--pop-size", "20", "--generations", "10", "--deformation", "cubic"])
    assert code == 0
    rep = json.loads((out / "fit_report.json").read_text())
    assert rep["settings"]["deformation"] == "cubic"
    assert rep["mean_error_cm"] <= 0.5 and rep["max_seam_mm"] <= 1.0


@pytest.mark.shared
def test_fit_on_a_bare_mesh_dresses_with_the_landmarks_it_found_and_a_failure_leaves_nothing(
    characters_dir, tmp_path, monkeypatch, capsys
):
    # an OBJ without its sidecar: no rig, no landmarks of its own; measuring
    # detects them, and the assembler must get them (it used to stop with
    # "cannot segment the body without a rig ... missing")
    import shutil

    import patternbridge.assemble as assemble
    from patternbridge.errors import InputError

    mesh = tmp_path / "bare.obj"
    shutil.copy(characters_dir / "E_average_male.obj", mesh)
    seen = {}

    def stop(character, *args, **kwargs):
        seen["landmarks"] = set(character.landmarks)
        seen["rigged"] = character.skeleton is not None
        raise InputError("stopped in the assembler")

    monkeypatch.setattr(assemble, "dress", stop)
    out = tmp_path / "out"
    code = main(["fit", str(mesh), "--garment", "shirt", "-o", str(out), "-q",
                 "--pop-size", "8", "--generations", "2"])
    assert code == 2
    assert "stopped in the assembler" in capsys.readouterr().err
    assert not seen["rigged"]
    assert {"crotch_point", "armpit_point_left", "armpit_point_right", "front_neck_point",
            "back_neck_point", "wrist_point_left"} <= seen["landmarks"]
    # nothing half-written: the output folder the run made is gone
    assert not out.exists()
    # a folder that was there before stays, empty as it was
    out.mkdir()
    assert main(["fit", str(mesh), "--garment", "shirt", "-o", str(out), "-q",
                 "--pop-size", "8", "--generations", "2"]) == 2
    assert out.is_dir() and not any(out.iterdir())


def test_the_drape_warnings_name_the_seams_welded_and_the_pieces_through_the_skin():
    from patternbridge.cli.fit import drape_warnings

    clean = {"penetrating_vertices": 0, "crossing_triangles": 0, "seams_open_before_weld": []}
    assert drape_warnings(clean) == []
    lines = drape_warnings(
        {
            "penetrating_vertices": 0,
            "crossing_triangles": 2,
            "crossing_pieces": ["cuff~mirror"],
            "seams_open_before_weld": [{"seam": "cuff_closure_left", "max_mm": 10.6}],
        }
    )
    assert len(lines) == 2
    assert "cuff_closure_left 11 mm" in lines[0]
    assert "2 triangle(s) crossing on cuff~mirror" in lines[1]
    folded = drape_warnings({**clean, "self_crossing_pieces": {"back": 4, "sleeve": 30, "cuff": 2, "collar": 1}})
    assert folded == [
        "[fit] the garment passes through itself in 37 triangle(s), most on sleeve 30, back 4, cuff 2 "
        "(folds pushed through the cloth beside them); look there before simulating it further"
    ]


def test_fit_choose_takes_the_front_row_asked_for(inputs, tmp_path, capsys):
    pattern_path, body_path = inputs
    out = tmp_path / "out"
    args = ["fit", str(body_path), "--garment", str(pattern_path), "--seed", "1", "--pop-size", "16",
            "--generations", "6", "--no-drape"]
    assert main([*args, "--choose", "0", "-o", str(out)]) == 0
    rep = json.loads((out / "fit_report.json").read_text())
    assert rep["pareto_front"]["chosen_index"] == 0
    assert rep["note"].endswith("started from front member 0 (chosen by the user)")
    # a row the front does not have is bad input: exit 2, one line naming the rows there are
    assert main([*args, "--choose", "9999", "-o", str(tmp_path / "bad")]) == 2
    assert "the Pareto front has rows 0 to" in capsys.readouterr().err
