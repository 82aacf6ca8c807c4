"""GLB with a skin: geometry, joints and weights are read and converted to cm."""

from __future__ import annotations

import json
import struct

import numpy as np
import pytest
import trimesh

from patternbridge.errors import MeshError
from patternbridge.mesh.load import load_character
from patternbridge.mesh.skinning import pose_vertices, rotation_about_axis


def _write_skinned_glb(path, vertices, faces, joints, weights, joint_nodes):
    """Minimal glTF 2.0 writer: one mesh node with a skin over a chain of joint nodes."""
    blobs, views, accessors = [], [], []

    def add(arr, ctype, kind, target=None):
        data = np.ascontiguousarray(arr).tobytes()
        offset = sum(len(b) for b in blobs)
        blobs.append(data + b"\0" * (-len(data) % 4))
        views.append(
            {
                "buffer": 0,
                "byteOffset": offset,
                "byteLength": len(data),
                **({"target": target} if target else {}),
            }
        )
        acc = {
            "bufferView": len(views) - 1,
            "componentType": ctype,
            "count": len(arr),
            "type": kind,
        }
        if kind == "VEC3" and ctype == 5126:
            acc["min"] = arr.min(axis=0).tolist()
            acc["max"] = arr.max(axis=0).tolist()
        accessors.append(acc)
        return len(accessors) - 1

    pos = add(vertices.astype(np.float32), 5126, "VEC3", 34962)
    idx = add(faces.astype(np.uint32).ravel(), 5125, "SCALAR", 34963)
    jnt = add(joints.astype(np.uint16), 5123, "VEC4", 34962)
    wgt = add(weights.astype(np.float32), 5126, "VEC4", 34962)
    nodes = [{"name": "body", "mesh": 0, "skin": 0}]
    for k, (name, t) in enumerate(joint_nodes):
        node = {"name": name, "translation": list(t)}
        if k + 1 < len(joint_nodes):
            node["children"] = [k + 2]
        nodes.append(node)
    doc = {
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0, 1]}],
        "nodes": nodes,
        "meshes": [
            {
                "primitives": [
                    {
                        "attributes": {
                            "POSITION": pos,
                            "JOINTS_0": jnt,
                            "WEIGHTS_0": wgt,
                        },
                        "indices": idx,
                    }
                ]
            }
        ],
        "skins": [{"joints": list(range(1, len(joint_nodes) + 1))}],
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{"byteLength": sum(len(b) for b in blobs)}],
    }
    js = json.dumps(doc).encode()
    js += b" " * (-len(js) % 4)
    binary = b"".join(blobs)
    total = 12 + 8 + len(js) + 8 + len(binary)
    path.write_bytes(
        struct.pack("<4sII", b"glTF", 2, total)
        + struct.pack("<I4s", len(js), b"JSON")
        + js
        + struct.pack("<I4s", len(binary), b"BIN\0")
        + binary
    )


@pytest.fixture()
def skinned(tmp_path):
    m = trimesh.creation.cylinder(radius=0.15, height=1.7, sections=32)
    v = np.asarray(m.vertices)[:, [0, 2, 1]] + [0, 0.85, 0]  # Y up, feet at 0, metres
    f = np.asarray(m.faces)[:, [0, 2, 1]]
    lower = v[:, 1] < 0.85
    joints = np.zeros((len(v), 4), dtype=np.int64)
    joints[:, 0] = np.where(lower, 0, 1)
    weights = np.zeros((len(v), 4))
    weights[:, 0] = 1.0
    path = tmp_path / "bar.glb"
    _write_skinned_glb(
        path,
        v,
        f,
        joints,
        weights,
        [("root", (0, 0, 0)), ("spine", (0, 0.85, 0)), ("head", (0, 0.8, 0))],
    )
    return path, v


def test_skinned_glb(skinned):
    path, v = skinned
    c, _ = load_character(path)
    assert c.assumed["units"].startswith("m") and c.assumed["up"].startswith("+Y")
    assert c.stature_cm == pytest.approx(170.0, abs=1e-3)
    np.testing.assert_allclose(c.vertices, v * 100, atol=1e-4)
    assert c.skeleton.names == ("root", "spine", "head")
    np.testing.assert_array_equal(c.skeleton.parents, [-1, 0, 1])
    np.testing.assert_allclose(
        c.skeleton.heads, [[0, 0, 0], [0, 85, 0], [0, 165, 0]], atol=1e-6
    )
    assert c.skin.bone_indices.shape == (len(v), 4)
    np.testing.assert_allclose(c.skin.weights.sum(axis=1), 1.0)
    # bend the upper half about the spine joint: the lower half stays
    r = rotation_about_axis([0, 0, 1], np.pi / 2)
    out = pose_vertices(c, {"spine": r})
    low = c.vertices[:, 1] < 85
    np.testing.assert_allclose(out[low], c.vertices[low])
    np.testing.assert_allclose(
        out[~low], (c.vertices[~low] - [0, 85, 0]) @ r.T + [0, 85, 0], atol=1e-9
    )


def test_gltf_extension_refused(tmp_path):
    path = tmp_path / "draco.gltf"
    path.write_text(
        json.dumps(
            {
                "asset": {"version": "2.0"},
                "extensionsRequired": ["KHR_draco_mesh_compression"],
            }
        )
    )
    with pytest.raises(MeshError, match="compress"):
        load_character(path)
    path.write_text(
        json.dumps({"asset": {"version": "2.0"}, "nodes": [], "meshes": []})
    )
    with pytest.raises(MeshError, match="no triangle"):
        load_character(path)
