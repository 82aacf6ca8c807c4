"""Measure the defects of a finished drape: seam lengths, anchor levels, stretch, and the faces to mark.

Pure functions over the meshed pattern and the garment's arrays; the
verdict (:mod:`.verdict`) judges what they measure.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING

import numpy as np

from ..pattern.model import Pattern
from .mesh2d import PatternMesh
from .place.wrap import anchor_position

if TYPE_CHECKING:
    from .place.length import LengthStretch

__all__ = [
    "anchor_levels_cm",
    "edge_stretch",
    "faces_touching",
    "girth_strain",
    "grain_directions",
    "hem_rise_cm",
    "seam_excess_cm",
]

GIRTH_STEP_CM = 1.0  # the garment's girths are measured on horizontal cuts this far apart
SHORT_EDGE_CM = 0.1  # pattern edges shorter than this (a corner collapsed by grading) are not measured
HEM_BAND_CM = 1.0  # the hem: boundary points within this of the piece's lowest point along its grain
HANGING_MIN_CM = 10.0  # pieces whose hem hangs less far below their anchor mark are not checked
HANGING_COS = 0.85  # ... nor those whose anchor-to-hem runs more than ~30° off the grain or, draped, off the vertical


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
        lm = anchor_position(character, body, pl, inst.copy.value == "mirror")
        if lm is None or pl.anchor_mark not in marks:
            continue
        out[inst.key] = float(abs(x[offsets[i] + marks[pl.anchor_mark], 1] - lm[1]))
    return out


def grain_directions(pattern: Pattern, pmesh: PatternMesh) -> np.ndarray:
    """(G, 2) float64: the unit grain direction of every piece instance in its pattern coordinates."""
    out = np.zeros((len(pmesh.instances), 2))
    for i, inst in enumerate(pmesh.instances):
        across = pattern.piece(inst.piece).across_grain  # the grain turned a quarter clockwise
        out[i] = (-across[1], across[0])
    return out


def hem_rise_cm(
    pattern: Pattern,
    pmesh: PatternMesh,
    x: np.ndarray,
    group: np.ndarray,
    grain: np.ndarray,
    worn: Mapping[str, LengthStretch] | None = None,
) -> dict[str, float]:
    """Instance key -> how much nearer its hem hangs to its anchor mark than the pattern has it, cm.

    The hem is the boundary of the piece within :data:`HEM_BAND_CM` of its
    farthest point along the grain from the anchor mark. The distance from the anchor mark to the
    hem's middle in the drape, less that distance in the pattern, is the rise
    (positive when the hem rode up or the cloth bunched along the grain: a
    leg ending at mid-calf instead of the ankle). Only pieces that hang from
    their anchor are measured: the hem at least :data:`HANGING_MIN_CM` below
    the mark, along the grain in the pattern and down the body in the drape
    (not a collar round the neck, nor a sleeve held out in an A pose).

    Parameters
    ----------
    x : (N, 3) float64, cm — the garment ; group : (N,) instance of each vertex
    grain : (G, 2) float64 — :func:`grain_directions`
    worn : instance key -> how a copy worn stretched to its hem's landmark was stretched
        (:mod:`.place.length`): its hem's distance is the worn one, the hem on its landmark
    """
    offsets = np.searchsorted(group, np.arange(len(pmesh.instances)))
    out: dict[str, float] = {}
    for i, inst in enumerate(pmesh.instances):
        pl = pattern.piece(inst.piece).placement
        mesh = pmesh.pieces[inst.piece]
        if pl is None or pl.anchor_mark not in mesh.marks:
            continue
        uv = mesh.points[: mesh.n_boundary]
        ls = (worn or {}).get(inst.key)
        if ls is not None:  # the worn pattern: stretched along the placement's axis below its pivot
            uv = np.stack([uv[:, 0], ls.heights(uv[:, 1])], axis=1)
        anchor = mesh.marks[pl.anchor_mark]
        along = uv @ grain[i] - uv[anchor] @ grain[i]
        down = along if along.max() > -along.min() else -along  # the grain's end away from the anchor
        hem = np.flatnonzero(down >= down.max() - HEM_BAND_CM)
        flat = uv[hem].mean(axis=0) - uv[anchor]
        length = float(np.linalg.norm(flat))
        if length < HANGING_MIN_CM or down[hem].mean() < HANGING_COS * length:
            continue
        drop = x[offsets[i] + hem].mean(axis=0) - x[offsets[i] + anchor]
        drape = float(np.linalg.norm(drop))
        if -drop[1] < HANGING_COS * drape:
            continue
        out[inst.key] = length - drape
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


def _cut(
    x: np.ndarray, uv: np.ndarray, faces: np.ndarray, edge_ids: np.ndarray, h: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The cut of each face by the plane ``y = h``.

    Returns
    -------
    drape, pattern : (F,) lengths of the cut in the drape and in the pattern (0 for faces not cut) ;
    ends : (F, 2) int64, the ids of the two edges the cut crosses (-1 for faces not cut)
    """
    y = x[faces, 1]  # (F, 3)
    above = y >= h
    seg_x = np.zeros((len(faces), 2, 3))
    seg_uv = np.zeros((len(faces), 2, 2))
    ends = np.full((len(faces), 2), -1, dtype=np.int64)
    count = np.zeros(len(faces), dtype=np.int64)
    for k, (a, b) in enumerate(((0, 1), (1, 2), (2, 0))):
        hit = above[:, a] != above[:, b]
        ya, yb = y[hit, a], y[hit, b]
        t = ((h - ya) / (yb - ya))[:, None]
        fa, fb = faces[hit, a], faces[hit, b]
        slot = np.minimum(count[hit], 1)
        seg_x[hit, slot] = x[fa] + t * (x[fb] - x[fa])
        seg_uv[hit, slot] = uv[fa] + t * (uv[fb] - uv[fa])
        ends[hit, slot] = edge_ids[hit, k]
        count[hit] += 1
    cut = count == 2  # a plane crosses a triangle's boundary at two points or none
    drape = np.where(cut, np.linalg.norm(seg_x[:, 1] - seg_x[:, 0], axis=1), 0.0)
    pattern = np.where(cut, np.linalg.norm(seg_uv[:, 1] - seg_uv[:, 0], axis=1), 0.0)
    return drape, pattern, np.where(cut[:, None], ends, -1)


def _closed(ends: np.ndarray, n_edges: int) -> np.ndarray:
    """(F,) int64: the closed curve each face's cut belongs to (-1: not cut, or a curve running off the cloth).

    A curve ending on an edge crossed by one face only runs off the cloth (a
    hem, an opening); the others close round. Curves are numbered in order of
    their lowest edge id.
    """
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    out = np.full(len(ends), -1, dtype=np.int64)
    cut = ends[:, 0] >= 0
    if not cut.any():
        return out
    e = ends[cut]
    g = coo_matrix((np.ones(len(e)), (e[:, 0], e[:, 1])), shape=(n_edges, n_edges))
    _, label = connected_components(g, directed=False)
    degree = np.bincount(e.ravel(), minlength=n_edges)
    open_curve = np.zeros(label.max() + 1, dtype=bool)
    open_curve[label[degree == 1]] = True
    curve = label[e[:, 0]]
    out[np.flatnonzero(cut)] = np.where(open_curve[curve], -1, curve)
    return out


def girth_strain(
    x: np.ndarray,
    uv: np.ndarray,
    faces: np.ndarray,
    weld: np.ndarray,
    step_cm: float = GIRTH_STEP_CM,
    skin_offset_cm: float = 0.0,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The strain of the garment's girths: its closed horizontal cuts, length worn / length in the pattern.

    The garment is cut by horizontal planes every ``step_cm`` between its
    lowest and highest point. The curves of a cut that close round (across
    the seams, on the welded garment) are girths round the body parts the
    garment dresses; curves that run off the cloth (at a hem, an opening)
    are left out. The length of the girths over the length of the same
    curves in the pattern is the strain of the cut. Folds do not shorten it
    (the curve follows the cloth), so a strain above 1 is a garment that only
    closes round the body there by stretching all the way round.

    The solver keeps the cloth ``skin_offset_cm`` off the skin (a margin for
    its contact, several times a fabric's thickness): the drape is the garment
    worn over a body that much thicker all round, and each closed curve round
    it is longer than the garment worn on the skin by the length of that
    margin all the way round. The girth worn is the curve moved in by the
    margin, the parallel curve of a closed simple curve: its length less
    2π × ``skin_offset_cm`` (a tight knit on a 33 cm calf reads 11 % more
    stretched without it). A closed curve shorter than twice that (4π ×
    the margin, a loop of cloth round nothing a garment closes round, less
    than 7.5 cm round at a margin of 0.6 cm) is a fold, not a girth.

    Parameters
    ----------
    x : (N, 3) float64, cm — the draped garment (y up)
    uv : (N, 2) float64, cm — the pattern coordinates of each vertex
    faces : (F, 3) int64
    weld : (N,) int64 — vertices sewn together share an id
    skin_offset_cm : the distance the solver kept the cloth from the skin (0: the drape's own lengths)

    Returns
    -------
    heights : (L,) float64, cm, the cuts with a closed curve ; strain : (L,) float64,
    worn / pattern length of their closed curves ; face_cut : (L, F) bool, the faces those curves cross
    """
    w = weld[faces]
    pairs = np.sort(np.stack([w[:, [0, 1]], w[:, [1, 2]], w[:, [2, 0]]], axis=1), axis=2)  # (F, 3, 2)
    _, edge_ids = np.unique(pairs.reshape(-1, 2), axis=0, return_inverse=True)
    edge_ids = edge_ids.reshape(-1, 3)
    n_edges = int(edge_ids.max()) + 1 if len(faces) else 0
    margin = 2.0 * np.pi * skin_offset_cm
    y = x[:, 1]
    heights, strain, face_cut = [], [], []
    for h in np.arange(y.min() + step_cm, y.max(), step_cm):
        drape, pattern, ends = _cut(x, uv, faces, edge_ids, float(h))
        curve = _closed(ends, n_edges)
        on = curve >= 0
        if not on.any():
            continue
        _, c = np.unique(curve[on], return_inverse=True)
        worn = np.bincount(c, weights=drape[on])
        flat = np.bincount(c, weights=pattern[on])
        girth = worn > 2.0 * margin  # a loop round a body part, not a fold
        keep = np.zeros(len(faces), dtype=bool)
        keep[np.flatnonzero(on)[girth[c]]] = True
        total = flat[girth].sum()
        if total > 0:
            heights.append(h)
            strain.append((worn[girth] - margin).sum() / total)
            face_cut.append(keep)
    return np.array(heights), np.array(strain), np.array(face_cut, dtype=bool).reshape(len(heights), len(faces))
