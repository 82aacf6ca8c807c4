"""Tape lengths: geodesic paths between datum points, chained through intermediate points.

Each leg is a geodesic of :mod:`patternbridge.geodesic` with tape correction
(the tape bridges hollows such as the spine groove or the gluteal cleft
instead of following the skin into them), except the legs listed in
:data:`ON_SKIN`, where the tape is held on the body (inside and outside leg).
A multi-point length (arm length:
shoulder point, elbow point, wrist point) is the sum of its legs, so the tape
bends at the intermediate points as a tailor's does. Heights (stature, knee
height) are vertical distances to the floor, not surface paths.
"""

from __future__ import annotations

import itertools
import logging
from collections.abc import Callable, Mapping, Sequence

import numpy as np

from ..errors import InputError, LandmarkError
from ..mesh.character import Landmark
from .definitions import DEFINITIONS
from .model import Measurement

__all__ = ["HEIGHTS", "ON_SKIN", "PATHS", "landmark_path_end", "measure_lengths"]

log = logging.getLogger(__name__)

#: geodesic length id -> chain(s) of landmark names; several chains are averaged
PATHS: dict[str, tuple[tuple[str, ...], ...]] = {
    "back_length": (("back_neck_point", "waist_back"),),
    "front_length": (("front_neck_point", "waist_front"),),
    "shoulder_width": (("shoulder_point_left", "back_neck_point", "shoulder_point_right"),),
    "back_width": (("axilla_back_left", "axilla_back_right"),),
    "front_width": (("axilla_front_left", "axilla_front_right"),),
    "waist_to_hip": (
        ("waist_side_left", "hip_side_left"),
        ("waist_side_right", "hip_side_right"),
    ),
    "side_length": (
        ("armpit_point_left", "waist_side_left"),
        ("armpit_point_right", "waist_side_right"),
    ),
    "crotch_length": (("waist_front", "crotch_point", "waist_back"),),
    **{
        f"{base}_{s}": (tuple(n.format(s=s) for n in chain),)
        for s in ("left", "right")
        for base, chain in {
            "shoulder_length": ("neck_shoulder_point_{s}", "shoulder_point_{s}"),
            "armhole": ("axilla_front_{s}", "shoulder_point_{s}", "axilla_back_{s}"),
            "arm_length": ("shoulder_point_{s}", "elbow_point_{s}", "wrist_point_{s}"),
            "neck_to_wrist": (
                "back_neck_point",
                "shoulder_point_{s}",
                "elbow_point_{s}",
                "wrist_point_{s}",
            ),
            "inside_leg": ("crotch_point", "ankle_inside_{s}"),
            "outside_leg": ("waist_side_{s}", "hip_side_{s}", "ankle_outside_{s}"),
        }.items()
    },
}

#: legs of a chain (by index) that follow the skin instead of bridging hollows:
#: a tailor holds the leg tapes on the leg, so their fall from the crotch or the
#: hip to the ankle keeps to the inner or outer leg (a taut chord would cut
#: across the A-pose leg's concave profile through the air)
ON_SKIN: dict[str, frozenset[int]] = {
    **{f"inside_leg_{s}": frozenset({0}) for s in ("left", "right")},
    **{f"outside_leg_{s}": frozenset({1}) for s in ("left", "right")},
}

#: vertical heights: id -> landmark
HEIGHTS: dict[str, str] = {
    "stature": "top_of_head",
    "knee_height_left": "knee_point_left",
    "knee_height_right": "knee_point_right",
}


def landmark_path_end(lm: Landmark, vertices: np.ndarray, faces: np.ndarray):
    """The landmark as a geodesic path end (:class:`~patternbridge.geodesic.SurfacePoint`) and its nearest vertex id.

    Its face and weights when it lies between vertices, else its vertex. A
    landmark known only by its position is first located on the surface
    (:func:`~patternbridge.mesh.surface_point.locate_on_surface`): the tape
    starts at the closest surface point, not at the nearest vertex, which
    lies up to half an edge away.

    Parameters
    ----------
    lm : the landmark ; vertices : (V, 3) float64, cm ; faces : (F, 3) int64 — the surface it lies on
    """
    from ..geodesic import SurfacePoint

    if lm.face is None and lm.vertex is None:
        from ..mesh.surface_point import locate_on_surface

        lm = locate_on_surface(vertices, faces, lm.position[None]).landmark(0, lm.name)
    if lm.face is None:
        return SurfacePoint.vertex(lm.vertex), int(lm.vertex)
    nearest = lm.vertex if lm.vertex is not None else faces[lm.face][int(np.argmax(lm.bary))]
    return SurfacePoint(face=lm.face, bary=lm.bary), int(nearest)


def _fail(errors: dict[str, str] | None, mid: str, exc: Exception) -> None:
    """Record ``exc`` as why ``mid`` failed, or raise it when failures are not collected."""
    if errors is None:
        raise exc
    errors[mid] = str(exc)


def _heights(
    ids: Sequence[str], landmarks: Mapping[str, Landmark], floor: float, errors: dict[str, str] | None
) -> dict[str, Measurement]:
    """The :data:`HEIGHTS` among ``ids``: vertical distance of the landmark above ``floor``."""
    out: dict[str, Measurement] = {}
    for mid in [m for m in ids if m in HEIGHTS]:
        name = HEIGHTS[mid]
        if name not in landmarks:
            _fail(errors, mid, LandmarkError(f"{mid}: landmark {name!r} is missing"))
            continue
        p = landmarks[name].position
        poly = np.array([p, [p[0], floor, p[2]]])
        out[mid] = Measurement(
            id=mid,
            value_cm=float(p[1] - floor),
            kind="length",
            method="vertical",
            polyline=poly,
            landmarks=(name,),
            details={"floor_y_cm": floor},
        )
    return out


def _has_tape() -> bool:
    import importlib.util

    if importlib.util.find_spec("patternbridge.geodesic.tape") is None:
        log.warning("tape correction is not available in this build; lengths follow the skin")
        return False
    return True


class _Legs:
    """Geodesic legs between surface points, each computed once (a reversed leg reuses its twin)."""

    def __init__(self, mesh) -> None:
        self.mesh = mesh
        self.cache: dict[tuple[object, object, bool], tuple[np.ndarray, float]] = {}

    def __call__(self, a, b, taut: bool) -> tuple[np.ndarray, float]:
        """(k, 3) points from ``a`` to ``b`` and the length, cm; ``taut`` applies the tape correction."""
        from ..geodesic import geodesic_path

        key = (a, b, taut)
        if key not in self.cache:
            if (b, a, taut) in self.cache:
                p = self.cache[(b, a, taut)]
                self.cache[key] = (p[0][::-1], p[1])
            else:
                path = geodesic_path(self.mesh, a, b, tape=taut)
                self.cache[key] = (np.asarray(path.points, dtype=np.float64), float(path.length))
        return self.cache[key]


def _chain(
    chain: tuple[str, ...], landmarks: Mapping[str, Landmark], legs: _Legs, skin: frozenset[int], tape: bool
) -> tuple[float, np.ndarray, list[float]]:
    """Length (cm) and (k, 3) path of a chain of landmarks, and the length of each leg.

    Legs whose index is in ``skin`` follow the skin; the others are taut when
    ``tape``. A leg between coincident points is skipped.
    """
    vids = [landmark_path_end(landmarks[n], legs.mesh.vertices, legs.mesh.faces)[0] for n in chain]
    total, pts, lengths = 0.0, [], []
    for j, (a, b) in enumerate(itertools.pairwise(vids)):
        if a == b:
            continue
        p, length = legs(a, b, tape and j not in skin)
        total += length
        lengths.append(length)
        pts.append(p if not pts else p[1:])
    return total, (np.concatenate(pts) if pts else landmarks[chain[0]].position[None]), lengths


def _path_length(mid: str, landmarks: Mapping[str, Landmark], legs: _Legs, tape: bool) -> Measurement:
    """The geodesic length ``mid`` of :data:`PATHS`: the mean of its chains, drawn along the first.

    Raises
    ------
    InputError
        When a leg cannot be found on the surface.
    """
    chains = PATHS[mid]
    values, polylines, leg_lengths = [], [], []
    for chain in chains:
        total, polyline, lengths = _chain(chain, landmarks, legs, ON_SKIN.get(mid, frozenset()), tape)
        values.append(total)
        polylines.append(polyline)
        leg_lengths += lengths
    ends = (landmarks[chains[0][0]].position, landmarks[chains[0][-1]].position)
    return Measurement(
        id=mid,
        value_cm=float(np.mean(values)),
        kind="length",
        method="geodesic",
        polyline=polylines[0],
        landmarks=tuple(DEFINITIONS[mid].landmarks),
        details={
            "legs_cm": leg_lengths,
            "straight_cm": float(np.linalg.norm(ends[1] - ends[0])),
            "tape": tape,
            **({"per_side_cm": values} if len(values) > 1 else {}),
        },
    )


def measure_lengths(
    vertices: np.ndarray,
    faces: np.ndarray,
    landmarks: Mapping[str, Landmark],
    *,
    ids: Sequence[str] | None = None,
    tape: bool = True,
    progress: Callable[[str, int, int], None] | None = None,
    errors: dict[str, str] | None = None,
) -> dict[str, Measurement]:
    """Geodesic lengths and heights.

    Parameters
    ----------
    vertices : (V, 3) float64, cm, +Y up
    faces : (F, 3) int64
    landmarks : name -> Landmark (their surface points are the path ends)
    ids : which lengths (default: all of :data:`PATHS` and :data:`HEIGHTS`)
    tape : apply the tape correction
    errors : when given, failures are recorded there (id -> reason) instead of raised

    Returns
    -------
    id -> Measurement (``polyline`` is the path; ``details`` holds the length of
    every leg and the straight-line distance between the end points).
    """
    ids = list(ids) if ids is not None else [*HEIGHTS, *PATHS]
    out = _heights(ids, landmarks, float(vertices[:, 1].min()), errors)
    todo = [m for m in ids if m in PATHS]
    if not todo:
        return out
    from ..geodesic import SurfaceMesh

    legs = _Legs(SurfaceMesh(vertices, faces))
    tape = tape and _has_tape()
    for i, mid in enumerate(todo):
        missing = sorted({n for chain in PATHS[mid] for n in chain if n not in landmarks})
        if missing:
            _fail(errors, mid, LandmarkError(f"{mid}: landmark(s) {', '.join(missing)} missing"))
            continue
        try:
            out[mid] = _path_length(mid, landmarks, legs, tape)
        except InputError as exc:
            _fail(errors, mid, exc)
            continue
        if progress is not None:
            progress("lengths", i + 1, len(todo))
    return out
