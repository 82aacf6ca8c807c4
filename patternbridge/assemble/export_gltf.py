"""Write the draped garment as a skinned glTF 2.0 binary (GLB).

The GLB is assembled by hand (numpy + struct + json, no extra dependency):

- one node per bone of the character's skeleton, placed at the bone heads
  (glTF is in metres: positions are divided by 100), a skin over them with the
  inverse bind matrices of that rest pose, and the garment mesh node bound to
  the skin;
- one primitive per cut piece (its own material, named after the piece), with
  ``POSITION``, ``NORMAL`` (of the welded surface, so a seam shades smoothly),
  ``TEXCOORD_0`` (the fabric coordinates in metres of cloth in glTF's
  convention, origin top-left: ``s = x / 100``, ``t = 1 - y / 100``, mirrored
  copies turned over, see :mod:`.export_attributes`), ``JOINTS_0``/``WEIGHTS_0`` (four slots a vertex,
  weights summing to 1, slots without weight on joint 0) and ``_PIECE`` (the
  piece index, float);
- sewn vertices of different pieces sit at exactly the same position.

The same inputs give the same bytes: no time stamp, keys in a fixed order.
The OBJ beside it is written by :mod:`.export_obj`, the USD stage by
:mod:`.export_usd`.
"""

from __future__ import annotations

import json
import os
import struct

import numpy as np

from ..atomic import write_bytes
from .export_attributes import fabric_uv, skin_slots, texcoords_top_left, vertex_normals

__all__ = ["glb_bytes", "read_glb", "write_glb"]

_FLOAT, _USHORT, _UINT = 5126, 5123, 5125
_ARRAY_BUFFER, _ELEMENT_ARRAY_BUFFER = 34962, 34963


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


def _skin(b: _Bin, skel) -> tuple[list[dict], dict]:
    """Joint nodes at the bone heads (metres, translation only) and the skin over them."""
    heads = skel.heads / 100.0
    parents = skel.parents
    nodes: list[dict] = []
    for j, name in enumerate(skel.names):
        p = parents[j]
        t = heads[j] - (heads[p] if p >= 0 else 0.0)
        nodes.append({"name": name, "translation": [float(x) for x in t]})
    for j, p in enumerate(parents):
        if p >= 0:
            nodes[p].setdefault("children", []).append(j)
    ibm = np.tile(np.eye(4, dtype=np.float32), (len(heads), 1, 1))
    ibm[:, :3, 3] = -heads
    ibm_acc = b.accessor(np.ascontiguousarray(ibm.transpose(0, 2, 1)).astype(np.float32), _FLOAT, "MAT4", None)
    roots = [int(j) for j in np.flatnonzero(parents < 0)]
    skin = {"joints": list(range(len(heads))), "inverseBindMatrices": ibm_acc, "skeleton": roots[0], "name": "skeleton"}
    return nodes, skin


def _primitive(b: _Bin, garment, i: int, normals: np.ndarray, uv: np.ndarray, skinned: bool) -> dict:
    """The attributes and indices of cut piece ``i`` (its vertices only, re-indexed from 0)."""
    vid = np.flatnonzero(garment.instance == i)
    local = np.full(len(garment.vertices), -1, dtype=np.int64)
    local[vid] = np.arange(len(vid))
    f = garment.faces[np.all(garment.instance[garment.faces] == i, axis=1)]

    def vec(a: np.ndarray, kind: str, minmax: bool = False) -> int:
        return b.accessor(a.astype(np.float32), _FLOAT, kind, _ARRAY_BUFFER, minmax)

    attrs = {
        "POSITION": vec(garment.vertices[vid] / 100.0, "VEC3", True),
        "NORMAL": vec(normals[vid], "VEC3"),
        "TEXCOORD_0": vec(texcoords_top_left(uv[vid]), "VEC2"),
        "_PIECE": vec(np.full(len(vid), float(i)), "SCALAR"),
    }
    if skinned:
        j, w = skin_slots(garment.joints[vid], garment.weights[vid])
        attrs["JOINTS_0"] = b.accessor(j.astype(np.uint16), _USHORT, "VEC4", _ARRAY_BUFFER)
        attrs["WEIGHTS_0"] = vec(w, "VEC4")
    idx = b.accessor(local[f].astype(np.uint32).ravel(), _UINT, "SCALAR", _ELEMENT_ARRAY_BUFFER)
    return {"attributes": attrs, "indices": idx, "mode": 4}


def _material(name: str, rgb: np.ndarray) -> dict:
    return {
        "name": name,
        "doubleSided": True,
        "pbrMetallicRoughness": {
            "baseColorFactor": [*map(float, rgb), 1.0],
            "metallicFactor": 0.0,
            "roughnessFactor": 0.9,
        },
    }


def _glb(doc: dict, binary: bytes) -> bytes:
    """GLB container: header, JSON chunk (space-padded), BIN chunk (zero-padded)."""
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


def glb_bytes(garment, *, colours: np.ndarray | None = None) -> bytes:
    """The garment as GLB bytes (see the module notes for the layout).

    Parameters
    ----------
    garment : :class:`~patternbridge.assemble.garment.Garment`
    colours : (k, 3) uint8 piece colours, cycled; default ``pictures.PIECE_COLOURS``
    """
    from .pictures import PIECE_COLOURS

    colours = PIECE_COLOURS if colours is None else colours
    b = _Bin()
    doc: dict = {"asset": {"version": "2.0", "generator": "patternbridge"}, "scene": 0}
    nodes: list[dict] = []
    skel = garment.skeleton
    skinned = skel is not None and garment.joints.shape[1] > 0
    if skinned:
        nodes, skin = _skin(b, skel)
        doc["skins"] = [skin]
    wv, wf = garment.welded()
    normals = vertex_normals(wv, wf)[np.unique(garment.weld, return_inverse=True)[1]]
    uv = fabric_uv(garment.uv, garment.faces, garment.instance)
    primitives, materials = [], []
    for i, name in enumerate(garment.instance_names):
        if not np.any(garment.instance == i):
            continue
        materials.append(_material(name, colours[i % len(colours)] / 255.0))
        primitives.append({**_primitive(b, garment, i, normals, uv, skinned), "material": len(materials) - 1})
    mesh_node = {"name": "garment", "mesh": 0}
    if skinned:
        mesh_node["skin"] = 0
    nodes.append(mesh_node)
    scene_nodes = [len(nodes) - 1] + ([int(j) for j in np.flatnonzero(skel.parents < 0)] if skinned else [])
    doc["nodes"] = nodes
    doc["scenes"] = [{"nodes": scene_nodes}]
    doc["meshes"] = [{"name": "garment", "primitives": primitives, "extras": {"pieces": list(garment.instance_names)}}]
    doc["materials"] = materials
    doc["accessors"] = b.accessors
    doc["bufferViews"] = b.views
    return _glb(doc, b"".join(b.chunks))


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
