"""Read the triangles, skeleton and skin weights of a GLB/glTF 2.0 file.

trimesh reads glTF geometry but drops the skin, so this small reader parses
the JSON and binary buffers itself. It supports the core of glTF 2.0: every
triangle primitive of every mesh node of the default scene, node matrices and
TRS transforms, and one skin (``JOINTS_0``/``WEIGHTS_0``, four influences).
Sparse accessors and Draco/meshopt compression are refused with a clear error.
"""

from __future__ import annotations

import base64
import json
import os
import struct
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import MeshError

__all__ = ["read_gltf"]

_DTYPES = {
    5120: np.int8,
    5121: np.uint8,
    5122: np.int16,
    5123: np.uint16,
    5125: np.uint32,
    5126: np.float32,
}
_WIDTH = {
    "SCALAR": 1,
    "VEC2": 2,
    "VEC3": 3,
    "VEC4": 4,
    "MAT2": 4,
    "MAT3": 9,
    "MAT4": 16,
}


def _split_glb(data: bytes, path: Path) -> tuple[dict, bytes]:
    if len(data) < 20 or data[:4] != b"glTF":
        raise MeshError(
            f"{path}: not a GLB file (bad magic {data[:4]!r}); export binary glTF 2.0"
        )
    offset = 12
    doc, binary = None, b""
    while offset + 8 <= len(data):
        length, kind = struct.unpack_from("<I4s", data, offset)
        chunk = data[offset + 8 : offset + 8 + length]
        if kind == b"JSON":
            doc = json.loads(chunk.decode("utf-8"))
        elif kind == b"BIN\x00":
            binary = chunk
        offset += 8 + length
    if doc is None:
        raise MeshError(f"{path}: GLB without a JSON chunk; re-export the file")
    return doc, binary


def _buffers(doc: dict, binary: bytes, path: Path) -> list[bytes]:
    out = []
    for i, buf in enumerate(doc.get("buffers", [])):
        uri = buf.get("uri")
        if uri is None:
            out.append(binary)
        elif uri.startswith("data:"):
            out.append(base64.b64decode(uri.split(",", 1)[1]))
        else:
            file = path.parent / uri
            if not file.is_file():
                raise MeshError(
                    f"{path}: buffer {i} file {uri!r} is missing; keep it beside the .gltf"
                )
            out.append(file.read_bytes())
    return out


def _accessor(doc: dict, buffers: list[bytes], index: int, path: Path) -> np.ndarray:
    acc = doc["accessors"][index]
    if "sparse" in acc:
        raise MeshError(
            f"{path}: sparse accessor {index} is not supported; export without sparse data"
        )
    dtype = np.dtype(_DTYPES[acc["componentType"]])
    width = _WIDTH[acc["type"]]
    count = acc["count"]
    if "bufferView" not in acc:
        return np.zeros((count, width))
    view = doc["bufferViews"][acc["bufferView"]]
    data = buffers[view["buffer"]]
    start = view.get("byteOffset", 0) + acc.get("byteOffset", 0)
    stride = view.get("byteStride") or dtype.itemsize * width
    if stride == dtype.itemsize * width:
        arr = np.frombuffer(
            data, dtype=dtype, count=count * width, offset=start
        ).reshape(count, width)
    else:
        rows = np.frombuffer(
            data,
            dtype=np.uint8,
            count=stride * (count - 1) + dtype.itemsize * width,
            offset=start,
        )
        arr = np.stack(
            [
                rows[i * stride : i * stride + dtype.itemsize * width].view(dtype)
                for i in range(count)
            ]
        )
    arr = arr.astype(np.float64)
    if acc.get("normalized") and dtype.kind in "iu":
        arr = arr / np.iinfo(dtype).max
    return arr


def _local_matrix(node: dict) -> np.ndarray:
    if "matrix" in node:
        return np.array(node["matrix"], dtype=np.float64).reshape(4, 4).T
    t = np.array(node.get("translation", [0, 0, 0]), dtype=np.float64)
    x, y, z, w = node.get("rotation", [0, 0, 0, 1])
    s = np.array(node.get("scale", [1, 1, 1]), dtype=np.float64)
    r = np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )
    m = np.eye(4)
    m[:3, :3] = r * s
    m[:3, 3] = t
    return m


def read_gltf(path: str | os.PathLike) -> dict[str, Any]:
    """Read a GLB/glTF file into arrays (file units, file frame).

    Returns
    -------
    dict with ``vertices`` (V, 3) float64, ``faces`` (F, 3) int64 and, when the
    file has a skin, ``skeleton`` (``names``, ``parents``, ``heads``, ``tails``
    of the skin's joints in rest pose) and ``skin`` (``indices``, ``weights``,
    (V, 4); -1 for vertices of unskinned primitives).

    Raises
    ------
    MeshError
        Not glTF 2.0, unsupported extension or no triangles.
    """
    path = Path(path)
    try:
        raw = path.read_bytes()
        if path.suffix.lower() == ".glb":
            doc, binary = _split_glb(raw, path)
        else:
            doc, binary = json.loads(raw.decode("utf-8")), b""
    except (OSError, ValueError, UnicodeDecodeError) as exc:
        raise MeshError(
            f"{path}: cannot read glTF ({exc}); re-export as glTF 2.0"
        ) from None
    required = set(doc.get("extensionsRequired", []))
    if required:
        raise MeshError(
            f"{path}: needs glTF extensions {sorted(required)} (compressed geometry); export without compression"
        )
    buffers = _buffers(doc, binary, path)
    nodes = doc.get("nodes", [])
    parent = {c: i for i, n in enumerate(nodes) for c in n.get("children", [])}
    world_cache: dict[int, np.ndarray] = {}

    def world(i: int) -> np.ndarray:
        if i not in world_cache:
            local = _local_matrix(nodes[i])
            world_cache[i] = world(parent[i]) @ local if i in parent else local
        return world_cache[i]

    scenes = doc.get("scenes", [])
    if scenes:
        stack = list(scenes[doc.get("scene", 0)].get("nodes", []))
        in_scene = []
        while stack:
            i = stack.pop()
            in_scene.append(i)
            stack.extend(nodes[i].get("children", []))
        in_scene.sort()
    else:
        in_scene = list(range(len(nodes)))

    vertices, faces, joints, weights = [], [], [], []
    skin_index = None
    offset = 0
    for ni in in_scene:
        node = nodes[ni]
        if "mesh" not in node:
            continue
        skinned = "skin" in node
        if skinned and skin_index is None:
            skin_index = node["skin"]
        matrix = world(ni)
        if skinned:
            skin = doc["skins"][node["skin"]]
            if "inverseBindMatrices" in skin:
                ibm = (
                    _accessor(doc, buffers, skin["inverseBindMatrices"], path)[0]
                    .reshape(4, 4)
                    .T
                )
                matrix = world(skin["joints"][0]) @ ibm
        for prim in doc["meshes"][node["mesh"]].get("primitives", []):
            if prim.get("mode", 4) != 4 or "POSITION" not in prim.get("attributes", {}):
                continue
            pos = _accessor(doc, buffers, prim["attributes"]["POSITION"], path)
            pos = pos @ matrix[:3, :3].T + matrix[:3, 3]
            if "indices" in prim:
                idx = (
                    _accessor(doc, buffers, prim["indices"], path)
                    .astype(np.int64)
                    .reshape(-1, 3)
                )
            else:
                idx = np.arange(len(pos), dtype=np.int64).reshape(-1, 3)
            attrs = prim["attributes"]
            if (
                skinned
                and node["skin"] == skin_index
                and "JOINTS_0" in attrs
                and "WEIGHTS_0" in attrs
            ):
                j = _accessor(doc, buffers, attrs["JOINTS_0"], path).astype(np.int64)
                w = _accessor(doc, buffers, attrs["WEIGHTS_0"], path)
                j = np.where(w > 0, j, -1)
            else:
                j = np.full((len(pos), 4), -1, dtype=np.int64)
                w = np.zeros((len(pos), 4))
            vertices.append(pos)
            faces.append(idx + offset)
            joints.append(j)
            weights.append(w)
            offset += len(pos)
    if not faces:
        raise MeshError(
            f"{path}: the glTF holds no triangle primitives; export the body as a mesh"
        )
    out: dict[str, Any] = {
        "vertices": np.concatenate(vertices),
        "faces": np.concatenate(faces),
    }
    if skin_index is not None:
        skin = doc["skins"][skin_index]
        jn = list(skin["joints"])
        pos_of = {n: world(n)[:3, 3] for n in jn}
        jset = {n: k for k, n in enumerate(jn)}
        parents = []
        for n in jn:
            p = parent.get(n)
            while p is not None and p not in jset:
                p = parent.get(p)
            parents.append(jset[p] if p is not None else -1)
        heads = np.array([pos_of[n] for n in jn])
        tails = heads.copy()
        for k, n in enumerate(jn):
            kids = [jset[c] for c in nodes[n].get("children", []) if c in jset]
            if kids:
                tails[k] = heads[kids].mean(axis=0)
            elif parents[k] >= 0:
                tails[k] = heads[k] + 0.5 * (heads[k] - heads[parents[k]])
            else:
                tails[k] = heads[k] + np.array([0.0, 0.1, 0.0])
        names = [nodes[n].get("name", f"joint{k}") for k, n in enumerate(jn)]
        out["skeleton"] = {
            "names": names,
            "parents": parents,
            "heads": heads,
            "tails": tails,
        }
        out["skin"] = {
            "indices": np.concatenate(joints),
            "weights": np.concatenate(weights),
        }
    return out
