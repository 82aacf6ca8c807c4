"""Grade a pattern to a character's measurements: seeds, NSGA-II, choice, final constrained step.

:func:`fit_pattern` is the grader's entry point:

1. build the control grids (:mod:`.grid`) and compile the targets
   (:mod:`.objectives`);
2. make the seeds and baselines: proportional scaling per the thesis's
   Algorithm 4 (one factor per piece, the largest measurement ratio),
   proportional scaling along and across the grain (one factor per axis per
   piece, from the measurements running mostly that way), the nearest graded
   size when the pattern has grade rules, and the original;
3. run pymoo's NSGA-II with the grader's sampling, crossover and mutation
   (:mod:`.operators`) on :class:`~.problem.GradingProblem`;
4. **final step** (:mod:`.refine`), from the proportional seed (before
   NSGA-II; its result also seeds the population) and from a few members
   of NSGA-II's front: a constrained Gauss–Newton method minimises the
   change of shape subject to every seam and notch closed, every
   measurement within a band around its target (with a small cost inside
   it), the straight grain-parallel edges kept straight, the grain lines
   kept in their direction and every dart at its length; the
   design-preservation (grid-interval) weight, and after it the all-vertex
   angle weight, step down while the result changes the design more than
   proportional scaling;
5. the refined solutions join NSGA-II's front, the dominated rows are
   removed, and the issue's rule chooses on that final front: the least
   shape error among the members within tolerance on measurements and
   seams (:func:`within_tolerance`).
"""

from __future__ import annotations

import dataclasses
import logging
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field

import numpy as np

from ..errors import SolverError
from ..pattern.model import Pattern
from ..report import Finding
from .forcing import Forcing, describe_forcing, shape_forcing
from .grid import PatternGrid, build_grid, deform_pattern
from .objectives import (
    FOLD_MARGIN,
    ObjectiveData,
    balanced_links,
    chord_lengths,
    evaluate,
    link_error,
    link_shares,
    objective_data,
    piece_axes_turn,
    residuals,
    shape_error_all,
)

__all__ = [
    "FitResult",
    "Scores",
    "Solution",
    "axis_scaling",
    "choose",
    "choose_member",
    "continuation_stages",
    "fit_pattern",
    "front_members",
    "nearest_size",
    "non_dominated",
    "refine_members",
    "repair",
    "score_points",
    "shape_standing",
    "split_ladder",
    "standing",
    "uniform_scaling",
    "within_tolerance",
]

log = logging.getLogger(__name__)

Progress = Callable[[str, int, int], None]


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class Scores:
    """Figures of one solution.

    target_cm, achieved_cm : (L,) per measurement link
    error_cm : (L,) signed ``achieved - target``, 0 where an ``at_least`` link is exceeded
    seam_mismatch_cm : (S,) ``L_b - L_a - ease`` per seam
    notch_cm : (M,) notch misalignment per notch pair ; notch_seam : (M,) seam index
    measurement_error : mean |error| cm (objective 1) ; seam_error : objective 2 ;
    shape_error : objective 3 (rad) ; shape_error_all : mean |Δ angle| over all vertices
    fold_margin : smallest relative cell corner cross product (> 0: no fold)
    is_simple : every piece outline free of self-intersections
    """

    target_cm: np.ndarray
    achieved_cm: np.ndarray
    error_cm: np.ndarray
    seam_mismatch_cm: np.ndarray
    notch_cm: np.ndarray
    notch_seam: np.ndarray
    measurement_error: float
    seam_error: float
    shape_error: float
    fold_margin: float
    shape_error_all: float = 0.0
    is_simple: bool

    @property
    def max_measurement_error(self) -> float:
        err = np.abs(self.error_cm)
        return float(err.max()) if len(err) else 0.0

    @property
    def max_seam_mismatch_cm(self) -> float:
        vals = np.abs(np.concatenate([self.seam_mismatch_cm, self.notch_cm]))
        return float(vals.max()) if len(vals) else 0.0

    @property
    def F(self) -> np.ndarray:
        return np.array([self.measurement_error, self.seam_error, self.shape_error])


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class Solution:
    """A named candidate: its pattern, genes (if it lives in the grid) and scores."""

    name: str
    pattern: Pattern
    scores: Scores
    x: np.ndarray | None = None
    note: str = ""
    seconds: float = 0.0


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class FitResult:
    """Everything :func:`fit_pattern` found.

    pattern : the graded pattern (the chosen solution after the final step)
    chosen : the same as a :class:`Solution`; ``ga_choice`` is the NSGA-II choice before it
    front_F : (n_front, 3) objectives of the final Pareto front: NSGA-II's
        front and the solutions of the final step, dominated rows removed
    front_X : (n_front, n_var) its genes ; chosen_index : row of ``chosen``
    front_refined : (n_front,) bool, the rows the final step produced
    front_within : (n_front,) bool, the rows within tolerance (:func:`within_tolerance`)
    baselines : ``"proportional"`` (along/across the grain),
        ``"proportional_uniform"`` (Algorithm 4) and ``"nearest_size"`` when
        the pattern has grade rules
    seconds : wall time of the whole fit
    finish_settings : keyword arguments of :func:`~.refine.refine` at the
        stage the continuation settled on (:func:`choose_member` re-runs the
        final step with them)
    findings : what :func:`~.checks.design_checks` found wrong with the
        chosen pattern (a collapsed piece, a flattened curve, a lost
        symmetry); empty when it still is the design
    forcing : when the chosen grading changes the shape more than
        proportional scaling, the measurements that force it and the
        critical points that carry the excess (:func:`~.forcing.shape_forcing`);
        None otherwise
    """

    pattern: Pattern
    original: Pattern
    chosen: Solution
    ga_choice: Solution
    front_F: np.ndarray
    front_X: np.ndarray
    chosen_index: int
    baselines: Mapping[str, Solution]
    measurements: Mapping[str, float]
    grid: PatternGrid
    data: ObjectiveData
    seconds: float
    seed: int
    pop_size: int
    n_gen: int
    history: np.ndarray = field(default_factory=lambda: np.zeros((0, 4)))
    front_refined: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=bool))
    front_within: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=bool))
    findings: tuple[Finding, ...] = ()
    finish_settings: Mapping[str, object] = field(default_factory=dict)
    forcing: Forcing | None = None


def _is_simple(pattern: Pattern) -> bool:
    import shapely

    return all(bool(shapely.is_simple(shapely.linearrings(p.outline))) for p in pattern.pieces)


def score_points(data: ObjectiveData, points: np.ndarray, *, fold_margin: float, pattern: Pattern) -> Scores:
    """:class:`Scores` of one solution given its outline points ``(N, 2)``."""
    ev = evaluate(data, points[None, :, :])
    return Scores(
        target_cm=data.target_cm.copy(),
        achieved_cm=ev.achieved_cm[0],
        error_cm=link_error(data, ev.achieved_cm[0]),
        seam_mismatch_cm=ev.seam_mismatch_cm[0],
        notch_cm=ev.notch_cm[0],
        notch_seam=data.notch_seam.copy(),
        measurement_error=float(ev.measurement_error[0]),
        seam_error=float(ev.seam_error[0]),
        shape_error=float(ev.shape_error[0]),
        shape_error_all=float(ev.shape_error_all[0]),
        fold_margin=float(fold_margin),
        is_simple=_is_simple(pattern),
    )


def _solution(grid: PatternGrid, data: ObjectiveData, name: str, x: np.ndarray, size: str, note: str = "") -> Solution:
    pattern = deform_pattern(grid, x, size=size)
    points = grid.outlines(x[None, :])[0]
    scores = score_points(data, points, fold_margin=float(grid.fold_margin(x[None, :])[0]), pattern=pattern)
    return Solution(name=name, pattern=pattern, scores=scores, x=np.array(x), note=note)


def _valid(sol: Solution) -> bool:
    return sol.scores.fold_margin > 0 and sol.scores.is_simple


#: a link shorter than this in the sample size (a difference of lengths, e.g. a band minus the edge it is
#: sewn to) says nothing about how much a piece grows: it gives no ratio to the proportional seeds
MIN_RATIO_LINK_CM = 0.5


def _link_ratios(data: ObjectiveData, grid: PatternGrid) -> np.ndarray:
    """(L,) target / sample length of every link; NaN where the sample length or the target is not positive."""
    achieved0 = _achieved(data, grid, grid.x0[None, :])[0][0]
    ok = (achieved0 > MIN_RATIO_LINK_CM) & (data.target_cm > 0)
    return np.where(ok, data.target_cm / np.where(ok, achieved0, 1.0), np.nan)


def _achieved(data: ObjectiveData, grid: PatternGrid, X: np.ndarray):
    from .objectives import measurement_error

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
    from .objectives import measurement_error

    table = graded_sew_lines(pattern)  # reference line of every piece in every size
    sizes = list(pattern.rules.sizes)
    pts = np.stack([np.concatenate([table[p.name][i] for p in pattern.pieces]) for i in range(len(sizes))])
    if pts.shape[1] != grid.n_points:
        return None
    _, err = measurement_error(data, pts)
    best = int(np.argmin(err))
    return sizes[best], pts[best]


def shape_standing(scores: Scores, reference: Scores) -> tuple[int, int, float]:
    """How a grading's change of shape stands against ``reference``'s (proportional scaling): smaller is better.

    Compares :attr:`Scores.shape_error` and :attr:`Scores.shape_error_all`
    (:func:`standing`).
    """
    return standing(scores.shape_error, scores.shape_error_all, reference.shape_error, reference.shape_error_all)


def standing(shape: float, shape_all: float, ref: float, ref_all: float) -> tuple[int, int, float]:
    """How a change of shape stands against a reference's (proportional scaling): smaller is better.

    ``(−passed, −critical, worst)``: ``passed`` counts the two shape
    measures — the critical points (:func:`~.objectives.shape_error`) and
    every outline vertex (:func:`~.objectives.shape_error_all`) — on which
    the grading changes the design no more than the reference; ``critical``
    is 1 when the critical points are one of them (the issue's own measure
    goes first between two that pass one each); ``worst`` is the larger of
    the two ratios to the reference's. A grading at or below scaling on both
    comes first; between two that pass alike, the smaller worst ratio wins:
    on a shirt whose critical points the fit forces above scaling's, the
    grading that bends its curves least is taken, not the one a hair lower
    at the critical points with every curve pulled flat.
    """
    pairs = ((shape, ref), (shape_all, ref_all))
    passed = sum(ours <= ref for ours, ref in pairs)
    worst = max(ours / max(ref, 1e-9) for ours, ref in pairs)
    return -int(passed), -int(shape <= ref), float(worst)


def continuation_stages(all_levels, design_levels) -> list[tuple[float, float]]:
    """The final step's continuation stages ``(all-vertex factor, grid-interval factor)``, in the order run.

    Decreasing weights. The strongest all-vertex factor (every outline vertex
    held hard: curves keep their shape) runs once, at the largest
    grid-interval factor; at the next all-vertex factor the grid-interval
    factor steps down through its levels; at every further (smaller)
    all-vertex factor through its levels but the largest: under the full
    grid-interval term a smaller all-vertex weight changed the critical
    points by at most 0.0002 rad (the slim female's, the average male's and
    the tall elder's shirts, the slim female's trousers), the grid holds them.
    """
    alls = sorted({float(a) for a in all_levels}, reverse=True)
    designs = sorted({float(d) for d in design_levels}, reverse=True)
    if len(alls) < 2:
        return [(a, d) for a in alls for d in designs]
    lower = designs[1:] or designs
    return ([(alls[0], designs[0])] + [(alls[1], d) for d in designs]
            + [(a, d) for a in alls[2:] for d in lower])


def split_ladder(stages: list[tuple[float, float]], hold_split: bool) -> list[tuple[float, float, float]]:
    """The continuation with and without the design's split of the girth reductions held, in the order run.

    ``(split factor, all-vertex factor, grid-interval factor)``: with
    ``hold_split`` (the pattern has a reduction a dart takes part in and the
    suppression term has a weight), every stage of ``stages``
    (:func:`continuation_stages`) whose grid-interval factor is above 0 runs
    first with the term and the dart-length ceiling on (split factor 1),
    then every stage without them (0), the same ladder again: where holding
    the split costs shape at every level (the slim female's trousers, whose
    waist is 8.3 cm under scaling's, so that the back's reduction grows to
    1.34 of the sample's), the gradings without it compete on the same
    standing rule. At grid-interval factor 0 the term is off anyway, so
    those stages run once, in the second half. Decreasing tuples, like
    ``stages``: the order ``st < first`` relies on.
    """
    if not hold_split:
        return [(0.0, a, d) for a, d in stages]
    return [(1.0, a, d) for a, d in stages if d > 0] + [(0.0, a, d) for a, d in stages]


def choose(F: np.ndarray, *, tol_measure_cm: float, tol_seam: float, within: np.ndarray | None = None,
           standing: np.ndarray | None = None) -> int:
    """Row of ``F`` with the least shape error among those within tolerance.

    ``within`` : (n,) bool, optional — which rows are within tolerance (e.g.
    :func:`within_tolerance`: every target of the fit met); without it a row
    is within tolerance when ``f1 <= tol_measure_cm`` and ``f2 <= tol_seam``.
    When no row is, the rows whose worst normalised violation
    ``max(f1/tol1, f2/tol2)`` is within 25 % of the best one compete instead.
    ``standing`` : (n, 3), optional — every row's :func:`standing` against
    proportional scaling, ``(−passed, −critical, worst ratio)``: among the
    rows that compete, those that keep the most of the two shape measures at
    or below scaling's come first (the critical points first between those
    that keep one); when they keep both, the least shape error decides (the
    rule above), else the smallest worst ratio (the measure they miss comes
    closest).
    """
    F = np.asarray(F, dtype=np.float64)
    score = np.maximum(F[:, 0] / tol_measure_cm, F[:, 1] / tol_seam)
    ok = score <= 1.0 if within is None else np.asarray(within, dtype=bool)
    if not ok.any():
        ok = score <= score.min() * 1.25
    if standing is not None:
        standing = np.asarray(standing, dtype=np.float64)
        for col in (0, 1):
            ok = ok & (standing[:, col] == standing[ok, col].min())
        rows = np.flatnonzero(ok)
        if standing[rows[0], 0] > -2:
            return int(rows[np.argmin(standing[rows, 2])])
    rows = np.flatnonzero(ok)
    return int(rows[np.argmin(F[rows, 2])])


def non_dominated(F: np.ndarray) -> np.ndarray:
    """(n,) bool: the rows of ``F (n, k)`` no other row dominates (all minimised).

    Identical rows do not dominate each other, so duplicates are all kept.
    """
    F = np.asarray(F, dtype=np.float64)
    le = np.all(F[:, None, :] <= F[None, :, :], axis=2)  # le[j, i]: row j no worse than row i
    lt = np.any(F[:, None, :] < F[None, :, :], axis=2)
    return ~np.any(le & lt, axis=0)


def refine_members(F: np.ndarray, choice: int, n: int, *, tol_measure_cm: float = 0.5,
                   tol_seam: float = 0.5) -> list[int]:
    """Front rows the final step starts from: at most ``n``, distinct.

    The NSGA-II choice first, then the row with the least normalised
    violation ``max(f1/tol1, f2/tol2)``, then the least measurement error and
    the least seam error.
    """
    F = np.asarray(F, dtype=np.float64)
    score = np.maximum(F[:, 0] / tol_measure_cm, F[:, 1] / tol_seam)
    order = [int(choice), int(np.argmin(score)), int(np.argmin(F[:, 0])), int(np.argmin(F[:, 1]))]
    return list(dict.fromkeys(order))[:max(int(n), 0)]


def within_tolerance(grid: PatternGrid, data: ObjectiveData, X: np.ndarray, *, mean_cm: float = 0.5,
                     max_cm: float = 1.5, seam_cm: float = 0.1, grain_deg: float | None = 0.5,
                     symmetry_cm: float | None = 0.2) -> np.ndarray:
    """(n_pop,) bool: which individuals meet the fit (objectives 1 and 2 within tolerance).

    Mean measurement error ≤ ``mean_cm``, every measurement within
    ``max_cm``, every seam length mismatch and notch misalignment within
    ``seam_cm``, every grain line turned by at most ``grain_deg`` (None: not
    checked; a piece cut off grain hangs askew however well it measures),
    every piece the design draws symmetric (:func:`~.symmetry.mirror_symmetries`)
    within ``symmetry_cm`` of its mirror image (None: not checked; NSGA-II's
    members are not held to it, and one of them tied in all three objectives
    with the refined grading while its skirt front was 3.2 cm lopsided),
    no folded grid cell and every outline simple. Vectorised over
    ``X (n_pop, n_var)``; the simplicity test runs only on the rows that pass
    the rest.
    """
    X = np.atleast_2d(np.asarray(X, dtype=np.float64))
    ev = evaluate(data, grid.outlines(X))
    err = np.abs(link_error(data, ev.achieved_cm))
    seams = np.abs(np.concatenate([ev.seam_mismatch_cm, ev.notch_cm], axis=1))
    ok = ((ev.measurement_error <= mean_cm) & (err.max(axis=1, initial=0.0) <= max_cm)
          & (seams.max(axis=1, initial=0.0) <= seam_cm) & (grid.fold_margin(X) > 0))
    if grain_deg is not None:
        from .refine import grain_tilt

        ok &= np.degrees(np.abs(grain_tilt(grid, X))).max(axis=1, initial=0.0) <= grain_deg
    if symmetry_cm is not None:
        from .symmetry import mirror_symmetries, symmetry_error

        ok &= symmetry_error(grid, mirror_symmetries(grid), X).max(axis=1, initial=0.0) <= symmetry_cm
    for i in np.flatnonzero(ok):
        ok[i] = _is_simple(deform_pattern(grid, X[i]))
    return ok


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

    x_start = np.asarray(x, dtype=np.float64).copy()
    scale = np.concatenate([np.full(2 * g.n_control, g.extent_cm) for g in grid.pieces])
    h = 1e-6 * scale
    A = np.zeros((0, len(x_start))) if linear is None else np.asarray(linear, dtype=np.float64)
    shared = balanced_links(data)
    share0 = link_shares(data, data.points0[None])[0][:, :, shared]
    axes0 = 0.0 if x_design is None else piece_axes_turn(data, grid.outlines(np.asarray(x_design)[None, :]))

    def resid_batch(X: np.ndarray) -> np.ndarray:
        pts = grid.outlines(X)
        r = residuals(data, pts, w_critical=10.0 * shape_scale, w_angle=4.0 * shape_scale)
        reg = w_reg * (X - x_start) / scale
        fold = w_fold * np.maximum(0.0, 2 * FOLD_MARGIN - grid.fold_margin(X))[:, None]
        bend = w_bend * grid.bending(X)
        lin = w_linear * (X @ A.T)
        share = w_share * (link_shares(data, pts)[0][:, :, shared] - share0).reshape(len(X), -1)
        axes = w_axes * (piece_axes_turn(data, pts) - axes0).reshape(len(X), -1)
        return np.concatenate([r, reg, bend, fold, lin, share, axes], axis=1)

    calls = {"n": 0}

    def fun(xv):
        calls["n"] += 1
        if progress is not None:
            progress("repair", min(calls["n"], max_nfev), max_nfev)
        return resid_batch(xv[None, :])[0]

    def jac(xv):
        base = resid_batch(xv[None, :])[0]
        Xp = xv[None, :] + np.diag(h)
        rp = resid_batch(Xp)
        return ((rp - base[None, :]) / h[:, None]).T

    sol = least_squares(fun, x_start, jac=jac, method="trf", x_scale=scale, max_nfev=max_nfev,
                        tr_solver="lsmr",
                        ftol=1e-10, xtol=1e-10, gtol=1e-10)
    if progress is not None:
        progress("repair", max_nfev, max_nfev)
    return sol.x, float(sol.cost)


class _ProgressCallback:
    """pymoo callback: reports generations and records the best objectives."""

    def __init__(self, n_gen: int, progress: Progress | None) -> None:
        self.n_gen = n_gen
        self.progress = progress
        self.history: list[tuple[float, float, float, float]] = []

    def __call__(self, algorithm) -> None:
        F = algorithm.opt.get("F") if algorithm.opt is not None else None
        if F is not None and len(F):
            self.history.append((algorithm.n_gen, *np.min(F, axis=0)))
        if self.progress is not None:
            self.progress("grade", int(algorithm.n_gen), self.n_gen)


def fit_pattern(
    pattern: Pattern,
    measurements: Mapping[str, float],
    *,
    seed: int = 0,
    pop_size: int = 80,
    n_gen: int = 120,
    max_lines: int = 6,
    max_cell_frac: float | None = 0.2,
    deformation: str = "bilinear",
    tol_measure_cm: float = 0.5,
    tol_seam: float = 0.5,
    size: str = "fit",
    do_repair: bool = True,
    measure_band_cm: float = 0.15,
    keep_straight: bool = True,
    keep_grain: bool = True,
    keep_symmetry: bool = True,
    refine_iter: int = 40,
    w_fit: float = 0.02,
    w_design: float = 0.7,
    w_share: float = 3.0,
    w_suppress: float = 3.0,
    design_levels: tuple[float, ...] = (1.0, 1.0 / 3.0, 1.0 / 9.0, 0.0),
    w_all: float = 1.0,
    all_levels: tuple[float, ...] = (3.0, 1.0, 0.5),
    n_refine: int = 3,
    n_trade: int = 2,
    source: str = "pattern",
    progress: Progress | None = None,
) -> FitResult:
    """Grade ``pattern`` to ``measurements``: NSGA-II, then least shape change under the fit.

    Parameters
    ----------
    pattern : pattern with bridge data (seams and measurement links)
    measurements : body measurement id -> cm (e.g. ``Measurements.values_cm()``)
    seed : every random draw derives from it; same seed, same result
    pop_size, n_gen : NSGA-II population size and generations
    max_lines, max_cell_frac : control grid resolution (:func:`~.grid.piece_grid`)
    deformation : map from the control points to the pieces,
        ``"bilinear"`` or ``"cubic"`` (C1 across grid lines;
        :func:`~.grid.cubic_weights`)
    tol_measure_cm, tol_seam : tolerances on objectives 1 and 2 for the choice
        on the Pareto front
    size : size name of the graded pieces (e.g. the character's name)
    do_repair : run the final constrained step (:func:`~.refine.refine`);
        without it the NSGA-II choice is the result
    measure_band_cm : the final step keeps every measurement within this of
        its target (seams and notches are closed exactly)
    keep_straight : straight grain-parallel edges (centre front, folds,
        straight hems) stay straight and keep their direction
    keep_symmetry : pieces drawn symmetric about a grain line (a front cut
        on the fold, a yoke, a collar) stay symmetric
        (:mod:`.symmetry`)
    refine_iter : iterations of each constrained Gauss–Newton run
    w_fit : cost of the measurement errors inside the band, rad of shape
        error per cm of mean measurement error (:func:`~.refine.refine`)
    w_design, w_share : weights of the design-preservation terms (control-grid
        intervals; each piece's share of the links with legs on several pieces)
    design_levels : factors on ``w_design`` tried in turn until the result
        changes the design less than proportional scaling (with one
        bisection step between the last level that did not and the first
        that did). ``w_share`` always keeps its full weight: the front/back
        split of a girth and the balance of the front and back rise are
        design facts a tailor checks, and without them a slim body's trousers
        came out with the back rise shorter than the front's.
    w_suppress : weight of the design's split of every reduction between
        two girth levels of a piece among its darts and seams
        (:mod:`.suppression`); it steps down with ``w_design``'s levels,
        and the continuation runs its stages first with the term (and the
        dart-length ceiling it brings) and then without it
        (:func:`split_ladder`), so that a grading where holding the split
        costs shape is not kept for it. 0: never held
    w_all, all_levels : weight of the every-vertex angle term of the final
        step (:func:`~.refine.refine`) and its factors, tried in turn when no
        ``design_levels`` factor brings the shape error below proportional
        scaling's (the slim bodies' trousers)
    n_refine : NSGA-II front members the final step starts from
    n_trade : versions of the best refined solution added to the front along
        the fit-against-shape trade (:func:`_trade_offs`): gradings within
        tolerance for the designer to choose from (``fit --choose K``); the
        default choice stays among the rows within ``measure_band_cm``
    source : pattern name for error messages
    progress : ``progress(stage, done, total)`` callback

    Returns
    -------
    FitResult

    Raises
    ------
    InputError
        No measurement links (message says how to add them), measurements the
        garment needs that the character lacks (listed), bad bridge data.
    SolverError
        No feasible (fold-free) solution was found.
    """
    from .blas import single_blas_thread

    with single_blas_thread():
        return _fit_pattern(
            pattern, measurements, seed=seed, pop_size=pop_size, n_gen=n_gen, max_lines=max_lines,
            max_cell_frac=max_cell_frac, deformation=deformation, tol_measure_cm=tol_measure_cm,
            tol_seam=tol_seam, size=size, do_repair=do_repair, measure_band_cm=measure_band_cm,
            keep_straight=keep_straight, keep_grain=keep_grain, keep_symmetry=keep_symmetry,
            refine_iter=refine_iter, w_fit=w_fit,
            w_design=w_design, w_share=w_share, w_suppress=w_suppress, design_levels=tuple(design_levels),
            w_all=w_all, all_levels=tuple(all_levels), n_refine=n_refine, n_trade=n_trade, source=source,
            progress=progress,
        )


def _checks(grid: PatternGrid, data: ObjectiveData, sol: Solution, reference: Solution) -> tuple[Finding, ...]:
    """:func:`~.checks.design_checks` of ``sol`` against proportional scaling."""
    from .checks import cut_line_turns, design_checks
    from .symmetry import mirror_symmetries, symmetry_error

    if sol.x is None or reference.x is None:
        return ()
    sym = mirror_symmetries(grid)
    err = symmetry_error(grid, sym, sol.x[None])[0]
    return design_checks(data, grid.outlines(sol.x[None])[0], grid.outlines(reference.x[None])[0],
                         piece_names=tuple(g.name for g in grid.pieces),
                         symmetry_cm={s.piece: float(e) for s, e in zip(sym, err, strict=True)},
                         cut_turn=cut_line_turns(grid.pattern, sol.pattern, reference.pattern))


def _forcing(grid: PatternGrid, data: ObjectiveData, sol: Solution, reference: Solution,
             finish: Callable[[ObjectiveData, np.ndarray], np.ndarray], band_cm: float,
             source: str) -> Forcing | None:
    """:func:`~.forcing.shape_forcing` of ``sol`` when its shape error is above ``reference``'s, logged."""
    if sol.x is None or reference.x is None or sol.scores.shape_error <= reference.scores.shape_error:
        return None
    forcing = shape_forcing(grid, data, sol.x, reference.x, finish, band_cm=band_cm)
    log.warning("%s: %s", source, describe_forcing(forcing))
    return forcing


CLOSE_RATIO = 1.5
"""When no continuation stage passed on the first start, later starts run the stage that came closest
at the critical points if its shape error came within this factor of scaling's (another start may pass
there: the slim female's trousers came within 1.29 and passed from an NSGA-II member), else the stage
that stood best on both measures."""

RELEASE_ITER = 6
"""Iterations of each release test of :func:`~.forcing.shape_forcing` (from the fitted solution)."""

TRADE_LEVELS = ((0.45, 0.0), (0.05, 0.2), (0.3, 0.005), (0.02, 1.0))
"""(measurement band cm, fit cost) of the front members that trade fit against shape: a looser
fit with less change of shape, a tighter one with more, and so on."""


def _max_link_error(grid: PatternGrid, data: ObjectiveData, X: np.ndarray) -> np.ndarray:
    """(n,) largest ``|achieved - target|`` over the links of every individual, cm."""
    achieved = _achieved(data, grid, np.atleast_2d(X))[0]
    return np.abs(link_error(data, achieved)).max(axis=1, initial=0.0)


def _trade_offs(grid: PatternGrid, data: ObjectiveData, refined: list[Solution], settings: dict, n: int,
                size: str, accept: dict, progress: Progress | None) -> list[Solution]:
    """Versions of the least-shape refined solution along the fit-against-shape trade.

    The final step is re-run from that solution (it starts fitted, so a few
    iterations suffice) with another measurement band and cost on the
    measurement errors inside it (:data:`TRADE_LEVELS`, the first ``n``): a
    wider band without cost gives a grading within tolerance that changes
    the shape less and misses the measurements by more, a narrower one with
    a larger cost the opposite. The default choice keeps to rows within the
    final step's own band, so the looser ones change nothing unless the user
    picks one (:func:`choose_member`).
    """
    from .refine import refine

    fitted = [s for s in refined if _meets(s, **accept)]
    if not fitted:
        return []
    base = min(fitted, key=lambda s: s.scores.shape_error)
    out = []
    for band, w_fit in TRADE_LEVELS[:max(int(n), 0)]:
        res = refine(grid, data, base.x, **{**settings, "measure_tol_cm": band, "w_fit": w_fit},
                     progress=progress)
        sol = _solution(grid, data, "nsga2+refine", res.x, size,
                        f"{base.note}; fit traded against shape: band {band:g} cm, fit cost {w_fit:g}")
        if _meets(sol, **accept):
            out.append(sol)
    return out


def choose_member(result: FitResult, k: int, *, size: str | None = None) -> FitResult:
    """``fit --choose K``: the final step re-run from row ``k`` of the final front, as the result.

    The start is the front member's genes; the final step runs with the
    settings the continuation settled on (:attr:`FitResult.finish_settings`).
    The front itself is kept; ``chosen_index`` becomes ``k`` and the checks
    and the release test (:attr:`FitResult.forcing`) are run on the new pattern.

    Raises
    ------
    InputError
        ``k`` is not a row of the front.
    """
    from ..errors import InputError
    from .refine import refine

    n = len(result.front_X)
    if not 0 <= int(k) < n:
        raise InputError(f"--choose {k}: the Pareto front has rows 0 to {n - 1}; pick one of them "
                         "(pareto.png numbers them)")
    size = size if size is not None else (result.pattern.pieces[0].size if result.pattern.pieces else "fit")
    with _single_thread():
        res = refine(result.grid, result.data, result.front_X[int(k)], **result.finish_settings)
    sol = _solution(result.grid, result.data, "nsga2+refine", res.x, size,
                    f"least shape change under the fit, started from front member {int(k)} (chosen by the user)")
    findings = _checks(result.grid, result.data, sol, result.baselines["proportional"])
    settings = {**result.finish_settings, "max_iter": RELEASE_ITER}

    def release_finish(d: ObjectiveData, x_start: np.ndarray) -> np.ndarray:
        return refine(result.grid, d, x_start, **settings).x

    with _single_thread():
        forcing = _forcing(result.grid, result.data, sol, result.baselines["proportional"], release_finish,
                           float(settings.get("measure_tol_cm", 0.15)), "fit --choose")
    return dataclasses.replace(result, pattern=sol.pattern, chosen=sol, chosen_index=int(k), findings=findings,
                               forcing=forcing)


def front_members(result: FitResult, n: int = 6) -> list[tuple[int, Pattern]]:
    """The front rows within tolerance worth showing, with their patterns: ``[(row, pattern), ...]``.

    At most ``n`` rows within tolerance, spread over the fit-against-shape
    trade (evenly over the rows sorted by measurement error, the chosen row
    always among them), each with its graded pattern, for the thumbnails of
    ``pareto.png``.
    """
    rows = np.flatnonzero(result.front_within)
    if not len(rows):
        return []
    rows = rows[np.argsort(result.front_F[rows, 0], kind="stable")]
    # one row per distinct grading: starts that converged to the same solution count once
    key = np.round(result.front_F[rows][:, [0, 2]] / [0.005, 5e-5]).astype(np.int64)
    _, first = np.unique(key, axis=0, return_index=True)
    rows = rows[np.sort(first)]
    if len(rows) > n:
        pick = np.unique(np.round(np.linspace(0, len(rows) - 1, n)).astype(int))
        rows = rows[pick]
        if result.chosen_index not in rows and result.front_within[result.chosen_index]:
            rows[np.argmin(np.abs(result.front_F[rows, 0] - result.front_F[result.chosen_index, 0]))] = \
                result.chosen_index
    size = result.pattern.pieces[0].size if result.pattern.pieces else "fit"
    return [(int(r), deform_pattern(result.grid, result.front_X[r], size=size)) for r in sorted(set(rows.tolist()))]


def _single_thread():
    from .blas import single_blas_thread

    return single_blas_thread()


def _meets(sol: Solution, *, mean_cm: float, max_cm: float, seam_cm: float) -> bool:
    sc = sol.scores
    return (_valid(sol) and sc.measurement_error <= mean_cm and sc.max_measurement_error <= max_cm
            and sc.max_seam_mismatch_cm <= seam_cm)


def _fit_pattern(pattern, measurements, *, seed, pop_size, n_gen, max_lines, max_cell_frac, deformation,
                 tol_measure_cm, tol_seam, size, do_repair, measure_band_cm, keep_straight, keep_grain,
                 keep_symmetry, refine_iter, w_fit, w_design, w_share, w_suppress, design_levels, w_all,
                 all_levels, n_refine, n_trade, source, progress):
    from pymoo.algorithms.moo.nsga2 import NSGA2
    from pymoo.optimize import minimize

    from .operators import GridCrossover, GridMutation, SeedSampling
    from .problem import GradingProblem
    from .refine import grain_constraints, refine, row_basis, straight_constraints, straight_edges
    from .suppression import suppression
    from .symmetry import mirror_symmetries, symmetry_constraints

    t0 = time.perf_counter()
    measurements = {str(k): float(v) for k, v in measurements.items()}
    grid = build_grid(pattern, max_lines=max_lines, max_cell_frac=max_cell_frac, deformation=deformation)
    data = objective_data(grid, measurements, source=source)
    linear = [straight_constraints(grid, straight_edges(grid))] if keep_straight else []
    if keep_grain:
        linear.append(grain_constraints(grid))
    symmetric = symmetry_constraints(grid, mirror_symmetries(grid)) if keep_symmetry else None
    straight = row_basis(np.concatenate(linear)) if linear else None
    if progress is not None:
        progress("seed", 0, 1)

    t_base = time.perf_counter()
    x_axis = axis_scaling(grid, data)
    base_axis = _solution(grid, data, "proportional", x_axis, size,
                          "each piece scaled along and across the grain by its measurements")
    t_uni = time.perf_counter()
    x_uniform = uniform_scaling(grid, data)
    base_uni = _solution(grid, data, "proportional_uniform", x_uniform, size,
                         "each piece scaled by its largest measurement ratio (thesis Algorithm 4)")
    t_end = time.perf_counter()
    baselines = {
        "proportional": dataclasses.replace(base_axis, seconds=t_uni - t_base),
        "proportional_uniform": dataclasses.replace(base_uni, seconds=t_end - t_uni),
    }
    seeds = [x_axis, x_uniform]
    t_near = time.perf_counter()
    near = nearest_size(pattern, data, grid)
    if near is not None:
        size_name, pts = near
        from ..pattern.grading import grade

        graded = grade(pattern, size_name)
        offs = grid.point_offsets
        x_near = grid.fit_controls([pts[offs[k]:offs[k + 1]] for k in range(len(grid.pieces))])
        scores = score_points(data, pts, fold_margin=float(grid.fold_margin(x_near[None, :])[0]),
                              pattern=graded)
        baselines["nearest_size"] = Solution(name="nearest_size", pattern=graded, scores=scores,
                                             x=None, note=f"graded size {size_name}",
                                             seconds=time.perf_counter() - t_near)
        seeds.append(x_near)
    seeds.append(grid.x0.copy())

    accept = {"mean_cm": min(tol_measure_cm, 0.5), "max_cm": 1.5, "seam_cm": 0.1}
    ref_scores = baselines["proportional"].scores
    shape_ref = ref_scores.shape_error
    # the continuation's stages in order: the grid-interval weight steps
    # down first; only when no level of it passes does the all-vertex angle
    # weight step down, and the grid-interval levels run again
    stages = split_ladder(continuation_stages(all_levels, design_levels),
                          w_suppress > 0 and suppression(grid, data).n_parts > 0)
    halves = sorted({st[0] for st in stages}, reverse=True)  # the split held (1), then not (0)
    start_stage = {h: next(st for st in stages if st[0] == h) for h in halves}  # where later starts begin
    settled = [stages[0]]  # the last stage that passed
    closest_run: list[Solution | None] = [None]  # the first passing run of the last start, else its closest
    later: dict[float, tuple] = {}  # no stage of a half passed on the first start: the stages later starts run
    stage_of: dict[bytes, tuple[float, float, float]] = {}  # the stage every refined solution ran at

    def settings_at(stage: tuple[float, float, float]) -> dict:
        split, w_all_level, level = stage
        return {"measure_tol_cm": measure_band_cm, "straight": straight, "max_iter": refine_iter,
                "x_design": x_axis, "w_design": w_design * level, "w_share": w_share, "w_fit": w_fit,
                "w_suppress": w_suppress * split * level, "dart_cap": w_suppress * split * level > 0,
                "w_all": w_all * w_all_level, "symmetric": symmetric}

    def finish_at(start_name: str, x_start: np.ndarray, stage: tuple[float, float, float]) -> Solution:
        split, w_all_level, level = stage
        res = refine(grid, data, x_start, **settings_at(stage), progress=progress)
        if res.max_violation_cm > 1e-3:
            log.info("%s: final step from the %s (design weight x%.3g) left a violation of %.3g cm",
                     source, start_name, level, res.max_violation_cm)
        note = (f"least shape change under the fit, started from the {start_name}, "
                f"design weight x{level:.3g}")
        if w_all_level != 1.0:
            note += f", all-vertex weight x{w_all_level:.3g}"
        if w_suppress > 0 and split == 0 and level > 0:
            note += ", the split of the girth reductions not held"
        return _solution(grid, data, "nsga2+refine", res.x, size, note)

    def finish(start_name: str, x_start: np.ndarray) -> Solution | None:
        """The constrained final step from ``x_start`` with the continuation on its tie-break weights.

        Stages run in order of decreasing weights (:func:`continuation_stages`),
        with the split of the girth reductions held and then without it
        (:func:`split_ladder`).
        Each stage starts from ``x_start``, not from the last stage's result:
        warm-started, the slim female's trousers settled at 0.0030 rad against
        scaling's 0.0027 (cold: 0.0019). Lower weights trade the all-vertex
        measure for the critical-point one, so the ladder stops at the first
        stage whose shape error at the critical points is below scaling's: a
        later stage could only bend more curves. When a level passes after
        one that did not (at the same all-vertex weight and split), the geometric mean
        of the two is tried once. Of the stages run, the result is the one
        that stands best against scaling on both measures
        (:func:`shape_standing`). Later starts begin at the stage that passed;
        when none did, later starts run only the stage that came closest at
        the critical points when it came within :data:`CLOSE_RATIO` of
        scaling's (another start may pass there), else only the stage that
        stood best. With the split of the girth reductions held, the ladder
        runs in two halves (:func:`split_ladder`), each on these rules: the
        stages with the split held, and only when their result does not keep
        both measures at or below scaling's, the stages without it; the
        result stands best of all the runs of both. When one half passes and
        the other passed nowhere, later starts skip the other; when neither
        passed, later starts run the one stage of both that came closest (or
        stood best). None when no run meets the fit.
        """
        todos = [list(later[h]) if h in later
                 else [start_stage[h]] + [st for st in stages if st[0] == h and st < start_stage[h]]
                 for h in halves]
        closest_run[0] = None
        done: dict[tuple[float, float, float], Solution] = {}
        best: list = [None, None]  # solution, stage

        def ladder(todo: list, run: Callable) -> tuple[float, float, float] | None:
            """Run ``todo`` in order until a stage passes at the critical points; that stage, or None."""
            failed: tuple[float, float, float] | None = None
            for stage in todo:
                cand = run(stage)
                if cand is None:
                    continue
                if closest_run[0] is None or cand.scores.shape_error < closest_run[0].scores.shape_error:
                    closest_run[0] = cand
                if cand.scores.shape_error < shape_ref:
                    if failed is not None and failed[:2] == stage[:2]:
                        level = stage[2]
                        mid = float(np.sqrt(failed[2] * level)) if level > 0 else failed[2] / 3.0
                        between = run((*stage[:2], mid))
                        if between is not None and between.scores.shape_error < shape_ref:
                            stage, closest_run[0] = (*stage[:2], mid), between
                    start_stage[stage[0]] = settled[0] = stage
                    return stage
                failed = stage
            return None

        def run(stage: tuple[float, float, float]) -> Solution | None:
            cand = finish_at(start_name, x_start, stage)
            stage_of[cand.x.tobytes()] = stage
            if not _meets(cand, **accept):
                return None
            done[stage] = cand
            if best[0] is None or shape_standing(cand.scores, ref_scores) < shape_standing(best[0].scores,
                                                                                         ref_scores):
                best[:] = [cand, stage]
            return cand

        passed, failed = set(), []  # the halves that passed at the critical points, that ran every stage and did not
        for todo in (t for t in todos if t):
            if ladder(todo, run) is not None:
                passed.add(todo[0][0])
            elif len(todo) > 1:
                failed.append(todo[0][0])
            if best[0] is not None and shape_standing(best[0].scores, ref_scores)[0] == -2:
                break  # both measures at or below scaling's: the split stays held
        if failed and done:
            if passed:  # later starts skip the half that passed nowhere
                later.update({h: () for h in failed})
            else:  # later starts run one stage of all: the closest at the critical points, else the best
                closest = min(done, key=lambda st: done[st].scores.shape_error)
                near = done[closest].scores.shape_error <= CLOSE_RATIO * shape_ref
                one = closest if near else best[1]
                later.update({h: (one,) if one[0] == h else () for h in halves})
        return best[0]

    refined: list[Solution] = []
    if do_repair:
        # the proportional seed finished first: a fitted, low-shape individual
        # seeds the population beside the proportional one
        first = finish("proportional seed", x_axis)
        if first is not None:
            refined.append(first)
            # NSGA-II is seeded with the run least changed at the critical points (the
            # objective it minimises), which the ladder's result need not be
            seeds.insert(1, closest_run[0].x)
    if progress is not None:
        progress("seed", 1, 1)

    problem = GradingProblem(grid, data)
    seeds_arr = np.clip(np.stack(seeds), problem.xl, problem.xu)
    algorithm = NSGA2(
        pop_size=pop_size,
        sampling=SeedSampling(grid, seeds_arr),
        crossover=GridCrossover(grid),
        mutation=GridMutation(grid, n_gen),
        eliminate_duplicates=False,
    )
    callback = _ProgressCallback(n_gen, progress)
    res = minimize(problem, algorithm, ("n_gen", n_gen), seed=int(seed), callback=callback,
                   verbose=False, save_history=False, copy_algorithm=False)
    opt = res.opt if res.opt is not None and len(res.opt) else None
    if opt is None:
        raise SolverError(f"{source}: NSGA-II found no fold-free solution in {n_gen} generations; "
                          "try more generations or a finer grid")
    ga_X = np.asarray(opt.get("X"), dtype=np.float64)
    ga_F = np.asarray(opt.get("F"), dtype=np.float64)
    order = np.lexsort((ga_F[:, 2], ga_F[:, 1], ga_F[:, 0]))
    ga_X, ga_F = ga_X[order], ga_F[order]
    ga_idx = choose(ga_F, tol_measure_cm=tol_measure_cm, tol_seam=tol_seam)
    ga_choice = _solution(grid, data, "nsga2", ga_X[ga_idx], size, "least shape error within tolerance")
    if do_repair:
        # the final step from a few members of NSGA-II's front: its own choice
        # and the members with the least measurement and seam error
        for i in refine_members(ga_F, ga_idx, n_refine, tol_measure_cm=tol_measure_cm, tol_seam=tol_seam):
            sol = finish("NSGA-II choice" if i == ga_idx else f"NSGA-II front member {i}", ga_X[i])
            if sol is not None:
                refined.append(sol)
    if do_repair and n_trade:
        fitted = [r for r in refined if _meets(r, **accept)]
        base_stage = stage_of.get(min(fitted, key=lambda r: r.scores.shape_error).x.tobytes(),
                                  settled[0]) if fitted else settled[0]
        refined += _trade_offs(grid, data, refined, settings_at(base_stage), n_trade, size, accept,
                               progress)
    # the final Pareto front: NSGA-II's front and the refined solutions, the
    # dominated ones removed; the choice is the rule on it
    front_X = np.concatenate([ga_X] + [s.x[None, :] for s in refined])
    front_F = np.concatenate([ga_F] + [s.scores.F[None, :] for s in refined])
    is_refined = np.r_[np.zeros(len(ga_X), bool), np.ones(len(refined), bool)]
    keep = non_dominated(front_F)
    front_X, front_F, is_refined = front_X[keep], front_F[keep], is_refined[keep]
    within = within_tolerance(grid, data, front_X, mean_cm=accept["mean_cm"], max_cm=accept["max_cm"],
                              seam_cm=accept["seam_cm"], grain_deg=0.5 if keep_grain else None,
                              symmetry_cm=0.2 if keep_symmetry else None)
    # the default choice keeps the honest fit: among the rows within
    # tolerance, those whose every measurement is within the final step's
    # band; the looser rows (less change of shape) stay on the front for the
    # user to pick (choose_member)
    honest = within & (_max_link_error(grid, data, front_X) <= measure_band_cm + 1e-3)
    all_vertex = shape_error_all(data, grid.outlines(front_X))
    ranks = np.array([standing(f, a, ref_scores.shape_error, ref_scores.shape_error_all)
                      for f, a in zip(front_F[:, 2], all_vertex, strict=True)])
    idx = choose(front_F, tol_measure_cm=tol_measure_cm, tol_seam=tol_seam,
                 within=honest if honest.any() else within, standing=ranks)
    by_x = {s.x.tobytes(): s for s in refined}
    chosen = by_x.get(front_X[idx].tobytes()) or _solution(
        grid, data, "nsga2", front_X[idx], size,
        "NSGA-II front member: least shape error within tolerance on the final front")
    if do_repair and not within[idx]:
        # nothing on the front meets the fit: the penalty repair of the NSGA-II
        # choice, when it gets closer
        x_rep, _ = repair(grid, data, ga_X[ga_idx], linear=straight, x_design=x_axis, progress=progress)
        rep = _solution(grid, data, "nsga2+repair", x_rep, size, "least-squares repair of the NSGA-II choice")
        if _valid(rep) and rep.scores.measurement_error < chosen.scores.measurement_error:
            chosen = rep
    findings = _checks(grid, data, chosen, baselines["proportional"])
    for f in findings:
        log.warning("%s: %s", source, f)
    chosen_stage = stage_of.get(chosen.x.tobytes(), settled[0]) if chosen.x is not None else settled[0]
    forcing = None
    if do_repair:
        def release_finish(d: ObjectiveData, x_start: np.ndarray) -> np.ndarray:
            # from the fitted solution, a few iterations show which way the shape goes
            return refine(grid, d, x_start, **{**settings_at(chosen_stage), "max_iter": RELEASE_ITER}).x

        forcing = _forcing(grid, data, chosen, baselines["proportional"], release_finish, measure_band_cm, source)
    seconds = time.perf_counter() - t0
    return FitResult(
        pattern=chosen.pattern, original=pattern, chosen=chosen, ga_choice=ga_choice,
        front_F=front_F, front_X=front_X, chosen_index=idx, front_refined=is_refined,
        front_within=within, baselines=baselines, findings=findings,
        finish_settings=settings_at(chosen_stage), forcing=forcing,
        measurements=measurements, grid=grid, data=data, seconds=seconds, seed=int(seed),
        pop_size=pop_size, n_gen=n_gen, history=np.array(callback.history, dtype=np.float64).reshape(-1, 4),
    )
