"""Pure polygon and polyline functions on ``(n, 2)`` float64 arrays (cm).

Outlines are closed implicitly (the first vertex is not repeated). Functions
that take a stack of outlines, ``(..., n, 2)``, vectorise over the leading
axes so the grader can evaluate a whole population at once.
"""

from __future__ import annotations

import numpy as np
import shapely

__all__ = [
    "arc_lengths",
    "area",
    "boundary_indices",
    "carry_allowance",
    "edge_lengths",
    "interior_angles",
    "is_ccw",
    "is_simple",
    "orient_ccw",
    "perimeter",
    "polyline_length",
    "range_length",
    "signed_area",
]


def signed_area(outline: np.ndarray) -> np.ndarray:
    """Shoelace area of closed outlines, positive when counter-clockwise.

    Parameters
    ----------
    outline : (..., n, 2) float64

    Examples
    --------
    >>> float(signed_area(np.array([[0, 0], [2, 0], [2, 1], [0, 1]], float)))
    2.0
    """
    x, y = outline[..., 0], outline[..., 1]
    return 0.5 * np.sum(x * np.roll(y, -1, axis=-1) - np.roll(x, -1, axis=-1) * y, axis=-1)


def area(outline: np.ndarray) -> np.ndarray:
    """Unsigned area of closed outlines, (...,) float64 in cm²."""
    return np.abs(signed_area(outline))


def is_ccw(outline: np.ndarray) -> bool:
    """True when a single outline runs counter-clockwise."""
    return bool(signed_area(np.asarray(outline, dtype=np.float64)) > 0)


def orient_ccw(outline: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Return ``(ccw_outline, order)`` where ``ccw_outline = outline[order]``.

    The first vertex is kept first so marks at vertex 0 survive.
    """
    outline = np.asarray(outline, dtype=np.float64)
    n = len(outline)
    order = np.arange(n)
    if not is_ccw(outline):
        order = np.concatenate([[0], np.arange(n - 1, 0, -1)])
    return outline[order], order


def edge_lengths(outline: np.ndarray, closed: bool = True) -> np.ndarray:
    """Lengths of the edges, (..., n) for closed outlines or (..., n-1) for open ones."""
    nxt = np.roll(outline, -1, axis=-2) if closed else outline[..., 1:, :]
    cur = outline if closed else outline[..., :-1, :]
    return np.linalg.norm(nxt - cur, axis=-1)


def perimeter(outline: np.ndarray) -> np.ndarray:
    """Perimeter of closed outlines, (...,) float64 in cm."""
    return edge_lengths(outline).sum(axis=-1)


def polyline_length(points: np.ndarray) -> np.ndarray:
    """Length of open polylines, (...,) float64."""
    return edge_lengths(points, closed=False).sum(axis=-1)


def arc_lengths(points: np.ndarray, closed: bool = False) -> np.ndarray:
    """Cumulative arc length at each vertex, starting at 0.

    For ``closed=True`` one more entry is appended: the full perimeter.
    """
    seg = edge_lengths(points, closed=closed)
    zero = np.zeros(seg.shape[:-1] + (1,))
    return np.concatenate([zero, np.cumsum(seg, axis=-1)], axis=-1)


def boundary_indices(n: int, start: int, end: int) -> np.ndarray:
    """Vertex indices from ``start`` to ``end`` inclusive, in outline order, wrapping.

    Examples
    --------
    >>> boundary_indices(6, 4, 1).tolist()
    [4, 5, 0, 1]
    """
    if end >= start:
        return np.arange(start, end + 1)
    return np.concatenate([np.arange(start, n), np.arange(0, end + 1)])


def range_length(outline: np.ndarray, start: int, end: int) -> np.ndarray:
    """Length along a closed outline from vertex ``start`` to ``end`` (outline order).

    ``outline`` may be stacked, ``(..., n, 2)``.
    """
    idx = boundary_indices(outline.shape[-2], start, end)
    return polyline_length(outline[..., idx, :])


def interior_angles(outline: np.ndarray) -> np.ndarray:
    """Interior angle at every vertex of CCW outlines, (..., n) radians in (0, 2π).

    A convex corner of a CCW outline is below π, a reflex one above.
    """
    prev = np.roll(outline, 1, axis=-2) - outline
    nxt = np.roll(outline, -1, axis=-2) - outline
    # angle measured CCW from the next edge to the previous edge
    cross = nxt[..., 0] * prev[..., 1] - nxt[..., 1] * prev[..., 0]
    dot = np.sum(nxt * prev, axis=-1)
    ang = np.arctan2(cross, dot)
    return np.where(ang < 0, ang + 2 * np.pi, ang)


def is_simple(outline: np.ndarray) -> bool:
    """True when a closed outline does not intersect itself."""
    ring = shapely.linearrings(np.asarray(outline, dtype=np.float64))
    return bool(shapely.is_simple(ring))


def _vertex_frames(line: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Unit tangent, outward normal and cos(half turn) at every vertex of a CCW ring.

    The tangent bisects the two edge directions, so a corner's frame does not
    depend on how long its edges are.
    """
    edges = np.roll(line, -1, axis=0) - line
    unit = edges / np.maximum(np.linalg.norm(edges, axis=1, keepdims=True), 1e-12)
    incoming = np.roll(unit, 1, axis=0)
    tangent = incoming + unit
    tangent /= np.maximum(np.linalg.norm(tangent, axis=1, keepdims=True), 1e-12)
    normal = np.stack([tangent[:, 1], -tangent[:, 0]], axis=1)  # right of travel = outside of a CCW ring
    half_cos = np.sqrt(np.clip((1.0 + np.sum(incoming * unit, axis=1)) / 2.0, 0.0, 1.0))
    return tangent, normal, half_cos


SHARP_TURN_COS_HALF = 0.5  # cos of half a 120° turn: sharper turns are dart points; the cut line spans the dart


def carry_allowance(
    sew: np.ndarray, cut: np.ndarray, new_sew: np.ndarray, mapped_cut: np.ndarray | None = None
) -> np.ndarray:
    """The cut line around a reshaped sew line, with the original seam allowance.

    CAD systems grade the sew (net) line and add the allowance afterwards; a
    deformation applied to both lines would instead widen or narrow the
    allowance wherever it stretches the piece unevenly. Every cut vertex keeps
    its offset from its sew vertex, written in the sew line's local frame at
    that vertex; the outward part is rescaled by the corner's mitre factor, so
    a mitred corner whose angle changes keeps the width of both edges.

    Parameters
    ----------
    sew, cut : (n, 2) float64, cm — the original sew line and cut line, one
        cut vertex per sew vertex, both closed and counter-clockwise
    new_sew : (n, 2) float64, cm — the sew line after grading
    mapped_cut : (n, 2) float64, cm, optional — the cut line moved by the
        grading's own deformation; taken where the sew line turns by more than
        120° before or after (a dart point: the cut line runs straight across
        the dart there, far from its sew vertex, and follows no sew-line frame)

    Returns
    -------
    (n, 2) float64, cm — the graded cut line
    """
    sew = np.asarray(sew, dtype=np.float64)
    new_sew = np.asarray(new_sew, dtype=np.float64)
    offset = np.asarray(cut, dtype=np.float64) - sew
    t0, n0, c0 = _vertex_frames(sew)
    t1, n1, c1 = _vertex_frames(new_sew)
    along = np.sum(offset * t0, axis=1)
    # c0 / c1 keeps a mitre's edge widths; bounded so a corner turned nearly back on itself cannot spike
    out = np.sum(offset * n0, axis=1) * np.clip(c0 / np.maximum(c1, 0.25), 0.25, 4.0)
    carried = new_sew + along[:, None] * t1 + out[:, None] * n1
    if mapped_cut is None:
        return carried
    sharp = (c0 < SHARP_TURN_COS_HALF) | (c1 < SHARP_TURN_COS_HALF)
    return np.where(sharp[:, None], np.asarray(mapped_cut, dtype=np.float64), carried)
