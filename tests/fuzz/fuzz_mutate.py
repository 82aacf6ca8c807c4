"""Seeded mutations of real input files, the classes of issue 20's malformed-input run.

Every mutation is a pure function ``(data: bytes, rng) -> bytes`` so a case is
fully described by (source file, mutation name, seed) and re-created byte for
byte. Families:

- bytes: truncation at a random offset, a run of random bytes overwritten;
- text lines: deletion and duplication of random lines;
- numbers: one numeric token replaced by NaN, ±inf, 1e308, 1e400, a huge
  integer, 0 or a denormal; every coordinate scaled by 1e300 (OBJ);
- strings: a name or text inflated to 2 MB (DXF piece name, JSON names);
- JSON: top level swapped for ``[]``/``null``, a random value swapped for
  another JSON type, a key deleted, 100 000-deep nesting, ``"pieces": []``;
- GLB: truncation, the BIN chunk dropped, accessor counts inflated beyond the
  buffer, bad component types and buffer-view indices, a node cycle, NaN in
  the positions, positions scaled to overflow.
"""

from __future__ import annotations

import json
import re
import struct
from collections.abc import Callable

import numpy as np

__all__ = ["BAD_NUMBERS", "MUTATIONS", "mutate"]

BAD_NUMBERS = (b"nan", b"NaN", b"inf", b"-inf", b"1e308", b"-1e308", b"1e400", b"99999999999999999999", b"0", b"4e-320")
_NUMBER = re.compile(rb"(?<![A-Za-z_0-9.])-?\d+(?:\.\d*)?(?:[eE][-+]?\d+)?")
HUGE = 2 * 2**20  # a 2 MB string


def _pick(rng: np.random.Generator, n: int) -> int:
    return int(rng.integers(0, max(n, 1)))


# ---------------------------------------------------------------- bytes and lines
def truncate(data: bytes, rng: np.random.Generator) -> bytes:
    return data[: _pick(rng, len(data))]


def garble(data: bytes, rng: np.random.Generator) -> bytes:
    start = _pick(rng, len(data))
    run = rng.integers(0, 256, size=int(rng.integers(1, 64)), dtype=np.uint8).tobytes()
    return data[:start] + run + data[start + len(run) :]


def _lines(data: bytes) -> list[bytes]:
    return data.splitlines(keepends=True)


def delete_lines(data: bytes, rng: np.random.Generator) -> bytes:
    lines = _lines(data)
    start = _pick(rng, len(lines))
    return b"".join(lines[:start] + lines[start + int(rng.integers(1, 4)) :])


def duplicate_lines(data: bytes, rng: np.random.Generator) -> bytes:
    lines = _lines(data)
    start = _pick(rng, len(lines))
    run = lines[start : start + int(rng.integers(1, 4))]
    return b"".join(lines[:start] + run + lines[start:])


def _replace_number(value: bytes) -> Callable[[bytes, np.random.Generator], bytes]:
    def mutation(data: bytes, rng: np.random.Generator) -> bytes:
        found = list(_NUMBER.finditer(data))
        if not found:
            return data
        m = found[_pick(rng, len(found))]
        return data[: m.start()] + value + data[m.end() :]

    return mutation


def scale_obj(data: bytes, rng: np.random.Generator) -> bytes:
    """Every ``v`` line of an OBJ multiplied by 1e300."""
    out = []
    for line in _lines(data):
        if line.startswith(b"v "):
            xyz = [float(t) * 1e300 for t in line.split()[1:4]]
            line = b"v " + b" ".join(repr(c).encode() for c in xyz) + b"\n"
        out.append(line)
    return b"".join(out)


def stray_triangle(data: bytes, rng: np.random.Generator) -> bytes:
    """One triangle 5 m above the body, in an OBJ (the unit-detection trap)."""
    n = sum(1 for line in _lines(data) if line.startswith(b"v "))
    extra = b"v 0 500 0\nv 1 500 0\nv 0 501 0\n" + f"f {n + 1} {n + 2} {n + 3}\n".encode()
    return data + extra


# ---------------------------------------------------------------- text formats
def huge_name(data: bytes, rng: np.random.Generator) -> bytes:
    """A DXF ``Piece Name:`` (or the first name-like text) inflated to 2 MB."""
    m = re.search(rb"(Piece Name: ?|\"name\": \")([^\r\n\"]*)", data)
    if m is None:
        return data
    return data[: m.start(2)] + b"N" * HUGE + data[m.end(2) :]


# ---------------------------------------------------------------- JSON
def _json(data: bytes):
    return json.loads(data.decode("utf-8"))


def _dump(obj) -> bytes:
    return json.dumps(obj, allow_nan=True).encode()


def _paths(obj, prefix=()):
    yield prefix
    if isinstance(obj, dict):
        for k, v in obj.items():
            yield from _paths(v, (*prefix, k))
    elif isinstance(obj, list):
        for i, v in enumerate(obj[:8]):  # the first items stand for the rest
            yield from _paths(v, (*prefix, i))


def _set(obj, path, value):
    if not path:
        return value
    target = obj
    for key in path[:-1]:
        target = target[key]
    target[path[-1]] = value
    return obj


_SWAPS = ([], {}, None, "x", 0, -1, True, 1e308, -1e308, float("nan"), float("inf"), 2**70, "N" * 4096)


def json_type_swap(data: bytes, rng: np.random.Generator) -> bytes:
    obj = _json(data)
    paths = list(_paths(obj))[1:]
    path = paths[_pick(rng, len(paths))]
    return _dump(_set(obj, path, _SWAPS[_pick(rng, len(_SWAPS))]))


def json_delete_key(data: bytes, rng: np.random.Generator) -> bytes:
    obj = _json(data)
    paths = [p for p in _paths(obj) if p and isinstance(p[-1], str)]
    if not paths:
        return data
    path = paths[_pick(rng, len(paths))]
    parent = obj
    for key in path[:-1]:
        parent = parent[key]
    del parent[path[-1]]
    return _dump(obj)


def json_top_level(data: bytes, rng: np.random.Generator) -> bytes:
    return (b"[]", b"null", b'"x"', b"1", b"{}", b"[" + data + b"]")[_pick(rng, 6)]


def json_deep(data: bytes, rng: np.random.Generator) -> bytes:
    """A value somewhere replaced by ``[[[...]]]`` 100 000 levels deep."""
    obj = _json(data)
    paths = list(_paths(obj))[1:]
    path = paths[_pick(rng, len(paths))]
    marker = "@@DEEP@@"
    text = _dump(_set(obj, path, marker))
    depth = 100_000
    return text.replace(f'"{marker}"'.encode(), b"[" * depth + b"]" * depth, 1)


def json_huge_string(data: bytes, rng: np.random.Generator) -> bytes:
    obj = _json(data)
    paths = [p for p in _paths(obj) if p and isinstance(_get(obj, p), str)]
    if not paths:
        return data
    return _dump(_set(obj, paths[_pick(rng, len(paths))], "N" * HUGE))


def _get(obj, path):
    for key in path:
        obj = obj[key]
    return obj


def json_no_pieces(data: bytes, rng: np.random.Generator) -> bytes:
    obj = _json(data)
    if isinstance(obj, dict) and "pieces" in obj:
        obj["pieces"] = []
    elif isinstance(obj, dict) and "measurements" in obj:
        obj["measurements"] = {}
    return _dump(obj)


def json_bad_number(data: bytes, rng: np.random.Generator) -> bytes:
    """One number of the JSON text replaced by NaN/Infinity/1e308/1e400/huge."""
    value = (b"NaN", b"Infinity", b"-Infinity", b"1e308", b"1e400", b"-1e308", b"99999999999999999999", b"0")[
        _pick(rng, 8)
    ]
    return _replace_number(value)(data, rng)


# ---------------------------------------------------------------- GLB
def _glb_parts(data: bytes) -> tuple[dict, bytes]:
    n = struct.unpack_from("<I", data, 12)[0]
    doc = json.loads(data[20 : 20 + n])
    m = struct.unpack_from("<I", data, 20 + n)[0]
    return doc, data[28 + n : 28 + n + m]


def _glb(doc: dict, binary: bytes | None) -> bytes:
    js = json.dumps(doc, allow_nan=True).encode()
    js += b" " * (-len(js) % 4)
    chunks = struct.pack("<I4s", len(js), b"JSON") + js
    if binary is not None:
        chunks += struct.pack("<I4s", len(binary), b"BIN\x00") + binary
    return struct.pack("<4sII", b"glTF", 2, 12 + len(chunks)) + chunks


def glb_drop_bin(data: bytes, rng: np.random.Generator) -> bytes:
    doc, _ = _glb_parts(data)
    return _glb(doc, None)


def glb_accessor_count(data: bytes, rng: np.random.Generator) -> bytes:
    doc, binary = _glb_parts(data)
    acc = doc["accessors"][_pick(rng, len(doc["accessors"]))]
    acc["count"] = int(acc["count"]) * int(rng.choice([2, 1000])) + 1
    return _glb(doc, binary)


def glb_accessor_field(data: bytes, rng: np.random.Generator) -> bytes:
    doc, binary = _glb_parts(data)
    acc = doc["accessors"][_pick(rng, len(doc["accessors"]))]
    key, value = [
        ("componentType", 9999),
        ("type", "VEC7"),
        ("bufferView", 99),
        ("byteOffset", 2**40),
        ("count", -1),
        ("bufferView", "0"),
    ][_pick(rng, 6)]
    acc[key] = value
    return _glb(doc, binary)


def glb_structure(data: bytes, rng: np.random.Generator) -> bytes:
    """A node cycle, a bad mesh/skin index, a missing buffer or a huge node scale."""
    doc, binary = _glb_parts(data)
    choice = _pick(rng, 6)
    nodes = doc["nodes"]
    if choice == 0 and len(nodes) > 2:
        nodes[-1].setdefault("children", []).append(1)  # cycle through the joint chain
    elif choice == 1:
        nodes[0]["mesh"] = 7
    elif choice == 2:
        nodes[0]["skin"] = 5
    elif choice == 3:
        doc["buffers"] = []
    elif choice == 4:
        nodes[0]["scale"] = [1e300, 1e300, 1e300]
    else:
        nodes[0]["matrix"] = [float("nan")] * 16
    return _glb(doc, binary)


def glb_nan_position(data: bytes, rng: np.random.Generator) -> bytes:
    doc, binary = _glb_parts(data)
    acc = doc["accessors"][doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"]]
    view = doc["bufferViews"][acc["bufferView"]]
    start = view.get("byteOffset", 0) + acc.get("byteOffset", 0) + 4 * 3 * _pick(rng, acc["count"])
    buf = bytearray(binary)
    buf[start : start + 4] = struct.pack("<f", float(rng.choice([np.nan, np.inf, 3e38])))
    return _glb(doc, bytes(buf))


def glb_scale_positions(data: bytes, rng: np.random.Generator) -> bytes:
    """Every position ×1e30 in float32 (beyond a sane mesh, still finite)."""
    doc, binary = _glb_parts(data)
    acc = doc["accessors"][doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"]]
    view = doc["bufferViews"][acc["bufferView"]]
    start = view.get("byteOffset", 0) + acc.get("byteOffset", 0)
    n = acc["count"] * 3
    pos = np.frombuffer(binary, dtype="<f4", count=n, offset=start) * np.float32(1e30)
    buf = bytearray(binary)
    buf[start : start + 4 * n] = pos.astype("<f4").tobytes()
    acc.pop("min", None), acc.pop("max", None)
    return _glb(doc, bytes(buf))


# ---------------------------------------------------------------- the catalogue
MUTATIONS: dict[str, Callable[[bytes, np.random.Generator], bytes]] = {
    "truncate": truncate,
    "garble": garble,
    "delete-lines": delete_lines,
    "duplicate-lines": duplicate_lines,
    **{f"number-{v.decode()}": _replace_number(v) for v in BAD_NUMBERS},
    "huge-name": huge_name,
    "scale-obj-1e300": scale_obj,
    "stray-triangle": stray_triangle,
    "json-type-swap": json_type_swap,
    "json-delete-key": json_delete_key,
    "json-top-level": json_top_level,
    "json-deep": json_deep,
    "json-huge-string": json_huge_string,
    "json-no-pieces": json_no_pieces,
    "json-bad-number": json_bad_number,
    "glb-truncate": truncate,
    "glb-drop-bin": glb_drop_bin,
    "glb-accessor-count": glb_accessor_count,
    "glb-accessor-field": glb_accessor_field,
    "glb-structure": glb_structure,
    "glb-nan-position": glb_nan_position,
    "glb-scale-positions": glb_scale_positions,
}


def mutate(data: bytes, mutation: str, seed: int) -> bytes:
    """Apply the named mutation to ``data`` with ``numpy.random.default_rng(seed)``."""
    return MUTATIONS[mutation](data, np.random.default_rng(seed))
