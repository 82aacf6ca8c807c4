"""OBJ export, and the same texture on the cloth whether the OBJ or the GLB is opened."""

from __future__ import annotations

import json
import struct

import numpy as np
import pytest
import trimesh
from scipy.spatial import cKDTree

from patternbridge.assemble import Garment
from patternbridge.assemble.export_gltf import glb_bytes, write_glb
from patternbridge.assemble.export_obj import obj_text, write_obj
from patternbridge.mesh.character import Skeleton


def _garment() -> Garment:
    # two squares in the z = 0 plane, counter-clockwise seen from +z, sewn along x = 10
    a = np.array([[0.0, 0, 0], [10, 0, 0], [10, 10, 0], [0, 10, 0]])
    v = np.concatenate([a, a + [10.0, 0, 0]])
    skel = Skeleton(names=("root",), parents=[-1], heads=[[0, 0, 0]], tails=[[0, 10, 0]])
    return Garment(
        vertices=v,
        faces=np.array([[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7]]),
        uv=np.concatenate([a[:, :2], a[:, :2] + [3.0, 0]]),
        instance=np.array([0, 0, 0, 0, 1, 1, 1, 1]),
        instance_names=("front", "back yoke"),
        weld=np.array([0, 1, 2, 3, 1, 5, 6, 2]),
        joints=np.tile([0, -1, -1, -1], (8, 1)),
        weights=np.tile([1.0, 0, 0, 0], (8, 1)),
        skeleton=skel,
    )


def _records(obj: str, key: str) -> np.ndarray:
    return np.array([ln.split()[1:] for ln in obj.splitlines() if ln.startswith(key + " ")], dtype=np.float64)


def test_obj_welds_sewn_vertices_and_carries_normals_and_uvs(tmp_path):
    g = _garment()
    obj, mtl = obj_text(g)
    v, vn, vt = _records(obj, "v"), _records(obj, "vn"), _records(obj, "vt")
    faces = [ln.split()[1:] for ln in obj.splitlines() if ln.startswith("f ")]
    assert len(v) == 6  # 8 vertices, 2 sewn pairs
    assert len(vn) == 6 and len(vt) == 8 and len(faces) == 4
    np.testing.assert_allclose(vn, [[0.0, 0.0, 1.0]] * 6)  # the side the faces turn counter-clockwise to
    np.testing.assert_allclose(vt * 100.0, g.uv, atol=1e-6)  # OBJ: origin bottom-left, v up
    for face in faces:
        for corner in face:
            iv, it, inorm = (int(x) for x in corner.split("/"))
            assert iv == inorm and 1 <= iv <= 6 and 1 <= it <= 8
    assert "g back_yoke" in obj and "newmtl back_yoke" in mtl and "newmtl front" in mtl
    write_obj(tmp_path / "garment.obj", g)
    assert (tmp_path / "garment.mtl").read_text() == mtl
    assert (tmp_path / "garment.obj").read_text() == obj


def _texture(size: int = 64) -> np.ndarray:
    """(size, size, 3) smooth periodic picture, row 0 at the top, unlike any of its mirror images."""
    r, c = np.mgrid[0:size, 0:size] + 0.5
    x, y = c / size, r / size
    return np.stack([np.cos(2 * np.pi * x), np.sin(2 * np.pi * y), np.sin(2 * np.pi * (x + 2 * y))], axis=-1)


def _sample(img: np.ndarray, across: np.ndarray, down: np.ndarray) -> np.ndarray:
    """Bilinear lookup with repeat wrapping; ``across``/``down`` are fractions of the image from its top-left."""
    h, w = img.shape[:2]
    x, y = across * w - 0.5, down * h - 0.5
    x0, y0 = np.floor(x).astype(np.int64), np.floor(y).astype(np.int64)
    fx, fy = (x - x0)[:, None], (y - y0)[:, None]
    c0, c1, r0, r1 = x0 % w, (x0 + 1) % w, y0 % h, (y0 + 1) % h
    top = img[r0, c0] * (1 - fx) + img[r0, c1] * fx
    bottom = img[r1, c0] * (1 - fx) + img[r1, c1] * fx
    return top * (1 - fy) + bottom * fy


def _glb_texcoords(data: bytes) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Material name -> (positions in cm, TEXCOORD_0 as stored), read from the GLB by the glTF rules."""
    jlen = struct.unpack_from("<I", data, 12)[0]
    doc = json.loads(data[20 : 20 + jlen])
    binary = data[20 + jlen + 8 :]

    def read(i: int, n: int) -> np.ndarray:
        acc = doc["accessors"][i]
        assert acc["componentType"] == 5126  # float
        view = doc["bufferViews"][acc["bufferView"]]
        return np.frombuffer(binary, np.float32, acc["count"] * n, view["byteOffset"]).reshape(-1, n)

    out = {}
    for prim in doc["meshes"][0]["primitives"]:
        name = doc["materials"][prim["material"]]["name"]
        out[name] = (read(prim["attributes"]["POSITION"], 3) * 100.0, read(prim["attributes"]["TEXCOORD_0"], 2))
    return out


def _agrees(near: list[list[int]], here: np.ndarray, there: np.ndarray) -> list[bool]:
    """Whether some vertex in ``near[i]`` shows (``there``) the colour vertex ``i`` shows ``here``."""
    return [np.abs(there[k] - c).max(axis=1).min() < 1e-4 for k, c in zip(near, here, strict=True)]


@pytest.mark.shared
def test_obj_and_glb_show_the_texture_the_same_way_up(draped_tshirt, tmp_path):
    write_obj(tmp_path / "garment.obj", draped_tshirt)
    write_glb(tmp_path / "garment.glb", draped_tshirt)
    img = _texture()
    obj = trimesh.load(tmp_path / "garment.obj", process=False)  # an independent OBJ reader
    glb_raw = _glb_texcoords((tmp_path / "garment.glb").read_bytes())
    # an importer as Blender's: trimesh turns glTF texture coordinates into its own bottom-left convention
    glb_imported = trimesh.load(tmp_path / "garment.glb", process=False)
    imported = {m.visual.material.name: m for m in glb_imported.geometry.values()}
    assert set(glb_raw) == set(imported) == {m.visual.material.name for m in obj.geometry.values()}
    n_matched = 0
    for mesh in obj.geometry.values():
        name = mesh.visual.material.name
        uv = mesh.visual.uv
        seen_in_obj = _sample(img, uv[:, 0], 1.0 - uv[:, 1])  # OBJ: origin bottom-left, v up
        pos, st = glb_raw[name]
        seen_in_glb = _sample(img, st[:, 0], st[:, 1])  # glTF: origin top-left, t down
        seen_if_unflipped = _sample(img, st[:, 0], 1.0 - st[:, 1])
        im = imported[name]
        seen_after_import = _sample(img, im.visual.uv[:, 0], 1.0 - im.visual.uv[:, 1])
        np.testing.assert_allclose(im.vertices * 100.0, pos, atol=1e-5)
        # a vertex of the OBJ and one of the GLB at the same place of the same piece (a piece sewn to
        # itself, as a sleeve, has two at one place): one of them must show the same colour
        near = cKDTree(pos).query_ball_point(mesh.vertices, r=1e-3)
        same = _agrees(near, seen_in_obj, seen_in_glb)
        assert all(same), f"{name}: {len(same) - sum(same)} of {len(same)} vertices show another texel"
        flipped = _agrees(near, seen_in_obj, seen_if_unflipped)
        assert sum(flipped) < len(flipped) / 2  # the picture tells its way up
        np.testing.assert_allclose(seen_after_import, seen_in_glb, atol=1e-5)
        n_matched += len(mesh.vertices)
    assert n_matched == sum(len(p) for p, _ in glb_raw.values()) == len(draped_tshirt.vertices)


def _uv_winding(uv: np.ndarray, faces: np.ndarray) -> np.ndarray:
    a, b, c = uv[faces[:, 0]], uv[faces[:, 1]], uv[faces[:, 2]]
    return np.sign((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]))


@pytest.mark.shared
def test_a_print_reads_the_right_way_on_every_piece(draped_tshirt, tmp_path):
    # faces turn counter-clockwise seen from outside; seen from outside, the picture must too, or it reads
    # backwards (the mirrored sleeve has the same pattern coordinates as the other one, turned over)
    assert (_uv_winding(draped_tshirt.uv, draped_tshirt.faces) < 0).any()
    write_obj(tmp_path / "garment.obj", draped_tshirt)
    write_glb(tmp_path / "garment.glb", draped_tshirt)
    for path in ("garment.obj", "garment.glb"):
        for mesh in trimesh.load(tmp_path / path, process=False).geometry.values():
            winding = _uv_winding(mesh.visual.uv, mesh.faces)  # trimesh's convention: origin bottom-left
            assert np.all(winding > 0), f"{path} {mesh.visual.material.name}: {np.sum(winding <= 0)} faces"


@pytest.mark.shared
def test_the_top_of_the_texture_is_up_on_the_body(draped_tshirt):
    # front and back hang from the shoulders: higher on the body is higher in the picture
    obj, _ = obj_text(draped_tshirt)
    v, vt = _records(obj, "v"), _records(obj, "vt")
    glb = _glb_texcoords(glb_bytes(draped_tshirt))
    welded = np.unique(draped_tshirt.weld, return_inverse=True)[1]  # garment vertex -> OBJ ``v``
    for piece in ("front", "back"):
        ids = np.flatnonzero(draped_tshirt.instance == draped_tshirt.instance_names.index(piece))
        height = v[welded[ids], 1]
        assert np.corrcoef(vt[ids, 1], height)[0, 1] > 0.9  # OBJ: v up
        pos, st = glb[piece]
        assert np.corrcoef(st[:, 1], pos[:, 1])[0, 1] < -0.9  # glTF: t down


@pytest.mark.shared
def test_obj_normals_point_away_from_the_body(draped_tshirt, character_e):
    obj, _ = obj_text(draped_tshirt)
    v, vn = _records(obj, "v"), _records(obj, "vn")
    np.testing.assert_allclose(np.linalg.norm(vn, axis=1), 1.0, atol=1e-5)
    # the skin's outward normal (trimesh's) at the nearest body vertex
    body = trimesh.Trimesh(character_e.vertices, character_e.faces, process=False)
    skin_normal = body.vertex_normals[cKDTree(body.vertices).query(v)[1]]
    away = np.einsum("ij,ij->i", vn, skin_normal) > 0
    print(f"OBJ normals pointing away from the body: {away.sum()} of {len(v)}")
    assert away.mean() > 0.95
