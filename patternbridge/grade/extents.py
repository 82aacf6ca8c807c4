"""Extents no link governs: a piece's height or width that the final step must not squash.

A shirt's yoke carries the shoulder width and part of the neck girth, both
across the grain; nothing measures its height. The seams fix the yoke's
height plus the back's below it (their armhole edges go into one sleeve
cap), not how the two share it, and the angle terms do not see the yoke
seam slide up: the final step moved its change of shape there and graded
the yoke to 0.36–0.69 of its proportional height. :func:`unlinked_axes`
finds every such axis from the links' legs and the seams (never a name),
and the final step keeps the piece's spread along it within
:data:`EXTENT_SLACK` of proportional scaling's
(:class:`~.step_terms.StepTerms`, ``w_extent``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .grid import PatternGrid
from .objectives import ObjectiveData

__all__ = ["EXTENT_SLACK", "MIN_AXIS_SHARE", "Extents", "axis_spread", "unlinked_axes"]

MIN_AXIS_SHARE = 0.15
"""An axis of a piece is linked when at least this share of the piece's link evidence runs along it
(the share :func:`~.seeds.axis_scaling` needs before it scales a piece along an axis by its own links)."""

EXTENT_SLACK = 0.25
"""Log change of an unlinked extent against proportional scaling's that the final step leaves free:
0.78–1.28 of it, inside the design check's 0.7 (:data:`~.checks.MIN_EXTENT_RATIO`). Held tighter
(0.1–0.15 of the log) the yoke took the change of shape back into the corners: the tall thin
elder's shirt 0.0106–0.0109 rad at the critical points against 0.0100."""


@dataclass(frozen=True, slots=True)
class Extents:
    """The unlinked axes of a grading problem.

    pieces : (E,) piece index ; axes : (E,) drawing axis (0: x, across the
    grain; 1: y, along it) ; spread_ref : (E,) the piece's spread along the
    axis (:func:`axis_spread`) in the reference grading, cm
    """

    pieces: np.ndarray
    axes: np.ndarray
    spread_ref: np.ndarray

    def __len__(self) -> int:
        return len(self.pieces)


def axis_spread(points: np.ndarray, axis: int) -> np.ndarray:
    """Root-mean-square spread ``(n_pop,)`` of one piece's outline ``(n_pop, n, 2)`` along a drawing axis, cm."""
    c = points[..., axis]
    return np.sqrt(np.mean((c - c.mean(axis=-1, keepdims=True)) ** 2, axis=-1))


def _sewn_to_links(data: ObjectiveData) -> np.ndarray:
    """(N,) 1 on every outline edge sewn to an edge that carries a link leg (a back's side seam sewn to
    a front's side, whose lengths are linked), else 0."""
    linked = (np.abs(data.link_edges) > 0).any(axis=1).astype(np.float64)  # (N,)
    a, b = data.seam_a_edges > 0, data.seam_b_edges > 0  # (N, S)
    a_linked = (linked @ a) > 0  # (S,) side a of the seam carries a leg
    b_linked = (linked @ b) > 0
    return ((a & b_linked[None, :]) | (b & a_linked[None, :])).any(axis=1).astype(np.float64)


def unlinked_axes(
    grid: PatternGrid,
    data: ObjectiveData,
    reference: np.ndarray,
    *,
    skip: np.ndarray | None = None,
    min_share: float = MIN_AXIS_SHARE,
) -> Extents:
    """Every (piece, axis) along which less than ``min_share`` of the piece's link evidence runs.

    The evidence is the piece's link legs (outline edges and chords, by their
    length along each axis) and every outline edge **sewn to an edge that
    carries a link leg**: the seam passes that length on (a back's height
    follows the front's linked side lengths through the side seams; a yoke's
    armhole edge, sewn into a sleeve cap no link runs along, does not).
    ``reference`` : (N, 2) outline points of the grading the spread is held
    at (proportional scaling) ; ``skip`` : pieces held otherwise (the bands,
    :func:`~.bands.band_axes`).
    """
    from .seeds import _link_ratios, _piece_link_shares

    length, frac_h = _piece_link_shares(data, grid)
    length = np.where(np.isfinite(_link_ratios(data, grid))[None, :], length, 0.0)
    P = len(grid.pieces)
    d = np.abs(data.points0[data.nxt] - data.points0) * _sewn_to_links(data)[:, None]  # (N, 2)
    sewn = np.zeros((P, 2))
    np.add.at(sewn, data.piece_of_point, d)
    evidence = np.stack([(length * frac_h).sum(axis=1), (length * (1.0 - frac_h)).sum(axis=1)]) + sewn.T  # (2, P)
    share = evidence / np.maximum(evidence.sum(axis=0), 1e-9)[None, :]
    skipped = np.zeros(P, dtype=bool)
    if skip is not None:
        skipped[np.asarray(skip, dtype=np.int64)] = True
    pairs = [(k, a) for k in range(P) for a in (0, 1) if not skipped[k] and share[a, k] < min_share]
    spread = [float(axis_spread(reference[data.piece_of_point == k][None], a)[0]) for k, a in pairs]
    return Extents(
        pieces=np.array([k for k, _ in pairs], dtype=np.int64),
        axes=np.array([a for _, a in pairs], dtype=np.int64),
        spread_ref=np.array(spread, dtype=np.float64),
    )
