"""The order a batch starts its cases in: the most work first, by an estimate from each garment's pattern.

A batch hands a case to a worker only when the worker is free (see
:mod:`.run`), so the order decides the tail: started last, a long case runs
alone while the other workers idle. Starting the longest cases first and
the shortest last (longest-processing-time-first list scheduling) leaves a
tail of about one short case. The estimate needs only the ranking of the
cases, not their seconds.
"""

from __future__ import annotations

import logging
from collections.abc import Mapping, Sequence

from .cases import Case

__all__ = ["garment_work", "pattern_work", "run_order"]

log = logging.getLogger(__name__)


def pattern_work(n_unknowns: int, n_points: int) -> float:
    """Relative grading work of a pattern whose grid has ``n_unknowns`` controls and ``n_points`` outline points.

    The grader's final least-change step solves least-squares problems with
    a residual per outline point (and per seam and measurement) in the grid's
    control unknowns; a dense solve costs about ``n_points * n_unknowns**2``.
    Measured (pop 16, 10 generations, no drape; docs/batch.md): on
    E_average_male the six library garments' CPU seconds rank as this
    estimate does but for three swapped neighbours (Spearman 0.83; the
    outline vertex count alone: 0.53), and every character of the cast spends
    more on its shirt than on its trousers (1.7 to 8.8 times), as estimated.

    Examples
    --------
    >>> pattern_work(200, 100) / pattern_work(100, 100)
    4.0
    """
    return float(n_unknowns) ** 2 * float(n_points)


def garment_work(spec: str, *, deformation: str = "bilinear") -> float:
    """:func:`pattern_work` of a library garment or pattern file (0 when it cannot be loaded).

    The grid is the one the grader builds (:func:`patternbridge.grade.grid.build_grid`,
    ``deformation`` as in :class:`~patternbridge.workflow.model.FitOptions`).
    A garment that does not load still runs (and fails on its worker with its
    error recorded); here it only sorts last.
    """
    from ..errors import PatternBridgeError
    from ..grade.grid import build_grid
    from ..io.load import load_pattern

    try:
        pattern, _ = load_pattern(spec)
        grid = build_grid(pattern, deformation=deformation)
    except (PatternBridgeError, OSError, ValueError) as exc:
        log.info("%s: no work estimate (%s); it starts last", spec, exc)
        return 0.0
    return pattern_work(grid.x0.size, int(grid.point_offsets[-1]))


def run_order(cases: Sequence[Case], work: Mapping[str, float]) -> list[Case]:
    """``cases`` sorted by the ``work`` of their garment spec, most first; ties keep the given order.

    Examples
    --------
    >>> a, b = (Case(character=c, character_path=c, garment=g, garment_spec=g) for c, g in (("x", "s"), ("x", "t")))
    >>> [c.key for c in run_order([a, b], {"s": 1.0, "t": 9.0})]
    ['x/t', 'x/s']
    """
    return sorted(cases, key=lambda case: -work.get(case.garment_spec, 0.0))
