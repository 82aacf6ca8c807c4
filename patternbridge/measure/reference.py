"""Girths at landmark levels: the definition of the shared reference measurements.

The reference files of ``shared/characters/variants`` take the bust, waist and
hip girths on the horizontal plane at the height of the bust points,
``waist_front`` and the hip side points, keeping the section loop that holds
the body's vertical axis (the line through the middle of ``waist_front`` and
``waist_back``). Our own ``chest_girth``/``waist_girth``/``hip_girth`` search a
band for the widest or narrowest level instead; :func:`landmark_level_girths`
takes the reference's definition, so the two can be compared like with like
(``docs/measurements.md``, "Reference values").
"""

from __future__ import annotations

import itertools
from collections.abc import Mapping

import numpy as np

from ..mesh.character import Character, Landmark
from .model import Measurement, Measurements
from .section import SlabIndex, hull_girth, plane_loops

__all__ = [
    "LEVEL_GIRTHS",
    "SKIN_CHAINS",
    "WAIST_LENGTHS",
    "comparable_values",
    "landmark_level_girths",
    "skin_lengths",
    "waist_line_lengths",
    "waist_line_marks",
]

#: girth id -> landmarks whose mean height is the level
LEVEL_GIRTHS: dict[str, tuple[str, ...]] = {
    "bust_girth": ("bust_point_left", "bust_point_right"),
    "waist_girth": ("waist_front",),
    "hip_girth": ("hip_side_left", "hip_side_right"),
}

#: reference length id -> the chain of landmarks its on-skin geodesic runs through
SKIN_CHAINS: dict[str, tuple[str, ...]] = {
    **{f"arm_length_{s}": (f"shoulder_point_{s}", f"elbow_point_{s}", f"wrist_point_{s}") for s in ("left", "right")},
    "back_length": ("back_neck_point", "waist_back"),
    "shoulder_width": ("shoulder_point_left", "back_neck_point", "shoulder_point_right"),
    "inside_leg_left": ("crotch_point", "ankle_inside_left"),
    "outside_leg_left": ("waist_side_left", "ankle_outside_left"),
}


def skin_lengths(vertices: np.ndarray, faces: np.ndarray, marks: Mapping[str, Landmark]) -> dict[str, float]:
    """On-skin geodesic lengths (cm, no tape correction) of :data:`SKIN_CHAINS`.

    The path ends are the landmarks' vertices, as in the reference files.
    """
    from ..geodesic import SurfaceMesh, geodesic_path

    mesh = SurfaceMesh(vertices, faces)
    cache: dict[tuple[int, int], float] = {}
    out: dict[str, float] = {}
    for mid, chain in SKIN_CHAINS.items():
        if not all(n in marks and marks[n].vertex is not None for n in chain):
            continue
        vids = [int(marks[n].vertex) for n in chain]
        total = 0.0
        for a, b in itertools.pairwise(vids):
            key = (min(a, b), max(a, b))
            if a != b and key not in cache:
                cache[key] = float(geodesic_path(mesh, a, b, tape=False).length)
            total += cache.get(key, 0.0)
        out[mid] = total
    return out


def landmark_level_girths(
    vertices: np.ndarray, faces: np.ndarray, marks: Mapping[str, np.ndarray]
) -> dict[str, Measurement]:
    """Convex-hull girths of the torso loop at the bust, waist-front and hip-point levels.

    Parameters
    ----------
    vertices : (V, 3) float64, cm, +Y up
    faces : (F, 3) int64
    marks : landmark name -> (3,) position, cm; needs ``waist_front`` and
        ``waist_back`` (the body axis) and the level landmarks

    Returns
    -------
    id -> Measurement (ids of :data:`LEVEL_GIRTHS` whose landmarks are present)
    """
    v = np.asarray(vertices, dtype=np.float64)
    if "waist_front" not in marks or "waist_back" not in marks:
        return {}
    axis = 0.5 * (np.asarray(marks["waist_front"]) + np.asarray(marks["waist_back"]))
    slabs = _slabs(v, faces)
    out: dict[str, Measurement] = {}
    for mid, names in LEVEL_GIRTHS.items():
        if not all(n in marks for n in names):
            continue
        y = float(np.mean([marks[n][1] for n in names]))
        sec, loops = _loops_round_axis(v, faces, slabs, axis, y, nearest=True)
        if not loops:
            continue
        g, ring = hull_girth(sec, loops[-1:])
        out[mid] = Measurement(
            id=mid,
            value_cm=g,
            kind="girth",
            method="hull",
            polyline=ring,
            landmarks=names,
            details={"level_y_cm": y},
        )
    return out


def _slabs(v: np.ndarray, faces: np.ndarray) -> SlabIndex:
    """Faces by height, in slabs of 1/200 of the body's height."""
    return SlabIndex(v, faces, axis=1, slab_cm=max(float(np.ptp(v[:, 1])) / 200.0, 0.1))


def _loops_round_axis(v, faces, slabs: SlabIndex, axis: np.ndarray, y: float, *, nearest: bool):
    """The horizontal section at height ``y`` and its closed loops round the body's vertical ``axis``.

    With ``nearest``, a section with no loop round the axis gives its loop
    nearest to it instead.
    """
    sec = plane_loops(v, faces, np.array([0.0, y, 0.0]), np.array([0.0, 1.0, 0.0]), candidates=slabs.faces_at(y))
    q = sec.to_uv(np.array([axis[0], y, axis[2]]))
    loops = [lp for lp in sec.loops if lp.closed and lp.contains_uv(q)]
    if not loops and nearest and sec.loops:
        loops = [min(sec.loops, key=lambda lp: lp.distance_uv(q))]
    return sec, loops


def comparable_values(character: Character, result: Measurements) -> dict[str, float]:
    """Our values under the reference files' ids (cm), each by the reference's definition.

    Stature is ours; girths are :func:`landmark_level_girths`; lengths are
    :func:`skin_lengths` between our landmarks.
    """
    marks = {k: lm.position for k, lm in result.landmarks.items()}
    out = {"stature": result.measurements["stature"].value_cm} if "stature" in result.measurements else {}
    out.update(skin_lengths(character.vertices, character.faces, result.landmarks))
    girths = landmark_level_girths(character.vertices, character.faces, marks)
    out.update({k: m.value_cm for k, m in girths.items()})
    return out


def waist_line_marks(
    vertices: np.ndarray,
    faces: np.ndarray,
    marks: Mapping[str, Landmark],
    level_y_cm: float,
) -> dict[str, Landmark]:
    """Waist front, back and side points on the horizontal waist line at ``level_y_cm``.

    The tailor's waist is a horizontal line round the natural waist (ISO 8559-1:
    the narrowest level between the lower ribs and the hip bones); back length
    runs from the nape down the spine to it and outside leg from its side. The
    reference files' fixed template vertices sit 3-7 cm off that line on the
    women, C and D, so this gives the points the tailor's way for a comparison.

    Parameters
    ----------
    vertices : (V, 3) float64, cm, +Y up, facing +Z, left = +X
    faces : (F, 3) int64
    marks : needs ``waist_front`` and ``waist_back`` (the body's vertical axis)
    level_y_cm : height of the waist line

    Returns
    -------
    ``waist_front``, ``waist_back``, ``waist_side_left``, ``waist_side_right``
    on their nearest vertices (empty when no torso loop is found there)

    Examples
    --------
    >>> import numpy as np
    >>> from patternbridge.mesh.character import Landmark
    >>> t = np.linspace(0, 2 * np.pi, 64, endpoint=False)
    >>> ring = np.c_[10 * np.cos(t), np.zeros(64), 5 * np.sin(t)]
    >>> v = np.concatenate([ring, ring + [0, 10, 0]])
    >>> f = np.array([[i, (i + 1) % 64, 64 + i] for i in range(64)]
    ...              + [[(i + 1) % 64, 64 + (i + 1) % 64, 64 + i] for i in range(64)])
    >>> m = {n: Landmark(name=n, position=p) for n, p in
    ...      (("waist_front", [0, 5, 5]), ("waist_back", [0, 5, -5]))}
    >>> w = waist_line_marks(v, f, m, 7.0)
    >>> [round(float(c), 1) + 0.0 for c in w["waist_back"].position], w["waist_side_left"].vertex
    ([0.0, 10.0, -5.0], 64)
    """
    v = np.asarray(vertices, dtype=np.float64)
    if "waist_front" not in marks or "waist_back" not in marks:
        return {}
    axis = 0.5 * (marks["waist_front"].position + marks["waist_back"].position)
    _, loops = _loops_round_axis(v, faces, _slabs(v, faces), axis, level_y_cm, nearest=False)
    if not loops:
        return {}
    pts = loops[-1].points
    near_mid = np.abs(pts[:, 0] - axis[0])
    behind = pts[:, 2] < axis[2]
    back = pts[behind][np.argmin(near_mid[behind])] if behind.any() else pts[np.argmin(pts[:, 2])]
    front = pts[~behind][np.argmin(near_mid[~behind])] if (~behind).any() else pts[np.argmax(pts[:, 2])]
    chosen = {
        "waist_front": front,
        "waist_back": back,
        "waist_side_left": pts[np.argmax(pts[:, 0])],
        "waist_side_right": pts[np.argmin(pts[:, 0])],
    }
    out = {}
    for name, p in chosen.items():
        vid = int(np.argmin(np.sum((v - p) ** 2, axis=1)))
        out[name] = Landmark(name=name, position=v[vid], vertex=vid)
    return out


#: lengths that run to the waist, and the waist point each ends on
WAIST_LENGTHS: dict[str, str] = {"back_length": "waist_back", "outside_leg_left": "waist_side_left"}


def waist_line_lengths(
    vertices: np.ndarray,
    faces: np.ndarray,
    marks: Mapping[str, Landmark],
    level_y_cm: float,
) -> dict[str, float]:
    """On-skin :data:`WAIST_LENGTHS` (cm) with their waist ends on the waist line at ``level_y_cm``.

    The tailor's back length and outside leg (ISO 8559-1) from ``marks``, the
    waist points replaced by :func:`waist_line_marks`.
    """
    line = waist_line_marks(vertices, faces, marks, level_y_cm)
    lengths = skin_lengths(vertices, faces, {**marks, **line})
    if not line:
        return {}
    return {k: lengths[k] for k in WAIST_LENGTHS if k in lengths}
