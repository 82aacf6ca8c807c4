"""The grader's seeds and baselines: proportional scaling, the nearest graded size, the original.

Proportional scaling per the thesis's Algorithm 4 (one factor per piece,
the largest measurement ratio, :func:`uniform_scaling`), proportional
scaling along and across the grain (one factor per axis per piece, from the
measurements running mostly that way, :func:`axis_scaling`), the nearest
graded size when the pattern has grade rules (:func:`nearest_size`) and the
original seed NSGA-II's population; :func:`baselines` scores them as the
figures the grading is compared with.
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from ..pattern.model import Pattern
from .grid import PatternGrid
from .objectives import ObjectiveData, chord_lengths, measurement_error
from .solution import Solution, score_points, solution

__all__ = ["MIN_RATIO_LINK_CM", "Seeds", "axis_scaling", "baselines", "nearest_size", "uniform_scaling"]


#: a link shorter than this in the sample size (a difference of lengths, e.g. a band minus the edge it is
#: sewn to) says nothing about how much a piece grows: it gives no ratio to the proportional seeds
MIN_RATIO_LINK_CM = 0.5


def _link_ratios(data: ObjectiveData, grid: PatternGrid) -> np.ndarray:
    """(L,) target / sample length of every link; NaN where the sample length or the target is not positive."""
    achieved0 = _achieved(data, grid, grid.x0[None, :])[0][0]
    ok = (achieved0 > MIN_RATIO_LINK_CM) & (data.target_cm > 0)
    return np.where(ok, data.target_cm / np.where(ok, achieved0, 1.0), np.nan)


def _achieved(data: ObjectiveData, grid: PatternGrid, X: np.ndarray):
    return measurement_error(data, grid.outlines(X))


def _piece_link_shares(data: ObjectiveData, grid: PatternGrid) -> tuple[np.ndarray, np.ndarray]:
    """Per piece and link: length share (P, L) and horizontal fraction (P, L)."""
    points0 = grid.outlines(grid.x0[None, :])[0]
    d = points0[data.nxt] - points0  # edge vectors (N, 2)
    P = len(grid.pieces)
    L = len(data.target_cm)
    piece_of_point = np.repeat(np.arange(P), np.diff(grid.point_offsets))
    length = np.zeros((P, L))
    horiz = np.zeros((P, L))
    w_len = np.abs(data.link_edges) * np.linalg.norm(d, axis=1)[:, None]
    w_h = np.abs(data.link_edges) * np.abs(d[:, 0])[:, None]
    np.add.at(length, piece_of_point, w_len)
    np.add.at(horiz, piece_of_point, w_h)
    if len(data.chord_a):
        cd = points0[data.chord_b] - points0[data.chord_a]
        cw = np.abs(data.link_chords)
        np.add.at(length, piece_of_point[data.chord_a], cw * chord_lengths(data, points0[None])[0][:, None])
        np.add.at(horiz, piece_of_point[data.chord_a], cw * np.abs(cd[:, 0])[:, None])
    # horizontal fraction by |dx| / (|dx| + |dy|) of the piece's part of each link
    vert = np.zeros((P, L))
    w_v = np.abs(data.link_edges) * np.abs(d[:, 1])[:, None]
    np.add.at(vert, piece_of_point, w_v)
    if len(data.chord_a):
        np.add.at(vert, piece_of_point[data.chord_a], cw * np.abs(cd[:, 1])[:, None])
    frac_h = np.where(horiz + vert > 0, horiz / np.maximum(horiz + vert, 1e-12), 0.5)
    return length, frac_h


def _scaled(grid: PatternGrid, factors: np.ndarray) -> np.ndarray:
    """Individual with piece ``k`` scaled by ``factors[k] = (sx, sy)`` about its centre."""
    x = grid.x0.copy()
    for k, g in enumerate(grid.pieces):
        c = g.control
        centre = 0.5 * (c.min(axis=0) + c.max(axis=0))
        x[grid.var_offsets[k]:grid.var_offsets[k + 1]] = (centre + (c - centre) * factors[k]).ravel()
    return x


def uniform_scaling(grid: PatternGrid, data: ObjectiveData) -> np.ndarray:
    """Thesis Algorithm 4: each piece scaled by the largest target/pattern ratio of its links.

    Pieces no link touches take the median ratio. Returns ``(n_var,)``.
    """
    ratios = _link_ratios(data, grid)
    length, _ = _piece_link_shares(data, grid)
    touched = (length > 0) & np.isfinite(ratios)[None, :]
    fallback = float(np.nanmedian(ratios)) if np.isfinite(ratios).any() else 1.0
    s = np.array([ratios[t].max() if t.any() else fallback for t in touched])
    return _scaled(grid, np.stack([s, s], axis=1))


def axis_scaling(grid: PatternGrid, data: ObjectiveData) -> np.ndarray:
    """Proportional scaling along and across the grain, one factor per axis per piece.

    The across factor (x) averages the target/pattern ratios of the piece's
    links weighted by how much of the link runs horizontally on the piece,
    the along factor (y) those running vertically; an axis no link covers
    takes the other axis's factor. Returns ``(n_var,)``.
    """
    ratios = _link_ratios(data, grid)
    length, frac_h = _piece_link_shares(data, grid)
    fallback = float(np.nanmedian(ratios)) if np.isfinite(ratios).any() else 1.0
    length = np.where(np.isfinite(ratios)[None, :], length, 0.0)
    ratios = np.nan_to_num(ratios, nan=0.0)
    factors = np.ones((len(grid.pieces), 2))
    for k in range(len(grid.pieces)):
        wh = length[k] * frac_h[k]
        wv = length[k] * (1 - frac_h[k])
        sx = float(wh @ ratios / wh.sum()) if wh.sum() > 1e-9 else None
        sy = float(wv @ ratios / wv.sum()) if wv.sum() > 1e-9 else None
        # an axis with little evidence leans on the other one
        total = wh.sum() + wv.sum()
        if sx is None and sy is None:
            sx = sy = fallback
        elif sx is None:
            sx = sy
        elif sy is None:
            sy = sx
        elif total > 0:
            bh, bv = wh.sum() / total, wv.sum() / total
            if bh < 0.15:
                sx = bh / 0.15 * sx + (1 - bh / 0.15) * sy
            if bv < 0.15:
                sy = bv / 0.15 * sy + (1 - bv / 0.15) * sx
        factors[k] = (sx, sy)
    return _scaled(grid, factors)


def nearest_size(pattern: Pattern, data: ObjectiveData, grid: PatternGrid) -> tuple[str, np.ndarray] | None:
    """The graded size with the least measurement error and its reference-line points.

    Returns ``(size, points (N, 2))`` or None when the pattern has no grade
    rules (or a single size).
    """
    if len(pattern.rules.sizes) < 2 or not pattern.rules.deltas:
        return None
    from ..library.seams import graded_sew_lines

    table = graded_sew_lines(pattern)  # reference line of every piece in every size
    sizes = list(pattern.rules.sizes)
    pts = np.stack([np.concatenate([table[p.name][i] for p in pattern.pieces]) for i in range(len(sizes))])
    if pts.shape[1] != grid.n_points:
        return None
    _, err = measurement_error(data, pts)
    best = int(np.argmin(err))
    return sizes[best], pts[best]


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class Seeds:
    """The seeds of NSGA-II's population and the baselines the grading is measured against.

    x_axis : (n_var,) proportional scaling along and across the grain (the
    final step's design reference) ; seeds : the seeds in order: scaling
    along/across the grain, Algorithm 4, the nearest graded size (when the
    pattern has grade rules), the original ; baselines : ``"proportional"``,
    ``"proportional_uniform"`` and ``"nearest_size"`` as scored solutions
    """

    x_axis: np.ndarray
    seeds: tuple[np.ndarray, ...]
    baselines: Mapping[str, Solution]


def baselines(pattern: Pattern, grid: PatternGrid, data: ObjectiveData, size: str) -> Seeds:
    """Proportional scaling (both kinds), the nearest graded size and the original, timed and scored."""
    t_base = time.perf_counter()
    x_axis = axis_scaling(grid, data)
    base_axis = solution(grid, data, "proportional", x_axis, size,
                         "each piece scaled along and across the grain by its measurements")
    t_uni = time.perf_counter()
    x_uniform = uniform_scaling(grid, data)
    base_uni = solution(grid, data, "proportional_uniform", x_uniform, size,
                        "each piece scaled by its largest measurement ratio (thesis Algorithm 4)")
    t_end = time.perf_counter()
    found = {
        "proportional": dataclasses.replace(base_axis, seconds=t_uni - t_base),
        "proportional_uniform": dataclasses.replace(base_uni, seconds=t_end - t_uni),
    }
    seeds = [x_axis, x_uniform]
    near = _nearest_size_seed(pattern, grid, data)
    if near is not None:
        found["nearest_size"] = near[0]
        seeds.append(near[1])
    seeds.append(grid.x0.copy())
    return Seeds(x_axis=x_axis, seeds=tuple(seeds), baselines=found)


def _nearest_size_seed(pattern: Pattern, grid: PatternGrid, data: ObjectiveData) -> tuple[Solution, np.ndarray] | None:
    """The nearest graded size (:func:`nearest_size`) as a scored baseline and its genes fitted to the grid."""
    t_near = time.perf_counter()
    near = nearest_size(pattern, data, grid)
    if near is None:
        return None
    size_name, pts = near
    from ..pattern.grading import grade

    graded = grade(pattern, size_name)
    offs = grid.point_offsets
    x_near = grid.fit_controls([pts[offs[k]:offs[k + 1]] for k in range(len(grid.pieces))])
    scores = score_points(data, pts, fold_margin=float(grid.fold_margin(x_near[None, :])[0]), pattern=graded)
    return Solution(name="nearest_size", pattern=graded, scores=scores, x=None, note=f"graded size {size_name}",
                    seconds=time.perf_counter() - t_near), x_near
