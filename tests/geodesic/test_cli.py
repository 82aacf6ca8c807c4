"""``patternbridge geodesic`` on the shared characters."""

from __future__ import annotations

import json

import numpy as np
import pytest

from patternbridge.cli.main import main

pytestmark = pytest.mark.shared


def test_json_output_between_landmarks(characters_dir, capsys):
    obj = characters_dir / "E_average_male.obj"
    rc = main(
        [
            "geodesic",
            str(obj),
            "--from",
            "back_neck_point",
            "--to",
            "waist_back",
            "--json",
        ]
    )
    assert rc == 0
    out = json.loads(capsys.readouterr().out)
    assert set(out) >= {"length_cm", "points", "seconds"}
    pts = np.array(out["points"])
    assert pts.shape[1] == 3
    # nape to waist on the back midline: an exact edge-flip geodesic measures 43.328 cm
    assert out["surface_length_cm"] == pytest.approx(43.328, abs=0.01)
    assert out["length_cm"] <= out["surface_length_cm"] + 1e-9
    length = np.linalg.norm(np.diff(pts, axis=0), axis=1).sum()
    assert length == pytest.approx(out["length_cm"], rel=1e-6)


def test_text_output_with_vertex_ids(characters_dir, capsys):
    obj = characters_dir / "E_average_male.obj"
    assert (
        main(["geodesic", str(obj), "--from", "8276", "--to", "10025", "--no-tape"])
        == 0
    )
    line = capsys.readouterr().out.strip()
    assert line.startswith("8276 -> 10025: ")
    value = float(line.split(": ")[1].split(" cm")[0])
    assert value == pytest.approx(29.57, abs=0.02)  # shoulder point to elbow point


def test_unknown_landmark_and_bad_vertex_exit_2(characters_dir, capsys):
    obj = characters_dir / "E_average_male.obj"
    assert main(["geodesic", str(obj), "--from", "navel", "--to", "waist_back"]) == 2
    assert "no such landmark" in capsys.readouterr().err
    assert main(["geodesic", str(obj), "--from", "0", "--to", "99999999"]) == 2
    assert "out of range" in capsys.readouterr().err


@pytest.mark.slow
def test_landmarks_file_for_the_hires_mesh(characters_dir, tmp_path, capsys):
    """The hi-res PLY shares the landmark ids of E (its first 13380 vertices)."""
    side = json.loads((characters_dir / "E_average_male.json").read_text())
    lm = tmp_path / "lm.json"
    lm.write_text(json.dumps({"landmarks": side["landmarks"]}))
    ply = characters_dir / "E_average_male_hires.ply"
    rc = main(
        [
            "geodesic",
            str(ply),
            "--from",
            "neck_shoulder_point_left",
            "--to",
            "shoulder_point_left",
            "--landmarks",
            str(lm),
            "--json",
            "--no-tape",
        ]
    )
    assert rc == 0
    out = json.loads(capsys.readouterr().out)
    assert out["length_cm"] == pytest.approx(13.585, abs=0.01)
