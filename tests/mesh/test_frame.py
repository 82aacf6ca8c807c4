"""The body's frame from its own geometry: units from the main component, facing, plausible stature."""

from __future__ import annotations

import json

import numpy as np
import pytest
import trimesh

from patternbridge.errors import UnitsError
from patternbridge.mesh.frame import FACING_TURNS, detect_facing
from patternbridge.mesh.load import load_character

pytestmark = pytest.mark.shared


@pytest.fixture(scope="module")
def e_mesh(characters_dir):
    m = trimesh.load(str(characters_dir / "E_average_male.obj"), process=False, maintain_order=True)
    return np.asarray(m.vertices), np.asarray(m.faces)


def test_stray_triangle_above_does_not_change_the_units(tmp_path, e_mesh):
    v, f = e_mesh
    stray = np.array([[0.0, 500.0, 0.0], [1.0, 500.0, 0.0], [0.0, 501.0, 0.0]])
    path = tmp_path / "e_stray.obj"
    trimesh.Trimesh(np.vstack([v, stray]), np.vstack([f, [[len(v), len(v) + 1, len(v) + 2]]]),
                    process=False).export(str(path))
    c, report = load_character(path)
    assert c.assumed["units"].startswith("cm")
    assert abs(c.stature_cm - 177.8) < 0.1
    assert "components" in report.codes()


def test_tiny_mesh_whose_sidecar_says_cm_is_refused(tmp_path, e_mesh):
    v, f = e_mesh
    path = tmp_path / "tiny.obj"
    trimesh.Trimesh(v * 1e-5, f, process=False).export(str(path))
    (tmp_path / "tiny.json").write_text(json.dumps({"units": "cm"}))
    with pytest.raises(UnitsError, match=r"tiny\.obj.*stature would be 0\.001778 cm") as exc:
        load_character(path)
    assert "\n" not in str(exc.value)


@pytest.mark.parametrize("direction", ["+Z", "-Z", "+X", "-X"])
def test_facing_of_a_turned_body(e_mesh, direction):
    v, _ = e_mesh
    turned = v @ FACING_TURNS[direction]  # inverse turn: the body now faces `direction`
    facing = detect_facing(turned)
    assert facing.direction == direction and facing.confidence > 0.5


def test_millimetre_body_facing_back_is_turned(shared_dir):
    c, report = load_character(shared_dir / "characters/variants/F_tall_thin_elder_mm_back.obj")
    assert c.assumed["units"].startswith("mm") and c.assumed["facing"].startswith("-Z")
    assert "facing-turned" in report.codes()
    ref = json.loads((shared_dir / "characters/variants/F_tall_thin_elder_mm_back.reference.json").read_text())
    # the file's left-side landmark (its -X) is on our +X side after the turn
    vid = ref["landmark_to_nearest_vertex"]["shoulder_point_left"]["vertex"]
    assert c.vertices[vid, 0] > 10.0
    assert abs(c.stature_cm - 181.21) < 0.1


def test_gltf_is_metres_without_a_warning(shared_dir):
    c, report = load_character(shared_dir / "characters/variants/B_slim_female_tpose.glb")
    assert c.assumed["units"] == "m (glTF)"
    assert not any(code.startswith("units") for code in report.codes())
