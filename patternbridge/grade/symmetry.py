"""Mirror symmetry of pieces: found once on the design, kept as linear constraints, measured after grading.

A piece drawn whole but cut symmetric (a T-shirt front cut on the fold, a
yoke, a collar) is the same left and right about a line along the grain.
The grader keeps that: every pair of mirror vertices of its reference line
keeps one common level and one common distance from the piece's axis
(:func:`symmetry_constraints`, linear in the genes since the outline is; the
final step weighs them as a strong cost, :func:`~.refine.refine`), so the
final step cannot give the left side what it takes from the right.
:func:`symmetry_error` is the check: the largest distance between a vertex
and its partner's mirror image, in cm.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .grid import PatternGrid

__all__ = ["MirrorSymmetry", "mirror_symmetries", "symmetry_constraints", "symmetry_error"]


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class MirrorSymmetry:
    """A piece symmetric about a line parallel to the grain (the drawing y axis).

    piece : piece name ; index : piece index in the grid ;
    pairs : (r, 2) int64 local reference-line indices ``(i, j)``, ``j`` the
    mirror partner of ``i`` (``i < j``; vertices on the axis pair with
    themselves and are listed as ``(i, i)``) ; axis_cm : the axis's ``x`` in
    the design
    """

    piece: str
    index: int
    pairs: np.ndarray
    axis_cm: float


def mirror_symmetries(grid: PatternGrid, *, tol_cm: float = 0.02) -> tuple[MirrorSymmetry, ...]:
    """The pieces whose reference line is its own mirror image about a vertical line.

    The axis is the middle of the piece's ``x`` range; every vertex must have
    a partner within ``tol_cm`` of its mirror image, and the pairing must be
    one to one. Returns one :class:`MirrorSymmetry` per such piece.
    """
    out = []
    for k, g in enumerate(grid.pieces):
        pts = g.outline_weights @ g.control
        axis = 0.5 * (pts[:, 0].min() + pts[:, 0].max())
        mirrored = np.column_stack([2.0 * axis - pts[:, 0], pts[:, 1]])
        dist = np.linalg.norm(mirrored[:, None, :] - pts[None, :, :], axis=-1)
        partner = np.argmin(dist, axis=1)
        if dist[np.arange(len(pts)), partner].max() > tol_cm or not np.array_equal(partner[partner],
                                                                                   np.arange(len(pts))):
            continue
        i = np.arange(len(pts))
        keep = i <= partner
        out.append(MirrorSymmetry(piece=g.name, index=k, pairs=np.stack([i[keep], partner[keep]], axis=1),
                                  axis_cm=float(axis)))
    return tuple(out)


def symmetry_constraints(grid: PatternGrid, symmetries: tuple[MirrorSymmetry, ...]) -> np.ndarray:
    """Linear constraints ``A x = 0`` keeping every symmetric piece symmetric.

    For each pair ``(i, j)``: ``y_i − y_j = 0`` (one level) and
    ``x_i + x_j − (x_a + x_b) = 0`` (one axis for every pair, ``(a, b)`` the
    first pair), on the graded reference line ``W x``. The axis itself may
    move and the piece may widen: only the difference between its halves is
    held.

    Returns
    -------
    (n_c, n_var) float64 (redundant rows included; :func:`~.refine.row_basis`
    removes them)
    """
    rows = []
    for s in symmetries:
        g = grid.pieces[s.index]
        w = g.outline_weights
        base = grid.var_offsets[s.index] + 2 * np.arange(g.n_control)
        a, b = s.pairs[0]
        for i, j in s.pairs:
            if i != j:
                r = np.zeros(grid.n_var)
                r[base + 1] = w[i] - w[j]
                rows.append(r)
            if (i, j) != (a, b):
                r = np.zeros(grid.n_var)
                r[base] = w[i] + w[j] - w[a] - w[b]
                rows.append(r)
    return np.stack(rows) if rows else np.zeros((0, grid.n_var))


def symmetry_error(grid: PatternGrid, symmetries: tuple[MirrorSymmetry, ...], X: np.ndarray) -> np.ndarray:
    """How far each symmetric piece is from symmetric, ``(n_pop, n_sym)`` cm.

    The largest distance between a vertex and the mirror image of its
    partner about the piece's own axis (the mean of its pairs' midpoints).
    """
    X = np.atleast_2d(np.asarray(X, dtype=np.float64))
    out = np.zeros((len(X), len(symmetries)))
    for c, s in enumerate(symmetries):
        pts = grid.piece_outline(X, s.index)
        pi, pj = pts[:, s.pairs[:, 0]], pts[:, s.pairs[:, 1]]
        axis = 0.5 * (pi[..., 0] + pj[..., 0]).mean(axis=1, keepdims=True)
        dx = pi[..., 0] + pj[..., 0] - 2.0 * axis
        dy = pi[..., 1] - pj[..., 1]
        out[:, c] = np.hypot(dx, dy).max(axis=1, initial=0.0)
    return out
