"""Loading characters: formats, units and up-axis detection, components, checks, landmarks."""

from __future__ import annotations

import json

import numpy as np
import pytest
import trimesh

from patternbridge.errors import InputError, LandmarkError, MeshError, UnitsError
from patternbridge.mesh.landmarks import LANDMARK_NAMES
from patternbridge.mesh.load import load_character, mesh_defects

pytestmark = pytest.mark.shared


@pytest.fixture(scope="module")
def b_obj(characters_dir):
    return characters_dir / "B_slim_female.obj"


@pytest.fixture(scope="module")
def b_mesh(b_obj):
    m = trimesh.load(str(b_obj), process=False, maintain_order=True)
    return np.asarray(m.vertices), np.asarray(m.faces)


def test_shared_obj_with_sidecar(b_obj, b_mesh):
    c, report = load_character(b_obj)
    assert c.vertices.shape == (13380, 3) and c.faces.shape == (26756, 3)
    np.testing.assert_allclose(c.vertices, b_mesh[0])  # ids and positions kept
    assert set(c.landmarks) == set(LANDMARK_NAMES)
    assert all(lm.source == "file" for lm in c.landmarks.values())
    assert c.landmarks["top_of_head"].vertex == 881
    assert len(c.skeleton.names) == 163 and c.skin.weights.shape == (13380, 4)
    np.testing.assert_allclose(c.skin.weights.sum(axis=1), 1.0, atol=1e-6)
    assert c.assumed["units"].startswith("cm") and c.assumed["up"].startswith("+Y")
    assert "0 of 1" in c.assumed["component"]
    assert abs(c.stature_cm - 166.0) < 0.05
    assert not report  # a clean, closed, single-component mesh


@pytest.mark.parametrize("suffix", [".stl", ".glb", ".ply", ".obj"])
def test_units_and_up_axis_detected(tmp_path, b_mesh, suffix):
    v, f = b_mesh
    z_up_m = (
        np.column_stack([v[:, 0], -v[:, 2], v[:, 1]]) / 100.0
    )  # Blender frame, metres
    path = tmp_path / f"b{suffix}"
    trimesh.Trimesh(z_up_m, f, process=False).export(str(path))
    c, report = load_character(path)
    assert c.assumed["up"].startswith("+Z") and c.assumed["units"].startswith("m ")
    # a glTF is in metres by definition: nothing assumed, nothing to warn about
    assert ("units-assumed" in report.codes()) == (suffix != ".glb")
    assert c.vertices.shape == (13380, 3)
    np.testing.assert_allclose(
        np.sort(c.vertices, axis=0), np.sort(v, axis=0), atol=1e-4
    )


def test_overrides(tmp_path, b_mesh):
    v, f = b_mesh
    path = tmp_path / "b.ply"
    trimesh.Trimesh(v * 10.0, f, process=False).export(str(path))  # millimetres
    c, _ = load_character(path, units="mm", up="Y")
    assert abs(c.stature_cm - 166.0) < 0.05
    assert c.assumed["units"] == "mm (given)" and c.assumed["up"] == "+Y (given)"
    with pytest.raises(UnitsError, match="stature would be"):
        load_character(path, units="m")
    with pytest.raises(InputError, match="unknown up axis"):
        load_character(path, up="W")
    with pytest.raises(UnitsError, match="unknown length unit") as bad_unit:
        load_character(path, units="furlong")
    assert str(bad_unit.value).startswith(f"{path}: --units: ")  # names the file and the option


def test_implausible_size_is_a_units_error(tmp_path, b_mesh):
    v, f = b_mesh
    path = tmp_path / "huge.ply"
    trimesh.Trimesh(v * 1e4, f, process=False).export(str(path))
    with pytest.raises(UnitsError, match="no unit gives a stature"):
        load_character(path)


def test_extra_components_are_dropped_and_reported(tmp_path, b_mesh):
    v, f = b_mesh
    eye = trimesh.creation.icosphere(subdivisions=2, radius=1.2)
    verts = np.vstack([v, eye.vertices + [3.0, 155.0, 9.0]])
    faces = np.vstack([f, eye.faces + len(v)])
    path = tmp_path / "with_eye.ply"
    trimesh.Trimesh(verts, faces, process=False).export(str(path))
    c, report = load_character(path)
    assert "components" in report.codes()
    assert c.vertices.shape == (13380, 3)
    np.testing.assert_allclose(c.vertices, v)  # the body keeps its vertex ids
    assert "of 2" in c.assumed["component"]


def test_holes_and_nonmanifold_edges(tmp_path, b_mesh):
    v, f = b_mesh
    path = tmp_path / "holes.ply"
    trimesh.Trimesh(v, f[10:], process=False).export(str(path))
    _, report = load_character(path)
    assert "mesh-holes" in report.codes()
    # a few faces glued onto existing edges: non-manifold, still measurable
    extra = np.column_stack([f[:20, 0], f[:20, 1], np.full(20, 5000)])
    path = tmp_path / "nm.ply"
    trimesh.Trimesh(v, np.vstack([f, extra]), process=False).export(str(path))
    _, report = load_character(path)
    assert "mesh-nonmanifold" in report.codes()
    # every face doubled with a third vertex: unusable
    junk = np.column_stack([f[:, 0], f[:, 1], (f[:, 2] + 7) % len(v)])
    path = tmp_path / "junk.ply"
    trimesh.Trimesh(v, np.vstack([f, junk, junk[:, [1, 0, 2]]]), process=False).export(
        str(path)
    )
    with pytest.raises(MeshError, match="non-manifold"):
        load_character(path)


def test_mesh_defects_counts():
    tet = np.array([[0, 1, 2], [0, 3, 1], [1, 3, 2], [2, 3, 0]])
    assert mesh_defects(tet) == {
        "boundary_edges": 0,
        "nonmanifold_edges": 0,
        "degenerate_faces": 0,
    }
    assert mesh_defects(tet[:3])["boundary_edges"] == 3
    assert mesh_defects(np.vstack([tet, [[0, 1, 4]]]))["nonmanifold_edges"] == 1


def test_bad_files(tmp_path):
    with pytest.raises(MeshError, match="no such file"):
        load_character(tmp_path / "missing.obj")
    (tmp_path / "x.fbx").write_text("x")
    with pytest.raises(MeshError, match="unsupported mesh format"):
        load_character(tmp_path / "x.fbx")
    (tmp_path / "empty.obj").write_text("# nothing\n")
    with pytest.raises(MeshError):
        load_character(tmp_path / "empty.obj")
    (tmp_path / "bad.glb").write_bytes(b"nope" * 10)
    with pytest.raises(MeshError, match="not a GLB"):
        load_character(tmp_path / "bad.glb")


def test_landmark_file(tmp_path, b_obj, b_mesh):
    v, _ = b_mesh
    target = v[881] + np.array([0.0, 2.0, 0.0])  # 2 cm above the head: snaps back down
    lm = tmp_path / "lm.json"
    lm.write_text(
        json.dumps(
            {
                "landmarks": {
                    "crotch_point": {"vertex": 6431},
                    "top_of_head": {"position": target.tolist()},
                }
            }
        )
    )
    c, _ = load_character(b_obj, landmarks=lm)
    assert c.landmarks["crotch_point"].vertex == 6431
    assert np.linalg.norm(c.landmarks["top_of_head"].position - v[881]) < 0.5
    assert c.landmarks["top_of_head"].position[1] < target[1] - 1.5


@pytest.mark.parametrize(
    ("content", "message"),
    [
        ({"landmarks": {"nose_tip": {"vertex": 1}}}, "unknown landmark 'nose_tip'"),
        ({"landmarks": {"crotch_point": {"vertex": 99999}}}, "out of range"),
        (
            {"landmarks": {"crotch_point": {"foo": 1}}},
            "neither 'vertex' nor 'position'",
        ),
        ({"landmarks": {"crotch_point": {"position": [1, 2]}}}, "not three numbers"),
        ({"points": {}}, "no 'landmarks' object"),
    ],
)
def test_bad_landmark_files(tmp_path, b_obj, content, message):
    lm = tmp_path / "lm.json"
    lm.write_text(json.dumps(content))
    with pytest.raises(LandmarkError, match=message) as info:
        load_character(b_obj, landmarks=lm)
    assert "\n" not in str(info.value)


def test_landmark_file_not_json(tmp_path, b_obj):
    lm = tmp_path / "lm.json"
    lm.write_text("{oops")
    with pytest.raises(LandmarkError, match="not valid JSON"):
        load_character(b_obj, landmarks=lm)
    with pytest.raises(LandmarkError, match="no such landmark file"):
        load_character(b_obj, landmarks=tmp_path / "none.json")


def test_vertex_id_landmarks_on_an_stl_are_refused(tmp_path, b_mesh):
    # STL welds repeated triangle corners: ids of the source mesh mean nothing there
    v, f = b_mesh
    stl = tmp_path / "b.stl"
    trimesh.Trimesh(v, f, process=False).export(str(stl))
    lm = tmp_path / "lm.json"
    lm.write_text(json.dumps({"landmarks": {"crotch_point": {"vertex": 6431}}}))
    with pytest.raises(LandmarkError, match=r"lm\.json: .*no vertex ids.*position"):
        load_character(stl, landmarks=lm)
    lm.write_text(
        json.dumps({"landmarks": {"crotch_point": {"position": v[6431].tolist()}}})
    )
    c, _ = load_character(stl, landmarks=lm)
    np.testing.assert_allclose(c.landmarks["crotch_point"].position, v[6431], atol=1e-6)


def test_measurements_beside_the_mesh_are_not_its_sidecar(tmp_path, b_obj):
    """`measure B.obj -o B.json` writes beside the mesh; the next load must not take that file for the sidecar."""
    from patternbridge.measure import measure
    from patternbridge.measure.model import write_measurements

    mesh = tmp_path / "B.obj"
    mesh.write_bytes(b_obj.read_bytes())
    bare, _ = load_character(mesh)
    write_measurements(tmp_path / "B.json", measure(bare, tape=False))
    again, report = load_character(mesh)
    assert "sidecar-ignored" in report.codes()
    assert not any(lm.source == "file" for lm in again.landmarks.values())
    assert not again.assumed["units"].endswith("(sidecar)")
