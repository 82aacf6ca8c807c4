"""The measure command on bodies whose frame, units or landmarks had to be found: one line each."""

from __future__ import annotations

import json
import shutil

import numpy as np
import pytest
import trimesh

from patternbridge.cli.main import main

pytestmark = pytest.mark.shared


def test_implausible_sidecar_units_exit_2_one_line(characters_dir, tmp_path, capsys):
    m = trimesh.load(str(characters_dir / "E_average_male.obj"), process=False, maintain_order=True)
    path = tmp_path / "tiny.obj"
    trimesh.Trimesh(np.asarray(m.vertices) * 1e-5, m.faces, process=False).export(str(path))
    (tmp_path / "tiny.json").write_text(json.dumps({"units": "cm"}))
    out = tmp_path / "m.json"
    assert main(["measure", str(path), "-o", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "tiny.obj" in err[0] and "stature would be" in err[0]
    assert not out.exists()


def test_t_pose_obj_alone_warns_of_its_coarse_landmarks(characters_dir, tmp_path, capsys):
    path = tmp_path / "C_heavy_male_tpose_remesh.obj"
    shutil.copy(characters_dir / "variants" / path.name, path)
    out = tmp_path / "m.json"
    png = tmp_path / "m.png"
    assert main(["measure", str(path), "-o", str(out), "--png", str(png)]) == 0
    err = capsys.readouterr().err
    assert "units assumed m" in err
    assert "landmark shoulder_point_left (detected, confidence 0.45)" in err
    data = json.loads(out.read_text())
    assert data["landmarks"]["shoulder_point_left"]["confidence"] == pytest.approx(0.45)
    assert data["landmarks"]["shoulder_point_left"]["evidence"]["rule"].startswith("level arm")
    assert png.stat().st_size > 0
