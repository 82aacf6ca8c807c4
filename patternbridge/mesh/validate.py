"""Checks of what a character file hands over: vertex arrays, the ``.json`` sidecar, landmark tables.

They run once, where the loader has read a file, and raise a one-line
:class:`~patternbridge.errors.MeshError` or
:class:`~patternbridge.errors.LandmarkError` naming the file, the field and
what was found, so nothing malformed reaches measuring or geodesics (where a
coordinate ×1e300 ended in a ``ZeroDivisionError`` or an ``IndexError``).
Unit choice is not made here: the limits are generous enough for any unit.
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from typing import Any

import numpy as np

from ..errors import LandmarkError, MeshError

__all__ = ["MAX_COORD", "check_landmark_table", "check_sidecar", "check_vertices"]

MAX_COORD = 1e7
"""Largest vertex coordinate in file units (10 km in mm); beyond it no unit makes a body."""
MIN_EXTENT = 1e-9
"""Smallest extent of a mesh in file units; below it the geometry is numerically a point."""
_MAX_NAME = 200


def _short(value: Any) -> str:
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


def check_vertices(vertices: np.ndarray, path: str | os.PathLike) -> None:
    """Raise when coordinates are not finite, beyond ``MAX_COORD`` or all (nearly) equal.

    Parameters
    ----------
    vertices : (V, 3) float64, file units
    path : the mesh file, for the message

    Raises
    ------
    MeshError
    """
    if vertices.size == 0:
        raise MeshError(f"{path}: the mesh has no vertices; export the body as a triangle mesh")
    if not np.all(np.isfinite(vertices)):
        raise MeshError(f"{path}: vertex coordinates contain NaN or infinity; repair the mesh")
    biggest = float(np.abs(vertices).max())
    if biggest > MAX_COORD:
        raise MeshError(
            f"{path}: a vertex coordinate is {biggest:.3g}, beyond ±{MAX_COORD:g} in any unit; "
            "repair or rescale the mesh"
        )
    extent = float(np.max(vertices.max(axis=0) - vertices.min(axis=0)))
    if extent < MIN_EXTENT:
        raise MeshError(f"{path}: all vertices lie within {extent:.3g} of each other; export the body itself")


def _numbers(value: Any, n: int, what: str, path, error: type) -> None:
    try:
        arr = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        arr = np.zeros(0)
    if arr.shape != (n,) or not np.all(np.isfinite(arr)) or np.abs(arr).max(initial=0) > MAX_COORD:
        count = {2: "two", 3: "three"}.get(n, str(n))
        raise error(f"{path}: {what} is {_short(value)}: not {count} numbers (finite, within ±{MAX_COORD:g}); fix it")


def _name(value: Any, what: str, path, error: type) -> None:
    if not isinstance(value, str) or not 0 < len(value) <= _MAX_NAME:
        raise error(f"{path}: {what} is {_short(value)}, expected a name of 1..{_MAX_NAME} characters; fix it")


def check_landmark_table(table: Any, path: str | os.PathLike) -> None:
    """Raise on an entry that is not ``{"vertex": id}`` or ``{"position": [x, y, z]}``.

    Raises
    ------
    LandmarkError
    """
    if not isinstance(table, Mapping):
        raise LandmarkError(f"{path}: 'landmarks' is {type(table).__name__}, expected an object; fix it")
    for name, entry in table.items():
        _name(name, "a landmark name", path, LandmarkError)
        if not isinstance(entry, Mapping):
            continue  # the loader names the expected forms
        vertex = entry.get("vertex")
        if vertex is not None and (isinstance(vertex, bool) or not isinstance(vertex, int)):
            raise LandmarkError(f"{path}: landmark {name!r} vertex {_short(vertex)} is not a vertex id; fix it")
        if vertex is None and "position" in entry:
            _numbers(entry["position"], 3, f"landmark {name!r} position", path, LandmarkError)


def _check_skeleton(skeleton: Any, path) -> int:
    if not isinstance(skeleton, Mapping) or not isinstance(skeleton.get("bones", []), list):
        raise MeshError(f"{path}: sidecar 'skeleton' is not an object with a 'bones' list; fix or remove it")
    bones = skeleton.get("bones", [])
    for k, bone in enumerate(bones):
        if not isinstance(bone, Mapping):
            raise MeshError(f"{path}: sidecar bone {k} is not an object; fix or remove it")
        _name(bone.get("name"), f"sidecar bone {k} name", path, MeshError)
        if bone.get("parent") is not None:
            _name(bone["parent"], f"sidecar bone {k} parent", path, MeshError)
        for key in ("head", "tail"):
            _numbers(bone.get(key), 3, f"sidecar bone {k} {key}", path, MeshError)
    return len(bones)


def _check_skinning(skinning: Any, n_vertices: int | None, path) -> None:
    if not isinstance(skinning, Mapping):
        raise MeshError(f"{path}: sidecar 'skinning' is not an object; fix or remove it")
    names = skinning.get("bone_names")
    if not isinstance(names, list):
        raise MeshError(f"{path}: sidecar skinning has no 'bone_names' list; fix or remove it")
    for k, n in enumerate(names):
        _name(n, f"sidecar skinning bone_names[{k}]", path, MeshError)
    try:
        idx = np.asarray(skinning.get("indices"), dtype=np.float64)
        w = np.asarray(skinning.get("weights"), dtype=np.float64)
    except (TypeError, ValueError):
        raise MeshError(f"{path}: sidecar skinning indices/weights are not number tables; fix or remove it") from None
    if idx.ndim != 2 or w.shape != idx.shape or (n_vertices is not None and len(idx) != n_vertices):
        raise MeshError(
            f"{path}: sidecar skinning indices {idx.shape} and weights {w.shape} do not match "
            f"({n_vertices} vertices); fix or remove it"
        )
    if not (np.all(np.isfinite(idx)) and np.all(idx == np.round(idx)) and np.all((-1 <= idx) & (idx < len(names)))):
        raise MeshError(f"{path}: sidecar skinning indices outside -1..{len(names) - 1}; fix or remove it")
    if not np.all(np.isfinite(w)) or (w.size and (w.min() < 0 or w.max() > 1e3)):
        raise MeshError(f"{path}: sidecar skinning weights are not finite non-negative numbers; fix or remove it")


def check_sidecar(data: Any, path: str | os.PathLike) -> None:
    """Raise when a character sidecar's fields have the wrong type, size or values.

    Only the fields the loader uses are checked: ``vertex_count``, ``units``,
    ``axes.up``, ``skeleton.bones``, ``skinning`` and ``landmarks``.

    Raises
    ------
    MeshError, LandmarkError
    """
    if not isinstance(data, Mapping):
        raise MeshError(f"{path}: the sidecar is not a JSON object; fix or remove it")
    count = data.get("vertex_count")
    if count is not None and (isinstance(count, bool) or not isinstance(count, int) or count < 0):
        raise MeshError(f"{path}: sidecar vertex_count {_short(count)} is not a count; fix or remove it")
    for key in ("units", "name"):
        if data.get(key) is not None and not (isinstance(data[key], str) and len(data[key]) <= _MAX_NAME):
            raise MeshError(f"{path}: sidecar {key} {_short(data[key])} is not a short text; fix or remove it")
    axes = data.get("axes")
    if axes is not None and not (isinstance(axes, Mapping) and isinstance(axes.get("up", ""), str)):
        raise MeshError(f"{path}: sidecar axes {_short(axes)} is not an object with an 'up' text; fix or remove it")
    if "skeleton" in data:
        _check_skeleton(data["skeleton"], path)
    if "skinning" in data:
        _check_skinning(data["skinning"], count, path)
    if "landmarks" in data:
        check_landmark_table(data["landmarks"], path)
