"""Measure a character: resolve its datum points, then take every girth and length."""

from __future__ import annotations

import logging
from collections.abc import Callable
from dataclasses import replace

import numpy as np

from ..errors import LandmarkError
from ..mesh.character import Character
from .definitions import DEFINITIONS, MEASUREMENT_IDS
from .girths import BodyFrame, measure_girths
from .lengths import measure_lengths
from .model import Measurement, Measurements

__all__ = ["measure"]

log = logging.getLogger(__name__)


def _carried_back(
    girths: dict[str, Measurement],
    rest_vertices: np.ndarray,
    vertices: np.ndarray,
    lowered_deg: dict[str, float],
) -> dict[str, Measurement]:
    """Girth polylines taken in the rest pose, moved with their nearest vertex to the given pose.

    The values stay those of the rest pose; the polylines (for pictures) follow
    the skin the user sees, and ``details["rest_pose_lowered_deg"]`` says so.
    """
    from scipy.spatial import cKDTree

    tree = cKDTree(rest_vertices)
    out = {}
    for mid, m in girths.items():
        poly = m.polyline
        if len(poly):
            _, near = tree.query(poly)
            poly = poly + (vertices[near] - rest_vertices[near])
        out[mid] = replace(m, polyline=poly, details={**m.details, "rest_pose_lowered_deg": dict(lowered_deg)})
    return out


def _check_landmarks(character: Character, marks: dict) -> None:
    """Raise LandmarkError naming the measurements that missing landmarks block."""
    needed = {n for d in DEFINITIONS.values() for n in d.landmarks} | {"top_of_head"}
    absent = sorted(n for n in needed if n not in marks)
    if absent:
        blocked = [d.id for d in DEFINITIONS.values() if set(d.landmarks) & set(absent)]
        raise LandmarkError(
            f"{character.name}: landmarks {', '.join(absent)} are missing, so {len(blocked)} measurements "
            f"({', '.join(blocked[:6])}{'...' if len(blocked) > 6 else ''}) cannot be taken; "
            "give them with --landmarks FILE or pass --partial"
        )


def _with_top_of_head(body: Character, positions: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """``positions`` (name -> (3,) cm) with the top of the head, by default the highest vertex of ``body``."""
    if "top_of_head" in positions:
        return positions
    return {**positions, "top_of_head": body.vertices[int(np.argmax(body.vertices[:, 1]))]}


def _ordered(found: dict[str, Measurement], errors: dict[str, str]) -> tuple[dict, dict]:
    """The measurements in the order of :data:`MEASUREMENT_IDS`, and why each absent one is missing."""
    ordered = {mid: found[mid] for mid in MEASUREMENT_IDS if mid in found}
    missing = {mid: errors.get(mid, "not measured") for mid in MEASUREMENT_IDS if mid not in found}
    return ordered, missing


def measure(
    character: Character,
    *,
    progress: Callable[[str, int, int], None] | None = None,
    partial: bool = False,
    detect: bool = True,
    tape: bool = True,
    rest_pose: bool = True,
) -> Measurements:
    """Every measurement of ``formats/measurements.md`` on one character.

    Parameters
    ----------
    character : the body (cm, +Y up); its ``landmarks`` are used first, then
        the skeleton's joints, then automatic detection (``detect``)
    progress : ``progress(stage, done, total)`` callback
    partial : return what could be measured and list the rest in
        ``Measurements.missing`` instead of raising
    detect : detect missing landmarks from the geometry
    tape : tape-correct the geodesic lengths
    rest_pose : a rigged character with raised arms is re-posed with its rig to
        the measuring rest pose (upper arms 45° below horizontal,
        :func:`~patternbridge.mesh.rest_pose.arms_down`); landmarks are found and
        girths taken there, while the surface lengths follow the skin of the
        given pose (what the skin itself does)

    Returns
    -------
    Measurements; ``landmarks`` records where each datum point came from.

    Raises
    ------
    LandmarkError
        (without ``partial``) landmarks are missing or a measurement could not
        be taken; the message lists them.
    """
    from ..mesh.landmarks import resolve_landmarks
    from ..mesh.rest_pose import arms_down

    rest = arms_down(character) if rest_pose else None
    body_c = rest.character if rest is not None else character
    marks = resolve_landmarks(body_c, detect=detect)
    positions = {k: lm.position for k, lm in marks.items()}  # in the measuring pose
    if rest is not None:  # back to the given pose: the same face and weights (or vertex id)
        marks = {k: lm.moved_to(character.vertices, character.faces) for k, lm in marks.items()}
        log.info("%s: measured girths with the upper arms lowered by %s", character.name, rest.lowered_deg)
    errors: dict[str, str] = {}
    if not partial:
        _check_landmarks(character, marks)
    body = BodyFrame(body_c.vertices, body_c.faces, _with_top_of_head(body_c, positions))
    girths = measure_girths(body, progress=progress, errors=errors)
    if rest is not None:
        girths = _carried_back(girths, body_c.vertices, character.vertices, rest.lowered_deg)
    lengths = measure_lengths(character.vertices, character.faces, marks, tape=tape, progress=progress, errors=errors)
    ordered, missing = _ordered({**girths, **lengths}, errors)
    if missing and not partial:
        first = next(iter(missing.items()))
        raise LandmarkError(
            f"{character.name}: {len(missing)} measurement(s) could not be taken "
            f"({', '.join(missing)}; first: {first[1]}); check the landmarks or pass --partial"
        )
    return Measurements(
        character=character.name,
        measurements=ordered,
        landmarks=marks,
        assumed=body_c.assumed,
        missing=missing,
    )
