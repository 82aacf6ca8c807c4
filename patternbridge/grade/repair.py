"""The penalty repair: a least-squares correction of one individual toward the fit (deterministic).

:func:`~.run.fit_pattern` falls back on it when nothing on the final front
meets the fit: it trades the measurement and seam residuals against the
shape, where the final step (:func:`~.refine.refine`) holds the fit as a
constraint.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .grid import PatternGrid
from .objectives import FOLD_MARGIN, ObjectiveData, balanced_links, link_shares, piece_axes_turn, residuals
from .solution import Progress

__all__ = ["repair"]



def repair(
    grid: PatternGrid,
    data: ObjectiveData,
    x: np.ndarray,
    *,
    max_nfev: int = 60,
    w_reg: float = 0.02,
    w_bend: float = 0.1,
    w_fold: float = 50.0,
    shape_scale: float = 1.0,
    linear: np.ndarray | None = None,
    w_linear: float = 100.0,
    w_share: float = 30.0,
    w_axes: float = 30.0,
    x_design: np.ndarray | None = None,
    progress: Progress | None = None,
) -> tuple[np.ndarray, float]:
    """Least-squares correction of one individual (deterministic).

    Minimises the weighted residuals of :func:`~.objectives.residuals` (all
    measurement, seam and notch errors plus the inner-angle changes) with a
    small pull back to ``x``, a smoothness term on the grid
    (:meth:`PatternGrid.bending`) and a barrier that keeps every grid cell convex,
    using scipy's trust-region reflective solver. The Jacobian is taken by
    forward differences evaluated as one vectorised batch: the perturbed
    individuals form a population.

    ``shape_scale`` multiplies the weights of the inner-angle terms.
    ``linear`` (``(n_c, n_var)``, the final step's straight-edge and grain
    rows, :func:`~.refine.straight_constraints`) are held by a strong cost,
    ``w_linear`` per cm, and every piece's share of a link over several
    pieces stays the design's (``w_share`` per unit of share): without them
    the repair met the fit by turning whole pieces off their folds and
    shearing bands into triangles, or by narrowing a front to widen a back.
    ``w_axes`` (per rad) holds the turn of every piece's drawing axes
    (:func:`~.objectives.piece_axes_turn`: its rotation and shear, which a
    straight edge along one axis does not see) at that of ``x_design``
    (proportional scaling), or at zero.

    Returns
    -------
    x : (n_var,) float64
    cost : half the sum of squared residuals at ``x``
    """
    from scipy.optimize import least_squares

    terms = _repair_terms(grid, data, x, linear=linear, x_design=x_design, weights=_RepairWeights(
        w_reg=w_reg, w_bend=w_bend, w_fold=w_fold, shape_scale=shape_scale, w_linear=w_linear, w_share=w_share,
        w_axes=w_axes))
    n_calls = 0

    def fun(xv):
        nonlocal n_calls
        n_calls += 1
        if progress is not None:
            progress("repair", min(n_calls, max_nfev), max_nfev)
        return _residuals(grid, data, terms, xv[None, :])[0]

    def jac(xv):
        return _forward_jacobian(grid, data, terms, xv)

    sol = least_squares(fun, terms.x_start, jac=jac, method="trf", x_scale=terms.scale, max_nfev=max_nfev,
                        tr_solver="lsmr",
                        ftol=1e-10, xtol=1e-10, gtol=1e-10)
    if progress is not None:
        progress("repair", max_nfev, max_nfev)
    return sol.x, float(sol.cost)


@dataclass(frozen=True, slots=True, kw_only=True)
class _RepairWeights:
    """The weights of :func:`repair`'s terms (see its parameters)."""

    w_reg: float
    w_bend: float
    w_fold: float
    shape_scale: float
    w_linear: float
    w_share: float
    w_axes: float


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class _RepairTerms:
    """What the repair's residuals compare with.

    x_start : (n_var,) the individual repaired ; scale : (n_var,) each
    gene's piece extent, cm ; h : (n_var,) its finite-difference step ;
    linear : (n_c, n_var) rows held at zero ; shared : the links whose
    shares are held ; share0 : the design's shares of them ; axes0 : the
    drawing axes' turn held (``x_design``'s, or 0)
    """

    x_start: np.ndarray
    scale: np.ndarray
    h: np.ndarray
    linear: np.ndarray
    shared: np.ndarray
    share0: np.ndarray
    axes0: np.ndarray | float
    weights: _RepairWeights


def _repair_terms(grid: PatternGrid, data: ObjectiveData, x: np.ndarray, *, linear: np.ndarray | None,
                  x_design: np.ndarray | None, weights: _RepairWeights) -> _RepairTerms:
    """:class:`_RepairTerms` of repairing ``x``."""
    x_start = np.asarray(x, dtype=np.float64).copy()
    scale = np.concatenate([np.full(2 * g.n_control, g.extent_cm) for g in grid.pieces])
    shared = balanced_links(data)
    return _RepairTerms(
        x_start=x_start, scale=scale, h=1e-6 * scale,
        linear=np.zeros((0, len(x_start))) if linear is None else np.asarray(linear, dtype=np.float64),
        shared=shared, share0=link_shares(data, data.points0[None])[0][:, :, shared],
        axes0=0.0 if x_design is None else piece_axes_turn(data, grid.outlines(np.asarray(x_design)[None, :])),
        weights=weights)


def _residuals(grid: PatternGrid, data: ObjectiveData, t: _RepairTerms, X: np.ndarray) -> np.ndarray:
    """(n_pop, n_res) weighted residuals of ``X (n_pop, n_var)``: fit and shape, pull back, bending, folds,
    linear rows, shares and drawing axes."""
    w = t.weights
    pts = grid.outlines(X)
    r = residuals(data, pts, w_critical=10.0 * w.shape_scale, w_angle=4.0 * w.shape_scale)
    reg = w.w_reg * (X - t.x_start) / t.scale
    fold = w.w_fold * np.maximum(0.0, 2 * FOLD_MARGIN - grid.fold_margin(X))[:, None]
    bend = w.w_bend * grid.bending(X)
    lin = w.w_linear * (X @ t.linear.T)
    share = w.w_share * (link_shares(data, pts)[0][:, :, t.shared] - t.share0).reshape(len(X), -1)
    axes = w.w_axes * (piece_axes_turn(data, pts) - t.axes0).reshape(len(X), -1)
    return np.concatenate([r, reg, bend, fold, lin, share, axes], axis=1)


def _forward_jacobian(grid: PatternGrid, data: ObjectiveData, t: _RepairTerms, xv: np.ndarray) -> np.ndarray:
    """(n_res, n_var) forward differences at ``xv``, the perturbed individuals evaluated as one population."""
    base = _residuals(grid, data, t, xv[None, :])[0]
    Xp = xv[None, :] + np.diag(t.h)
    rp = _residuals(grid, data, t, Xp)
    return ((rp - base[None, :]) / t.h[:, None]).T
