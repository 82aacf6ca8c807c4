"""Grade a pattern to a character's measurements: seeds, NSGA-II, choice, final constrained step.

:func:`fit_pattern` is the grader's entry point; :func:`_fit_pattern` reads
as its pipeline:

1. build the control grids (:mod:`.grid`) and compile the targets
   (:mod:`.objectives`);
2. make the seeds and baselines (:mod:`.seeds`): proportional scaling per
   the thesis's Algorithm 4 (one factor per piece, the largest measurement
   ratio), proportional scaling along and across the grain (one factor per
   axis per piece, from the measurements running mostly that way), the
   nearest graded size when the pattern has grade rules, and the original;
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
   proportional scaling (:mod:`.continuation`);
5. the refined solutions join NSGA-II's front, the dominated rows are
   removed, and the issue's rule chooses on that final front
   (:mod:`.front`): the least shape error among the members within
   tolerance on measurements and seams (:func:`~.front.within_tolerance`); when
   none is, the penalty repair (:mod:`.repair`) of NSGA-II's choice, if it
   gets closer;
6. the design checks (:mod:`.checks`) and the release test
   (:mod:`.forcing`) of the chosen grading.
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
from .continuation import (
    Continuation,
    FinishSettings,
    Stage,
    continuation_stages,
    shape_standing,
    split_ladder,
    standing,
)
from .forcing import Forcing, describe_forcing, shape_forcing
from .front import (
    choose,
    final_front,
    front_members,
    front_solution,
    non_dominated,
    refine_members,
    trade_offs,
    within_tolerance,
)
from .grid import PatternGrid, build_grid
from .objectives import ObjectiveData, objective_data
from .repair import repair
from .seeds import axis_scaling, baselines, nearest_size, uniform_scaling
from .solution import Acceptance, Progress, Scores, Solution, is_valid, meets, score_points, solution

__all__ = [
    "RELEASE_ITER",
    "FitResult",
    "FitSettings",
    "Scores",
    "Solution",
    "axis_scaling",
    "build_grid",
    "choose",
    "choose_member",
    "continuation_stages",
    "fit_pattern",
    "front_members",
    "nearest_size",
    "non_dominated",
    "objective_data",
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


RELEASE_ITER = 6
"""Iterations of each release test of :func:`~.forcing.shape_forcing` (from the fitted solution)."""


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class FitResult:
    """Everything :func:`fit_pattern` found.

    pattern : the graded pattern (the chosen solution after the final step)
    chosen : the same as a :class:`Solution`; ``ga_choice`` is the NSGA-II choice before it
    front_F : (n_front, 3) objectives of the final Pareto front: NSGA-II's
        front and the solutions of the final step, dominated rows removed
    front_X : (n_front, n_var) its genes ; chosen_index : row of ``chosen``
    front_refined : (n_front,) bool, the rows the final step produced
    front_within : (n_front,) bool, the rows within tolerance (:func:`~.front.within_tolerance`)
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


@dataclass(frozen=True, slots=True, kw_only=True)
class FitSettings:
    """:func:`fit_pattern`'s settings, as its parameters of the same names describe them."""

    seed: int
    pop_size: int
    n_gen: int
    max_lines: int
    max_cell_frac: float | None
    deformation: str
    tol_measure_cm: float
    tol_seam: float
    size: str
    do_repair: bool
    measure_band_cm: float
    keep_straight: bool
    keep_grain: bool
    keep_symmetry: bool
    refine_iter: int
    w_fit: float
    w_design: float
    w_share: float
    w_suppress: float
    design_levels: tuple[float, ...]
    w_all: float
    all_levels: tuple[float, ...]
    n_refine: int
    n_trade: int
    source: str


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
        (:func:`~.continuation.split_ladder`), so that a grading where holding the split
        costs shape is not kept for it. 0: never held
    w_all, all_levels : weight of the every-vertex angle term of the final
        step (:func:`~.refine.refine`) and its factors, tried in turn when no
        ``design_levels`` factor brings the shape error below proportional
        scaling's (the slim bodies' trousers)
    n_refine : NSGA-II front members the final step starts from
    n_trade : versions of the best refined solution added to the front along
        the fit-against-shape trade (:func:`~.front.trade_offs`): gradings within
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

    settings = FitSettings(
        seed=seed, pop_size=pop_size, n_gen=n_gen, max_lines=max_lines, max_cell_frac=max_cell_frac,
        deformation=deformation, tol_measure_cm=tol_measure_cm, tol_seam=tol_seam, size=size, do_repair=do_repair,
        measure_band_cm=measure_band_cm, keep_straight=keep_straight, keep_grain=keep_grain,
        keep_symmetry=keep_symmetry, refine_iter=refine_iter, w_fit=w_fit, w_design=w_design, w_share=w_share,
        w_suppress=w_suppress, design_levels=tuple(design_levels), w_all=w_all, all_levels=tuple(all_levels),
        n_refine=n_refine, n_trade=n_trade, source=source)
    with single_blas_thread():
        return _fit_pattern(pattern, measurements, settings, progress)


def _fit_pattern(pattern: Pattern, measurements: Mapping[str, float], fs: FitSettings,
                 progress: Progress | None) -> FitResult:
    """:func:`fit_pattern`'s pipeline (on one BLAS thread)."""
    t0 = time.perf_counter()
    measurements = {str(k): float(v) for k, v in measurements.items()}
    setup = _setup(pattern, measurements, fs)
    grid, data = setup.grid, setup.data
    if progress is not None:
        progress("seed", 0, 1)
    start = baselines(pattern, grid, data, fs.size)
    reference = start.baselines["proportional"]
    accept = Acceptance(mean_cm=min(fs.tol_measure_cm, 0.5), max_cm=1.5, seam_cm=0.1)
    ladder = _continuation(setup, start.x_axis, reference.scores, accept, fs, progress)
    refined: list[Solution] = []
    seeds = list(start.seeds)
    if fs.do_repair:
        # the proportional seed finished first: a fitted, low-shape individual
        # seeds the population beside the proportional one
        first = ladder.finish("proportional seed", start.x_axis)
        if first is not None:
            refined.append(first)
            # NSGA-II is seeded with the run least changed at the critical points (the
            # objective it minimises), which the ladder's result need not be
            seeds.insert(1, ladder.closest.x)
    if progress is not None:
        progress("seed", 1, 1)
    ga = _nsga2(grid, data, seeds, fs, progress)
    ga_idx = choose(ga.F, tol_measure_cm=fs.tol_measure_cm, tol_seam=fs.tol_seam)
    ga_choice = solution(grid, data, "nsga2", ga.X[ga_idx], fs.size, "least shape error within tolerance")
    if fs.do_repair:
        refined += _finish_members(ladder, ga, ga_idx, fs)
    if fs.do_repair and fs.n_trade:
        refined += trade_offs(grid, data, refined, ladder.settings_at(_trade_stage(ladder, refined, accept)),
                              fs.n_trade, fs.size, accept, progress)
    front = final_front(grid, data, ga.X, ga.F, refined, reference.scores, accept=accept,
                        tol_measure_cm=fs.tol_measure_cm, tol_seam=fs.tol_seam,
                        measure_band_cm=fs.measure_band_cm, keep_grain=fs.keep_grain,
                        keep_symmetry=fs.keep_symmetry)
    chosen = front_solution(grid, data, front, refined, fs.size)
    if fs.do_repair and not front.within[front.index]:
        chosen = _repaired_if_closer(setup, ga.X[ga_idx], start.x_axis, chosen, fs.size, progress)
    findings = _checks(grid, data, chosen, reference)
    for f in findings:
        log.warning("%s: %s", fs.source, f)
    settings = ladder.settings_at(ladder.stage_for(chosen.x))
    forcing = (_release(grid, data, chosen, reference, settings, fs.measure_band_cm, fs.source)
               if fs.do_repair else None)
    return FitResult(
        pattern=chosen.pattern, original=pattern, chosen=chosen, ga_choice=ga_choice,
        front_F=front.F, front_X=front.X, chosen_index=front.index, front_refined=front.refined,
        front_within=front.within, baselines=start.baselines, findings=findings,
        finish_settings=settings, forcing=forcing,
        measurements=measurements, grid=grid, data=data, seconds=time.perf_counter() - t0, seed=int(fs.seed),
        pop_size=fs.pop_size, n_gen=fs.n_gen, history=ga.history,
    )


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class _Setup:
    """The compiled grading problem: grids, targets and the final step's linear rows.

    straight : (n_c, n_var) orthonormal rows of the straight-edge and grain
    constraints, or None ; symmetric : (n_s, n_var) rows zero on a
    symmetric piece, or None
    """

    grid: PatternGrid
    data: ObjectiveData
    straight: np.ndarray | None
    symmetric: np.ndarray | None


def _setup(pattern: Pattern, measurements: Mapping[str, float], fs: FitSettings) -> _Setup:
    """Build the control grids (:mod:`.grid`), compile the targets (:mod:`.objectives`) and the linear rows."""
    from .refine import grain_constraints, row_basis, straight_constraints, straight_edges
    from .symmetry import mirror_symmetries, symmetry_constraints

    grid = build_grid(pattern, max_lines=fs.max_lines, max_cell_frac=fs.max_cell_frac, deformation=fs.deformation)
    data = objective_data(grid, measurements, source=fs.source)
    linear = [straight_constraints(grid, straight_edges(grid))] if fs.keep_straight else []
    if fs.keep_grain:
        linear.append(grain_constraints(grid))
    symmetric = symmetry_constraints(grid, mirror_symmetries(grid)) if fs.keep_symmetry else None
    straight = row_basis(np.concatenate(linear)) if linear else None
    return _Setup(grid=grid, data=data, straight=straight, symmetric=symmetric)


def _continuation(setup: _Setup, x_axis: np.ndarray, reference: Scores, accept: Acceptance, fs: FitSettings,
                  progress: Progress | None) -> Continuation:
    """The continuation of the final step over the fit's stages.

    The grid-interval weight steps down first; only when no level of it
    passes does the all-vertex angle weight step down, and the
    grid-interval levels run again; with the design's split of the girth
    reductions held, then without it (:func:`~.continuation.split_ladder`).
    """
    from .suppression import suppression

    grid, data = setup.grid, setup.data
    stages = split_ladder(continuation_stages(fs.all_levels, fs.design_levels),
                          fs.w_suppress > 0 and suppression(grid, data).n_parts > 0)
    settings = FinishSettings(measure_band_cm=fs.measure_band_cm, straight=setup.straight,
                              refine_iter=fs.refine_iter, x_design=x_axis, w_design=fs.w_design,
                              w_share=fs.w_share, w_fit=fs.w_fit, w_suppress=fs.w_suppress, w_all=fs.w_all,
                              symmetric=setup.symmetric)
    return Continuation(grid, data, settings, stages, reference=reference, accept=accept, size=fs.size,
                        source=fs.source, progress=progress)


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class _GaFront:
    """NSGA-II's front sorted by objectives: ``X (n, n_var)``, ``F (n, 3)``; ``history (n_gen, 4)``."""

    X: np.ndarray
    F: np.ndarray
    history: np.ndarray


def _nsga2(grid: PatternGrid, data: ObjectiveData, seeds: list[np.ndarray], fs: FitSettings,
           progress: Progress | None) -> _GaFront:
    """pymoo's NSGA-II with the grader's sampling, crossover and mutation (:mod:`.operators`) from ``seeds``.

    Raises
    ------
    SolverError
        No fold-free solution in the generations.
    """
    from pymoo.algorithms.moo.nsga2 import NSGA2
    from pymoo.optimize import minimize

    from .operators import GridCrossover, GridMutation, SeedSampling
    from .problem import GradingProblem

    problem = GradingProblem(grid, data)
    seeds_arr = np.clip(np.stack(seeds), problem.xl, problem.xu)
    algorithm = NSGA2(
        pop_size=fs.pop_size,
        sampling=SeedSampling(grid, seeds_arr),
        crossover=GridCrossover(grid),
        mutation=GridMutation(grid, fs.n_gen),
        eliminate_duplicates=False,
    )
    callback = _ProgressCallback(fs.n_gen, progress)
    res = minimize(problem, algorithm, ("n_gen", fs.n_gen), seed=int(fs.seed), callback=callback,
                   verbose=False, save_history=False, copy_algorithm=False)
    opt = res.opt if res.opt is not None and len(res.opt) else None
    if opt is None:
        raise SolverError(f"{fs.source}: NSGA-II found no fold-free solution in {fs.n_gen} generations; "
                          "try more generations or a finer grid")
    ga_X = np.asarray(opt.get("X"), dtype=np.float64)
    ga_F = np.asarray(opt.get("F"), dtype=np.float64)
    order = np.lexsort((ga_F[:, 2], ga_F[:, 1], ga_F[:, 0]))
    return _GaFront(X=ga_X[order], F=ga_F[order],
                    history=np.array(callback.history, dtype=np.float64).reshape(-1, 4))


def _finish_members(ladder: Continuation, ga: _GaFront, ga_idx: int, fs: FitSettings) -> list[Solution]:
    """The final step from a few members of NSGA-II's front: its own choice and the members with the least
    measurement and seam error (:func:`refine_members`)."""
    out = []
    for i in refine_members(ga.F, ga_idx, fs.n_refine, tol_measure_cm=fs.tol_measure_cm, tol_seam=fs.tol_seam):
        sol = ladder.finish("NSGA-II choice" if i == ga_idx else f"NSGA-II front member {i}", ga.X[i])
        if sol is not None:
            out.append(sol)
    return out


def _trade_stage(ladder: Continuation, refined: list[Solution], accept: Acceptance) -> Stage:
    """The stage the least-shape fitted solution ran at (the one :func:`trade_offs` starts from)."""
    fitted = [r for r in refined if meets(r, accept)]
    return ladder.stage_for(min(fitted, key=lambda r: r.scores.shape_error).x) if fitted else ladder.settled


def _repaired_if_closer(setup: _Setup, x_ga: np.ndarray, x_axis: np.ndarray, chosen: Solution, size: str,
                        progress: Progress | None) -> Solution:
    """Nothing on the front meets the fit: the penalty repair of the NSGA-II choice, when it gets closer."""
    x_rep, _ = repair(setup.grid, setup.data, x_ga, linear=setup.straight, x_design=x_axis, progress=progress)
    rep = solution(setup.grid, setup.data, "nsga2+repair", x_rep, size, "least-squares repair of the NSGA-II choice")
    if is_valid(rep) and rep.scores.measurement_error < chosen.scores.measurement_error:
        return rep
    return chosen


def _release(grid: PatternGrid, data: ObjectiveData, chosen: Solution, reference: Solution,
             settings: Mapping[str, object], band_cm: float, source: str) -> Forcing | None:
    """The release test of the chosen grading (:func:`_forcing`) with the final step at ``settings`` re-run
    from the fitted solution for :data:`RELEASE_ITER` iterations: they show which way the shape goes."""
    from .refine import refine

    def release_finish(d: ObjectiveData, x_start: np.ndarray) -> np.ndarray:
        return refine(grid, d, x_start, **{**settings, "max_iter": RELEASE_ITER}).x

    return _forcing(grid, data, chosen, reference, release_finish, band_cm, source)


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
    sol = solution(result.grid, result.data, "nsga2+refine", res.x, size,
                   f"least shape change under the fit, started from front member {int(k)} (chosen by the user)")
    reference = result.baselines["proportional"]
    findings = _checks(result.grid, result.data, sol, reference)
    with _single_thread():
        forcing = _release(result.grid, result.data, sol, reference, result.finish_settings,
                           float(result.finish_settings.get("measure_tol_cm", 0.15)), "fit --choose")
    return dataclasses.replace(result, pattern=sol.pattern, chosen=sol, chosen_index=int(k), findings=findings,
                               forcing=forcing)


def _single_thread():
    from .blas import single_blas_thread

    return single_blas_thread()
