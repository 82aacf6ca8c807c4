"""The final step's residuals and constraints, and their Jacobian by piece-wise forward differences.

:func:`~.refine.refine` minimises ``½‖s(x)‖²`` subject to ``c(x) = 0`` and a
band on the measurements ``m(x)``. The residuals fall in two kinds:

* **local** terms that depend on the genes of one piece only: the inner-angle
  changes at its critical points and at every vertex, its rotation and drift,
  the grid smoothness, the barrier on squeezed cells and the grid-interval
  design term;
* **global** terms that join pieces: the stitch intervals and turning angles
  along seams, each piece's share of the links, the measurement cost, the
  symmetry rows; and the constraints (seam lengths, notches, straight edges,
  levels of girths taken across the grain, dart lengths).

The Jacobian is taken by forward differences, the perturbed individuals
evaluated as one population. A local term of piece ``k`` is evaluated only on
the perturbations of piece ``k``'s genes (its block of the Jacobian; every
other gene leaves it unchanged, so that block is exactly zero): the cost of
those terms falls from ``n_var · N`` to ``Σ_k n_var,k · N_k`` vertex
evaluations, about the number of pieces times less. The global terms are
evaluated on the whole perturbed population.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .bands import Bands, outline_width
from .extents import EXTENT_SLACK, Extents, axis_spread
from .grid import PatternGrid
from .objectives import (
    ObjectiveData,
    _angles,
    _edge_lengths,
    _notch_positions,
    _turning,
    dart_lengths,
    level_slip,
    link_error,
    link_lengths,
    link_shares,
    residuals,
)
from .suppression import Suppression, suppression_terms

__all__ = ["StepTerms"]


def _wrap(a: np.ndarray) -> np.ndarray:
    return (a + np.pi) % (2 * np.pi) - np.pi


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class _SeamBlock:
    """The seam samples, stitch intervals and turns a block of the Jacobian needs.

    samples : (q,) indices into the seam samples ; interval_a/b : (i, 2) and
    turn_a/b : (t, 3) indices into ``samples`` ; turn_sign_b, turn0, ease :
    per turn / interval ; columns : (i + t,) their columns among all the
    seam shape terms (intervals first, then turns)
    """

    samples: np.ndarray
    interval_a: np.ndarray
    interval_b: np.ndarray
    turn_a: np.ndarray
    turn_b: np.ndarray
    turn_sign_b: np.ndarray
    turn0: np.ndarray
    ease: np.ndarray
    columns: np.ndarray
    n_columns: int


def _seam_blocks(grid: PatternGrid, data: ObjectiveData) -> tuple[_SeamBlock, ...]:
    """The block of every seam term, then one block per piece: the terms with a side on that piece."""
    if not data.n_seams:
        return ()
    counts = np.maximum(np.bincount(data.interval_seam, minlength=data.n_seams), 1)
    ease = data.seam_ease_cm[data.interval_seam] / counts[data.interval_seam]
    sample_piece = data.piece_of_point[data.sample_i0]
    n_int, n_turn = len(data.interval_a), len(data.turn_a)

    def block(imask: np.ndarray, tmask: np.ndarray) -> _SeamBlock:
        ia, ib, ta, tb = data.interval_a[imask], data.interval_b[imask], data.turn_a[tmask], data.turn_b[tmask]
        used = np.unique(np.concatenate([ia.ravel(), ib.ravel(), ta.ravel(), tb.ravel()]).astype(np.int64))
        remap = np.zeros(len(data.sample_i0), dtype=np.int64)
        remap[used] = np.arange(len(used))
        columns = np.concatenate([np.flatnonzero(imask), n_int + np.flatnonzero(tmask)])
        return _SeamBlock(
            samples=used,
            interval_a=remap[ia],
            interval_b=remap[ib],
            turn_a=remap[ta],
            turn_b=remap[tb],
            turn_sign_b=data.turn_sign_b[tmask],
            turn0=data.turn0[tmask],
            ease=ease[imask],
            columns=columns.astype(np.int64),
            n_columns=n_int + n_turn,
        )

    blocks = [block(np.ones(n_int, dtype=bool), np.ones(n_turn, dtype=bool))]
    for k in range(len(grid.pieces)):
        on_k = np.any(sample_piece[data.interval_a] == k, axis=1) | np.any(sample_piece[data.interval_b] == k, axis=1)
        turn_k = np.any(sample_piece[data.turn_a] == k, axis=1) | np.any(sample_piece[data.turn_b] == k, axis=1)
        blocks.append(block(on_k, turn_k))
    return tuple(blocks)


W_DART_CAP = 30.0
"""Weight of a dart's length beyond its reference, per unit of its reference length (``StepTerms.dart_cap``)."""

BAND_SLACK_CM = 0.1
"""Change of a band's width (cm) the final step leaves free: a band that keeps its width adds nothing to the step."""

SHEAR_SLACK = np.radians(2.0)
"""Shear (rad, the angle between a piece's drawing axes against ``x_design``'s) the final step leaves free."""


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class StepTerms:
    """Residuals ``s``, constraints ``c`` and measurements ``m`` of the final step.

    grid, data : the grading problem ; straight : (n_c, n_var) linear
    equality rows ; symmetric : (n_s, n_var) symmetry rows or None ;
    x_design : (n_var,) design reference or None ; level : (C,) bool, chord
    legs taken across the grain ; dart_ref : (D,) dart lengths to keep or
    None ; share_ref, shared : the design's link shares and the links
    over several pieces that add up ; axes_ref : (P, 2) turn of every
    piece's drawing axes in ``x_design`` (:func:`~.objectives.piece_axes_turn`)
    or None ; suppress : the design's split of every reduction between
    girth levels among darts and seams (:mod:`.suppression`) or None ;
    dart_cap : the dart lengths ``dart_ref`` are a ceiling (a strong
    one-sided cost, :data:`W_DART_CAP`) instead of an equality ;
    bands : the long narrow pieces whose width no link governs
    (:func:`~.bands.band_axes`), held at their sample width (beyond
    :data:`BAND_SLACK_CM`) at ``w_band`` per cm, or None ; extents : the
    pieces' axes no link governs (:func:`~.extents.unlinked_axes`), their
    spread held at proportional scaling's (beyond
    :data:`~.extents.EXTENT_SLACK`) at ``w_extent`` per unit of log ratio,
    or None ;
    w_* : weights (see :func:`~.refine.refine`)
    """

    grid: PatternGrid
    data: ObjectiveData
    straight: np.ndarray
    symmetric: np.ndarray | None
    x_design: np.ndarray | None
    level: np.ndarray
    dart_ref: np.ndarray | None
    share_ref: np.ndarray | None
    shared: np.ndarray | None
    axes_ref: np.ndarray | None
    suppress: Suppression | None = None
    w_suppress: float = 0.0
    dart_cap: bool = False
    bands: Bands | None = None
    w_band: float = 0.0
    extents: Extents | None = None
    w_extent: float = 0.0
    w_rotation: float
    w_axes: float
    w_shift: float
    w_bend: float
    w_cell: float
    min_cell_ratio: float
    w_design: float
    design_slack: float
    w_share: float
    w_fit: float
    w_interval: float
    w_turn: float
    w_symmetry: float
    w_proportion: float
    w_direction: float
    seam_blocks: tuple = ()

    @classmethod
    def build(cls, grid: PatternGrid, data: ObjectiveData, **kwargs) -> StepTerms:
        """The terms with their seam blocks: every seam sample, interval and turn, and those of each piece."""
        return cls(grid=grid, data=data, seam_blocks=_seam_blocks(grid, data), **kwargs)

    def local(self, X: np.ndarray, k: int, wc: np.ndarray, wa: np.ndarray) -> np.ndarray:
        """The local terms of piece ``k`` for the individuals ``X (n_pop, n_var)``, ``(n_pop, n_k)``.

        ``wc`` weighs the critical points (one weight each, in
        ``data.critical`` order), ``wa`` every vertex (scalar or ``(N,)``).
        """
        data, grid = self.data, self.grid
        a, b = int(grid.point_offsets[k]), int(grid.point_offsets[k + 1])
        pts = grid.piece_outline(X, k)
        d = _wrap(_angles(pts, data.prv[a:b] - a, data.nxt[a:b] - a) - data.angle0[a:b])
        crit = (data.critical >= a) & (data.critical < b)
        terms = [wc[crit] * d[:, data.critical[crit] - a], np.broadcast_to(wa, (len(data.angle0),))[a:b] * d]
        centre = pts.mean(axis=1)
        q = pts - centre[:, None, :]
        q0 = data.points0[a:b] - data.centre0[k]
        cs = (q0[:, 0] * q[..., 1] - q0[:, 1] * q[..., 0]).sum(axis=1)
        ds = (q0[:, 0] * q[..., 0] + q0[:, 1] * q[..., 1]).sum(axis=1)
        terms.append(self.w_rotation * np.arctan2(cs, ds)[:, None])
        if self.axes_ref is not None and self.w_axes > 0:
            # the piece's best-fit linear map keeps the angle between its axes of x_design: no shear
            m = np.einsum("pni,nj->pij", q, q0) @ np.linalg.inv(q0.T @ q0 + 1e-12 * np.eye(2))
            axes = np.stack([np.arctan2(m[:, 1, 0], m[:, 0, 0]), np.arctan2(-m[:, 0, 1], m[:, 1, 1])], axis=1)
            d = _wrap(axes - self.axes_ref[k])
            shear = d[:, 1:] - d[:, :1]
            terms.append(self.w_axes * np.sign(shear) * np.maximum(np.abs(shear) - SHEAR_SLACK, 0.0))
        terms.append(self.w_shift * (centre - data.centre0[k]) / data.extent_cm[k])
        if self.bands is not None and self.w_band > 0 and np.any(self.bands.pieces == k):
            j = int(np.flatnonzero(self.bands.pieces == k)[0])
            d = outline_width(pts) - self.bands.width0[j]
            terms.append(self.w_band * (np.sign(d) * np.maximum(np.abs(d) - BAND_SLACK_CM, 0.0))[:, None])
        if self.extents is not None and self.w_extent > 0:
            for j in np.flatnonzero(self.extents.pieces == k):
                spread = np.maximum(axis_spread(pts, int(self.extents.axes[j])), 1e-9)
                r = np.log(spread / self.extents.spread_ref[j])
                terms.append(self.w_extent * (np.sign(r) * np.maximum(np.abs(r) - EXTENT_SLACK, 0.0))[:, None])
        ext = float(np.mean(data.extent_cm))
        terms.append((self.w_bend / ext) * grid.bending(X, pieces=[k]))
        terms.append(self.w_cell * np.maximum(0.0, self.min_cell_ratio - grid.corner_ratios(X, pieces=[k])))
        if self.x_design is not None and self.w_design > 0:
            from .refine import design_deviation

            terms.append(self.w_design * design_deviation(grid, X, self.x_design, slack=self.design_slack, pieces=[k]))
        return np.concatenate(terms, axis=1)

    def seam_shape(self, pts: np.ndarray, block: _SeamBlock) -> np.ndarray:
        """Stitch-interval differences and turning-angle disagreements of ``block``, ``(n_pop, I_b + T_b)``.

        ``pts (n_pop, N, 2)``; the full block (``seam_blocks[0]``) gives
        every interval and turn of every seam, a piece's block those that
        have a side on that piece (the values are the same, element by
        element).
        """
        data = self.data
        w = data.sample_w[block.samples][None, :, None]
        smp = (1 - w) * pts[:, data.sample_i0[block.samples], :] + w * pts[:, data.sample_i1[block.samples], :]
        la = np.linalg.norm(smp[:, block.interval_a[:, 1]] - smp[:, block.interval_a[:, 0]], axis=-1)
        lb = np.linalg.norm(smp[:, block.interval_b[:, 1]] - smp[:, block.interval_b[:, 0]], axis=-1)
        ta = _turning(smp, block.turn_a)
        tb = _turning(smp, block.turn_b) * block.turn_sign_b
        ang = _wrap((ta - tb) - block.turn0)
        return np.concatenate([self.w_interval * (lb - la - block.ease), self.w_turn * ang], axis=1)

    def joint(self, X: np.ndarray, wm: np.ndarray, *, seams: bool = True) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The global terms, the constraints and the measurements of ``X (n_pop, n_var)``.

        The seam shape terms (:meth:`seam_shape`) come first, unless
        ``seams`` is False (the Jacobian takes them piece by piece).
        """
        data, grid = self.data, self.grid
        pts = grid.outlines(X)
        edges = _edge_lengths(data, pts)
        terms = [np.zeros((len(X), 0))]
        if seams and self.seam_blocks:
            terms.append(self.seam_shape(pts, self.seam_blocks[0]))
        if self.symmetric is not None:
            terms.append(self.w_symmetry * (X @ self.symmetric.T))
        c = [X @ self.straight.T]  # straight edges: linear, cm
        if self.level.any():  # girths across the grain stay at their levels
            c.append(level_slip(data, pts)[:, self.level])
        if self.dart_ref is not None and len(self.dart_ref):
            lengths = dart_lengths(data, pts)
            if self.dart_cap:
                # a dart may shorten with its intake (keeping its angle) but never reach past its reference length
                terms.append(W_DART_CAP * np.maximum(lengths / self.dart_ref - 1.0, 0.0))
            else:
                c.append(lengths - self.dart_ref)
        if data.n_seams:
            mismatch = edges @ data.seam_b_edges - edges @ data.seam_a_edges - data.seam_ease_cm
            pos_a, pos_b = _notch_positions(data, edges)
            c = [mismatch, (pos_b - pos_a) - data.notch_offset0, *c]
        if self.share_ref is not None and self.w_share > 0:
            sh = link_shares(data, pts, edges)[0][:, :, self.shared]
            w_sh = self.w_share / np.sqrt(max(int(self.shared.sum()), 1))
            terms.append(w_sh * (sh - self.share_ref).reshape(len(X), -1))
        if self.suppress is not None and self.suppress.n_parts and self.w_suppress > 0:
            w_su = self.w_suppress / np.sqrt(self.suppress.n_parts)
            terms.append(w_su * suppression_terms(self.suppress, data, pts, edges))
        achieved = link_lengths(data, pts, edges)
        if self.w_fit > 0:
            terms.append(wm * link_error(data, achieved))
        if self.w_proportion or self.w_direction:
            terms.append(
                residuals(
                    data,
                    pts,
                    w_measure=0.0,
                    w_seam=0.0,
                    w_notch=0.0,
                    w_interval=0.0,
                    w_turn=0.0,
                    w_critical=0.0,
                    w_angle=0.0,
                    w_rotation=0.0,
                    w_shift=0.0,
                    w_proportion=self.w_proportion,
                    w_direction=self.w_direction,
                )
            )
        return np.concatenate(terms, axis=1), np.concatenate(c, axis=1), achieved

    def evaluate(
        self, X: np.ndarray, wc: np.ndarray, wa: np.ndarray, wm: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(s, c, m)`` of the individuals ``X (n_pop, n_var)``: local terms piece by piece, then global."""
        local = [self.local(X, k, wc, wa) for k in range(len(self.grid.pieces))]
        s_joint, c, m = self.joint(X, wm)
        return np.concatenate([*local, s_joint], axis=1), c, m

    def jacobian(
        self,
        x: np.ndarray,
        s: np.ndarray,
        c: np.ndarray,
        m: np.ndarray,
        h: np.ndarray,
        wc: np.ndarray,
        wa: np.ndarray,
        wm: np.ndarray,
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Forward-difference Jacobians ``(J_s, J_c, J_m)`` at ``x`` (with ``s, c, m`` its values).

        ``h`` is the step per gene. The local terms of piece ``k`` are
        differenced on piece ``k``'s genes only (the rest of their block is
        exactly zero); the global terms on every gene.
        """
        grid = self.grid
        n_var = len(x)
        Xp = x[None, :] + np.diag(h)
        sg, cp, mp = self.joint(Xp, wm, seams=False)
        Js = np.zeros((len(s), n_var))
        row = 0
        for k in range(len(grid.pieces)):
            cols = slice(int(grid.var_offsets[k]), int(grid.var_offsets[k + 1]))
            lk = self.local(Xp[cols], k, wc, wa)
            rows = slice(row, row + lk.shape[1])
            Js[rows, cols] = ((lk - s[None, rows]) / h[cols, None]).T
            row += lk.shape[1]
        if self.seam_blocks:
            n_seam = self.seam_blocks[0].n_columns
            for k, block in enumerate(self.seam_blocks[1:]):
                cols = slice(int(grid.var_offsets[k]), int(grid.var_offsets[k + 1]))
                sk = self.seam_shape(grid.outlines(Xp[cols]), block)
                rows = row + block.columns
                Js[rows, cols] = ((sk - s[None, rows]) / h[cols, None]).T
            row += n_seam
        Js[row:] = ((sg - s[None, row:]) / h[:, None]).T
        Jc = ((cp - c[None, :]) / h[:, None]).T
        Jm = ((mp - m[None, :]) / h[:, None]).T
        return Js, Jc, Jm
