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
