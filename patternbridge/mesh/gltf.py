"""Read the triangles, skeleton and skin weights of a GLB/glTF 2.0 file.

trimesh reads glTF geometry but drops the skin, so this small reader parses
the JSON and binary buffers itself. It supports the core of glTF 2.0: every
triangle primitive of every mesh node of the default scene, node matrices and
TRS transforms, and one skin (``JOINTS_0``/``WEIGHTS_0``, four influences).
Sparse accessors and Draco/meshopt compression are refused with a clear error.
"""

from __future__ import annotations

import base64
import os
import struct
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import MeshError
from ..io.json_file import loads_json

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


MAX_COUNT = 50_000_000
"""Most elements an accessor may declare (a character has well under a million vertices)."""
MAX_ABS = 1e9
"""Largest vertex coordinate or node transform value accepted, in file units."""


def _fail(path: Path, what: str, hint: str = "re-export the file as glTF 2.0") -> MeshError:
    return MeshError(f"{path}: {what}; {hint}")


def _split_glb(data: bytes, path: Path) -> tuple[dict, bytes | None]:
    """JSON document and BIN chunk (``None`` when absent) of a GLB container."""
    if len(data) < 20 or data[:4] != b"glTF":
        raise _fail(path, f"not a GLB file (bad magic {data[:4]!r})", "export binary glTF 2.0")
    version, total = struct.unpack_from("<II", data, 4)
    if version != 2:
        raise _fail(path, f"GLB container version {version}, expected 2")
    if total > len(data):
        raise _fail(path, f"truncated GLB (header says {total} bytes, the file has {len(data)})")
    offset = 12
    doc, binary = None, None
    while offset + 8 <= total:
        length, kind = struct.unpack_from("<I4s", data, offset)
        if offset + 8 + length > total:
            raise _fail(
                path, f"truncated GLB (chunk {kind!r} at byte {offset} needs {length} bytes, {total - offset - 8} left)"
            )
        chunk = data[offset + 8 : offset + 8 + length]
        if offset == 12 and kind != b"JSON":
            raise _fail(path, f"GLB whose first chunk is {kind!r}, not JSON")
        if kind == b"JSON":
            doc = loads_json(chunk, str(path), error=MeshError, hint="re-export the file as glTF 2.0")
        elif kind == b"BIN\x00" and binary is None:
            binary = chunk
        offset += 8 + length
    if doc is None:
        raise _fail(path, "GLB without a JSON chunk")
    return doc, binary


def _items(doc: dict, key: str, path: Path) -> list:
    value = doc.get(key, [])
    if not isinstance(value, list):
        raise _fail(path, f"glTF {key!r} is not an array")
    return value


def _item(doc: dict, key: str, index: Any, path: Path, who: str) -> dict:
    """``doc[key][index]`` after checking the index and that the item is an object."""
    items = _items(doc, key, path)
    if isinstance(index, bool) or not isinstance(index, int) or not 0 <= index < len(items):
        raise _fail(path, f"{who} refers to {key}[{str(index)[:20]}], the file has {len(items)}")
    if not isinstance(items[index], dict):
        raise _fail(path, f"glTF {key}[{index}] is not an object")
    return items[index]


def _uint(obj: dict, key: str, default: int | None, path: Path, who: str) -> int:
    value = obj.get(key, default)
    if isinstance(value, bool) or not isinstance(value, int) or value < 0:
        raise _fail(path, f"{who} {key} is {str(value)[:20]}, expected a non-negative integer")
    return value


def _buffers(doc: dict, binary: bytes | None, path: Path) -> list[bytes]:
    out = []
    for i, buf in enumerate(_items(doc, "buffers", path)):
        if not isinstance(buf, dict):
            raise _fail(path, f"glTF buffers[{i}] is not an object")
        uri = buf.get("uri")
        if uri is None:
            if binary is None:
                raise _fail(path, f"buffer {i} lives in the GLB binary chunk, and the file has none")
            data = binary
        elif not isinstance(uri, str):
            raise _fail(path, f"buffer {i} uri is not a string")
        elif uri.startswith("data:"):
            try:
                data = base64.b64decode(uri.split(",", 1)[1], validate=True)
            except (IndexError, ValueError) as exc:
                raise _fail(path, f"buffer {i} data URI is not base64 ({exc})") from None
        else:
            file = path.parent / uri
            if not file.is_file():
                raise MeshError(f"{path}: buffer {i} file {uri[:200]!r} is missing; keep it beside the .gltf")
            data = file.read_bytes()
        declared = _uint(buf, "byteLength", len(data), path, f"buffer {i}")
        if declared > len(data):
            raise _fail(path, f"buffer {i} declares {declared} bytes, only {len(data)} are present (truncated file?)")
        out.append(data)
    return out


def _accessor(doc: dict, buffers: list[bytes], index: Any, path: Path, who: str = "a primitive") -> np.ndarray:
    """Accessor ``index`` as a (count, width) float64 array, bounds checked against its buffer."""
    acc = _item(doc, "accessors", index, path, who)
    where = f"accessor {index}"
    if "sparse" in acc:
        raise MeshError(f"{path}: sparse {where} is not supported; export without sparse data")
    ctype, kind = acc.get("componentType"), acc.get("type")
    if not isinstance(ctype, int) or not isinstance(kind, str) or ctype not in _DTYPES or kind not in _WIDTH:
        raise _fail(path, f"{where} has componentType {str(ctype)[:20]} / type {str(kind)[:20]}, not glTF 2.0")
    dtype = np.dtype(_DTYPES[ctype])
    width = _WIDTH[kind]
    count = _uint(acc, "count", None, path, where)
    if count > MAX_COUNT:
        raise _fail(path, f"{where} declares {count} elements (at most {MAX_COUNT})")
    if "bufferView" not in acc:
        return np.zeros((count, width))
    view = _item(doc, "bufferViews", acc["bufferView"], path, where)
    buffer_index = view.get("buffer")
    if isinstance(buffer_index, bool) or not isinstance(buffer_index, int) or not 0 <= buffer_index < len(buffers):
        raise _fail(
            path,
            f"bufferView {acc['bufferView']} refers to buffer {str(buffer_index)[:20]}, the file has {len(buffers)}",
        )
    data = buffers[buffer_index]
    view_start = _uint(view, "byteOffset", 0, path, "bufferView")
    view_length = _uint(view, "byteLength", len(data) - view_start, path, "bufferView")
    start = _uint(acc, "byteOffset", 0, path, where)
    element = dtype.itemsize * width
    stride = view.get("byteStride") or element
    if isinstance(stride, bool) or not isinstance(stride, int) or stride < element:
        raise _fail(path, f"bufferView byteStride {str(stride)[:20]} is smaller than one element ({element} bytes)")
    need = start + (stride * (count - 1) + element if count else 0)
    have = min(view_length, len(data) - view_start)
    if need > have:
        raise _fail(
            path,
            f"{where} needs {need} bytes ({count} × {kind} {dtype.name}), its buffer view holds {max(have, 0)}",
        )
    arr = np.ndarray(
        (count, width), dtype=dtype.newbyteorder("<"), buffer=data, offset=view_start + start,
        strides=(stride, dtype.itemsize),
    ).astype(np.float64)
    if acc.get("normalized") and dtype.kind in "iu":
        arr = arr / np.iinfo(dtype).max
    if not np.all(np.isfinite(arr)) or (arr.size and np.abs(arr).max() > MAX_ABS):
        raise _fail(path, f"{where} holds NaN, infinite or values beyond ±{MAX_ABS:g}", "repair the mesh")
    return arr


def _numbers(node: dict, key: str, default: list[float], path: Path, index: int) -> np.ndarray:
    value = node.get(key, default)
    try:
        arr = np.array(value, dtype=np.float64)
    except (TypeError, ValueError):
        arr = np.zeros(0)
    if arr.shape != (len(default),) or not np.all(np.isfinite(arr)) or np.abs(arr).max() > MAX_ABS:
        raise _fail(path, f"node {index} {key} is not {len(default)} finite numbers within ±{MAX_ABS:g}")
    return arr


def _local_matrix(node: dict, path: Path, index: int) -> np.ndarray:
    """4×4 local transform of a node (``matrix`` or translation/rotation/scale)."""
    if "matrix" in node:
        return _numbers(node, "matrix", [0.0] * 16, path, index).reshape(4, 4).T
    t = _numbers(node, "translation", [0.0, 0.0, 0.0], path, index)
    x, y, z, w = _numbers(node, "rotation", [0.0, 0.0, 0.0, 1.0], path, index)
    s = _numbers(node, "scale", [1.0, 1.0, 1.0], path, index)
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


def _node_tree(doc: dict, path: Path) -> tuple[list[dict], dict[int, int], list[np.ndarray]]:
    """Nodes, child -> parent map and world matrices; refuses cycles and shared children."""
    nodes = _items(doc, "nodes", path)
    parent: dict[int, int] = {}
    for i, node in enumerate(nodes):
        if not isinstance(node, dict):
            raise _fail(path, f"glTF nodes[{i}] is not an object")
        children = node.get("children", [])
        if not isinstance(children, list):
            raise _fail(path, f"node {i} children is not an array")
        for c in children:
            _item(doc, "nodes", c, path, f"node {i}")
            if c in parent or c == i:
                raise _fail(path, f"node {c} has two parents or is its own child (the node tree must be a forest)")
            parent[c] = i
    world: list[np.ndarray | None] = [None] * len(nodes)
    for i in range(len(nodes)):
        chain = [i]
        while world[chain[-1]] is None and chain[-1] in parent:
            chain.append(parent[chain[-1]])
            if len(chain) > len(nodes):
                raise _fail(path, f"the node tree has a cycle through node {i}")
        for k in reversed(chain):
            if world[k] is None:
                local = _local_matrix(nodes[k], path, k)
                world[k] = world[parent[k]] @ local if k in parent else local
    return nodes, parent, world  # type: ignore[return-value]


def _scene_nodes(doc: dict, nodes: list[dict], path: Path) -> list[int]:
    """Indices of the nodes of the default scene (every node when there is no scene)."""
    scenes = _items(doc, "scenes", path)
    if not scenes:
        return list(range(len(nodes)))
    scene = _item(doc, "scenes", doc.get("scene", 0), path, "the default scene")
    roots = scene.get("nodes", [])
    if not isinstance(roots, list):
        raise _fail(path, "scene nodes is not an array")
    for i in roots:
        _item(doc, "nodes", i, path, "the scene")
    stack = list(roots)
    seen: set[int] = set()
    while stack:
        i = stack.pop()
        if i not in seen:
            seen.add(i)
            stack.extend(nodes[i].get("children", []))
    return sorted(seen)


def _primitive(doc: dict, buffers: list[bytes], prim: Any, matrix: np.ndarray, path: Path):
    """(positions, faces, joints, weights) of one triangle primitive, or None to skip it."""
    if not isinstance(prim, dict) or not isinstance(prim.get("attributes", {}), dict):
        raise _fail(path, "a mesh primitive is not an object with attributes")
    attrs = prim.get("attributes", {})
    if prim.get("mode", 4) != 4 or "POSITION" not in attrs:
        return None
    pos = _accessor(doc, buffers, attrs["POSITION"], path, "POSITION")
    if pos.shape[1] != 3:
        raise _fail(path, f"POSITION accessor has {pos.shape[1]} components, expected 3")
    pos = pos @ matrix[:3, :3].T + matrix[:3, 3]
    if "indices" in prim:
        idx = _accessor(doc, buffers, prim["indices"], path, "indices").astype(np.int64)
    else:
        idx = np.arange(len(pos), dtype=np.int64)
    if idx.size % 3 or (idx.size and (idx.min() < 0 or idx.max() >= len(pos))):
        raise _fail(
            path,
            f"triangle indices: {idx.size} values (a multiple of 3 expected) in "
            f"{idx.min(initial=0)}..{idx.max(initial=0)} for {len(pos)} vertices",
        )
    return pos, idx.reshape(-1, 3), attrs


def _skin_arrays(doc, buffers, attrs, n_vertices: int, n_joints: int, path: Path):
    """JOINTS_0/WEIGHTS_0 as (V, 4) int64 (-1 where the weight is 0) and float64."""
    j = _accessor(doc, buffers, attrs["JOINTS_0"], path, "JOINTS_0").astype(np.int64)
    w = _accessor(doc, buffers, attrs["WEIGHTS_0"], path, "WEIGHTS_0")
    if j.shape != (n_vertices, 4) or w.shape != (n_vertices, 4):
        raise _fail(path, f"JOINTS_0/WEIGHTS_0 are {j.shape}/{w.shape}, expected ({n_vertices}, 4) each")
    j = np.where(w > 0, j, -1)
    if j.max(initial=-1) >= n_joints or w.min(initial=0) < 0:
        raise _fail(path, f"skin joint indices reach {j.max()} for {n_joints} joints, or a weight is negative")
    return j, w


def _skeleton(doc: dict, skin: dict, nodes: list[dict], parent: dict[int, int], world, path: Path) -> dict:
    """Rest-pose skeleton of ``skin``: names, parents, heads, tails of its joints."""
    jn = list(skin["joints"])
    jset = {n: k for k, n in enumerate(jn)}
    parents = []
    for n in jn:
        p = parent.get(n)
        while p is not None and p not in jset:
            p = parent.get(p)
        parents.append(jset[p] if p is not None else -1)
    heads = np.array([world[n][:3, 3] for n in jn]).reshape(-1, 3)
    tails = heads.copy()
    for k, n in enumerate(jn):
        kids = [jset[c] for c in nodes[n].get("children", []) if c in jset]
        if kids:
            tails[k] = heads[kids].mean(axis=0)
        elif parents[k] >= 0:
            tails[k] = heads[k] + 0.5 * (heads[k] - heads[parents[k]])
        else:
            tails[k] = heads[k] + np.array([0.0, 0.1, 0.0])
    names = [str(nodes[n].get("name", f"joint{k}"))[:200] for k, n in enumerate(jn)]
    return {"names": names, "parents": parents, "heads": heads, "tails": tails}


def _skin(doc: dict, index: Any, path: Path) -> dict:
    skin = _item(doc, "skins", index, path, "a mesh node")
    joints = skin.get("joints")
    if not isinstance(joints, list) or not joints or len(set(map(str, joints))) != len(joints):
        raise _fail(path, f"skin {index} joints is not a non-empty list of distinct nodes")
    for n in joints:
        _item(doc, "nodes", n, path, f"skin {index}")
    return skin


def _read_document(path: Path) -> tuple[dict, bytes | None]:
    try:
        raw = path.read_bytes()
    except OSError as exc:
        raise _fail(path, f"cannot read glTF ({exc.strerror})") from None
    if path.suffix.lower() == ".glb":
        doc, binary = _split_glb(raw, path)
    else:
        doc, binary = loads_json(raw, str(path), error=MeshError, hint="re-export the file as glTF 2.0"), None
    if not isinstance(doc, dict):
        raise _fail(path, "the glTF JSON is not an object")
    required = doc.get("extensionsRequired", [])
    if required:
        raise MeshError(
            f"{path}: needs glTF extensions {sorted(map(str, required))[:10]} (compressed geometry); "
            "export without compression"
        )
    return doc, binary


def read_gltf(path: str | os.PathLike) -> dict[str, Any]:
    """Read a GLB/glTF file into arrays (file units, file frame).

    Every index, count and byte range in the file is checked against what the
    file holds before it is used.

    Returns
    -------
    dict with ``vertices`` (V, 3) float64, ``faces`` (F, 3) int64 and, when the
    file has a skin, ``skeleton`` (``names``, ``parents``, ``heads``, ``tails``
    of the skin's joints in rest pose) and ``skin`` (``indices``, ``weights``,
    (V, 4); -1 for vertices of unskinned primitives).

    Raises
    ------
    MeshError
        Not glTF 2.0, truncated or inconsistent, unsupported extension or no triangles.
    """
    path = Path(path)
    doc, binary = _read_document(path)
    buffers = _buffers(doc, binary, path)
    nodes, parent, world = _node_tree(doc, path)
    vertices, faces, joints, weights = [], [], [], []
    skin_index = None
    offset = 0
    for ni in _scene_nodes(doc, nodes, path):
        node = nodes[ni]
        if "mesh" not in node:
            continue
        mesh = _item(doc, "meshes", node["mesh"], path, f"node {ni}")
        skinned = "skin" in node
        matrix = world[ni]
        if skinned:
            skin = _skin(doc, node["skin"], path)
            skin_index = node["skin"] if skin_index is None else skin_index
            if "inverseBindMatrices" in skin:
                ibm = _accessor(doc, buffers, skin["inverseBindMatrices"], path, "inverseBindMatrices")
                if ibm.shape[1] != 16 or len(ibm) == 0:
                    raise _fail(path, "inverseBindMatrices is not a non-empty MAT4 accessor")
                matrix = world[skin["joints"][0]] @ ibm[0].reshape(4, 4).T
        primitives = mesh.get("primitives", [])
        for prim in primitives if isinstance(primitives, list) else [None]:
            got = _primitive(doc, buffers, prim, matrix, path)
            if got is None:
                continue
            pos, idx, attrs = got
            if skinned and node["skin"] == skin_index and "JOINTS_0" in attrs and "WEIGHTS_0" in attrs:
                j, w = _skin_arrays(doc, buffers, attrs, len(pos), len(skin["joints"]), path)
            else:
                j, w = np.full((len(pos), 4), -1, dtype=np.int64), np.zeros((len(pos), 4))
            vertices.append(pos)
            faces.append(idx + offset)
            joints.append(j)
            weights.append(w)
            offset += len(pos)
    if not faces or not sum(len(f) for f in faces):
        raise MeshError(f"{path}: the glTF holds no triangle primitives; export the body as a mesh")
    out: dict[str, Any] = {"vertices": np.concatenate(vertices), "faces": np.concatenate(faces)}
    if not np.all(np.isfinite(out["vertices"])) or np.abs(out["vertices"]).max() > MAX_ABS:
        raise _fail(path, f"node transforms put vertices beyond ±{MAX_ABS:g}", "repair the scene's transforms")
    if skin_index is not None:
        skin = _skin(doc, skin_index, path)
        out["skeleton"] = _skeleton(doc, skin, nodes, parent, world, path)
        out["skin"] = {"indices": np.concatenate(joints), "weights": np.concatenate(weights)}
    return out
