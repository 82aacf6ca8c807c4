"""Write the draped garment as a skinned glTF 2.0 binary (GLB) and as OBJ + MTL.

The GLB is assembled by hand (numpy + struct + json, no extra dependency):

- one node per bone of the character's skeleton, placed at the bone heads
  (glTF is in metres: positions are divided by 100), a skin over them with the
  inverse bind matrices of that rest pose, and the garment mesh node bound to
  the skin;
- one primitive per cut piece (its own material, named after the piece), with
  ``POSITION``, ``NORMAL``, ``TEXCOORD_0`` (the pattern coordinates in metres:
  ``u = x / 100``, ``v = y / 100``), ``JOINTS_0``/``WEIGHTS_0`` (four bones a
  vertex, weights summing to 1) and ``_PIECE`` (the piece index, float);
- sewn vertices of different pieces sit at exactly the same position.

The OBJ keeps centimetres (as the character files do), shares one position
between sewn vertices (one ``v`` per welded vertex), carries ``vt`` in
centimetres of pattern space divided by 100 (same as the GLB) and a ``g`` +
``usemtl`` per piece.
"""

from __future__ import annotations

import json
import os
import struct

import numpy as np

from ..atomic import write_bytes, write_text

__all__ = ["glb_bytes", "obj_text", "read_glb", "write_glb", "write_obj"]

_FLOAT, _USHORT, _UINT = 5126, 5123, 5125
_ARRAY_BUFFER, _ELEMENT_ARRAY_BUFFER = 34962, 34963


def vertex_normals(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """(V, 3) area-weighted unit vertex normals."""
    fn = np.cross(
        vertices[faces[:, 1]] - vertices[faces[:, 0]],
        vertices[faces[:, 2]] - vertices[faces[:, 0]],
    )
    vn = np.zeros_like(vertices)
    for k in range(3):
        np.add.at(vn, faces[:, k], fn)
    ln = np.linalg.norm(vn, axis=1, keepdims=True)
    return np.where(ln > 0, vn / np.maximum(ln, 1e-30), np.array([0.0, 1.0, 0.0]))


class _Bin:
    def __init__(self) -> None:
        self.chunks: list[bytes] = []
        self.size = 0
        self.views: list[dict] = []
        self.accessors: list[dict] = []

    def view(self, data: bytes, target: int | None) -> int:
        pad = (-self.size) % 4
        if pad:
            self.chunks.append(b"\0" * pad)
            self.size += pad
        v = {"buffer": 0, "byteOffset": self.size, "byteLength": len(data)}
        if target is not None:
            v["target"] = target
        self.chunks.append(data)
        self.size += len(data)
        self.views.append(v)
        return len(self.views) - 1

    def accessor(
        self,
        a: np.ndarray,
        ctype: int,
        kind: str,
        target: int | None,
        minmax: bool = False,
    ) -> int:
        acc = {
            "bufferView": self.view(a.tobytes(), target),
            "componentType": ctype,
            "count": len(a),
            "type": kind,
        }
        if minmax:
            acc["min"] = [float(x) for x in a.reshape(len(a), -1).min(axis=0)]
            acc["max"] = [float(x) for x in a.reshape(len(a), -1).max(axis=0)]
        self.accessors.append(acc)
        return len(self.accessors) - 1


def glb_bytes(garment, *, colours: np.ndarray | None = None) -> bytes:
    """The garment as GLB bytes (see the module notes for the layout)."""
    from .pictures import PIECE_COLOURS

    colours = PIECE_COLOURS if colours is None else colours
    b = _Bin()
    doc: dict = {"asset": {"version": "2.0", "generator": "patternbridge"}, "scene": 0}
    nodes: list[dict] = []
    skel = garment.skeleton
    skinned = skel is not None and garment.joints.shape[1] > 0
    if skinned:
        heads = skel.heads / 100.0
        parents = skel.parents
        for j, name in enumerate(skel.names):
            p = parents[j]
            t = heads[j] - (heads[p] if p >= 0 else 0.0)
            nodes.append({"name": name, "translation": [float(x) for x in t]})
        for j, p in enumerate(parents):
            if p >= 0:
                nodes[p].setdefault("children", []).append(j)
        ibm = np.tile(np.eye(4, dtype=np.float32), (len(heads), 1, 1))
        ibm[:, :3, 3] = -heads
        ibm_acc = b.accessor(
            np.ascontiguousarray(ibm.transpose(0, 2, 1)).astype(np.float32),
            _FLOAT,
            "MAT4",
            None,
        )
        roots = [int(j) for j in np.flatnonzero(parents < 0)]
        doc["skins"] = [
            {
                "joints": list(range(len(heads))),
                "inverseBindMatrices": ibm_acc,
                "skeleton": roots[0],
                "name": "skeleton",
            }
        ]
    normals = vertex_normals(*garment.welded())[np.unique(garment.weld, return_inverse=True)[1]]
    primitives, materials = [], []
    for i, name in enumerate(garment.instance_names):
        vid = np.flatnonzero(garment.instance == i)
        if len(vid) == 0:
            continue
        local = np.full(len(garment.vertices), -1, dtype=np.int64)
        local[vid] = np.arange(len(vid))
        f = garment.faces[np.all(garment.instance[garment.faces] == i, axis=1)]
        attrs = {
            "POSITION": b.accessor(
                (garment.vertices[vid] / 100.0).astype(np.float32),
                _FLOAT,
                "VEC3",
                _ARRAY_BUFFER,
                True,
            ),
            "NORMAL": b.accessor(normals[vid].astype(np.float32), _FLOAT, "VEC3", _ARRAY_BUFFER),
            "TEXCOORD_0": b.accessor(
                (garment.uv[vid] / 100.0).astype(np.float32),
                _FLOAT,
                "VEC2",
                _ARRAY_BUFFER,
            ),
            "_PIECE": b.accessor(
                np.full(len(vid), float(i), dtype=np.float32),
                _FLOAT,
                "SCALAR",
                _ARRAY_BUFFER,
            ),
        }
        if skinned:
            j = np.where(garment.joints[vid] >= 0, garment.joints[vid], 0).astype(np.uint16)
            w = np.where(garment.joints[vid] >= 0, garment.weights[vid], 0.0).astype(np.float32)
            attrs["JOINTS_0"] = b.accessor(j, _USHORT, "VEC4", _ARRAY_BUFFER)
            attrs["WEIGHTS_0"] = b.accessor(w, _FLOAT, "VEC4", _ARRAY_BUFFER)
        idx = b.accessor(local[f].astype(np.uint32).ravel(), _UINT, "SCALAR", _ELEMENT_ARRAY_BUFFER)
        rgb = colours[i % len(colours)] / 255.0
        materials.append(
            {
                "name": name,
                "doubleSided": True,
                "pbrMetallicRoughness": {
                    "baseColorFactor": [*map(float, rgb), 1.0],
                    "metallicFactor": 0.0,
                    "roughnessFactor": 0.9,
                },
            }
        )
        primitives.append(
            {
                "attributes": attrs,
                "indices": idx,
                "material": len(materials) - 1,
                "mode": 4,
            }
        )
    mesh_node = {"name": "garment", "mesh": 0}
    if skinned:
        mesh_node["skin"] = 0
    nodes.append(mesh_node)
    scene_nodes = [len(nodes) - 1] + ([int(j) for j in np.flatnonzero(skel.parents < 0)] if skinned else [])
    doc["nodes"] = nodes
    doc["scenes"] = [{"nodes": scene_nodes}]
    doc["meshes"] = [
        {
            "name": "garment",
            "primitives": primitives,
            "extras": {"pieces": list(garment.instance_names)},
        }
    ]
    doc["materials"] = materials
    doc["accessors"] = b.accessors
    doc["bufferViews"] = b.views
    binary = b"".join(b.chunks)
    binary += b"\0" * ((-len(binary)) % 4)
    doc["buffers"] = [{"byteLength": len(binary)}]
    js = json.dumps(doc, separators=(",", ":")).encode("utf-8")
    js += b" " * ((-len(js)) % 4)
    total = 12 + 8 + len(js) + 8 + len(binary)
    return b"".join(
        [
            struct.pack("<4sII", b"glTF", 2, total),
            struct.pack("<I4s", len(js), b"JSON"),
            js,
            struct.pack("<I4s", len(binary), b"BIN\0"),
            binary,
        ]
    )


def write_glb(path: str | os.PathLike, garment, character=None) -> None:
    """Write ``garment`` as a skinned GLB (atomically)."""
    write_bytes(path, glb_bytes(garment))


def read_glb(data: bytes) -> tuple[dict, bytes]:
    """Split GLB bytes into the JSON document and the binary chunk (for checks).

    Raises
    ------
    ValueError
        The bytes are not a well-formed GLB 2.0 file.
    """
    magic, version, total = struct.unpack_from("<4sII", data, 0)
    if magic != b"glTF" or version != 2 or total != len(data):
        raise ValueError(f"not a GLB 2.0 file (magic {magic!r}, version {version}, length {total} vs {len(data)})")
    jlen, jtype = struct.unpack_from("<I4s", data, 12)
    if jtype != b"JSON":
        raise ValueError("first GLB chunk is not JSON")
    doc = json.loads(data[20 : 20 + jlen])
    off = 20 + jlen
    blen, btype = struct.unpack_from("<I4s", data, off)
    if btype != b"BIN\0":
        raise ValueError("second GLB chunk is not BIN")
    return doc, data[off + 8 : off + 8 + blen]


def obj_text(garment, mtl_name: str = "garment.mtl") -> tuple[str, str]:
    """OBJ and MTL texts: welded positions (cm), pattern UVs, one group and material per piece."""
    from .pictures import PIECE_COLOURS

    wv, _ = garment.welded()
    _, inv = np.unique(garment.weld, return_inverse=True)
    lines = [
        "# patternbridge garment: positions in cm, +Y up; vt = pattern coordinates / 100",
        f"mtllib {mtl_name}",
    ]
    lines += [f"v {x:.5f} {y:.5f} {z:.5f}" for x, y, z in wv]
    lines += [f"vt {u:.6f} {v:.6f}" for u, v in garment.uv / 100.0]
    mtl = ["# patternbridge garment materials"]
    for i, name in enumerate(garment.instance_names):
        f = garment.faces[garment.instance[garment.faces[:, 0]] == i]
        safe = name.replace(" ", "_")
        lines += [f"g {safe}", f"usemtl {safe}"]
        lines += [f"f {a}/{ta} {b}/{tb} {c}/{tc}" for (a, b, c), (ta, tb, tc) in zip(inv[f] + 1, f + 1, strict=True)]
        rgb = PIECE_COLOURS[i % len(PIECE_COLOURS)] / 255.0
        mtl += [
            f"newmtl {safe}",
            f"Kd {rgb[0]:.4f} {rgb[1]:.4f} {rgb[2]:.4f}",
            "Ka 0 0 0",
            "Ks 0 0 0",
            "d 1",
            "illum 1",
            "",
        ]
    return "\n".join(lines) + "\n", "\n".join(mtl) + "\n"


def write_obj(path: str | os.PathLike, garment) -> None:
    """Write ``garment.obj`` and the ``.mtl`` beside it (atomically)."""
    path = os.fspath(path)
    mtl_path = os.path.splitext(path)[0] + ".mtl"
    obj, mtl = obj_text(garment, os.path.basename(mtl_path))
    write_text(mtl_path, mtl)
    write_text(path, obj)
