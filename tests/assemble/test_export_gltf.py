"""Skinned GLB export: parsed back by hand, and checked by the Khronos glTF validator."""

from __future__ import annotations

import json
import shutil
import struct
import subprocess
from pathlib import Path

import numpy as np
import pytest

from patternbridge.assemble import Garment, export_gltf
from patternbridge.assemble.export_gltf import glb_bytes, read_glb, write_glb
from patternbridge.mesh.character import Skeleton

TOOLS = Path(__file__).resolve().parents[1] / "tools"

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
    joints[5:] = [2, 1, -1, -1]  # bone 1 named with no weight: must not reach the file
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


def accessor(doc: dict, binary: bytes, i: int) -> np.ndarray:
    """Accessor ``i`` read from the binary chunk by the glTF rules, (count, components)."""
    acc = doc["accessors"][i]
    view = doc["bufferViews"][acc["bufferView"]]
    n = acc["count"] * _SIZES[acc["type"]]
    dt = _DTYPES[acc["componentType"]]
    assert view["byteOffset"] % 4 == 0
    assert view["byteOffset"] + view["byteLength"] <= len(binary)
    assert view["byteLength"] == n * np.dtype(dt).itemsize
    a = np.frombuffer(binary, dtype=dt, count=n, offset=view["byteOffset"] + acc.get("byteOffset", 0))
    return a.reshape(acc["count"], -1)


def khronos_report(path: Path) -> dict:
    """The Khronos glTF validator's report on ``path`` (skips without node or the npm package)."""
    node = shutil.which("node")
    if node is None or not (TOOLS / "node_modules" / "gltf-validator").is_dir():
        pytest.skip("node or the npm package gltf-validator is missing (make test installs it in tests/tools)")
    run = subprocess.run(
        [node, str(TOOLS / "validate_gltf.mjs"), str(path)], capture_output=True, text=True, timeout=120, check=True
    )
    return json.loads(run.stdout)


def _summary(report: dict) -> str:
    issues = report["issues"]
    codes = sorted({m["code"] for m in issues["messages"]})
    return f"{issues['numErrors']} errors, {issues['numWarnings']} warnings, {issues['numInfos']} infos {codes}"


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
        pos = accessor(doc, binary, attrs["POSITION"])
        count = len(pos)
        total += count
        for name in ("NORMAL", "TEXCOORD_0", "JOINTS_0", "WEIGHTS_0", "_PIECE"):
            assert doc["accessors"][attrs[name]]["count"] == count
        idx = accessor(doc, binary, prim["indices"]).ravel()
        assert idx.max() < count
        w = accessor(doc, binary, attrs["WEIGHTS_0"])
        np.testing.assert_allclose(w.sum(axis=1), 1.0, atol=1e-6)
        j = accessor(doc, binary, attrs["JOINTS_0"])
        assert j.max() < n_joints
        # glTF's texture origin is the top-left corner: t runs down the image
        st = accessor(doc, binary, attrs["TEXCOORD_0"])
        np.testing.assert_allclose(st[:, 0] * 100.0, g.uv[g.instance == k, 0], atol=1e-4)
        np.testing.assert_allclose((1.0 - st[:, 1]) * 100.0, g.uv[g.instance == k, 1], atol=1e-4)
        np.testing.assert_allclose(pos * 100.0, g.vertices[g.instance == k], atol=1e-4)
        np.testing.assert_array_equal(accessor(doc, binary, attrs["_PIECE"]).ravel(), k)
        acc = doc["accessors"][attrs["POSITION"]]
        np.testing.assert_allclose(acc["min"], pos.min(axis=0))
        assert doc["materials"][prim["material"]]["name"] == ("front", "back")[k]
    assert total == len(g.vertices)
    ibm = accessor(doc, binary, doc["skins"][0]["inverseBindMatrices"]).reshape(3, 4, 4).transpose(0, 2, 1)
    np.testing.assert_allclose(ibm[:, :3, 3], -g.skeleton.heads / 100.0, atol=1e-6)
    # node translations rebuild the bone heads
    nodes = doc["nodes"]
    np.testing.assert_allclose(
        np.cumsum([nodes[i]["translation"] for i in range(3)], axis=0),
        g.skeleton.heads / 100.0,
    )
    assert nodes[-1]["skin"] == 0 and nodes[-1]["mesh"] == 0


def test_joint_slots_without_weight_name_joint_zero():
    doc, binary = read_glb(glb_bytes(_garment()))
    for prim in doc["meshes"][0]["primitives"]:
        j = accessor(doc, binary, prim["attributes"]["JOINTS_0"])
        w = accessor(doc, binary, prim["attributes"]["WEIGHTS_0"])
        assert np.all(j[w == 0] == 0)
        assert np.all(w[j > 0] > 0)
    back = doc["meshes"][0]["primitives"][1]
    np.testing.assert_array_equal(accessor(doc, binary, back["attributes"]["JOINTS_0"])[1:], [[2, 0, 0, 0]] * 3)


def test_unskinned_glb_has_no_skin():
    doc, _ = read_glb(glb_bytes(_garment(skinned=False)))
    assert "skins" not in doc
    assert "JOINTS_0" not in doc["meshes"][0]["primitives"][0]["attributes"]


def test_read_glb_rejects_other_bytes():
    with pytest.raises(ValueError, match="GLB"):
        read_glb(struct.pack("<4sII", b"abcd", 2, 12))


def test_same_garment_same_bytes(tmp_path):
    write_glb(tmp_path / "a.glb", _garment())
    write_glb(tmp_path / "b.glb", _garment())
    assert (tmp_path / "a.glb").read_bytes() == (tmp_path / "b.glb").read_bytes()
    assert not list(tmp_path.glob(".*"))  # no temporary file left behind


@pytest.mark.shared
def test_draped_glb_passes_the_khronos_validator(draped_tshirt, tmp_path):
    path = tmp_path / "garment.glb"
    write_glb(path, draped_tshirt)
    report = khronos_report(path)
    print("Khronos glTF validator", report["validatorVersion"], "on the draped T-shirt:", _summary(report))
    assert report["issues"]["numErrors"] == 0, report["issues"]["messages"]
    assert report["issues"]["numWarnings"] == 0, report["issues"]["messages"]
    assert report["info"]["hasSkins"] and report["info"]["materialCount"] == 4


def test_khronos_validator_unskinned_and_small(tmp_path):
    for skinned in (True, False):
        path = tmp_path / f"g{skinned}.glb"
        write_glb(path, _garment(skinned))
        issues = khronos_report(path)["issues"]
        assert (issues["numErrors"], issues["numWarnings"]) == (0, 0), issues["messages"]


@pytest.mark.shared
def test_khronos_validator_sees_joints_named_without_weight(draped_tshirt, tmp_path, monkeypatch):
    # the draped T-shirt has bones listed with no weight; written as they are, the validator warns
    def raw(joints, weights):
        return np.maximum(joints, 0), weights

    monkeypatch.setattr(export_gltf, "skin_slots", raw)
    path = tmp_path / "raw.glb"
    write_glb(path, draped_tshirt)
    report = khronos_report(path)
    codes = {m["code"] for m in report["issues"]["messages"] if m["severity"] == 1}
    assert "ACCESSOR_JOINTS_USED_ZERO_WEIGHT" in codes
