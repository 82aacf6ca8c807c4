"""Load a character mesh (OBJ, PLY, STL, GLB/glTF) into a :class:`Character`.

The loader converts to the internal frame (centimetres, +Y up, the character
facing +Z), keeps the body component, checks the surface and picks up the
skeleton, skin weights and landmarks from a ``<stem>.json`` sidecar or from the
glTF skin. Everything it had to assume is written to ``Character.assumed`` and
to the returned :class:`~patternbridge.report.Report`.

Notes
-----
Unit detection: a standing character is between 20 and 300 cm tall. The
vertical extent is tried as centimetres, metres, millimetres and inches, in
that order (metres first for glTF, whose unit is the metre); the first unit
that gives a plausible stature wins and a Finding says when another one would
have fitted too.

Up axis: +Y or +Z, whichever has the larger extent (for a rigged file: the
axis along which the head joints lie farthest above the root). A Z-up file is
turned with ``(x, y, z) -> (x, z, -y)`` so that a character facing -Y (the
Blender convention) faces +Z afterwards.
"""

from __future__ import annotations

import functools
import logging
import os
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import InputError, LandmarkError, MeshError, UnitsError
from ..io.json_file import read_json
from ..report import Report
from ..units import unit_factor
from .character import Character, Landmark, LandmarkEvidence, Skeleton, Skin
from .frame import STATURE_RANGE_CM, detect_facing, facing_matrix, main_component
from .surface_point import locate_on_surface
from .validate import check_landmark_table, check_sidecar, check_vertices

__all__ = [
    "MESH_SUFFIXES",
    "STATURE_RANGE_CM",
    "load_character",
    "load_landmark_file",
    "mesh_defects",
    "read_mesh_arrays",
    "snap_to_surface",
]

log = logging.getLogger(__name__)

MESH_SUFFIXES = (".obj", ".ply", ".stl", ".glb", ".gltf")
_UNIT_ORDER = ("cm", "m", "mm", "in")
_UP_CHOICES = ("+Y", "-Y", "+Z", "-Z")


# --------------------------------------------------------------------------- reading
def read_mesh_arrays(path: str | os.PathLike) -> dict[str, Any]:
    """Read the triangles of a mesh file without changing vertex order.

    Returns
    -------
    dict with ``vertices`` (V, 3) float64 in file units, ``faces`` (F, 3) int64
    and, for a skinned glTF, ``skeleton`` (dict of names/parents/heads/tails,
    file frame) and ``skin`` (indices/weights (V, 4)).

    Raises
    ------
    MeshError
        The file is missing, unreadable or holds no triangles.
    """
    path = Path(path)
    suffix = path.suffix.lower()
    if not path.is_file():
        raise MeshError(f"{path}: no such file; give the path of an OBJ, PLY, STL, GLB or glTF mesh")
    if suffix not in MESH_SUFFIXES:
        raise MeshError(
            f"{path}: unsupported mesh format {suffix or '(no suffix)'!r} "
            f"(known: {', '.join(MESH_SUFFIXES)}); convert it to one of these"
        )
    if suffix in (".glb", ".gltf"):
        from .gltf import read_gltf

        return read_gltf(path)
    import trimesh

    try:
        mesh = trimesh.load(str(path), force="mesh", process=False, maintain_order=True)
    except Exception as exc:  # trimesh raises many kinds on corrupt input
        raise MeshError(
            f"{path}: cannot read the mesh ({type(exc).__name__}: {exc}); "
            f"check the file is a valid {suffix[1:].upper()}"
        ) from None
    vertices = np.asarray(getattr(mesh, "vertices", np.zeros((0, 3))), dtype=np.float64)
    faces = np.asarray(getattr(mesh, "faces", np.zeros((0, 3))), dtype=np.int64)
    if faces.ndim != 2 or faces.shape[0] == 0 or vertices.shape[0] < 3:
        raise MeshError(
            f"{path}: the file holds no triangles ({vertices.shape[0]} vertices, "
            f"{faces.shape[0] if faces.ndim == 2 else 0} faces); export the body as a triangle or polygon mesh"
        )
    if suffix == ".stl":  # STL repeats the corners of every triangle: weld exact copies
        vertices, inverse = np.unique(vertices, axis=0, return_inverse=True)
        faces = inverse.reshape(-1)[faces]
    return {"vertices": vertices, "faces": faces}


def _read_sidecar(path: Path) -> tuple[dict[str, Any] | None, str | None]:
    """The character sidecar beside ``path``, or why the JSON there is not one.

    A JSON that names one of PatternBridge's own output formats (``"format": "patternbridge-…"``, e.g. the
    measurements ``measure -o`` wrote beside the mesh) is not a character sidecar: it is left unread and named.
    """
    sidecar = path.with_suffix(".json")
    if not sidecar.is_file():
        return None, None
    data = read_json(sidecar, error=MeshError, hint="fix or remove it", what="sidecar")
    kind = data.get("format") if isinstance(data, dict) else None
    if isinstance(kind, str) and kind.startswith("patternbridge-"):
        return None, f"{sidecar} is a {kind} file, not a character sidecar: it was not read as one"
    check_sidecar(data, sidecar)
    data["_path"] = str(sidecar)
    return data, None


# --------------------------------------------------------------------------- checks
def mesh_defects(faces: np.ndarray) -> dict[str, int]:
    """Count surface defects from the triangle list alone.

    Parameters
    ----------
    faces : (F, 3) int64

    Returns
    -------
    dict with ``boundary_edges`` (edges of one face: holes), ``nonmanifold_edges``
    (edges of three or more faces) and ``degenerate_faces`` (repeated vertex ids).

    Examples
    --------
    >>> mesh_defects(np.array([[0, 1, 2]]))["boundary_edges"]
    3
    """
    faces = np.asarray(faces, dtype=np.int64)
    edges = np.sort(faces[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), axis=1)
    _, counts = np.unique(edges, axis=0, return_counts=True)
    degenerate = (faces[:, 0] == faces[:, 1]) | (faces[:, 1] == faces[:, 2]) | (faces[:, 0] == faces[:, 2])
    return {
        "boundary_edges": int(np.count_nonzero(counts == 1)),
        "nonmanifold_edges": int(np.count_nonzero(counts > 2)),
        "degenerate_faces": int(np.count_nonzero(degenerate)),
    }


def _components(n_vertices: int, faces: np.ndarray) -> np.ndarray:
    """Label of the connected component of every vertex, (V,) int64 (-1: unused)."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    a = faces[:, [0, 1, 2]].ravel()
    b = faces[:, [1, 2, 0]].ravel()
    graph = coo_matrix((np.ones(a.size, dtype=np.int8), (a, b)), shape=(n_vertices, n_vertices))
    _, labels = connected_components(graph, directed=False)
    used = np.zeros(n_vertices, dtype=bool)
    used[faces.ravel()] = True
    labels = labels.astype(np.int64)
    labels[~used] = -1
    return labels


def _face_areas(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    tri = vertices[faces]
    return 0.5 * np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1)


# --------------------------------------------------------------------------- frame
def _up_matrix(up: str) -> np.ndarray:
    """Rotation taking the file frame with ``up`` to +Y up (row vectors: v @ R.T)."""
    return {
        "+Y": np.eye(3),
        "-Y": np.array([[1.0, 0, 0], [0, -1, 0], [0, 0, -1]]),
        "+Z": np.array([[1.0, 0, 0], [0, 0, 1], [0, -1, 0]]),
        "-Z": np.array([[1.0, 0, 0], [0, 0, -1], [0, 1, 0]]),
    }[up]


def _normalise_up(up: str, path: Path) -> str:
    key = up.strip().upper()
    if not key.startswith(("+", "-")):
        key = "+" + key
    if key not in _UP_CHOICES:
        raise InputError(f"{path}: unknown up axis {up!r} (known: {', '.join(_UP_CHOICES)}); pass --up Y or --up Z")
    return key


def _detect_up(vertices: np.ndarray, skeleton: dict | None) -> tuple[str, str]:
    if skeleton is not None and len(skeleton["names"]) > 1:
        heads = np.asarray(skeleton["heads"], dtype=np.float64)
        names = [n.lower() for n in skeleton["names"]]
        head_ids = [i for i, n in enumerate(names) if "head" in n or "neck" in n]
        root = heads[0]
        if head_ids:
            d = heads[head_ids].mean(axis=0) - root
            axis = 1 if abs(d[1]) >= abs(d[2]) else 2
            sign = "+" if d[axis] >= 0 else "-"
            return f"{sign}{'YZ'[axis - 1]}", "skeleton (head joints above the root)"
    ext = np.ptp(vertices, axis=0)
    if ext[2] > 1.15 * ext[1]:
        return "+Z", f"extents (z {ext[2]:.4g} > y {ext[1]:.4g})"
    return "+Y", f"extents (y {ext[1]:.4g} >= z {ext[2]:.4g})"


def _detect_units(height: float, preferred: str | None, path: Path, report: Report) -> str:
    lo, hi = STATURE_RANGE_CM
    order = list(_UNIT_ORDER)
    if preferred in order:
        order.remove(preferred)
        order.insert(0, preferred)
    fits = [u for u in order if lo <= height * unit_factor(u) <= hi]
    if not fits:
        tried = ", ".join(f"{height * unit_factor(u):.4g} cm as {u}" for u in _UNIT_ORDER)
        raise UnitsError(
            f"{path}: no unit gives a stature between {lo:g} and {hi:g} cm (height {height:.4g} "
            f"file units: {tried}); pass --units or check the mesh is one standing character"
        )
    if len(fits) > 1:
        others = ", ".join(f"{u} ({height * unit_factor(u):.4g} cm)" for u in fits[1:])
        report.add(
            "units-ambiguous",
            f"assumed {fits[0]} (stature {height * unit_factor(fits[0]):.4g} cm); {others} "
            "would also be plausible: pass --units to be sure",
            where=str(path),
        )
    return fits[0]


def _frame_up(
    up: str | None, sidecar: dict | None, body_v: np.ndarray, skel_raw: dict | None, path: Path
) -> tuple[str, str]:
    if up is not None:
        return _normalise_up(up, path), "given"
    if sidecar is not None and isinstance(sidecar.get("axes"), dict) and sidecar["axes"].get("up"):
        return _normalise_up(str(sidecar["axes"]["up"]), path), "sidecar"
    return _detect_up(body_v, skel_raw)


def _frame_units(units: str | None, sidecar: dict | None, height: float, path: Path, report: Report) -> tuple[str, str]:
    """The unit of the file and why; a given or sidecar unit must give a plausible stature."""
    lo, hi = STATURE_RANGE_CM
    if units is not None or (sidecar is not None and sidecar.get("units")):
        unit, why = (units, "given") if units is not None else (str(sidecar["units"]), "sidecar")
        try:
            stature = height * unit_factor(unit)
        except UnitsError as exc:
            raise UnitsError(f"{path}: {'--units' if why == 'given' else 'sidecar units'}: {exc}") from None
        if not lo <= stature <= hi:
            what = f"--units {unit}" if why == "given" else f"the sidecar's units {unit!r}"
            raise UnitsError(
                f"{path}: with {what} the stature would be {stature:.4g} cm, outside the plausible "
                f"{lo:g}..{hi:g} cm (body height {height:.4g} file units); check the units and the up axis"
            )
        return unit, why
    if path.suffix.lower() in (".glb", ".gltf"):
        stature = height * unit_factor("m")
        if lo <= stature <= hi:
            return "m", "glTF"
        report.add(
            "units-not-metres",
            f"a glTF is in metres, but then the body would be {stature:.4g} cm tall; "
            "detecting the unit from the stature instead",
            where=str(path),
        )
    unit = _detect_units(height, None, path, report)
    report.add(
        "units-assumed",
        f"units assumed {unit} from the stature of the main component ({height * unit_factor(unit):.4g} cm)",
        where=str(path),
    )
    return unit, "detected from stature"


def _sidecar_facing(sidecar: dict | None, rot: np.ndarray) -> str | None:
    """The sidecar's forward axis (``axes: {"forward ...": "-Y"}``) in the +Y-up frame."""
    axes = sidecar.get("axes") if sidecar is not None else None
    if not isinstance(axes, dict):
        return None
    fwd = next((str(v) for k, v in axes.items() if str(k).startswith(("forward", "facing"))), "")
    key = fwd.strip().upper()
    key = key if key.startswith(("+", "-")) else "+" + key
    if len(key) != 2 or key[1] not in "XYZ":
        return None
    vec = np.zeros(3)
    vec["XYZ".index(key[1])] = 1.0 if key[0] == "+" else -1.0
    turned = rot @ vec
    axis = int(np.argmax(np.abs(turned)))
    if axis == 1:
        return None
    return f"{'+' if turned[axis] > 0 else '-'}{'XYZ'[axis]}"


def _frame_facing(
    sidecar: dict | None, rot: np.ndarray, body_cm: np.ndarray, path: Path, report: Report
) -> tuple[str, str]:
    """Which way the body faces (in the +Y-up frame) and why; the loader turns it to +Z."""
    given = _sidecar_facing(sidecar, rot)
    if given is not None:
        return given, "sidecar"
    facing = detect_facing(body_cm)
    if facing.confidence < 0.3:
        report.add(
            "facing-uncertain",
            f"could not tell which way the body faces ({facing.evidence}); assumed +Z",
            where=str(path),
        )
        return "+Z", f"assumed; {facing.evidence}"
    if facing.direction != "+Z":
        report.add(
            "facing-turned",
            f"the body faces {facing.direction} ({facing.evidence}); turned it to face +Z",
            where=str(path),
            fixed=True,
        )
    return facing.direction, f"detected: {facing.evidence}"


# --------------------------------------------------------------------------- landmarks
def load_landmark_file(path: str | os.PathLike) -> dict[str, dict[str, Any]]:
    """Read a landmark file: ``{"landmarks": {name: {"vertex": id} | {"position": [x, y, z]}}}``.

    Raises
    ------
    LandmarkError
        Unreadable file, missing ``landmarks`` object, or an entry with neither
        a vertex nor a position.
    """
    path = Path(path)
    data = read_json(path, error=LandmarkError, hint="give a JSON file with a 'landmarks' object", what="landmark file")
    table = data.get("landmarks") if isinstance(data, dict) else None
    if not isinstance(table, dict):
        raise LandmarkError(
            f"{path}: no 'landmarks' object "
            f"(top-level keys: {sorted(data) if isinstance(data, dict) else type(data).__name__}); "
            'write {"landmarks": {"name": {"vertex": id}}}'
        )
    return _check_landmark_table(table, str(path))


def _check_landmark_table(table: Mapping[str, Any], where: str) -> dict[str, dict[str, Any]]:
    from .landmarks import LANDMARK_NAMES

    check_landmark_table(table, where)
    out: dict[str, dict[str, Any]] = {}
    for name, entry in table.items():
        if name not in LANDMARK_NAMES:
            raise LandmarkError(
                f"{where}: unknown landmark {name!r} (known: {', '.join(LANDMARK_NAMES)}); rename or remove it"
            )
        if not isinstance(entry, dict) or ("vertex" not in entry and "position" not in entry):
            raise LandmarkError(
                f"{where}: landmark {name!r} has neither 'vertex' nor 'position' ({entry!r}); "
                'give {"vertex": id} or {"position": [x, y, z]}'
            )
        out[name] = dict(entry)
    return out


def _place_landmarks(
    table: Mapping[str, Mapping[str, Any]],
    vertices: np.ndarray,
    faces: np.ndarray,
    old_to_new: np.ndarray,
    transform,
    where: str,
    source: str,
) -> dict[str, Landmark]:
    """Turn a checked landmark table into :class:`Landmark` objects on the kept mesh."""
    n_old = old_to_new.shape[0]
    out: dict[str, Landmark] = {}
    snap_names, snap_points = [], []
    for name, entry in table.items():
        if "vertex" in entry and entry["vertex"] is not None:
            vid = entry["vertex"]
            if not isinstance(vid, (int, np.integer)) or not 0 <= int(vid) < n_old:
                raise LandmarkError(
                    f"{where}: landmark {name!r} vertex {vid!r} is out of range (mesh has {n_old} vertices); "
                    "use ids of this mesh"
                )
            new = int(old_to_new[int(vid)])
            if new < 0:
                raise LandmarkError(
                    f"{where}: landmark {name!r} vertex {vid} is not on the body component; "
                    "use ids of the body or pass --landmarks with positions"
                )
            out[name] = Landmark(
                name=name,
                position=vertices[new],
                vertex=new,
                source=source,
                evidence=LandmarkEvidence(rule=f"{Path(where).name}: vertex {int(vid)}"),
            )
        else:
            p = np.asarray(entry["position"], dtype=np.float64)
            if p.shape != (3,) or not np.all(np.isfinite(p)):
                raise LandmarkError(
                    f"{where}: landmark {name!r} position {entry['position']!r} is not three numbers; fix it"
                )
            snap_names.append(name)
            snap_points.append(transform(p[None])[0])
    if snap_names:
        at = locate_on_surface(vertices, faces, np.array(snap_points))
        moved = np.linalg.norm(at.positions - np.asarray(snap_points), axis=1)
        for i, (name, d) in enumerate(zip(snap_names, moved, strict=True)):
            out[name] = at.landmark(
                i,
                name,
                source=source,
                evidence=LandmarkEvidence(rule=f"{Path(where).name}: position, snapped {d:.2g} cm to the surface"),
            )
    return out


def snap_to_surface(vertices: np.ndarray, faces: np.ndarray, points: np.ndarray):
    """Closest surface points and their nearest vertex (:func:`locate_on_surface`).

    Returns
    -------
    positions : (n, 3) float64, on the surface
    vertex : (n,) int64, the nearest vertex of the face the point lies on
    """
    where = locate_on_surface(vertices, faces, points)
    return where.positions, where.vertex


def _sidecar_rig(sidecar: dict | None, raw: dict) -> tuple[dict | None, dict | None]:
    """The skeleton and skin in the file frame: the sidecar's, else the mesh file's (glTF skin)."""
    skel_raw: dict | None = raw.get("skeleton")
    skin_raw: dict | None = raw.get("skin")
    if sidecar is not None and "skeleton" in sidecar:
        bones = sidecar["skeleton"].get("bones", [])
        names = [b["name"] for b in bones]
        index = {n: i for i, n in enumerate(names)}
        skel_raw = {
            "names": names,
            "parents": [index.get(b.get("parent"), -1) if b.get("parent") else -1 for b in bones],
            "heads": [b["head"] for b in bones],
            "tails": [b["tail"] for b in bones],
        }
        if "skinning" in sidecar:
            s = sidecar["skinning"]
            remap = np.array([index.get(n, -1) for n in s["bone_names"]] + [-1], dtype=np.int64)
            idx = np.asarray(s["indices"], dtype=np.int64)
            skin_raw = {
                "indices": remap[idx],
                "weights": np.asarray(s["weights"], dtype=np.float64),
            }
    return skel_raw, skin_raw


def _mesh_checks(new_faces: np.ndarray, path: Path, report: Report) -> None:
    """Holes, non-manifold and degenerate faces become findings; too many non-manifold edges an error."""
    where = str(path)
    defects = mesh_defects(new_faces)
    if defects["boundary_edges"]:
        report.add(
            "mesh-holes",
            f"the body has holes ({defects['boundary_edges']} boundary edges); girths are unaffected, "
            "geodesic lengths may detour around them",
            where=where,
        )
    if defects["nonmanifold_edges"]:
        n_nm = defects["nonmanifold_edges"]
        if n_nm > 0.05 * len(new_faces):
            raise MeshError(
                f"{path}: {n_nm} non-manifold edges out of {len(new_faces) * 3 // 2} "
                "(more than 5 %); repair the mesh (merge by distance, remove internal faces)"
            )
        report.add(
            "mesh-nonmanifold",
            f"{n_nm} non-manifold edges (shared by 3+ faces); geodesic lengths may be less accurate",
            where=where,
        )
    if defects["degenerate_faces"]:
        report.add(
            "mesh-degenerate",
            f"{defects['degenerate_faces']} degenerate triangles",
            where=where,
        )


def _rig_in_frame(skel_raw, skin_raw, transform, shift, keep: np.ndarray, report: Report, path: Path):
    """Skeleton and skin in the internal frame, the skin cut to the body component."""
    where = str(path)
    skeleton = skin = None
    if skel_raw is not None and len(skel_raw["names"]):
        skeleton = Skeleton(
            names=tuple(skel_raw["names"]),
            parents=np.asarray(skel_raw["parents"], dtype=np.int64),
            heads=transform(np.asarray(skel_raw["heads"])) + shift,
            tails=transform(np.asarray(skel_raw["tails"])) + shift,
        )
        if skin_raw is not None:
            idx = np.asarray(skin_raw["indices"], dtype=np.int64)
            w = np.asarray(skin_raw["weights"], dtype=np.float64)
            if idx.shape[0] == len(keep):
                idx = idx[keep]
                w = np.where(idx >= 0, w[keep], 0.0)
                total = w.sum(axis=1, keepdims=True)
                w = np.divide(w, total, out=np.zeros_like(w), where=total > 0)
                skin = Skin(bone_indices=idx, weights=w)
            else:
                report.add(
                    "skin-mismatch",
                    "skin weights do not match the vertex count and were ignored",
                    where=where,
                )
    return skeleton, skin


def _landmark_tables(sidecar: dict | None, landmarks, path: Path) -> list[tuple[Mapping[str, Any], str]]:
    """Checked landmark tables with where they came from: the sidecar's, then the given file's."""
    tables: list[tuple[Mapping[str, Any], str]] = []
    if sidecar is not None and isinstance(sidecar.get("landmarks"), dict):
        path_ = sidecar["_path"]
        tables.append((_check_landmark_table(sidecar["landmarks"], path_), path_))
    if landmarks is not None:
        if isinstance(landmarks, Mapping):
            lm_where = "landmarks"
            table = landmarks.get("landmarks", landmarks)
            if not isinstance(table, Mapping):
                raise LandmarkError("landmarks: no 'landmarks' object; give {name: {'vertex': id}}")
            table = _check_landmark_table(table, lm_where)
        else:
            lm_where = str(landmarks)
            table = load_landmark_file(landmarks)
        by_id = [n for n, e in table.items() if e.get("vertex") is not None]
        if by_id and path.suffix.lower() == ".stl":
            raise LandmarkError(
                f"{lm_where}: landmark {by_id[0]!r} is given by vertex id, but an STL file "
                f"has no vertex ids (its triangles repeat their corners; {path.name}); "
                'give {"position": [x, y, z]} for STL meshes'
            )
        tables.append((table, lm_where))
    return tables


# --------------------------------------------------------------------------- main
@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class _FileFrame:
    """How the file's coordinates map to the internal frame, and why.

    rotation : (3, 3) float64, file axes to +Y up facing +Z
    factor : file unit to cm
    unit, up, facing : the file's unit, up axis and facing (in the +Y-up frame)
    *_why : the evidence for each
    """

    rotation: np.ndarray
    factor: float
    unit: str
    unit_why: str
    up: str
    up_why: str
    facing: str
    facing_why: str


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class _Body:
    """The body component in the internal frame (before standing it on the floor).

    vertices : (n, 3) float64, cm ; faces : (F, 3) int64 into ``vertices``
    keep : (V,) bool, the file's vertices that belong to the body
    old_to_new : (V,) int64, file vertex id to body vertex id (-1 = dropped)
    component : which component was kept, in words
    """

    vertices: np.ndarray
    faces: np.ndarray
    keep: np.ndarray
    old_to_new: np.ndarray
    component: str


def _read_checked(path: Path) -> dict[str, Any]:
    """The file's arrays, with finite vertices and face indices in range."""
    raw = read_mesh_arrays(path)
    vertices, faces = raw["vertices"], raw["faces"]
    check_vertices(vertices, path)
    if faces.min() < 0 or faces.max() >= len(vertices):
        raise MeshError(
            f"{path}: face indices out of range "
            f"(0..{len(vertices) - 1} expected, got {faces.min()}..{faces.max()}); repair the mesh"
        )
    return raw


def _usable_sidecar(path: Path, n_vertices: int, report: Report) -> dict | None:
    """The sidecar beside ``path`` when there is one for a mesh of ``n_vertices``."""
    where = str(path)
    sidecar, not_sidecar = _read_sidecar(path)
    if not_sidecar is not None:
        report.add("sidecar-ignored", not_sidecar, where=where)
    if sidecar is not None and int(sidecar.get("vertex_count", n_vertices)) != n_vertices:
        report.add(
            "sidecar-mismatch",
            f"sidecar {sidecar['_path']} is for {sidecar.get('vertex_count')} vertices, the mesh has "
            f"{n_vertices}: its skeleton, skin and landmarks were ignored",
            where=where,
        )
        return None
    return sidecar


def _file_frame(
    body_v: np.ndarray,
    path: Path,
    report: Report,
    *,
    up: str | None,
    units: str | None,
    sidecar: dict | None,
    skel_raw: dict | None,
) -> _FileFrame:
    """Up axis, unit and facing, each given, from the sidecar or detected on the body's vertices."""
    up_key, up_why = _frame_up(up, sidecar, body_v, skel_raw, path)
    rot = _up_matrix(up_key)
    height = float(np.ptp(body_v @ rot.T[:, 1]))
    unit, units_why = _frame_units(units, sidecar, height, path, report)
    factor = unit_factor(unit)
    facing, facing_why = _frame_facing(sidecar, rot, (body_v @ rot.T) * factor, path, report)
    return _FileFrame(
        rotation=facing_matrix(facing) @ rot,
        factor=factor,
        unit=unit,
        unit_why=units_why,
        up=up_key,
        up_why=up_why,
        facing=facing,
        facing_why=facing_why,
    )


def _to_frame(frame: _FileFrame, p: np.ndarray) -> np.ndarray:
    """(n, 3) file points in the internal frame (cm, +Y up, facing +Z)."""
    return (np.asarray(p, dtype=np.float64) @ frame.rotation.T) * frame.factor


def _body_mesh(
    v_all: np.ndarray, faces: np.ndarray, labels: np.ndarray, body: int, path: Path, report: Report
) -> _Body:
    """Component ``body`` of the mesh (``labels`` per vertex); the others become a finding."""
    where = str(path)
    n_comp = int(labels.max()) + 1
    if n_comp > 1:
        areas = np.bincount(labels[faces[:, 0]], weights=_face_areas(v_all, faces), minlength=n_comp)
        counts = np.bincount(labels[labels >= 0], minlength=n_comp)
        component = f"{body} of {n_comp} (largest by area, {counts[body]} vertices, {areas[body]:.4g} cm²)"
        report.add(
            "components",
            f"{n_comp} connected components; measured the largest by area ({counts[body]} vertices), "
            f"ignored {n_comp - 1} (eyes, teeth, props...)",
            where=where,
        )
    else:
        component = f"0 of 1 ({int(np.count_nonzero(labels == 0))} vertices)"
    keep = labels == body
    old_to_new = np.full(len(v_all), -1, dtype=np.int64)
    old_to_new[keep] = np.arange(int(np.count_nonzero(keep)))
    new_faces = old_to_new[faces[keep[faces[:, 0]]]]
    if len(new_faces) < 4:
        raise MeshError(f"{path}: the body component has only {len(new_faces)} triangles; give a body mesh")
    if n_comp == 1 and not np.all(keep):
        report.add(
            "unused-vertices",
            f"{int(np.count_nonzero(~keep))} vertices belong to no face and were dropped",
            where=where,
        )
    return _Body(vertices=v_all[keep], faces=new_faces, keep=keep, old_to_new=old_to_new, component=component)


def _floor_shift(vertices: np.ndarray, path: Path, report: Report) -> np.ndarray:
    """(3,) the move that stands the body on y = 0; zero when it is within 0.5 cm already."""
    floor = float(vertices[:, 1].min())
    shift = np.zeros(3)
    if abs(floor) > 0.5:
        shift[1] = -floor
        report.add(
            "floor-moved",
            f"moved the body by {-floor:+.4g} cm in y to stand on y = 0",
            where=str(path),
            fixed=True,
        )
    return shift


def _file_landmarks(
    tables: list[tuple[Mapping[str, Any], str]], body: _Body, vertices: np.ndarray, place
) -> dict[str, Landmark]:
    """The landmarks of the tables on the body (later tables override earlier ones)."""
    marks: dict[str, Landmark] = {}
    for table, lm_where in tables:
        marks.update(_place_landmarks(table, vertices, body.faces, body.old_to_new, place, lm_where, "file"))
    return marks


def _assumed(path: Path, frame: _FileFrame, body: _Body, shift: np.ndarray, rig: str) -> dict[str, str]:
    """``Character.assumed``: what the loader found or assumed, in words."""
    return {
        "source": path.name,
        "units": f"{frame.unit} ({frame.unit_why})",
        "up": f"{frame.up} ({frame.up_why})",
        "facing": f"{frame.facing} ({frame.facing_why})",
        "component": body.component,
        "floor": f"y = 0 (moved {shift[1]:+.4g} cm)" if shift[1] else "y = 0",
        "rig": rig,
    }


def load_character(
    path: str | os.PathLike,
    *,
    units: str | None = None,
    up: str | None = None,
    landmarks: str | os.PathLike | Mapping[str, Any] | None = None,
) -> tuple[Character, Report]:
    """Load a character mesh in cm, +Y up, with its rig and landmarks when known.

    Parameters
    ----------
    path : OBJ, PLY, STL, GLB or glTF file. A ``<stem>.json`` sidecar beside it
        (as in ``shared/characters``) supplies units, skeleton, skin and landmarks.
    units : source length unit (``"m"``, ``"cm"``, ``"mm"``, ``"in"``...);
        detected from the stature when None.
    up : ``"Y"``/``"+Y"``, ``"-Y"``, ``"Z"``/``"+Z"`` or ``"-Z"``; detected when None.
    landmarks : a landmark JSON file or an already parsed
        ``{name: {"vertex": id} | {"position": [x, y, z]}}`` mapping (or the
        whole file object with a ``landmarks`` key). Vertex ids index the file's
        vertices; positions are in the file's units and frame and snap to the
        surface. Overrides sidecar landmarks of the same name.

    Returns
    -------
    character : :class:`Character`; ``assumed`` holds ``units``, ``up``,
        ``component``, ``source`` and ``floor``. Landmarks from the sidecar or
        the ``landmarks`` argument have source ``"file"``.
    report : findings (holes, non-manifold edges, ambiguous units, extra
        components dropped, sidecar ignored...).

    Raises
    ------
    MeshError, UnitsError, LandmarkError, InputError
    """
    path = Path(path)
    report = Report()
    raw = _read_checked(path)
    vertices, faces = raw["vertices"], raw["faces"]
    sidecar = _usable_sidecar(path, len(vertices), report)
    skel_raw, skin_raw = _sidecar_rig(sidecar, raw)

    # the main component first: the frame and units are read from the body, not strays
    labels = _components(len(vertices), faces)
    body_id = main_component(labels, faces, _face_areas(vertices, faces)) if labels.max() > 0 else 0
    frame = _file_frame(
        vertices[labels == body_id], path, report, up=up, units=units, sidecar=sidecar, skel_raw=skel_raw
    )
    transform = functools.partial(_to_frame, frame)
    body = _body_mesh(transform(vertices), faces, labels, body_id, path, report)
    shift = _floor_shift(body.vertices, path, report)
    new_vertices = body.vertices + shift if shift[1] else body.vertices
    _mesh_checks(body.faces, path, report)

    skeleton, skin = _rig_in_frame(skel_raw, skin_raw, transform, shift, body.keep, report, path)
    marks = _file_landmarks(
        _landmark_tables(sidecar, landmarks, path), body, new_vertices, lambda p: transform(p) + shift
    )
    rig = (
        "sidecar" if sidecar is not None and skeleton is not None else ("gltf skin" if skeleton is not None else "none")
    )
    assumed = _assumed(path, frame, body, shift, rig)
    character = Character(
        vertices=new_vertices,
        faces=body.faces,
        name=path.stem,
        skeleton=skeleton,
        skin=skin,
        landmarks=marks,
        assumed=assumed,
    )
    log.info("loaded %s: %d vertices, %d faces, %s", path.name, len(new_vertices), len(body.faces), assumed)
    return character, report
