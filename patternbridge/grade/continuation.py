"""The final step's continuation: the ladder of tie-break weights, run from every start.

:func:`~.refine.refine` holds the design with tie-break weights (the
grid-interval term, the all-vertex angle term, the design's split of the
girth reductions). They step down while the result changes the design more
than proportional scaling: :func:`continuation_stages` and
:func:`split_ladder` give the stages in order, :func:`standing` says how a
grading's change of shape stands against scaling's, and
:class:`Continuation` runs the ladder from each start, remembering across
starts where it settled.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np

from .grid import PatternGrid
from .objectives import ObjectiveData
from .solution import Acceptance, Progress, Scores, Solution, meets, solution

__all__ = [
    "CLOSE_RATIO",
    "Continuation",
    "FinishSettings",
    "Stage",
    "continuation_stages",
    "shape_standing",
    "split_ladder",
    "standing",
]

log = logging.getLogger(__name__)


Stage = tuple[float, float, float]
"""A continuation stage ``(split factor, all-vertex factor, grid-interval factor)``."""

CLOSE_RATIO = 1.5
"""When no continuation stage passed on the first start, later starts run the stage that came closest
at the critical points if its shape error came within this factor of scaling's (another start may pass
there: the slim female's trousers came within 1.29 and passed from an NSGA-II member), else the stage
that stood best on both measures."""


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


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class FinishSettings:
    """The final step's settings the continuation's factors apply to (:meth:`at`)."""

    measure_band_cm: float
    straight: np.ndarray | None
    refine_iter: int
    x_design: np.ndarray
    w_design: float
    w_share: float
    w_fit: float
    w_suppress: float
    w_all: float
    symmetric: np.ndarray | None

    def at(self, stage: Stage) -> dict[str, object]:
        """Keyword arguments of :func:`~.refine.refine` at ``stage``."""
        split, w_all_level, level = stage
        return {"measure_tol_cm": self.measure_band_cm, "straight": self.straight, "max_iter": self.refine_iter,
                "x_design": self.x_design, "w_design": self.w_design * level, "w_share": self.w_share,
                "w_fit": self.w_fit, "w_suppress": self.w_suppress * split * level,
                "dart_cap": self.w_suppress * split * level > 0, "w_all": self.w_all * w_all_level,
                "symmetric": self.symmetric}


class Continuation:
    """The constrained final step with the continuation on its tie-break weights, over several starts.

    Stateful across starts (:meth:`finish`): the stage where each half of
    the ladder settled, the stages later starts run, the stage every
    refined solution ran at (:meth:`stage_for`) and the run of the last
    start least changed at the critical points (:attr:`closest`).
    """

    def __init__(self, grid: PatternGrid, data: ObjectiveData, settings: FinishSettings, stages: list[Stage], *,
                 reference: Scores, accept: Acceptance, size: str, source: str,
                 progress: Progress | None) -> None:
        self.grid, self.data, self.settings, self.stages = grid, data, settings, stages
        self.reference, self.accept, self.size, self.source = reference, accept, size, source
        self.progress = progress
        self.halves = sorted({st[0] for st in stages}, reverse=True)  # the split held (1), then not (0)
        self.start_stage = {h: next(st for st in stages if st[0] == h) for h in self.halves}  # where starts begin
        self.settled: Stage = stages[0]  # the last stage that passed
        self.closest: Solution | None = None  # the first passing run of the last start, else its closest
        self.later: dict[float, tuple[Stage, ...]] = {}  # halves no stage passed in: the stages later starts run
        self.stage_of: dict[bytes, Stage] = {}  # the stage every refined solution ran at

    def stage_for(self, x: np.ndarray | None) -> Stage:
        """The stage the refined genes ``x`` ran at; the settled stage for any other."""
        return self.stage_of.get(x.tobytes(), self.settled) if x is not None else self.settled

    def settings_at(self, stage: Stage) -> dict[str, object]:
        """Keyword arguments of :func:`~.refine.refine` at ``stage``."""
        return self.settings.at(stage)

    def run_at(self, start_name: str, x_start: np.ndarray, stage: Stage) -> Solution:
        """The final step from ``x_start`` at ``stage``, as a solution with a note saying so."""
        from .refine import refine

        split, w_all_level, level = stage
        res = refine(self.grid, self.data, x_start, **self.settings_at(stage), progress=self.progress)
        if res.max_violation_cm > 1e-3:
            log.info("%s: final step from the %s (design weight x%.3g) left a violation of %.3g cm",
                     self.source, start_name, level, res.max_violation_cm)
        note = (f"least shape change under the fit, started from the {start_name}, "
                f"design weight x{level:.3g}")
        if w_all_level != 1.0:
            note += f", all-vertex weight x{w_all_level:.3g}"
        if self.settings.w_suppress > 0 and split == 0 and level > 0:
            note += ", the split of the girth reductions not held"
        return solution(self.grid, self.data, "nsga2+refine", res.x, self.size, note)

    def finish(self, start_name: str, x_start: np.ndarray) -> Solution | None:
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
        self.closest = None
        runs = _StartRuns(self, start_name, x_start)
        passed, failed = set(), []  # the halves that passed at the critical points, that ran every stage and did not
        for todo in (t for t in self._todos() if t):
            if self._ladder(todo, runs) is not None:
                passed.add(todo[0][0])
            elif len(todo) > 1:
                failed.append(todo[0][0])
            if runs.best is not None and shape_standing(runs.best.scores, self.reference)[0] == -2:
                break  # both measures at or below scaling's: the split stays held
        if failed and runs.done:
            self._plan_later(passed, failed, runs)
        return runs.best

    def _todos(self) -> list[list[Stage]]:
        """Per half, the stages this start runs: from where the half settled down, or what an earlier start left."""
        return [list(self.later[h]) if h in self.later
                else [self.start_stage[h]] + [st for st in self.stages if st[0] == h and st < self.start_stage[h]]
                for h in self.halves]

    def _ladder(self, todo: list[Stage], runs: _StartRuns) -> Stage | None:
        """Run ``todo`` in order until a stage passes at the critical points; that stage, or None."""
        shape_ref = self.reference.shape_error
        failed: Stage | None = None
        for stage in todo:
            cand = runs.run(stage)
            if cand is None:
                continue
            if self.closest is None or cand.scores.shape_error < self.closest.scores.shape_error:
                self.closest = cand
            if cand.scores.shape_error < shape_ref:
                if failed is not None and failed[:2] == stage[:2]:
                    level = stage[2]
                    mid = float(np.sqrt(failed[2] * level)) if level > 0 else failed[2] / 3.0
                    between = runs.run((*stage[:2], mid))
                    if between is not None and between.scores.shape_error < shape_ref:
                        stage, self.closest = (*stage[:2], mid), between
                self.start_stage[stage[0]] = self.settled = stage
                return stage
            failed = stage
        return None

    def _plan_later(self, passed: set[float], failed: list[float], runs: _StartRuns) -> None:
        """What later starts run of the halves that passed nowhere on this start."""
        if passed:  # later starts skip the half that passed nowhere
            self.later.update({h: () for h in failed})
            return
        # later starts run one stage of all: the closest at the critical points, else the best
        closest = min(runs.done, key=lambda st: runs.done[st].scores.shape_error)
        near = runs.done[closest].scores.shape_error <= CLOSE_RATIO * self.reference.shape_error
        one = closest if near else runs.best_stage
        self.later.update({h: (one,) if one[0] == h else () for h in self.halves})


class _StartRuns:
    """The runs of one start: those that meet the fit by stage, and the one that stands best against scaling."""

    def __init__(self, ladder: Continuation, start_name: str, x_start: np.ndarray) -> None:
        self.ladder, self.start_name, self.x_start = ladder, start_name, x_start
        self.done: dict[Stage, Solution] = {}
        self.best: Solution | None = None
        self.best_stage: Stage | None = None

    def run(self, stage: Stage) -> Solution | None:
        """The final step at ``stage``; None when it misses the fit."""
        ladder = self.ladder
        cand = ladder.run_at(self.start_name, self.x_start, stage)
        ladder.stage_of[cand.x.tobytes()] = stage
        if not meets(cand, ladder.accept):
            return None
        self.done[stage] = cand
        if self.best is None or (shape_standing(cand.scores, ladder.reference)
                                 < shape_standing(self.best.scores, ladder.reference)):
            self.best, self.best_stage = cand, stage
        return cand
