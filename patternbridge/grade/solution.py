"""A candidate grading and its figures: :class:`Scores`, :class:`Solution` and how one is scored.

Every stage of :func:`~.run.fit_pattern` (the seeds, NSGA-II's choice, the
final step's runs, the repair) hands on its candidates as
:class:`Solution`; :func:`meets` is the fit they are accepted on.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..pattern.model import Pattern
from .grid import PatternGrid, deform_pattern
from .objectives import ObjectiveData, evaluate, link_error

__all__ = ["Acceptance", "Progress", "Scores", "Solution", "is_simple", "is_valid", "meets", "score_points", "solution"]

Progress = Callable[[str, int, int], None]
"""``progress(stage, done, total)``: the grader's progress report."""


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


@dataclass(frozen=True, slots=True, kw_only=True)
class Acceptance:
    """The fit a candidate of the final step must meet to count (:func:`meets`).

    mean_cm : mean measurement error ; max_cm : every measurement error ;
    seam_cm : every seam length mismatch and notch misalignment
    """

    mean_cm: float
    max_cm: float
    seam_cm: float


def is_simple(pattern: Pattern) -> bool:
    """Every piece outline of ``pattern`` free of self-intersections."""
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
        is_simple=is_simple(pattern),
    )


def solution(grid: PatternGrid, data: ObjectiveData, name: str, x: np.ndarray, size: str, note: str = "") -> Solution:
    """The :class:`Solution` of the genes ``x (n_var,)``: its pattern (graded as ``size``) and scores."""
    pattern = deform_pattern(grid, x, size=size)
    points = grid.outlines(x[None, :])[0]
    scores = score_points(data, points, fold_margin=float(grid.fold_margin(x[None, :])[0]), pattern=pattern)
    return Solution(name=name, pattern=pattern, scores=scores, x=np.array(x), note=note)


def is_valid(sol: Solution) -> bool:
    """No folded grid cell and every outline simple."""
    return sol.scores.fold_margin > 0 and sol.scores.is_simple


def meets(sol: Solution, accept: Acceptance) -> bool:
    """``sol`` is valid (:func:`is_valid`) and within ``accept`` on measurements and seams."""
    sc = sol.scores
    return (is_valid(sol) and sc.measurement_error <= accept.mean_cm and sc.max_measurement_error <= accept.max_cm
            and sc.max_seam_mismatch_cm <= accept.seam_cm)
