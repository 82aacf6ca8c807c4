"""Self-contact of the cloth: vertex-triangle and edge-edge pairs that keep their sides, as solver constraints.

At every time step the pairs of a vertex and a cloth triangle it lies over,
closer than ``thickness_cm`` plus a margin, are found from the step's start
(a k-d tree of the vertices against the triangle centres) and remember on
which side of the triangle the vertex was. While the solver iterates, a pair
whose vertex has come closer than ``thickness_cm`` (or gone through) gives
the vertex and the triangle's corners targets that restore the distance on
the remembered side (shared by barycentric weight, as a point-triangle
constraint of position-based dynamics); a vertex in several pairs takes the
mean. Edge-edge pairs do the same along the direction that joined their
closest points at the step's start (two edges crossing like the threads of
a weave, which no vertex-triangle pair sees). Vertices near each other on the sewn cloth (within two edges, across
seams) never form a pair: they touch by construction.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["EdgePairs", "SelfPairs", "find_edge_pairs", "find_pairs", "near_keys", "resolve_pairs"]


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class SelfPairs:
    """Vertex-triangle pairs of one step.

    vertex : (k,) int64 ; triangle : (k,) int64 face id ; side : (k,) float64, ±1 —
    the side of the triangle the vertex was on at the step's start
    """

    vertex: np.ndarray
    triangle: np.ndarray
    side: np.ndarray

    def __len__(self) -> int:
        return len(self.vertex)


def near_keys(n: int, pairs: np.ndarray, rings: int = 2) -> np.ndarray:
    """Sorted int64 keys ``i * n + j`` of vertex pairs within ``rings`` edges of each other along ``pairs`` (P, 2)."""
    from scipy.sparse import coo_matrix, identity

    a = coo_matrix((np.ones(2 * len(pairs)), (pairs.ravel(), pairs[:, ::-1].ravel())), shape=(n, n)).tocsr()
    a = (a + identity(n, format="csr")).astype(bool).astype(np.float64)
    r = a
    for _ in range(rings - 1):
        r = (r @ a).astype(bool).astype(np.float64)
    r = r.tocoo()
    return np.sort(r.row.astype(np.int64) * n + r.col.astype(np.int64))


def _is_in(keys: np.ndarray, sorted_keys: np.ndarray) -> np.ndarray:
    pos = np.clip(np.searchsorted(sorted_keys, keys), 0, max(len(sorted_keys) - 1, 0))
    return sorted_keys[pos] == keys if len(sorted_keys) else np.zeros(len(keys), dtype=bool)


def _normals(tri: np.ndarray) -> np.ndarray:
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    return n / np.maximum(np.linalg.norm(n, axis=1), 1e-12)[:, None]


def _barycentric(p: np.ndarray, tri: np.ndarray) -> np.ndarray:
    """(n, 3) barycentric weights of the feet of ``p`` (n, 3) on the planes of ``tri`` (n, 3, 3)."""
    e1, e2, w = tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0], p - tri[:, 0]
    d11, d12, d22 = (np.einsum("ij,ij->i", a, b) for a, b in ((e1, e1), (e1, e2), (e2, e2)))
    w1, w2 = np.einsum("ij,ij->i", w, e1), np.einsum("ij,ij->i", w, e2)
    den = np.maximum(d11 * d22 - d12 * d12, 1e-18)
    b1 = (d22 * w1 - d12 * w2) / den
    b2 = (d11 * w2 - d12 * w1) / den
    return np.stack([1.0 - b1 - b2, b1, b2], axis=1)


def find_pairs(x: np.ndarray, faces: np.ndarray, near: np.ndarray, reach_cm: float) -> SelfPairs:
    """The vertex-triangle pairs of the cloth ``x`` (N, 3) / ``faces`` (F, 3) closer than ``reach_cm``.

    Only a vertex over a triangle's inside (its foot within the triangle,
    with a small tolerance) pairs with it; pairs whose vertex is within two
    edges of a corner (``near``, see :func:`near_keys`) are left out.
    """
    from scipy.spatial import cKDTree

    n = len(x)
    tri = x[faces]
    centre = tri.mean(axis=1)
    radius = np.sqrt(np.max(np.sum((tri - centre[:, None]) ** 2, axis=2), axis=1))
    r_max = float(radius.max(initial=0.0)) + reach_cm
    found = cKDTree(x).sparse_distance_matrix(cKDTree(centre), r_max, output_type="ndarray")
    v, t = found["i"].astype(np.int64), found["j"].astype(np.int64)
    keep = found["v"] <= radius[t] + reach_cm
    v, t = v[keep], t[keep]
    keep = ~(_is_in(v[:, None] * n + faces[t], near).any(axis=1))
    v, t = v[keep], t[keep]
    nrm = _normals(tri[t])
    d = np.einsum("ij,ij->i", x[v] - tri[t, 0], nrm)
    bary = _barycentric(x[v], tri[t])
    keep = (np.abs(d) < reach_cm) & (np.abs(d) > 1e-9) & np.all(bary > -0.05, axis=1)
    return SelfPairs(vertex=v[keep], triangle=t[keep], side=np.sign(d[keep]))


def _accumulate(
    x: np.ndarray, faces: np.ndarray, pairs: SelfPairs, thickness_cm: float, delta: np.ndarray, count: np.ndarray
) -> None:
    """Add the corrections of the violated vertex-triangle pairs to ``delta`` (N, 3) and ``count`` (N,)."""
    if len(pairs) == 0:
        return
    f = faces[pairs.triangle]
    tri = x[f]
    nrm = _normals(tri)
    d = np.einsum("ij,ij->i", x[pairs.vertex] - tri[:, 0], nrm)
    depth = thickness_cm - pairs.side * d
    bary = _barycentric(x[pairs.vertex], tri)
    bad = (depth > 0) & np.all(bary > -0.05, axis=1)
    if not bad.any():
        return
    v, f, side, depth, bary, nrm = pairs.vertex[bad], f[bad], pairs.side[bad], depth[bad], bary[bad], nrm[bad]
    bary = np.clip(bary, 0.0, 1.0)
    bary /= bary.sum(axis=1, keepdims=True)
    push = (side * depth / (1.0 + np.sum(bary**2, axis=1)))[:, None] * nrm
    np.add.at(delta, v, push)
    np.add.at(count, v, 1.0)
    for k in range(3):
        np.add.at(delta, f[:, k], -bary[:, k, None] * push)
        np.add.at(count, f[:, k], 1.0)


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class EdgePairs:
    """Edge-edge pairs of one step.

    edges : (k, 2, 2) int64 — the two edges of every pair ; direction : (k, 3) float64 —
    the unit direction from the second edge's closest point to the first's at the step's start
    """

    edges: np.ndarray
    direction: np.ndarray

    def __len__(self) -> int:
        return len(self.edges)


def _segment_params(p1, p2, q1, q2) -> tuple[np.ndarray, np.ndarray]:
    """Parameters (s, t) in [0, 1] of the closest points of the segments p1p2 and q1q2 (each (k, 3))."""
    d1, d2, r = p2 - p1, q2 - q1, p1 - q1
    a = np.einsum("ij,ij->i", d1, d1)
    e = np.einsum("ij,ij->i", d2, d2)
    f = np.einsum("ij,ij->i", d2, r)
    c = np.einsum("ij,ij->i", d1, r)
    b = np.einsum("ij,ij->i", d1, d2)
    den = np.maximum(a * e - b * b, 1e-12)
    s = np.clip((b * f - c * e) / den, 0.0, 1.0)
    t = np.clip((b * s + f) / np.maximum(e, 1e-12), 0.0, 1.0)
    s = np.clip((b * t - c) / np.maximum(a, 1e-12), 0.0, 1.0)
    return s, t


def find_edge_pairs(x: np.ndarray, edges: np.ndarray, near: np.ndarray, reach_cm: float) -> EdgePairs:
    """The pairs of cloth edges (E, 2) closer than ``reach_cm`` at ``x`` (N, 3), not within two edges of each other."""
    from scipy.spatial import cKDTree

    n = len(x)
    mid = 0.5 * (x[edges[:, 0]] + x[edges[:, 1]])
    half = 0.5 * np.linalg.norm(x[edges[:, 0]] - x[edges[:, 1]], axis=1)
    # (an edge stretched past the 99th percentile is reached from near its middle only)
    r = 2 * float(np.percentile(half, 99)) + reach_cm if len(half) else reach_cm
    found = cKDTree(mid).query_pairs(r, output_type="ndarray")
    if len(found) == 0:
        return EdgePairs(edges=np.zeros((0, 2, 2), np.int64), direction=np.zeros((0, 3)))
    i, j = found[:, 0], found[:, 1]
    ei, ej = edges[i], edges[j]
    keys = ei[:, :, None] * n + ej[:, None, :]
    keep = ~_is_in(keys.reshape(-1), near).reshape(-1, 4).any(axis=1)
    ei, ej = ei[keep], ej[keep]
    p1, p2, q1, q2 = x[ei[:, 0]], x[ei[:, 1]], x[ej[:, 0]], x[ej[:, 1]]
    s, t = _segment_params(p1, p2, q1, q2)
    d = (p1 + s[:, None] * (p2 - p1)) - (q1 + t[:, None] * (q2 - q1))
    dist = np.linalg.norm(d, axis=1)
    keep = (dist < reach_cm) & (dist > 1e-6) & (s > 0.0) & (s < 1.0) & (t > 0.0) & (t < 1.0)
    return EdgePairs(edges=np.stack([ei[keep], ej[keep]], axis=1), direction=d[keep] / dist[keep, None])


def _accumulate_edges(
    x: np.ndarray, pairs: EdgePairs, thickness_cm: float, delta: np.ndarray, count: np.ndarray
) -> None:
    """Add the corrections of the edge pairs closer than ``thickness_cm`` along their starting direction."""
    if len(pairs) == 0:
        return
    e = pairs.edges
    p1, p2, q1, q2 = x[e[:, 0, 0]], x[e[:, 0, 1]], x[e[:, 1, 0]], x[e[:, 1, 1]]
    s, t = _segment_params(p1, p2, q1, q2)
    d = (p1 + s[:, None] * (p2 - p1)) - (q1 + t[:, None] * (q2 - q1))
    sep = np.einsum("ij,ij->i", d, pairs.direction)
    depth = thickness_cm - sep
    bad = (depth > 0) & (s > 0.0) & (s < 1.0) & (t > 0.0) & (t < 1.0)
    if not bad.any():
        return
    e, s, t, depth, u = e[bad], s[bad], t[bad], depth[bad], pairs.direction[bad]
    w = [1.0 - s, s, -(1.0 - t), -t]
    norm = sum(c * c for c in w)
    push = (depth / norm)[:, None] * u
    for c, ids in zip(w, (e[:, 0, 0], e[:, 0, 1], e[:, 1, 0], e[:, 1, 1]), strict=True):
        np.add.at(delta, ids, c[:, None] * push)
        np.add.at(count, ids, 1.0)


def resolve_pairs(
    x: np.ndarray, faces: np.ndarray, pairs: SelfPairs, thickness_cm: float, edge_pairs: EdgePairs | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """Per-vertex targets that put every violated pair back ``thickness_cm`` apart on its side.

    Returns
    -------
    ids : (k,) int64 vertices in a violated pair ; targets : (k, 3) float64, cm
    """
    delta = np.zeros_like(x)
    count = np.zeros(len(x))
    _accumulate(x, faces, pairs, thickness_cm, delta, count)
    if edge_pairs is not None:
        _accumulate_edges(x, edge_pairs, thickness_cm, delta, count)
    ids = np.flatnonzero(count)
    return ids, x[ids] + delta[ids] / count[ids, None]
