"""Skinned GLB and OBJ export, parsed back."""

from __future__ import annotations

import struct

import numpy as np
import pytest

from patternbridge.assemble import Garment
from patternbridge.assemble.export_gltf import (
    glb_bytes,
    obj_text,
    read_glb,
    write_glb,
    write_obj,
)
from patternbridge.mesh.character import Skeleton

_SIZES = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT4": 16}
_DTYPES = {5126: np.float32, 5123: np.uint16, 5125: np.uint32}


def _garment(skinned: bool = True) -> Garment:
    # two unit-ish squares sharing an edge (x = 10): sewn vertices coincide
    a = np.array([[0.0, 0, 0], [10, 0, 0], [10, 10, 0], [0, 10, 0]])
    b = a + [10.0, 0, 0]
    v = np.concatenate([a, b])
    f = np.array([[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7]])
    uv = np.concatenate([a[:, :2], a[:, :2] + [3.0, 0]])
    weld = np.array([0, 1, 2, 3, 1, 5, 6, 2])
    skel = Skeleton(
        names=("root", "spine", "arm"),
        parents=[-1, 0, 1],
        heads=[[0, 0, 0], [0, 10, 0], [10, 10, 0]],
        tails=[[0, 10, 0], [10, 10, 0], [20, 10, 0]],
    )
    joints = np.tile([0, 1, -1, -1], (8, 1))
    weights = np.tile([0.25, 0.75, 0.0, 0.0], (8, 1))
    joints[5:] = [2, -1, -1, -1]
    weights[5:] = [1.0, 0, 0, 0]
    return Garment(
        vertices=v,
        faces=f,
        uv=uv,
        instance=np.array([0, 0, 0, 0, 1, 1, 1, 1]),
        instance_names=("front", "back"),
        weld=weld,
        joints=joints if skinned else np.zeros((8, 0), np.int64),
        weights=weights if skinned else np.zeros((8, 0)),
        skeleton=skel if skinned else None,
    )


def _accessor(doc, binary, i):
    acc = doc["accessors"][i]
    view = doc["bufferViews"][acc["bufferView"]]
    n = acc["count"] * _SIZES[acc["type"]]
    dt = _DTYPES[acc["componentType"]]
    assert view["byteOffset"] % 4 == 0
    assert view["byteOffset"] + view["byteLength"] <= len(binary)
    assert view["byteLength"] == n * np.dtype(dt).itemsize
    a = np.frombuffer(binary, dtype=dt, count=n, offset=view["byteOffset"] + acc.get("byteOffset", 0))
    return a.reshape(acc["count"], -1)


def test_glb_parses_back_with_consistent_buffers():
    g = _garment()
    data = glb_bytes(g)
    doc, binary = read_glb(data)
    assert doc["asset"]["version"] == "2.0"
    assert doc["buffers"][0]["byteLength"] == len(binary)
    assert len(data) % 4 == 0
    prims = doc["meshes"][0]["primitives"]
    assert len(prims) == 2  # one primitive per piece
    n_joints = len(doc["skins"][0]["joints"])
    assert n_joints == 3
    total = 0
    for k, prim in enumerate(prims):
        attrs = prim["attributes"]
        pos = _accessor(doc, binary, attrs["POSITION"])
        count = len(pos)
        total += count
        for name in ("NORMAL", "TEXCOORD_0", "JOINTS_0", "WEIGHTS_0", "_PIECE"):
            assert doc["accessors"][attrs[name]]["count"] == count
        idx = _accessor(doc, binary, prim["indices"]).ravel()
        assert idx.max() < count
        w = _accessor(doc, binary, attrs["WEIGHTS_0"])
        np.testing.assert_allclose(w.sum(axis=1), 1.0, atol=1e-6)
        j = _accessor(doc, binary, attrs["JOINTS_0"])
        assert j.max() < n_joints
        uv = _accessor(doc, binary, attrs["TEXCOORD_0"])
        np.testing.assert_allclose(uv * 100.0, g.uv[g.instance == k], atol=1e-4)
        np.testing.assert_allclose(pos * 100.0, g.vertices[g.instance == k], atol=1e-4)
        np.testing.assert_array_equal(_accessor(doc, binary, attrs["_PIECE"]).ravel(), k)
        acc = doc["accessors"][attrs["POSITION"]]
        np.testing.assert_allclose(acc["min"], pos.min(axis=0))
        assert doc["materials"][prim["material"]]["name"] == ("front", "back")[k]
    assert total == len(g.vertices)
    ibm = _accessor(doc, binary, doc["skins"][0]["inverseBindMatrices"]).reshape(3, 4, 4).transpose(0, 2, 1)
    np.testing.assert_allclose(ibm[:, :3, 3], -g.skeleton.heads / 100.0, atol=1e-6)
    # node translations rebuild the bone heads
    nodes = doc["nodes"]
    np.testing.assert_allclose(
        np.cumsum([nodes[i]["translation"] for i in range(3)], axis=0),
        g.skeleton.heads / 100.0,
    )
    assert nodes[-1]["skin"] == 0 and nodes[-1]["mesh"] == 0


def test_unskinned_glb_has_no_skin():
    doc, _ = read_glb(glb_bytes(_garment(skinned=False)))
    assert "skins" not in doc
    assert "JOINTS_0" not in doc["meshes"][0]["primitives"][0]["attributes"]


def test_read_glb_rejects_other_bytes():
    with pytest.raises(ValueError, match="GLB"):
        read_glb(struct.pack("<4sII", b"abcd", 2, 12))


def test_obj_welds_sewn_vertices_and_keeps_uvs(tmp_path):
    g = _garment()
    obj, mtl = obj_text(g)
    v = [ln for ln in obj.splitlines() if ln.startswith("v ")]
    vt = [ln for ln in obj.splitlines() if ln.startswith("vt ")]
    faces = [ln for ln in obj.splitlines() if ln.startswith("f ")]
    assert len(v) == 6  # 8 vertices, 2 sewn pairs
    assert len(vt) == 8 and len(faces) == 4
    assert "newmtl front" in mtl and "newmtl back" in mtl
    write_obj(tmp_path / "garment.obj", g)
    write_glb(tmp_path / "garment.glb", g)
    assert (tmp_path / "garment.mtl").read_text() == mtl
    assert (tmp_path / "garment.glb").read_bytes()[:4] == b"glTF"
