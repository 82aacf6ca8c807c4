"""Measure the defects of a finished drape: seam lengths, anchor levels, stretch, and the faces to mark.

Pure functions over the meshed pattern and the garment's arrays; the
verdict (:mod:`.verdict`) judges what they measure.
"""

from __future__ import annotations

import numpy as np

from ..pattern.model import Pattern
from .mesh2d import PatternMesh
from .place.wrap import landmark_position

__all__ = ["anchor_levels_cm", "edge_stretch", "faces_touching", "seam_excess_cm"]

SHORT_EDGE_CM = 0.1  # pattern edges shorter than this (a corner collapsed by grading) are not measured


def seam_excess_cm(pattern: Pattern, pmesh: PatternMesh) -> dict[str, float]:
    """Seam id -> |(length of side b - length of side a) - declared ease|, cm, on the meshed pattern.

    The solver gathers the longer side of a seam into the shorter one; an
    excess beyond the seam's ``ease_cm`` is a pattern error it would sew
    silently into a ruffle.
    """
    ease = {s.id: s.ease_cm for s in pattern.seams}
    out: dict[str, float] = {}
    for sp in pmesh.seams:
        lengths = [
            float(np.linalg.norm(np.diff(pmesh.pieces[inst.piece].points[ids], axis=0), axis=1).sum())
            for inst, ids in ((sp.a, sp.a_vertices), (sp.b, sp.b_vertices))
        ]
        excess = abs(lengths[1] - lengths[0] - ease.get(sp.seam, 0.0))
        out[sp.seam] = max(out.get(sp.seam, 0.0), excess)
    return out


def anchor_levels_cm(
    character, body: np.ndarray, pattern: Pattern, pmesh: PatternMesh, x: np.ndarray, group: np.ndarray
) -> dict[str, float]:
    """Instance key -> |height of its anchor mark - height of the landmark it hangs from|, cm.

    Parameters
    ----------
    character : the character (landmarks)
    body : (V, 3) float64, cm — the body in the pose of ``x`` (the rest pose)
    x : (N, 3) float64, cm — the garment ; group : (N,) instance of each vertex

    Instances whose landmark the character lacks are left out.
    """
    offsets = np.searchsorted(group, np.arange(len(pmesh.instances)))
    out: dict[str, float] = {}
    for i, inst in enumerate(pmesh.instances):
        pl = pattern.piece(inst.piece).placement
        marks = pmesh.pieces[inst.piece].marks
        lm = landmark_position(character, body, pl.anchor, inst.copy.value == "mirror")
        if lm is None or pl.anchor_mark not in marks:
            continue
        out[inst.key] = float(abs(x[offsets[i] + marks[pl.anchor_mark], 1] - lm[1]))
    return out


def edge_stretch(x: np.ndarray, edges: np.ndarray, rest: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Edge length / pattern length of the measured edges, and which edges are measured.

    Returns
    -------
    ratio : (E',) float64 ; measured : (E,) bool, edges at least
    :data:`SHORT_EDGE_CM` long in the pattern (all when none is)
    """
    measured = rest >= SHORT_EDGE_CM
    if not measured.any():
        measured = np.ones_like(measured)
    e = edges[measured]
    ratio = np.linalg.norm(x[e[:, 0]] - x[e[:, 1]], axis=1) / np.maximum(rest[measured], 1e-9)
    return ratio, measured


def faces_touching(faces: np.ndarray, vertices: np.ndarray, n: int) -> np.ndarray:
    """(F,) bool: faces with a corner among ``vertices`` (ids below ``n``)."""
    mark = np.zeros(n, dtype=bool)
    mark[np.asarray(vertices, dtype=np.int64).ravel()] = True
    return mark[faces].any(axis=1)
