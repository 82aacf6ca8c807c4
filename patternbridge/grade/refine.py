"""The grader's final step: least change of shape subject to the fit.

NSGA-II (:mod:`.run`) finds the trade-off between the three objectives and the
basin of good solutions; it does not close seams to a tenth of a millimetre.
:func:`refine` finishes a solution with a deterministic **constrained**
Gauss–Newton method (sequential quadratic programming):

    minimise    ½‖s(x)‖²                      (shape: inner-angle changes, grid smoothness, ...)
    subject to  c(x) = 0                       (seam length mismatches, notch offsets)
                A x = 0                        (straight grain-parallel edges stay straight, no tilt;
                                                grain lines keep their direction)
                ℓ(x) = ℓ_ref                   (every dart keeps its length; its intake is free)
                |m(x) − t| ≤ tol               (every measurement within a band around its target)

A small L1 cost on ``m(x) − t`` inside the band (``w_fit``) keeps most
measurements exact instead of at the band edge.

Every iteration linearises ``s``, ``c`` and ``m`` (forward differences, the
perturbed individuals evaluated as one population) and solves the quadratic
sub-problem ``min ½‖s + J_s d‖² + ½μ‖d‖²`` under the linearised constraints
with a small primal active set for the measurement band, each solve one KKT
system. The damping ``μ`` adapts (Levenberg–Marquardt) on an exact-penalty
merit function. Unlike a penalty repair, the fit residuals are not traded
against the shape: the fit is a constraint, and all the remaining freedom goes
to keeping the design.

:func:`straight_edges` finds the edges a pattern maker keeps straight: runs of
the reference line that are straight and parallel or perpendicular to the
grain (the drawing axes), such as a centre front, a fold, a straight hem or a
waistband edge. They stay straight and keep their direction exactly (linear
equality constraints on the genes).
"""

from __future__ import annotations

import logging
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from .bands import band_axes
from .extents import unlinked_axes
from .grid import PatternGrid, map_weights
from .objectives import (
    FOLD_MARGIN,
    ObjectiveData,
    across_legs,
    angle_change,
    balanced_links,
    dart_lengths,
    link_error,
    link_shares,
    measurement_error,
    piece_axes_turn,
)
from .solution import Progress
from .step_terms import StepTerms
from .suppression import suppression

__all__ = [
    "RefineResult",
    "StraightEdge",
    "design_deviation",
    "grain_constraints",
    "grain_tilt",
    "refine",
    "row_basis",
    "straight_constraints",
    "straight_edges",
]

log = logging.getLogger(__name__)



@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class StraightEdge:
    """A straight run of a piece's reference line parallel to a drawing axis.

    piece : piece name ; points : (r,) int64 local outline indices, in order ;
    axis : 0 when the run is parallel to y (constant x, e.g. a centre front
    along the grain), 1 when parallel to x (constant y, e.g. a straight hem) ;
    length_cm : its length in the original pattern ;
    cut : the run is on the cut outline (else on the reference line, the
    sew line when the piece has one) ;
    direction : (2,) unit direction of the run's chord in the original
    (within ``tol_deg`` of its axis: a fold drawn 0.06° off the axis is a
    straight edge all the same); default the axis direction
    """

    piece: str
    points: np.ndarray
    axis: int
    length_cm: float
    cut: bool = False
    direction: np.ndarray | None = None

    def __post_init__(self) -> None:
        d = np.zeros(2) if self.direction is None else np.array(self.direction, dtype=np.float64)
        if self.direction is None:
            d[1 - self.axis] = 1.0
        d.flags.writeable = False
        object.__setattr__(self, "direction", d)


def straight_edges(
    grid: PatternGrid,
    *,
    tol_deg: float = 0.5,
    min_length_frac: float = 0.15,
    max_offset_cm: float = 0.02,
) -> tuple[StraightEdge, ...]:
    """Straight, axis-parallel runs of every piece's reference line.

    A run is a maximal sequence of consecutive outline edges, each within
    ``tol_deg`` of the same drawing axis, whose vertices all lie within
    ``max_offset_cm`` of the chord joining its ends (a long fold drawn a
    hair off the axis counts: measured from an axis-parallel line its 65 cm
    would leave 0.7 mm), and which is at least
    ``min_length_frac`` of the piece's extent long. Both the reference line
    and (when it differs) the cut outline are searched, so a straight centre
    front stays straight on the stitching line and on the cutting line.
    """
    out = []
    tan = np.tan(np.radians(tol_deg))
    lines = [(k, g, False) for k, g in enumerate(grid.pieces)]
    lines += [(k, g, True) for k, g in enumerate(grid.pieces) if g.cut_weights is not g.outline_weights
              and not np.array_equal(g.cut_weights, g.outline_weights)]
    for _k, g, cut in lines:
        pts = (g.cut_weights if cut else g.outline_weights) @ g.control
        n = len(pts)
        d = np.roll(pts, -1, axis=0) - pts
        for axis in (0, 1):
            along, across = d[:, 1 - axis], d[:, axis]
            flag = (np.abs(along) > 1e-9) & (np.abs(across) <= tan * np.abs(along))
            if flag.all() or not flag.any():
                continue
            start = int(np.flatnonzero(~flag)[0])
            order = (start + 1 + np.arange(n)) % n  # begin right after a non-flagged edge
            runs, cur = [], []
            for e in order:
                if flag[e] and (not cur or np.sign(along[e]) == np.sign(along[cur[0]])):
                    cur.append(int(e))
                else:
                    if cur:
                        runs.append(cur)
                    cur = [int(e)] if flag[e] else []
            if cur:
                runs.append(cur)
            for run in runs:
                idx = np.array([*run, (run[-1] + 1) % n], dtype=np.int64)
                chord = pts[idx[-1]] - pts[idx[0]]
                u = chord / max(float(np.hypot(*chord)), 1e-12)
                rel = pts[idx] - pts[idx[0]]
                offset = rel[:, 1] * u[0] - rel[:, 0] * u[1]  # distance from the chord
                length = float(np.abs(along[run]).sum())
                if np.ptp(offset) <= max_offset_cm and length >= min_length_frac * g.extent_cm:
                    out.append(StraightEdge(piece=g.name, points=idx, axis=axis, length_cm=length, cut=cut,
                                            direction=u))
    return tuple(out)


def straight_constraints(grid: PatternGrid, edges: tuple[StraightEdge, ...]) -> np.ndarray:
    """Linear constraints ``A x = 0`` keeping ``edges`` straight and in their original direction.

    For every edge, each vertex's offset from the line through its first
    vertex along the edge's original direction ``u`` (``u × (p_i − p_0)``;
    for an axis-parallel edge the constant coordinate minus that of the
    first vertex), taken at the vertices' projections onto the run's chord:
    the original meets the constraints exactly, and the run's own drawing
    noise (up to ``max_offset_cm``) is carried along instead of flattened by
    the cells it lies in; redundant rows are removed (orthonormal row basis).

    Returns
    -------
    (n_c, n_var) float64
    """
    rows = []
    for e in edges:
        k = grid.piece_index(e.piece)
        g = grid.pieces[k]
        weights = g.cut_weights if e.cut else g.outline_weights
        # taken at the run's vertices projected onto its chord: a drawn run
        # lies within 0.2 mm of its chord, not on it, and holding the
        # vertices themselves on one line asks every cell they cross at
        # slightly different heights to flatten (a CLO sleeve hem's 0.19 mm
        # of drawing noise pulled the row above onto the fold limit)
        # (a vertex on its chord keeps its own row: exactly straight runs, the
        # library's, keep exactly the rows they had)
        pts = weights[e.points] @ g.control
        rel = pts - pts[0]
        off = rel[:, 1] * e.direction[0] - rel[:, 0] * e.direction[1]
        wp = weights[e.points].copy()
        noisy = np.abs(off) > 1e-6  # cm: float noise, far below any drawing noise
        if noisy.any():
            on_chord = pts[0] + np.outer(rel[noisy] @ e.direction, e.direction)
            wp[noisy] = map_weights(on_chord, g.xs, g.ys, g.deformation)
        w = wp[1:] - wp[0][None, :]
        r = np.zeros((len(w), grid.n_var))
        base = grid.var_offsets[k] + 2 * np.arange(g.n_control)
        # the offset of every vertex from the line through the first along the original direction
        r[:, base] = -e.direction[1] * w
        r[:, base + 1] = e.direction[0] * w
        rows.append(r)
    if not rows:
        return np.zeros((0, grid.n_var))
    return row_basis(np.concatenate(rows))


def row_basis(a: np.ndarray) -> np.ndarray:
    """Orthonormal basis ``(r, n)`` of the rows of ``a (m, n)``: the same constraints ``a x = 0``, none redundant."""
    a = np.atleast_2d(np.asarray(a, dtype=np.float64))
    if not len(a):
        return a
    _, s, vt = np.linalg.svd(a, full_matrices=False)
    keep = s > 1e-9 * max(s.max(), 1.0)
    return vt[keep]


def _grain_weights(grid: PatternGrid) -> list[tuple[int, np.ndarray, np.ndarray]]:
    """Per piece with a grain line: (piece index, (2, m) grid weights of its ends, (2,) unit direction)."""
    out = []
    for k, (piece, g) in enumerate(zip(grid.pattern.pieces, grid.pieces, strict=False)):
        line = piece.grain_line
        if line is None:
            continue
        pts = np.asarray(line.points, dtype=np.float64)
        d = pts[-1] - pts[0]
        if np.hypot(*d) < 1e-6:
            continue
        w = map_weights(pts[[0, -1]], g.xs, g.ys, g.deformation)
        out.append((k, w, d / np.hypot(*d)))
    return out


def grain_constraints(grid: PatternGrid) -> np.ndarray:
    """Linear constraints ``A x = 0`` keeping every grain line in its original direction.

    The grain line's ends move with the grid (fixed ``(u, v)``), so the cross
    product of its original direction ``d0`` with the graded line,
    ``d0 × (p1 - p0)``, is linear in the genes; zero means the line has not
    turned. In the drawing frame, where the straight edges also keep their
    axis directions, this is the grain of the cloth: a graded piece cut with
    a tilted grain hangs askew.

    Returns
    -------
    (n_c, n_var) float64, one row per piece with a grain line
    """
    rows = []
    for k, w, d0 in _grain_weights(grid):
        g = grid.pieces[k]
        dw = w[1] - w[0]
        r = np.zeros(grid.n_var)
        base = grid.var_offsets[k] + 2 * np.arange(g.n_control)
        r[base] = -d0[1] * dw
        r[base + 1] = d0[0] * dw
        rows.append(r)
    if not rows:
        return np.zeros((0, grid.n_var))
    return row_basis(np.stack(rows))


def grain_tilt(grid: PatternGrid, X: np.ndarray) -> np.ndarray:
    """Turn of every grain line against the original, ``(n_pop, n_grain)`` rad (in piece order)."""
    X = np.atleast_2d(np.asarray(X, dtype=np.float64))
    out = []
    for k, w, d0 in _grain_weights(grid):
        c = grid.control(X, k).reshape(len(X), -1, 2)
        d = np.einsum("m,pmc->pc", w[1] - w[0], c)
        out.append(np.arctan2(d0[0] * d[:, 1] - d0[1] * d[:, 0], d @ d0))
    return np.stack(out, axis=1) if out else np.zeros((len(X), 0))


def design_deviation(grid: PatternGrid, X: np.ndarray, x_ref: np.ndarray, *, slack: float = 0.0,
                     pieces: Sequence[int] | None = None) -> np.ndarray:
    """Log-ratio of every grid interval's length to the same interval of ``x_ref``.

    For every piece, the distance between each pair of neighbouring control
    points (along both grid directions) divided by that distance in the
    reference individual, as a natural logarithm, times
    ``1 / sqrt(n_intervals · n_pieces)`` so every piece weighs alike and
    ``‖·‖²`` is a mean over pieces of per-piece means. Invariant to moving and
    rotating a piece. With ``x_ref`` the proportional (per-axis scaled)
    solution it measures how far the piece's dimensions have left the
    proportions of the design: a few per cent of stretch costs little, a cuff
    that loses its height or a front that gives its hem width to the back
    costs a lot (the logarithm grows without bound as an interval
    collapses), while the angles at the critical points may not change.

    Parameters
    ----------
    X : (n_pop, n_var) genes ; x_ref : (n_var,) reference genes
    pieces : piece indices to compute the terms of (in that order; the
        normalisation stays the whole pattern's), None for all

    Returns
    -------
    (n_pop, n_terms) float64, dimensionless
    """
    X = np.atleast_2d(np.asarray(X, dtype=np.float64))
    ref = np.asarray(x_ref, dtype=np.float64)[None, :]
    parts = []
    n_pieces = max(len(grid.pieces), 1)
    for k in range(len(grid.pieces)) if pieces is None else pieces:
        g = grid.pieces[k]
        c, c_ref = grid.control(X, k), grid.control(ref, k)
        eps2 = (1e-3 * g.extent_cm) ** 2
        lengths = []
        for axis in (1, 2):
            if c.shape[axis] < 2:
                continue
            v = np.diff(c, axis=axis).reshape(len(X), -1, 2)
            v_ref = np.diff(c_ref, axis=axis).reshape(1, -1, 2)
            r = 0.5 * np.log(((v ** 2).sum(axis=-1) + eps2) / ((v_ref ** 2).sum(axis=-1) + eps2))
            lengths.append(np.sign(r) * np.maximum(np.abs(r) - slack, 0.0))
            # turn of the interval against the reference: a sheared grid
            # (a tilted grain line) keeps its lengths but not its directions
            lengths.append(np.arctan2(v_ref[..., 0] * v[..., 1] - v_ref[..., 1] * v[..., 0],
                                      (v_ref * v).sum(axis=-1)))
        if lengths:
            t = np.concatenate(lengths, axis=1)
            parts.append(t / np.sqrt(t.shape[1] * n_pieces))
    if not parts:
        return np.zeros((len(X), 0))
    return np.concatenate(parts, axis=1)


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class RefineResult:
    """Outcome of :func:`refine`.

    x : (n_var,) refined genes ; iterations : outer iterations run ;
    shape_cost : ½‖s‖² at ``x`` ; max_violation_cm : worst remaining
    violation of the seam, notch and measurement-band constraints ;
    converged : the last step was below the step tolerance with every
    constraint met
    """

    x: np.ndarray
    iterations: int
    shape_cost: float
    max_violation_cm: float
    converged: bool


def _solve_qp(H, g, A_eq, b_eq, Jm, lo, hi, *, max_active: int = 30):
    """``min ½dᵀHd + gᵀd`` s.t. ``A_eq d = b_eq``, ``lo ≤ Jm d ≤ hi`` (primal active set)."""
    n = len(g)
    active: dict[int, float] = {}  # link -> bound value (in d-space)
    d = np.zeros(n)
    for _ in range(max_active):
        idx = sorted(active)
        A = np.vstack([A_eq, Jm[idx]]) if idx else A_eq
        b = np.concatenate([b_eq, [active[i] for i in idx]]) if idx else b_eq
        m = len(A)
        K = np.zeros((n + m, n + m))
        K[:n, :n] = H
        K[:n, n:] = A.T
        K[n:, :n] = A
        # a tiny negative diagonal makes the KKT matrix quasi-definite, so
        # repeated constraints (a seam and its mirror copy) do not make it
        # singular
        K[n:, n:] = -1e-10 * np.eye(m)
        rhs = np.concatenate([-g, b])
        try:
            sol = np.linalg.solve(K, rhs)
        except np.linalg.LinAlgError:
            sol = np.linalg.lstsq(K, rhs, rcond=1e-12)[0]
        d = sol[:n]
        lam = sol[n + len(b_eq):]
        changed = False
        # release bounds whose multiplier pushes the wrong way
        for i, li in zip(idx, lam, strict=False):
            upper = active[i] >= hi[i] - 1e-12
            if (upper and li < -1e-9) or (not upper and li > 1e-9):
                del active[i]
                changed = True
        lin = Jm @ d
        for i in range(len(lo)):
            if i in active:
                continue
            if lin[i] > hi[i] + 1e-9:
                active[i] = hi[i]
                changed = True
            elif lin[i] < lo[i] - 1e-9:
                active[i] = lo[i]
                changed = True
        if not changed:
            break
    return d


def refine(
    grid: PatternGrid,
    data: ObjectiveData,
    x: np.ndarray,
    *,
    measure_tol_cm: float = 0.15,
    straight: np.ndarray | None = None,
    max_iter: int = 40,
    w_shape: float = 1.0,
    w_all: float = 1.0,
    w_interval: float = 0.01,
    w_turn: float = 0.005,
    w_direction: float = 0.0,
    w_proportion: float = 0.0,
    w_rotation: float = 0.05,
    w_axes: float = 2.0,
    w_shift: float = 0.01,
    w_bend: float = 0.02,
    irls_eps: float = 1e-3,
    min_cell_ratio: float = 0.4,
    w_cell: float = 0.3,
    max_push_cm: float = 2.0,
    x_design: np.ndarray | None = None,
    w_design: float = 0.7,
    design_slack: float = 0.0,
    w_share: float = 3.0,
    w_suppress: float = 0.0,
    keep_darts: bool = True,
    dart_cap: bool = False,
    w_band: float = 1.0,
    w_extent: float = 1.0,
    w_fit: float = 0.02,
    fit_eps_cm: float = 0.01,
    stall_window: int = 10,
    symmetric: np.ndarray | None = None,
    w_symmetry: float = 3.0,
    progress: Progress | None = None,
) -> RefineResult:
    """Least change of shape subject to the fit, from the individual ``x``.

    Parameters
    ----------
    grid, data : the grading problem
    x : (n_var,) start (e.g. the NSGA-II choice)
    measure_tol_cm : half-width of the band around every measurement target
    straight : (n_c, n_var) linear constraints ``A x = 0``
        (:func:`straight_constraints`), or None
    max_iter : outer Gauss–Newton iterations
    w_* : weights of the shape terms: the inner-angle changes at the critical
        points and at every vertex (``w_shape``; weighted so that ``½‖s‖²``
        is the squared counterpart of the shape objective), stitch-interval
        differences and turning-angle disagreement along seams, direction of
        the spans between critical points, their proportions, each piece's
        rotation and drift, and the grid smoothness term
    x_design : (n_var,) design-preservation reference, normally the
        proportional (per-axis scaled) solution, or None for no such term
    w_design : weight of :func:`design_deviation` from ``x_design``: the
        dimensions no measurement or seam fixes (a cuff's height, the split
        of a girth between front and back) follow the proportional solution
        instead of drifting where the angle terms cannot see them
    w_axes : weight (per rad, beyond a free 2°, :data:`~.step_terms.SHEAR_SLACK`)
        of the shear of every piece under its best-fit linear map against
        ``x_design``'s (:func:`~.objectives.piece_axes_turn`), which straight
        edges along one axis and the angle terms at a few corners let
        through (a loose tank's back slanted 10° off its fold)
    w_share : weight of each piece's share of the links with legs on
        several pieces that add up (:func:`~.objectives.balanced_links`),
        against the design's share
    w_suppress : weight of the design's split of every reduction between
        two girth levels of a piece among its darts' intake and its seams'
        slopes (:mod:`.suppression`), per unit of share, over the root of
        the number of parts
    keep_darts : every dart keeps the length it has in ``x_design`` (or in
        ``x``): an equality constraint; its intake stays free. The grid gives
        a dart lines of its own (:func:`~.grid.pattern_darts`), and without
        this the step lengthened the slim female's back dart past the hip
        line, which changes no angle
    dart_cap : with ``keep_darts``, a dart may shorten but not lengthen
        (a strong one-sided cost instead of the equality): with the split of
        the reduction held (``w_suppress``), a dart whose intake shrinks
        keeps its angle by shortening
    w_band : weight, per cm, of the width of every band (a placket, a
        collar stand, a binding: a piece at most :data:`~.bands.BAND_ASPECT`
        as wide as long whose width no measurement link governs,
        :func:`~.bands.band_axes`) against its sample width; without it
        nothing but the bending term holds that width and the pieces sewn to
        a band drag it (a polo's collar stand graded to 0.65 of its height)
    w_extent : weight, per unit of log ratio beyond
        :data:`~.extents.EXTENT_SLACK`, of every piece's spread along a
        drawing axis no link runs along (:func:`~.extents.unlinked_axes`: a
        yoke's height) against ``x_design``'s (or ``x``'s); without it the
        seams fix only the sum of a yoke's and a back's heights and the
        step moved the yoke seam up (the apple-shaped woman's yoke graded
        to 0.36 of its proportional height)
    w_fit : cost of the measurement errors inside the band, in rad of shape
        error per cm of mean ``|m − t|``: iteratively reweighted
        (``1/sqrt(|m − t| + fit_eps_cm)``) so that it acts as an L1 cost,
        which leaves most measurements exact; 0 spends the whole band on
        the shape
    symmetric : (n_s, n_var) linear rows that are zero on a symmetric piece
        (:func:`~.symmetry.symmetry_constraints`), or None
    w_symmetry : weight of ``symmetric @ x`` per cm: a strong cost rather
        than a constraint, because on a symmetric piece every right-side
        seam and notch is the mirror of a left-side one and, as hard
        constraints, the two sets are dependent up to finite-difference
        noise (the step stalled 0.02 mm from feasible on the T-shirt)
    stall_window : iterations without a 1 % fall of the shape cost (with
        the fit met) after which the step stops (5 halves the iterations but
        leaves the slim female's trousers above scaling's shape error)
    progress : ``progress("refine", i, max_iter)``

    Returns
    -------
    RefineResult
    """
    x = np.asarray(x, dtype=np.float64).copy()
    scale = np.concatenate([np.full(2 * g.n_control, g.extent_cm) for g in grid.pieces])
    A_st = np.zeros((0, len(x))) if straight is None else np.asarray(straight, dtype=np.float64)
    A_sym = None if symmetric is None or not len(symmetric) else np.asarray(symmetric, dtype=np.float64)
    x_des = None if x_design is None else np.asarray(x_design, dtype=np.float64)
    x_ref = np.asarray(x if x_design is None else x_design, dtype=np.float64)
    share_ref, shared, axes_ref = _design_shares(grid, data, x_des)
    bands = band_axes(data) if w_band > 0 else None
    extents = (unlinked_axes(grid, data, grid.outlines(x_ref[None, :])[0],
                             skip=bands.pieces if bands is not None else None)
               if w_extent > 0 else None)
    terms = StepTerms.build(
        grid, data, straight=A_st, symmetric=A_sym, x_design=x_des,
        level=across_legs(data),
        dart_ref=dart_lengths(data, grid.outlines(x_ref[None, :]))[0] if keep_darts else None,
        share_ref=share_ref, shared=shared, axes_ref=axes_ref,
        suppress=suppression(grid, data) if x_design is not None and w_suppress > 0 else None,
        w_suppress=w_suppress, dart_cap=dart_cap, w_axes=w_axes,
        bands=bands, w_band=w_band, extents=extents, w_extent=w_extent, w_rotation=w_rotation,
        w_shift=w_shift, w_bend=w_bend,
        w_cell=w_cell, min_cell_ratio=min_cell_ratio, w_design=w_design, design_slack=design_slack,
        w_share=w_share, w_fit=w_fit, w_interval=w_interval, w_turn=w_turn, w_symmetry=w_symmetry,
        w_proportion=w_proportion, w_direction=w_direction)
    step = _StepProblem(grid=grid, data=data, terms=terms, measure_tol_cm=measure_tol_cm, scale=scale,
                        h=1e-6 * scale, damp=np.diag((scale.mean() / scale) ** 2),
                        weights=_base_weights(data, w_shape=w_shape, w_all=w_all, w_fit=w_fit),
                        irls_eps=irls_eps, fit_eps_cm=fit_eps_cm)
    return _gauss_newton(step, x, max_iter=max_iter, max_push_cm=max_push_cm, stall_window=stall_window,
                         progress=progress)


def _design_shares(grid: PatternGrid, data: ObjectiveData, x_design: np.ndarray | None):
    """``(share_ref, shared, axes_ref)`` the design terms hold, or three Nones without ``x_design``.

    The design's own split of every girth over several pieces (a sum of
    positive legs), not proportional scaling's: per-axis factors per piece
    move it by themselves; the drawing axes' turn is ``x_design``'s.
    """
    if x_design is None:
        return None, None, None
    shared = balanced_links(data)
    share_ref = link_shares(data, data.points0[None])[0][:, :, shared]
    axes_ref = piece_axes_turn(data, grid.outlines(x_design[None, :]))[0]
    return share_ref, shared, axes_ref


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class _BaseWeights:
    """Weights of the shape and fit terms before the reweighting.

    critical : (K,) per critical point, so that ½‖s‖² of their terms is the
    squared counterpart of the shape objective (per-piece means, pieces
    weighted alike) ; every : every outline vertex's ; fit : the
    measurement errors'
    """

    critical: np.ndarray
    every: float
    fit: float


def _base_weights(data: ObjectiveData, *, w_shape: float, w_all: float, w_fit: float) -> _BaseWeights:
    """:class:`_BaseWeights` from the step's ``w_shape``, ``w_all`` and ``w_fit``."""
    P = len(data.centre0)
    crit_piece = data.piece_of_point[data.critical]
    per_piece = np.bincount(crit_piece, minlength=P).astype(np.float64)
    n_pieces = max(int((per_piece > 0).sum()), 1)
    return _BaseWeights(
        critical=w_shape * np.sqrt(1.0 / (n_pieces * np.maximum(per_piece[crit_piece], 1.0))),
        every=w_all * np.sqrt(1.0 / max(len(data.points0), 1)),
        fit=np.sqrt(w_fit / max(len(data.target_cm), 1)))


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class _StepProblem:
    """What every iteration of one :func:`refine` run shares.

    scale : (n_var,) each gene's piece extent, cm ; h : (n_var,) its
    finite-difference step ; damp : (n_var, n_var) the Levenberg–Marquardt
    damping's metric
    """

    grid: PatternGrid
    data: ObjectiveData
    terms: StepTerms
    measure_tol_cm: float
    scale: np.ndarray
    h: np.ndarray
    damp: np.ndarray
    weights: _BaseWeights
    irls_eps: float
    fit_eps_cm: float


@dataclass(frozen=True, slots=True, eq=False)
class _Point:
    """An iterate: genes ``x (n_var,)`` with its shape terms ``s``, constraints ``c`` and measurements ``m``."""

    x: np.ndarray
    s: np.ndarray
    c: np.ndarray
    m: np.ndarray


def _irls_weights(prob: _StepProblem, x: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(wc, wa, wm)``: the weights of the critical-point, every-vertex and fit terms at ``x``.

    Iteratively reweighted least squares: ``w = 1/sqrt(|d| + eps)`` makes
    the squared residual ``|d|``, so ½‖s‖² follows the shape objective (a
    mean of |Δ angle|, which prefers a few clear changes to many small ones)
    rather than its square.
    """
    grid, data, base = prob.grid, prob.data, prob.weights
    pts = grid.outlines(x[None, :])
    d = np.abs(angle_change(data, pts)[0])
    e = np.abs(link_error(data, measurement_error(data, pts)[0][0]))
    wm = base.fit / np.sqrt(e + prob.fit_eps_cm)
    if prob.irls_eps <= 0:
        return base.critical, base.every, wm
    return base.critical / np.sqrt(d[data.critical] + prob.irls_eps), base.every / np.sqrt(d + prob.irls_eps), wm


def _violation(prob: _StepProblem, c: np.ndarray, m: np.ndarray) -> np.ndarray:
    """|seam and notch constraints| and how far every measurement lies outside its band, cm."""
    over = np.maximum(np.abs(link_error(prob.data, m)) - prob.measure_tol_cm, 0.0)
    return np.concatenate([np.abs(c), over])


def _band(prob: _StepProblem, m: np.ndarray, alpha: float) -> tuple[np.ndarray, np.ndarray]:
    """Bounds ``(lo, hi)`` on the change of the measurements ``m``; outside the band, ``alpha`` of the way in."""
    data, tol = prob.data, prob.measure_tol_cm
    lo = data.target_cm - tol - m
    hi = np.where(data.at_least, np.inf, data.target_cm + tol - m)
    lo = np.where(lo > 0, alpha * lo, lo)  # below the band: move up by alpha of the way
    hi = np.where(hi < 0, alpha * hi, hi)
    return lo, hi


def _merit(prob: _StepProblem, p: _Point, rho: float) -> float:
    """Exact-penalty merit: ½‖s‖² plus ``rho`` times the summed violation."""
    return 0.5 * float(p.s @ p.s) + rho * float(_violation(prob, p.c, p.m).sum())


def _point(prob: _StepProblem, x: np.ndarray, w: tuple) -> _Point | None:
    """The iterate at ``x``, or None when a grid cell folds there."""
    if prob.grid.fold_margin(x[None, :])[0] < FOLD_MARGIN:
        return None
    return _Point(x, *(a[0] for a in prob.terms.evaluate(x[None, :], *w)))


def _line_search(prob: _StepProblem, cur: _Point, w: tuple, *, rho: float, mu: float,
                 alpha: float) -> tuple[_Point, np.ndarray, float] | None:
    """One damped SQP step from ``cur``: ``(new iterate, step d, damping μ)``, or None after 10 rejections.

    A trial whose merit rises gets a second-order correction (pulled back
    onto the constraints with the same linearisation: Maratos); a trial
    still rejected, or one that folds a cell, damps the shape step (μ × 8)
    and asks for half as much of the constraint correction (``alpha``).
    """
    Js, Jc, Jm = prob.terms.jacobian(cur.x, cur.s, cur.c, cur.m, prob.h, *w)
    H = Js.T @ Js
    gvec = Js.T @ cur.s
    n_var = len(cur.x)
    f0 = _merit(prob, cur, rho)
    for _ in range(10):
        Hd = H + (mu * float(np.trace(H) / n_var + 1e-12)) * prob.damp
        b_eq = -alpha * cur.c
        lo, hi = _band(prob, cur.m, alpha)
        d = _solve_qp(Hd, gvec, Jc, b_eq, Jm, lo, hi)
        trial = _point(prob, cur.x + d, w)
        if trial is not None and not _accepts(prob, cur, trial, f0=f0, rho=rho, alpha=alpha):
            lo2, hi2 = _band(prob, trial.m, 1.0)
            d = d + _solve_qp(Hd, np.zeros(n_var), Jc, -trial.c, Jm, lo2, hi2)
            trial = _point(prob, cur.x + d, w)
        if trial is not None and _accepts(prob, cur, trial, f0=f0, rho=rho, alpha=alpha):
            return trial, d, mu
        mu *= 8.0
        alpha *= 0.5
    return None


def _accepts(prob: _StepProblem, cur: _Point, trial: _Point, *, f0: float, rho: float, alpha: float) -> bool:
    """The merit did not rise, or (at the full step) the fit is met and the shape cost fell."""
    fn = _merit(prob, trial, rho)
    return fn <= f0 + 1e-12 or (alpha == 1.0 and _violation(prob, trial.c, trial.m).max(initial=0.0) < 2e-4
                                and trial.s @ trial.s < cur.s @ cur.s)


def _stalled(history: list[float], window: int) -> bool:
    """No shape cost of the last ``window`` iterations 1 % below the one before them."""
    return len(history) > window and min(history[-window:]) > 0.99 * history[-window - 1]


def _gauss_newton(prob: _StepProblem, x: np.ndarray, *, max_iter: int, max_push_cm: float, stall_window: int,
                  progress: Progress | None) -> RefineResult:
    """The constrained Gauss–Newton iterations of :func:`refine` from ``x``."""
    w = _irls_weights(prob, x)
    cur = _Point(x, *(a[0] for a in prob.terms.evaluate(x[None, :], *w)))
    rho = 10.0 * max(1.0, float(np.sqrt(cur.s @ cur.s)))
    mu = 1e-4
    it = 0
    converged = False
    history: list[float] = []
    for it in range(1, max_iter + 1):
        if progress is not None:
            progress("refine", it, max_iter)
        if prob.irls_eps > 0 and it > 1:
            w = _irls_weights(prob, cur.x)
            cur = _Point(cur.x, prob.terms.evaluate(cur.x[None, :], *w)[0][0], cur.c, cur.m)
        # continuation: far from feasible, ask the linear model for at most
        # max_push_cm of correction per iteration
        v0 = _violation(prob, cur.c, cur.m)
        alpha = min(1.0, max_push_cm / max(float(v0.max(initial=0.0)), 1e-12))
        found = _line_search(prob, cur, w, rho=rho, mu=mu, alpha=alpha)
        if found is None:
            break
        cur, d, mu = found
        step = float(np.max(np.abs(d) / prob.scale))
        mu = max(mu / 4.0, 1e-8)
        log.debug("refine %d: shape cost %.3g, violation %.3g, mu %.2g, step %.2g",
                  it, 0.5 * float(cur.s @ cur.s), _violation(prob, cur.c, cur.m).max(initial=0.0), mu, step)
        history.append(0.5 * float(cur.s @ cur.s))
        feasible = _violation(prob, cur.c, cur.m).max(initial=0.0) < 1e-4
        # converged: a tiny step, or the shape cost has stopped falling (the
        # reweighting makes single iterations noisy) with the fit met
        if feasible and (step < 1e-7 or _stalled(history, stall_window)):
            converged = True
            break
    viol = _violation(prob, cur.c, cur.m)
    return RefineResult(x=cur.x, iterations=it, shape_cost=0.5 * float(cur.s @ cur.s),
                        max_violation_cm=float(viol.max(initial=0.0)), converged=converged)
