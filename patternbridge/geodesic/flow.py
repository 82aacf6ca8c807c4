"""Geodesic curvature flow of a polyline as sparse linear systems.

The discrete curvature at ``p_i`` is ``p_{i-1} - 2 p_i + p_{i+1}`` (``K P``);
its geodesic part is what is left after removing the component along the
tangent-plane normal ``n_i`` of the closest vertex. Two schemes:

* least squares: ``(K - n n^T K) P = [p_1, 0, ..., 0, p_m]`` stacked with the
  tangent-plane rows ``n n^T P = n n^T Pbar`` (``Pbar``: the points projected
  onto their tangent planes), solved for all points at once;
* implicit Euler: ``(I + mu (n n^T - K + n n^T K)) P_{t+1} = P_t + mu n n^T Pbar_t``.

Both re-estimate closest vertices and tangent planes for a few outer
iterations and re-sample segments that span several faces.
"""

from __future__ import annotations

import logging

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import spsolve
from scipy.spatial import cKDTree

from .surface import SurfaceMesh

__all__ = [
    "corridor",
    "euler_step",
    "flow_path",
    "lsq_step",
    "tangent_planes",
    "tangent_step",
]

log = logging.getLogger(__name__)


def corridor(mesh: SurfaceMesh, vids, rings: int = 3) -> np.ndarray:
    """Vertices within ``rings`` edge hops of ``vids`` (sorted int64).

    A breadth-first growth from the path that only expands the newest ring.
    """
    seen = np.zeros(mesh.n_vertices, dtype=bool)
    front = np.unique(np.asarray(vids, dtype=np.int64))
    seen[front] = True
    for _ in range(rings):
        _, nxt, prv = mesh.ring_entries(front)
        nb = np.concatenate([nxt, prv])
        nb = np.unique(nb[~seen[nb]])
        if len(nb) == 0:
            break
        seen[nb] = True
        front = nb
    return np.flatnonzero(seen)


def tangent_planes(
    mesh: SurfaceMesh, points: np.ndarray, tree: cKDTree, verts: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Closest corridor vertex, its tangent normal and the projected points.

    Returns
    -------
    anchors : (m,) int64 vertex ids
    normals : (m, 3) float64 unit normals
    pbar : (m, 3) float64, cm, points projected onto their tangent planes
    """
    _, k = tree.query(points)
    anchors = verts[k]
    n = mesh.vertex_normals(anchors)
    off = np.einsum("ij,ij->i", points - mesh.vertices[anchors], n)
    return anchors, n, points - off[:, None] * n


def _laplacian(m: int) -> sp.csr_matrix:
    """(3m, 3m) K: second differences on interior points, zero end rows."""
    i = np.arange(1, m - 1)
    rows = np.repeat(i, 3)
    cols = np.stack([i - 1, i, i + 1], axis=1).ravel()
    vals = np.tile([1.0, -2.0, 1.0], m - 2)
    k1 = sp.csr_matrix((vals, (rows, cols)), shape=(m, m))
    return sp.kron(k1, sp.identity(3), format="csr")


def _block_nn(normals: np.ndarray) -> sp.csr_matrix:
    m = len(normals)
    blocks = normals[:, :, None] * normals[:, None, :]
    rows = np.repeat(np.arange(3 * m).reshape(m, 3), 3, axis=1).ravel()
    cols = np.tile(np.arange(3 * m).reshape(m, 3), (1, 3)).ravel()
    return sp.csr_matrix((blocks.ravel(), (rows, cols)), shape=(3 * m, 3 * m))


def lsq_step(
    points: np.ndarray, normals: np.ndarray, pbar: np.ndarray, plane_weight: float = 1.0
) -> np.ndarray:
    """One least-squares solve of the geodesic-curvature system.

    Parameters
    ----------
    points : (m, 3) float64, cm; rows 0 and m-1 are kept fixed
    normals : (m, 3) float64 unit tangent-plane normals
    pbar : (m, 3) float64, points projected on their tangent planes
    plane_weight : weight of the tangent-plane rows

    Returns
    -------
    (m, 3) float64 new points
    """
    m = len(points)
    if m < 3:
        return points.copy()
    K = _laplacian(m)
    NN = _block_nn(normals)
    A1 = (K - NN @ K).tolil()
    rhs1 = np.zeros(3 * m)
    for r in (0, m - 1):  # fixed end points
        for c in range(3):
            A1.rows[3 * r + c] = [3 * r + c]
            A1.data[3 * r + c] = [1.0]
            rhs1[3 * r + c] = points[r, c]
    A1 = A1.tocsr()
    inner = np.ones(m)
    inner[[0, -1]] = 0.0
    NNw = _block_nn(normals * np.sqrt(inner)[:, None]) * plane_weight
    A = sp.vstack([A1, NNw], format="csr")
    rhs = np.concatenate([rhs1, NNw @ pbar.ravel()])
    x = spsolve((A.T @ A).tocsc(), A.T @ rhs).reshape(m, 3)
    x[[0, -1]] = points[[0, -1]]  # exactly, not up to round-off
    return x


def tangent_step(
    points: np.ndarray, normals: np.ndarray, pbar: np.ndarray
) -> np.ndarray:
    """The least-squares step solved exactly in tangent coordinates (fast path).

    The stacked system of :func:`lsq_step` is consistent: three independent rows
    per inner point. Writing each inner point as ``pbar_i + T_i u_i`` (``T_i`` an
    orthonormal basis of its tangent plane) satisfies the plane rows and leaves
    ``T_i^T (p_{i-1} - 2 p_i + p_{i+1}) = 0``: a block-tridiagonal (2m, 2m)
    system, solved as a banded matrix in O(m). Same result as :func:`lsq_step`.
    """
    from scipy.linalg.lapack import dgbsv

    from .propagate import _tangent_bases

    m = len(points)
    if m < 3:
        return points.copy()
    t1, t2 = _tangent_bases(normals[1:-1])
    T = np.stack([t1, t2], axis=-1)  # (k, 3, 2), k = m - 2 inner points
    k = m - 2
    base = pbar.copy()
    base[[0, -1]] = points[[0, -1]]
    lap = base[:-2] - 2.0 * base[1:-1] + base[2:]
    rhs = -np.einsum("kci,kc->ki", T, lap).ravel()
    n = 2 * k
    # LAPACK band storage with (kl, ku) = (3, 3) and kl spare rows on top:
    # entry (r, c) of the matrix sits at ab[6 + r - c, c]
    ab = np.zeros((10, n))
    ab[6] = -2.0
    if k > 1:
        lo = np.einsum("kci,kcj->kij", T[1:], T[:-1])  # T_i^T T_{i-1}
        up = np.einsum("kci,kcj->kij", T[:-1], T[1:])  # T_i^T T_{i+1}
        for i_ in range(2):
            for j_ in range(2):
                # rows 2b + i, columns 2(b - 1) + j, for b = 1 .. k-1
                ab[8 + i_ - j_, j_ : n - 2 : 2] = lo[:, i_, j_]
                # rows 2(b - 1) + i, columns 2b + j
                ab[4 + i_ - j_, 2 + j_ : n : 2] = up[:, i_, j_]
    _, _, x, info = dgbsv(3, 3, ab, rhs, overwrite_ab=True, overwrite_b=True)
    if info != 0:  # singular: tangent planes at right angles to the path
        from scipy.linalg import LinAlgError

        raise LinAlgError(f"singular tangent system (info {info})")
    u = x.reshape(k, 2)
    out = base.copy()
    out[1:-1] += np.einsum("kcj,kj->kc", T, u)
    return out


def euler_step(
    points: np.ndarray, normals: np.ndarray, pbar: np.ndarray, mu: float
) -> np.ndarray:
    """One implicit-Euler step ``(I + mu (nn^T - K + nn^T K)) P' = P + mu nn^T Pbar``.

    The end points are kept fixed (their rows are the identity).
    """
    m = len(points)
    if m < 3:
        return points.copy()
    K = _laplacian(m)
    NN = _block_nn(normals)
    A = (sp.identity(3 * m) + mu * (NN - K + NN @ K)).tolil()
    rhs = points.ravel() + mu * (NN @ pbar.ravel())
    for r in (0, m - 1):
        for c in range(3):
            A.rows[3 * r + c] = [3 * r + c]
            A.data[3 * r + c] = [1.0]
            rhs[3 * r + c] = points[r, c]
    x = spsolve(A.tocsc(), rhs).reshape(m, 3)
    x[[0, -1]] = points[[0, -1]]
    return x


def _resample(points: np.ndarray, max_seg: float) -> np.ndarray:
    seg = np.linalg.norm(np.diff(points, axis=0), axis=1)
    n_sub = np.maximum(np.ceil(seg / max_seg).astype(np.int64), 1)
    if (n_sub == 1).all():
        return points
    # segment i becomes points[i] + (j / k) (points[i + 1] - points[i]), j = 1..k
    seg_of = np.repeat(np.arange(len(seg)), n_sub)
    k = n_sub[seg_of]
    j = np.arange(len(seg_of)) - np.repeat(np.cumsum(n_sub) - n_sub, n_sub) + 1
    t = (j / k)[:, None]
    p0 = points[seg_of]
    new = p0 + t * (points[seg_of + 1] - p0)
    return np.vstack([points[:1], new])


def flow_path(
    mesh: SurfaceMesh,
    vpath,
    start,
    end,
    *,
    scheme: str = "lsq",
    n_outer: int = 7,
    mu: float = 4.0,
    omega: float = 1.3,
    rings: int = 14,
    fast: bool = True,
) -> np.ndarray:
    """Run the curvature flow from an edge path.

    Parameters
    ----------
    mesh : SurfaceMesh
    vpath : (k,) int vertex path
    start, end : Endpoint (positions of the fixed ends)
    scheme : ``"lsq"`` or ``"euler"``
    n_outer : outer iterations (tangent planes re-estimated each time)
    mu : implicit-Euler step
    omega : over-relaxation of each outer step after the first (1: plain)
    rings : least width of the vertex corridor searched for closest vertices
        (at least 1/16 of the edge path length in edges)
    fast : solve the least-squares step in tangent coordinates (same result)

    Returns
    -------
    (m, 3) float64, cm: the floating polyline, ends included
    """
    vp = np.asarray(vpath, dtype=np.int64)
    pts = mesh.vertices[vp]
    if start.vertex is None:
        pts = np.vstack([start.xyz, pts])
    if end.vertex is None:
        pts = np.vstack([pts, end.xyz])
    if len(pts) < 3:
        return pts.copy()
    # the flow may move the path sideways by a fraction of its edge count
    verts = corridor(mesh, vp, rings=max(rings, len(vp) // 16))
    tree = cKDTree(mesh.vertices[verts], balanced_tree=False)  # faster to build
    max_seg = 1.5 * mesh.edge_mean
    for it in range(n_outer):
        _, n, pbar = tangent_planes(mesh, pts, tree, verts)
        if scheme == "lsq":
            new = tangent_step(pts, n, pbar) if fast else lsq_step(pts, n, pbar)
        else:
            new = euler_step(pts, n, pbar, mu)
        pts = pts + omega * (new - pts) if it > 0 else new
        pts = _resample(pts, max_seg)
    return pts
