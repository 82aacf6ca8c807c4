"""Self-contact of the cloth: vertex-triangle pairs that keep the side they started on, as solver constraints.

At every time step the pairs of a vertex and a cloth triangle it lies over,
closer than ``thickness_cm`` plus a margin, are found from the step's start
(a k-d tree of the vertices against the triangle centres) and remember on
which side of the triangle the vertex was. While the solver iterates, a pair
whose vertex has come closer than ``thickness_cm`` (or gone through) gives
the vertex and the triangle's corners targets that restore the distance on
the remembered side (shared by barycentric weight, as a point-triangle
constraint of position-based dynamics); a vertex in several pairs takes the
mean. Vertices near each other on the sewn cloth (within two edges, across
seams) never form a pair: they touch by construction.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["SelfPairs", "find_pairs", "near_keys", "resolve_pairs"]


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


def resolve_pairs(
    x: np.ndarray, faces: np.ndarray, pairs: SelfPairs, thickness_cm: float
) -> tuple[np.ndarray, np.ndarray]:
    """Per-vertex targets that put every violated pair back ``thickness_cm`` apart on its side.

    Returns
    -------
    ids : (k,) int64 vertices in a violated pair ; targets : (k, 3) float64, cm
    """
    if len(pairs) == 0:
        return np.zeros(0, np.int64), np.zeros((0, 3))
    f = faces[pairs.triangle]
    tri = x[f]
    nrm = _normals(tri)
    d = np.einsum("ij,ij->i", x[pairs.vertex] - tri[:, 0], nrm)
    depth = thickness_cm - pairs.side * d
    bary = _barycentric(x[pairs.vertex], tri)
    bad = (depth > 0) & np.all(bary > -0.05, axis=1)
    if not bad.any():
        return np.zeros(0, np.int64), np.zeros((0, 3))
    v, f, side, depth, bary, nrm = pairs.vertex[bad], f[bad], pairs.side[bad], depth[bad], bary[bad], nrm[bad]
    bary = np.clip(bary, 0.0, 1.0)
    bary /= bary.sum(axis=1, keepdims=True)
    push = (side * depth / (1.0 + np.sum(bary**2, axis=1)))[:, None] * nrm
    delta = np.zeros_like(x)
    count = np.zeros(len(x))
    np.add.at(delta, v, push)
    np.add.at(count, v, 1.0)
    for k in range(3):
        np.add.at(delta, f[:, k], -bary[:, k, None] * push)
        np.add.at(count, f[:, k], 1.0)
    ids = np.flatnonzero(count)
    return ids, x[ids] + delta[ids] / count[ids, None]
