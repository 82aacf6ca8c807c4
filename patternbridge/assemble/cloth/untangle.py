"""Untangling the cloth: crossings that exist are undone by shrinking their intersection contours.

Self-contact (:mod:`.selfcontact`) keeps every layer on the side it started
a step on, so a fold that is already through the cloth beside it stays
through. Where two parts of the cloth cross, their triangles intersect
along closed (or boundary-ending) polylines, the intersection contours.
Following intersection-contour minimisation (Volino and Magnenat-Thalmann
2006), every crossing of an edge through a triangle is a point of a
contour, and a relative motion of the edge against the triangle moves
that point along the edge; the motion that shortens the contour is

    R = G - N (G·E) / (E·N)

where ``G`` is the gradient of the contour's length at the point (the sum
of the unit vectors from its two neighbours on the contour), ``E`` the
edge and ``N`` the triangle's normal. Moving the edge by ``-R`` and the
triangle by ``+R`` shrinks every contour until it vanishes: the smaller
region enclosed by it is pulled back through, without knowing beforehand
which side was right. A crossing whose contour has no neighbour (two
triangles meeting at a single point of the mesh) falls back to moving the
edge's shallower end back through the plane.

:func:`find_crossings` is exact (a segment against a triangle, strictly
through its inside); :func:`untangle_targets` gives per-vertex moves
whose targets the solver adds as constraints for one step.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["Crossings", "edge_faces", "find_crossings", "untangle_targets"]


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class Crossings:
    """Edges passing through triangles.

    edge : (k,) int64 index into the edges ; triangle : (k,) int64 face id ;
    point : (k, 3) float64, cm — where the edge pierces the triangle ;
    depth : (k, 2) float64, cm — signed distances of the edge's two ends from the triangle's plane
    """

    edge: np.ndarray
    triangle: np.ndarray
    point: np.ndarray
    depth: np.ndarray

    def __len__(self) -> int:
        return len(self.edge)


def edge_faces(faces: np.ndarray, edges: np.ndarray) -> np.ndarray:
    """(E, 2) int64: the (one or two) faces beside every edge of ``edges`` (E, 2), -1 where there is none."""
    f = np.asarray(faces, dtype=np.int64)
    n = int(max(f.max(initial=0), edges.max(initial=0))) + 1
    he = np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]])
    owner = np.tile(np.arange(len(f)), 3)
    key = np.sort(he, axis=1) @ np.array([n, 1], dtype=np.int64)
    ekey = np.sort(edges, axis=1) @ np.array([n, 1], dtype=np.int64)
    order = np.argsort(ekey)
    pos = order[np.clip(np.searchsorted(ekey[order], key), 0, len(ekey) - 1)]
    ok = ekey[pos] == key
    out = np.full((len(edges), 2), -1, dtype=np.int64)
    pos, owner = pos[ok], owner[ok]
    srt = np.argsort(pos, kind="stable")
    pos, owner = pos[srt], owner[srt]
    first = np.ones(len(pos), dtype=bool)
    first[1:] = pos[1:] != pos[:-1]
    out[pos[first], 0] = owner[first]
    out[pos[~first], 1] = owner[~first]
    return out


def _normals(tri: np.ndarray) -> np.ndarray:
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    return n / np.maximum(np.linalg.norm(n, axis=1), 1e-12)[:, None]


def _candidates(x: np.ndarray, faces: np.ndarray, edges: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Edge-triangle pairs whose bounding spheres overlap."""
    from scipy.spatial import cKDTree

    tri = x[faces]
    centre = tri.mean(axis=1)
    radius = np.sqrt(np.max(np.sum((tri - centre[:, None]) ** 2, axis=2), axis=1))
    mid = 0.5 * (x[edges[:, 0]] + x[edges[:, 1]])
    half = 0.5 * np.linalg.norm(x[edges[:, 0]] - x[edges[:, 1]], axis=1)
    r = float(radius.max(initial=0.0) + half.max(initial=0.0))
    found = cKDTree(mid).sparse_distance_matrix(cKDTree(centre), r, output_type="ndarray")
    e, t = found["i"].astype(np.int64), found["j"].astype(np.int64)
    keep = found["v"] <= half[e] + radius[t]
    return e[keep], t[keep]


def find_crossings(x: np.ndarray, faces: np.ndarray, edges: np.ndarray, label: np.ndarray | None = None) -> Crossings:
    """Every edge of ``edges`` (E, 2) passing strictly through a triangle of ``faces`` (F, 3) at ``x`` (N, 3).

    ``label`` (N,) int64: vertices with one label are one point (the sides
    of a seam, see ``weld_groups``); an edge never crosses a triangle it
    shares a point with.
    """
    x = np.asarray(x, dtype=np.float64)
    label = np.arange(len(x)) if label is None else np.asarray(label)
    empty = Crossings(
        edge=np.zeros(0, np.int64), triangle=np.zeros(0, np.int64), point=np.zeros((0, 3)), depth=np.zeros((0, 2))
    )
    if len(edges) == 0 or len(faces) == 0:
        return empty
    e, t = _candidates(x, faces, edges)
    le, lt = label[edges[e]], label[faces[t]]
    keep = ~(le[:, :, None] == lt[:, None, :]).any(axis=(1, 2))
    e, t = e[keep], t[keep]
    tri = x[faces[t]]
    nrm = _normals(tri)
    p, q = x[edges[e, 0]], x[edges[e, 1]]
    dp = np.einsum("ij,ij->i", p - tri[:, 0], nrm)
    dq = np.einsum("ij,ij->i", q - tri[:, 0], nrm)
    across = (dp * dq < 0) & (np.abs(dp) > 1e-9) & (np.abs(dq) > 1e-9)
    s = dp / np.where(across, dp - dq, 1.0)
    m = p + s[:, None] * (q - p)
    inside = across.copy()
    for k in range(3):
        u, v = tri[:, k], tri[:, (k + 1) % 3]
        inside &= np.einsum("ij,ij->i", np.cross(v - u, m - u), nrm) > 0.0
    return Crossings(edge=e[inside], triangle=t[inside], point=m[inside], depth=np.stack([dp, dq], axis=1)[inside])


def _contour_gradient(crossings: Crossings, beside: np.ndarray) -> np.ndarray:
    """(k, 3) gradient of the contour length at every crossing point (zero where it has no neighbour).

    Two crossing points are neighbours on a contour when they lie on the
    intersection segment of the same two triangles: the triangle pierced and
    one of the faces ``beside`` (E, 2) the piercing edge.
    """
    k = len(crossings)
    grad = np.zeros((k, 3))
    f = beside[crossings.edge]  # (k, 2)
    t = crossings.triangle
    point = np.repeat(np.arange(k), 2)
    a, b = f.ravel(), np.repeat(t, 2)
    ok = a >= 0
    point, a, b = point[ok], a[ok], b[ok]
    key = np.minimum(a, b) * (max(int(a.max(initial=0)), int(b.max(initial=0))) + 1) + np.maximum(a, b)
    order = np.argsort(key, kind="stable")
    key, point = key[order], point[order]
    # a segment: a key held by exactly two points
    start = np.flatnonzero(np.r_[True, key[1:] != key[:-1]])
    size = np.diff(np.r_[start, len(key)])
    pair = start[size == 2]
    i, j = point[pair], point[pair + 1]
    d = crossings.point[i] - crossings.point[j]
    d /= np.maximum(np.linalg.norm(d, axis=1), 1e-12)[:, None]
    np.add.at(grad, i, d)
    np.add.at(grad, j, -d)
    return grad


def untangle_targets(
    x: np.ndarray,
    faces: np.ndarray,
    edges: np.ndarray,
    beside: np.ndarray,
    label: np.ndarray,
    step_cm: float,
    held: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray, int]:
    """Per-vertex moves that shrink every intersection contour of the cloth by about ``step_cm``.

    Parameters
    ----------
    x : (N, 3) float64, cm ; faces : (F, 3) int64 ; edges : (E, 2) int64
    beside : (E, 2) int64, the faces beside every edge (:func:`edge_faces`)
    label : (N,) int64, see :func:`find_crossings`
    step_cm : relative motion of an edge against the triangle it crosses
    held : (N,) bool, vertices the untangling leaves alone: a crossing with an end or a corner there is
        not moved (the cloth round a seam still open, which the seam's spring is pulling)

    Returns
    -------
    ids : (m,) int64 vertices of crossing edges and crossed triangles ;
    moves : (m, 3) float64, cm (the mean of every crossing's move of the vertex) ;
    n_crossings : the crossings found
    """
    c = find_crossings(x, faces, edges, label)
    if held is not None and len(c):
        free = ~(held[edges[c.edge]].any(axis=1) | held[faces[c.triangle]].any(axis=1))
        c = Crossings(edge=c.edge[free], triangle=c.triangle[free], point=c.point[free], depth=c.depth[free])
    if len(c) == 0:
        return np.zeros(0, np.int64), np.zeros((0, 3)), 0
    e, t = edges[c.edge], faces[c.triangle]
    nrm = _normals(x[t])
    vec = x[e[:, 1]] - x[e[:, 0]]
    g = _contour_gradient(c, beside)
    en = np.einsum("ij,ij->i", vec, nrm)
    en = np.where(np.abs(en) < 1e-6, np.copysign(1e-6, en), en)
    r = g - nrm * (np.einsum("ij,ij->i", g, vec) / en)[:, None]
    # no neighbour on a contour: the edge's shallower end goes back through the plane
    shallow = np.where(np.abs(c.depth[:, 0]) < np.abs(c.depth[:, 1]), c.depth[:, 0], c.depth[:, 1])
    lone = np.linalg.norm(g, axis=1) < 1e-9
    r[lone] = np.sign(shallow[lone])[:, None] * nrm[lone]
    r /= np.maximum(np.linalg.norm(r, axis=1), 1e-12)[:, None]
    move = (0.5 * step_cm) * r
    delta = np.zeros_like(x)
    count = np.zeros(len(x))
    for k in range(2):
        np.add.at(delta, e[:, k], -move)
        np.add.at(count, e[:, k], 1.0)
    for k in range(3):
        np.add.at(delta, t[:, k], move)
        np.add.at(count, t[:, k], 1.0)
    # the sides of a seam are one point: they take one move (the mean of their crossings' moves), so the
    # untangling carries a seam through the cloth whole and never pulls its two sides apart
    gdelta = np.zeros((int(label.max(initial=0)) + 1, 3))
    gcount = np.zeros(len(gdelta))
    np.add.at(gdelta, label, delta)
    np.add.at(gcount, label, count)
    ids = np.flatnonzero(gcount[label])
    return ids, gdelta[label[ids]] / gcount[label[ids], None], len(c)
