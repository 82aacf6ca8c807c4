"""New boundary vertices on a piece's straight segments, keeping every vertex index consistent.

A mark must be a boundary vertex (seams, links and landmarks name marks), so a
point that lies between two vertices (a band's joint placed in proportion to
the opening it binds) becomes one: the outline and the matching sew line
(``sew_lines[0]`` when it pairs vertex for vertex with the outline) gain a
vertex at the same fraction of the same segment, without a grade rule (it is
graded by arc length between its neighbours' rules, as every point between
rule points is), and the marks and notches after it move up by one.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence

import numpy as np

from .model import Piece, VertexKind

__all__ = ["insert_vertices", "segment_at"]


def segment_at(outline: np.ndarray, xy: np.ndarray, tol_cm: float) -> tuple[int, float] | None:
    """``(k, t)``: the point ``xy`` on outline segment k (vertex k to k + 1) at fraction t, or None.

    None when ``xy`` is within ``tol_cm`` of a vertex (it is one already) or
    farther than ``tol_cm`` from every segment.

    Examples
    --------
    >>> square = np.array([[0.0, 0.0], [4.0, 0.0], [4.0, 4.0], [0.0, 4.0]])
    >>> segment_at(square, np.array([1.0, 0.0]), 0.05)
    (0, 0.25)
    >>> segment_at(square, np.array([4.0, 0.01]), 0.05) is None
    True
    """
    pts = np.asarray(outline, dtype=np.float64)
    xy = np.asarray(xy, dtype=np.float64)
    if np.min(np.hypot(*(pts - xy).T)) <= tol_cm:
        return None
    a, b = pts, np.roll(pts, -1, axis=0)
    d = b - a
    t = np.clip(np.einsum("ij,ij->i", xy - a, d) / np.maximum(np.einsum("ij,ij->i", d, d), 1e-18), 0.0, 1.0)
    dist = np.hypot(*(a + t[:, None] * d - xy).T)
    k = int(np.argmin(dist))
    if dist[k] > tol_cm:
        return None
    return k, float(t[k])


def _insert_line(points: np.ndarray, kinds, rules, at: list[tuple[int, float]]):
    """``points`` (n, 2) closed, with a vertex at each ``(k, t)``; ``at`` sorted, last first."""
    original = np.asarray(points, dtype=np.float64)
    pts = [tuple(p) for p in original]
    kinds = list(kinds) if kinds is not None else None
    rules = list(rules) if rules is not None else None
    n = len(pts)
    for k, t in at:  # last first: each lands at k + 1, ahead of those of the same segment inserted before
        p0, p1 = original[k], original[(k + 1) % n]
        pts.insert(k + 1, tuple(p0 + t * (p1 - p0)))
        if kinds is not None:
            kinds.insert(k + 1, VertexKind.TURN)
        if rules is not None:
            rules.insert(k + 1, None)
    return np.array(pts, dtype=np.float64), None if kinds is None else tuple(kinds), rules and tuple(rules)


def insert_vertices(piece: Piece, at: Sequence[tuple[int, float]]) -> tuple[Piece, np.ndarray]:
    """``piece`` with a new vertex at fraction t of each outline segment k of ``at``, and the index map.

    Parameters
    ----------
    piece : the piece
    at : ``(k, t)`` pairs, segment k (vertex k to k + 1) of the given
        outline, 0 < t < 1

    Returns
    -------
    piece : the new piece (marks, notches and the paired sew line follow)
    index : (n,) int64, the new index of every old vertex

    Examples
    --------
    >>> from patternbridge.pattern.model import Piece
    >>> p = Piece(name="strip", outline=[[0, 0], [10, 0], [10, 2], [0, 2]], marks={"top": 2})
    >>> q, index = insert_vertices(p, [(0, 0.3)])
    >>> q.outline[1].tolist(), q.marks["top"], index.tolist()
    ([3.0, 0.0], 3, [0, 2, 3, 4])
    """
    order = sorted(((int(k), float(t)) for k, t in at), reverse=True)
    n = len(piece.outline)
    index = np.arange(n, dtype=np.int64)
    for k, _ in order:
        index[k + 1 :] += 1
    if not order:
        return piece, index
    outline, kinds, rules = _insert_line(piece.outline, piece.kinds, piece.rules, order)
    sew = list(piece.sew_lines)
    if sew and sew[0].closed and len(sew[0].points) == n:
        pts, skinds, srules = _insert_line(sew[0].points, sew[0].kinds, sew[0].rules, order)
        sew[0] = dataclasses.replace(sew[0], points=pts, kinds=skinds, rules=srules)
    new = dataclasses.replace(
        piece,
        outline=outline,
        kinds=kinds,
        rules=rules,
        sew_lines=tuple(sew),
        marks={name: int(index[v]) for name, v in piece.marks.items()},
        notches=tuple(dataclasses.replace(m, vertex=int(index[m.vertex])) for m in piece.notches),
    )
    return new, index
