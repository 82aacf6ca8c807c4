"""The grading problem as a pymoo :class:`~pymoo.core.problem.Problem`.

``_evaluate`` receives the whole population ``X (n_pop, n_var)``, turns it into
every piece outline with one matrix product per piece
(:meth:`PatternGrid.outlines`) and scores it with the vectorised objectives of
:mod:`patternbridge.grade.objectives`; there is no loop over individuals.
"""

from __future__ import annotations

import numpy as np
from pymoo.core.problem import Problem

from .grid import PatternGrid
from .objectives import FOLD_MARGIN, ObjectiveData, evaluate

__all__ = ["GradingProblem", "variable_bounds"]


def variable_bounds(grid: PatternGrid, *, spread: float = 1.5) -> tuple[np.ndarray, np.ndarray]:
    """Box bounds of the genes: each control point may move ``spread`` piece extents.

    Returns
    -------
    xl, xu : (n_var,) float64, cm
    """
    reach = np.concatenate([
        np.full(2 * g.n_control, spread * g.extent_cm) for g in grid.pieces
    ])
    return grid.x0 - reach, grid.x0 + reach


class GradingProblem(Problem):
    """Three objectives (measurement, seam, shape error) and one fold constraint.

    Parameters
    ----------
    grid : control grids of the pattern (gene layout)
    data : compiled targets (:func:`patternbridge.grade.objectives.objective_data`)
    """

    def __init__(self, grid: PatternGrid, data: ObjectiveData, *, spread: float = 1.5) -> None:
        xl, xu = variable_bounds(grid, spread=spread)
        super().__init__(n_var=grid.n_var, n_obj=3, n_ieq_constr=1, xl=xl, xu=xu)
        self.grid = grid
        self.data = data

    def _evaluate(self, X, out, *args, **kwargs):
        X = np.asarray(X, dtype=np.float64)
        points = self.grid.outlines(X)
        ev = evaluate(self.data, points)
        out["F"] = ev.F
        out["G"] = (FOLD_MARGIN - self.grid.fold_margin(X))[:, None]
