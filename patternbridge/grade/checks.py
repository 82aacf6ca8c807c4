"""Checks that a graded pattern still is the design: findings for a collapsed piece, a flattened curve, a lost symmetry.

The fit figures (measurements, seams) and the shape error can all look
good while the pattern is not the design any more: a yoke squeezed to half
its height, a neckline pulled straight, a front that gave one side what it
took from the other. A fold-free grid and simple outlines do not see any of
that. These checks compare the graded pattern with proportional scaling
(the same design, only scaled per axis) and return one
:class:`~patternbridge.report.Finding` per problem; :func:`design_checks`
is run on the chosen solution by :func:`~.run.fit_pattern` and the findings
go into the fit report.

The functions on points are vectorised over the population, like the
objectives.
"""

from __future__ import annotations

import numpy as np

from ..report import Finding
from .objectives import ObjectiveData

__all__ = [
    "MAX_SYMMETRY_CM",
    "MIN_CURVE_RATIO",
    "MIN_EXTENT_RATIO",
    "design_checks",
    "piece_extents",
    "span_sagitta",
]

MIN_EXTENT_RATIO = 0.7
"""A piece narrower or shorter than this share of its proportional size (or wider or
longer than its inverse) has collapsed or ballooned."""

MIN_CURVE_RATIO = 0.5
"""A curve whose depth (sagitta over chord) falls below this share of the design's is flattened."""

MIN_CURVE_DEPTH = 0.04
"""Spans whose depth in the design is below this (sagitta / chord) count as straight."""

MAX_SYMMETRY_CM = 0.2
"""A symmetric piece further than this from its mirror image has lost its symmetry."""


def piece_extents(data: ObjectiveData, points: np.ndarray) -> np.ndarray:
    """Width and height of every piece in the drawing axes, ``(n_pop, P, 2)`` cm."""
    points = np.asarray(points, dtype=np.float64)
    P = len(data.centre0)
    lo = np.full((points.shape[0], P, 2), np.inf)
    hi = np.full((points.shape[0], P, 2), -np.inf)
    np.minimum.at(lo.transpose(1, 0, 2), data.piece_of_point, points.transpose(1, 0, 2))
    np.maximum.at(hi.transpose(1, 0, 2), data.piece_of_point, points.transpose(1, 0, 2))
    return hi - lo


def span_sagitta(data: ObjectiveData, points: np.ndarray) -> np.ndarray:
    """Depth of every span between consecutive critical points, ``(n_pop, B)``, sagitta / chord.

    The largest distance of the span's vertices from the chord joining its
    ends, over the chord's length: 0 for a straight span, about 0.2 for a
    neckline's quarter circle.
    """
    points = np.asarray(points, dtype=np.float64)
    a = points[:, data.span_a, :]
    b = points[:, data.span_b, :]
    chord = b - a
    length = np.maximum(np.linalg.norm(chord, axis=-1), 1e-9)
    # (n_pop, N, B) distance of every vertex from every chord, kept where the vertex is on the span
    rel = points[:, :, None, :] - a[:, None, :, :]
    dist = np.abs(rel[..., 0] * chord[:, None, :, 1] - rel[..., 1] * chord[:, None, :, 0]) / length[:, None, :]
    on_span = data.span_edges > 0
    return np.where(on_span[None], dist, 0.0).max(axis=1) / length


def design_checks(
    data: ObjectiveData,
    points: np.ndarray,
    reference: np.ndarray,
    *,
    piece_names: tuple[str, ...],
    symmetry_cm: dict[str, float] | None = None,
) -> tuple[Finding, ...]:
    """Findings for one graded solution against its proportional reference.

    Parameters
    ----------
    data : the grading problem
    points : (N, 2) graded reference-line vertices, cm
    reference : (N, 2) the same under proportional scaling (per-axis), cm
    piece_names : (P,) names in piece order
    symmetry_cm : symmetric piece name -> distance from its mirror image, cm
        (:func:`~.symmetry.symmetry_error`)

    Returns
    -------
    tuple of Finding with codes ``piece-collapsed``, ``piece-stretched``,
    ``curve-flattened`` and ``symmetry-lost`` (all warnings)
    """
    pts = np.asarray(points, dtype=np.float64)[None]
    ref = np.asarray(reference, dtype=np.float64)[None]
    out: list[Finding] = []
    ratio = piece_extents(data, pts)[0] / np.maximum(piece_extents(data, ref)[0], 1e-9)
    for p, name in enumerate(piece_names):
        for axis, what in ((0, "width"), (1, "height")):
            r = float(ratio[p, axis])
            if r < MIN_EXTENT_RATIO:
                out.append(Finding(code="piece-collapsed", where=name, message=(
                    f"{what} is {r:.2f} of its proportional {what} (limit {MIN_EXTENT_RATIO})")))
            elif r > 1.0 / MIN_EXTENT_RATIO:
                out.append(Finding(code="piece-stretched", where=name, message=(
                    f"{what} is {r:.2f} of its proportional {what} (limit {1.0 / MIN_EXTENT_RATIO:.2f})")))
    depth0 = span_sagitta(data, data.points0[None])[0]
    depth = span_sagitta(data, pts)[0]
    curved = depth0 >= MIN_CURVE_DEPTH
    for s in np.flatnonzero(curved & (depth < MIN_CURVE_RATIO * depth0)):
        p = int(data.span_piece[s])
        first = int(np.flatnonzero(data.piece_of_point == p)[0])
        out.append(Finding(code="curve-flattened", where=piece_names[p], message=(
            f"the curve between outline points {int(data.span_a[s]) - first} and {int(data.span_b[s]) - first} is "
            f"{depth[s] / depth0[s]:.2f} as deep as in the design (limit {MIN_CURVE_RATIO})")))
    for name, err in (symmetry_cm or {}).items():
        if err > MAX_SYMMETRY_CM:
            out.append(Finding(code="symmetry-lost", where=name, message=(
                f"{err * 10:.1f} mm from its mirror image (limit {MAX_SYMMETRY_CM * 10:.0f} mm)")))
    return tuple(out)
