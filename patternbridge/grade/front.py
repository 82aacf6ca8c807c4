"""The final Pareto front and the choice on it.

NSGA-II's front and the final step's solutions are put together, the
dominated rows removed (:func:`non_dominated`), and the issue's rule
chooses on that front (:func:`choose`): the least shape error among the
members within tolerance on measurements and seams (:func:`within_tolerance`),
keeping to the rows within the final step's band; versions of the best
refined solution along the fit-against-shape trade (:func:`trade_offs`) stay
on the front for the designer to pick.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..pattern.model import Pattern
from .grid import PatternGrid, deform_pattern
from .objectives import ObjectiveData, evaluate, link_error, measurement_error, shape_error_all
from .refine import Progress
from .solution import Acceptance, Scores, Solution, is_simple, meets, solution

if TYPE_CHECKING:
    from .run import FitResult

__all__ = [
    "TRADE_LEVELS",
    "Front",
    "choose",
    "final_front",
    "front_members",
    "front_solution",
    "non_dominated",
    "refine_members",
    "trade_offs",
    "within_tolerance",
]


def choose(F: np.ndarray, *, tol_measure_cm: float, tol_seam: float, within: np.ndarray | None = None,
           standing: np.ndarray | None = None) -> int:
    """Row of ``F`` with the least shape error among those within tolerance.

    ``within`` : (n,) bool, optional — which rows are within tolerance (e.g.
    :func:`within_tolerance`: every target of the fit met); without it a row
    is within tolerance when ``f1 <= tol_measure_cm`` and ``f2 <= tol_seam``.
    When no row is, the rows whose worst normalised violation
    ``max(f1/tol1, f2/tol2)`` is within 25 % of the best one compete instead.
    ``standing`` : (n, 3), optional — every row's :func:`~.continuation.standing` against
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
        ok[i] = is_simple(deform_pattern(grid, X[i]))
    return ok


TRADE_LEVELS = ((0.45, 0.0), (0.05, 0.2), (0.3, 0.005), (0.02, 1.0))
"""(measurement band cm, fit cost) of the front members that trade fit against shape: a looser
fit with less change of shape, a tighter one with more, and so on."""


def _max_link_error(grid: PatternGrid, data: ObjectiveData, X: np.ndarray) -> np.ndarray:
    """(n,) largest ``|achieved - target|`` over the links of every individual, cm."""
    achieved = measurement_error(data, grid.outlines(np.atleast_2d(X)))[0]
    return np.abs(link_error(data, achieved)).max(axis=1, initial=0.0)


def trade_offs(grid: PatternGrid, data: ObjectiveData, refined: list[Solution], settings: dict, n: int,
               size: str, accept: Acceptance, progress: Progress | None) -> list[Solution]:
    """Versions of the least-shape refined solution along the fit-against-shape trade.

    The final step is re-run from that solution (it starts fitted, so a few
    iterations suffice) with another measurement band and cost on the
    measurement errors inside it (:data:`TRADE_LEVELS`, the first ``n``): a
    wider band without cost gives a grading within tolerance that changes
    the shape less and misses the measurements by more, a narrower one with
    a larger cost the opposite. The default choice keeps to rows within the
    final step's own band, so the looser ones change nothing unless the user
    picks one (:func:`~.run.choose_member`).
    """
    from .refine import refine

    fitted = [s for s in refined if meets(s, accept)]
    if not fitted:
        return []
    base = min(fitted, key=lambda s: s.scores.shape_error)
    out = []
    for band, w_fit in TRADE_LEVELS[:max(int(n), 0)]:
        res = refine(grid, data, base.x, **{**settings, "measure_tol_cm": band, "w_fit": w_fit},
                     progress=progress)
        sol = solution(grid, data, "nsga2+refine", res.x, size,
                        f"{base.note}; fit traded against shape: band {band:g} cm, fit cost {w_fit:g}")
        if meets(sol, accept):
            out.append(sol)
    return out


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class Front:
    """The final Pareto front and the row chosen on it.

    X : (n_front, n_var) genes ; F : (n_front, 3) objectives ;
    refined : (n_front,) bool, the rows the final step produced ;
    within : (n_front,) bool, the rows within tolerance (:func:`within_tolerance`) ;
    index : the chosen row
    """

    X: np.ndarray
    F: np.ndarray
    refined: np.ndarray
    within: np.ndarray
    index: int


def final_front(grid: PatternGrid, data: ObjectiveData, ga_X: np.ndarray, ga_F: np.ndarray,
                refined: list[Solution], reference: Scores, *, accept: Acceptance, tol_measure_cm: float,
                tol_seam: float, measure_band_cm: float, keep_grain: bool, keep_symmetry: bool) -> Front:
    """NSGA-II's front ``(ga_X, ga_F)`` and the refined solutions, dominated rows removed, and the choice on it.

    The default choice keeps the honest fit: among the rows within
    tolerance, those whose every measurement is within the final step's
    band (``measure_band_cm``); the looser rows (less change of shape) stay
    on the front for the user to pick (:func:`~.run.choose_member`). Rows
    compete on their :func:`~.continuation.standing` against ``reference``
    (proportional scaling).
    """
    from .continuation import standing

    front_X = np.concatenate([ga_X] + [s.x[None, :] for s in refined])
    front_F = np.concatenate([ga_F] + [s.scores.F[None, :] for s in refined])
    is_refined = np.r_[np.zeros(len(ga_X), bool), np.ones(len(refined), bool)]
    keep = non_dominated(front_F)
    front_X, front_F, is_refined = front_X[keep], front_F[keep], is_refined[keep]
    within = within_tolerance(grid, data, front_X, mean_cm=accept.mean_cm, max_cm=accept.max_cm,
                              seam_cm=accept.seam_cm, grain_deg=0.5 if keep_grain else None,
                              symmetry_cm=0.2 if keep_symmetry else None)
    honest = within & (_max_link_error(grid, data, front_X) <= measure_band_cm + 1e-3)
    all_vertex = shape_error_all(data, grid.outlines(front_X))
    ranks = np.array([standing(f, a, reference.shape_error, reference.shape_error_all)
                      for f, a in zip(front_F[:, 2], all_vertex, strict=True)])
    idx = choose(front_F, tol_measure_cm=tol_measure_cm, tol_seam=tol_seam,
                 within=honest if honest.any() else within, standing=ranks)
    return Front(X=front_X, F=front_F, refined=is_refined, within=within, index=idx)


def front_solution(grid: PatternGrid, data: ObjectiveData, front: Front, refined: list[Solution],
                   size: str) -> Solution:
    """The chosen row as a solution: the refined one it came from, else an NSGA-II front member."""
    by_x = {s.x.tobytes(): s for s in refined}
    return by_x.get(front.X[front.index].tobytes()) or solution(
        grid, data, "nsga2", front.X[front.index], size,
        "NSGA-II front member: least shape error within tolerance on the final front")


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
