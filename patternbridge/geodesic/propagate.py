"""Single source, all destinations: the wavefront propagation with curvature flow.

No priority queue: the wavefront grows in bands of one mean edge length (the
radius limit ``r_max`` of the propagation rises band by band); a new vertex
takes the *straightest* path among its visited neighbours (the smallest turn
between the neighbour's path tangent and the edge towards the new vertex,
among neighbours whose distance estimate is close to the best) and extends it
by the edge; then the path is relaxed by the least-squares curvature flow.

* windowed form (``window=w``): only the last ``w`` samples of each path are
  re-solved, the rest is frozen, so each vertex costs a constant and the whole
  propagation is linear in the number of vertices. The windows of one band are
  independent and solved together as a stack of small dense systems.
* full form (``window="full"``): every path is re-solved whole (slow; small
  meshes only).

``window=None`` (default) sizes the window from the mesh resolution: the
error comes from the kink where a window starts, so the window has to span a
length (about 5.5 cm), not a fixed number of samples.
"""

from __future__ import annotations

import logging
from collections.abc import Callable

import numpy as np

from ..errors import MeshError
from .surface import SurfaceMesh, SurfacePoint

__all__ = ["geodesic_distances", "solve_windows"]

log = logging.getLogger(__name__)

_FIX_WEIGHT = 1e4
#: automatic windows span about this much path, cm
WINDOW_CM = 5.5
#: candidate parents: distance estimate within this many edge lengths of the best
_NEAR = 0.05
#: windows up to this many samples are solved densely (one stacked LAPACK call)
_DENSE_W = 24
#: wavefront band width, mean edge lengths
_BAND = 1.0


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Row-wise cross product of (..., 3) arrays (faster than ``np.cross``)."""
    out = np.zeros(np.broadcast_shapes(a.shape, b.shape))
    out[..., 0] = a[..., 1] * b[..., 2] - a[..., 2] * b[..., 1]
    out[..., 1] = a[..., 2] * b[..., 0] - a[..., 0] * b[..., 2]
    out[..., 2] = a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]
    return out


def _tangent_bases(normals: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Two unit tangent vectors per normal (..., 3) -> (..., 3), (..., 3)."""
    helper = np.where(
        (np.abs(normals[..., 0]) < 0.9)[..., None], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]
    )
    t1 = _cross(normals, helper)
    t1 /= np.sqrt((t1 * t1).sum(axis=-1))[..., None]
    return t1, _cross(normals, t1)


def solve_windows(
    points: np.ndarray,
    normals: np.ndarray,
    anchors_xyz: np.ndarray,
    free: np.ndarray,
    *,
    tangents: np.ndarray | None = None,
) -> np.ndarray:
    """Least-squares curvature flow on a stack of windows at once.

    Parameters
    ----------
    points : (B, w, 3) float64, cm, current samples
    normals : (B, w, 3) float64, tangent-plane normals at the samples
    anchors_xyz : (B, w, 3) float64, a point of each tangent plane (the vertex)
    free : (B, w) bool, samples that may move; the first and last must be fixed
    tangents : (B, w, 3, 2) float64 or None, orthonormal tangent bases of the
        normals (computed from ``normals`` when None; the propagation passes
        per-vertex bases computed once)

    Returns
    -------
    (B, w, 3) float64 relaxed samples with zero tangential curvature
    ``(I - n n^T) K p = 0`` and ``n . p = n . anchor`` at the free samples.

    Notes
    -----
    The system of :func:`patternbridge.geodesic.flow.lsq_step` is consistent
    (three independent rows per free sample), so its least-squares solution
    solves it exactly. Writing each free sample as ``anchor + T u`` with ``T`` an
    orthonormal tangent basis satisfies the plane rows identically and leaves
    two tangential rows per sample: a block-tridiagonal system per window,
    solved for the whole stack at once by block elimination (2x2 blocks), in
    time linear in the window length.
    """
    B, w, _ = points.shape
    if tangents is None:
        t1, t2 = _tangent_bases(normals)
        T = np.stack([t1, t2], axis=-1)  # (B, w, 3, 2)
    else:
        T = tangents
    fr = free.astype(np.float64)
    base = np.where(free[..., None], anchors_xyz, points)  # p = base + T u (free)
    # rows of inner sample i: T_i^T (p_{i-1} - 2 p_i + p_{i+1}) = 0; fixed: u_i = 0
    TT = np.einsum("bwki,bwkj->bwij", T[:, 1:-1], T[:, :-2])  # T_i^T T_{i-1}
    TU = np.einsum("bwki,bwkj->bwij", T[:, 1:-1], T[:, 2:])  # T_i^T T_{i+1}
    TT *= (fr[:, :-2] * fr[:, 1:-1])[..., None, None]
    TU *= (fr[:, 2:] * fr[:, 1:-1])[..., None, None]
    lo = np.zeros((B, w, 2, 2))
    up = np.zeros((B, w, 2, 2))
    lo[:, 1:-1] = TT
    up[:, 1:-1] = TU
    diag = np.where(free, -2.0, 1.0)  # diagonal blocks are multiples of I
    lap = base[:, :-2] - 2.0 * base[:, 1:-1] + base[:, 2:]
    rhs = np.zeros((B, w, 2))
    rhs[:, 1:-1] = -np.einsum("bwki,bwk->bwi", T[:, 1:-1], lap)
    rhs *= fr[..., None]
    u = (
        _block_dense(lo, diag, up, rhs)
        if w <= _DENSE_W
        else _block_thomas(lo, diag, up, rhs)
    )
    return base + np.einsum("bwki,bwi->bwk", T, u) * fr[..., None]


def _block_dense(lo, diag, up, rhs):
    """The block-tridiagonal systems of :func:`_block_thomas` as one stacked
    dense solve (B, 2w, 2w): one LAPACK call instead of a Python loop over the
    samples, faster for short windows."""
    B, w = diag.shape
    A = np.zeros((B, w, 2, w, 2))
    i = np.arange(w)
    A[:, i, 0, i, 0] = diag
    A[:, i, 1, i, 1] = diag
    j = i[1:]
    # two advanced indices split by a slice put their axis first
    A[:, j, :, j - 1, :] = lo[:, 1:].swapaxes(0, 1)
    A[:, j - 1, :, j, :] = up[:, :-1].swapaxes(0, 1)
    A = A.reshape(B, 2 * w, 2 * w)
    return np.linalg.solve(A, rhs.reshape(B, 2 * w, 1)).reshape(B, w, 2)


def _inv2(m: np.ndarray) -> np.ndarray:
    """Inverse of a stack of 2x2 matrices (B, 2, 2)."""
    det = m[:, 0, 0] * m[:, 1, 1] - m[:, 0, 1] * m[:, 1, 0]
    out = np.zeros_like(m)
    out[:, 0, 0] = m[:, 1, 1]
    out[:, 1, 1] = m[:, 0, 0]
    out[:, 0, 1] = -m[:, 0, 1]
    out[:, 1, 0] = -m[:, 1, 0]
    return out / det[:, None, None]


def _block_thomas(lo, diag, up, rhs):
    """Solve stacks of block-tridiagonal systems with 2x2 blocks.

    Row i: ``lo_i u_{i-1} + diag_i u_i + up_i u_{i+1} = rhs_i`` for each of the
    B windows at once; one sweep over the w samples, vectorised over B.
    """
    B, w = diag.shape
    cp = np.zeros((B, w, 2, 2))
    rp = np.zeros((B, w, 2))
    eye = np.eye(2)
    inv = _inv2(diag[:, 0, None, None] * eye)
    cp[:, 0] = inv @ up[:, 0]
    rp[:, 0] = (inv @ rhs[:, 0, :, None])[..., 0]
    for i in range(1, w):
        m = diag[:, i, None, None] * eye - lo[:, i] @ cp[:, i - 1]
        inv = _inv2(m)
        cp[:, i] = inv @ up[:, i]
        rp[:, i] = (
            inv @ (rhs[:, i] - (lo[:, i] @ rp[:, i - 1, :, None])[..., 0])[..., None]
        )[..., 0]
    u = np.zeros((B, w, 2))
    u[:, -1] = rp[:, -1]
    for i in range(w - 2, -1, -1):
        u[:, i] = rp[:, i] - (cp[:, i] @ u[:, i + 1, :, None])[..., 0]
    return u


def _neighbours(indptr, indices, verts):
    cnt = indptr[verts + 1] - indptr[verts]
    own = np.repeat(verts, cnt)
    pos = np.repeat(indptr[verts] - np.cumsum(cnt) + cnt, cnt) + np.arange(cnt.sum())
    return own, indices[pos]


def geodesic_distances(
    mesh: SurfaceMesh,
    source,
    *,
    r_max: float | None = None,
    window: int | str | None = None,
    progress: Callable[[str, int, int], None] | None = None,
) -> np.ndarray:
    """Geodesic distance from one source vertex to every vertex.

    Parameters
    ----------
    mesh : SurfaceMesh
    source : int vertex id or SurfacePoint at a vertex (a face point is snapped
        to its nearest corner)
    r_max : float, cm, or None
        Stop the propagation at this radius; vertices beyond get ``inf``.
    window : int, ``"full"`` or None
        Samples re-solved per new vertex (>= 3). ``None`` picks the window from
        the mesh resolution so that it spans about ``WINDOW_CM`` of path (at
        least 12 samples); ``"full"`` re-solves whole paths (the full form:
        slow, small meshes only).
    progress : optional ``progress(stage, done, total)``

    Returns
    -------
    (V,) float64, cm; ``inf`` for vertices beyond ``r_max`` or not connected.
    """
    if not isinstance(mesh, SurfaceMesh):
        raise MeshError(
            f"geodesic: expected a SurfaceMesh, got {type(mesh).__name__}; "
            "wrap the arrays with SurfaceMesh(vertices, faces)"
        )
    sp_ = mesh.check_point(source, "source")
    if sp_.vertex_id is None:
        sp_ = SurfacePoint.vertex(int(mesh.faces[sp_.face, int(np.argmax(sp_.bary))]))
    src = sp_.vertex_id
    if window is None:
        window = int(min(64, max(12, np.ceil(WINDOW_CM / max(mesh.edge_mean, 1e-12)))))
    full = isinstance(window, str)
    if (full and window != "full") or (not full and int(window) < 3):
        raise MeshError(
            f"geodesic: window {window!r} is not a sample count >= 3 or 'full'; "
            "pass window >= 3, 'full' for the full form, or None for automatic"
        )
    if r_max is not None and not r_max > 0:
        raise MeshError(
            f"geodesic: r_max {r_max} is not a positive length in cm; "
            "pass r_max > 0 or None"
        )
    w = 3 if full else int(window)
    g = mesh.graph
    indptr, indices = g.indptr, g.indices
    V = mesh.vertices
    nv = mesh.n_vertices
    step = mesh.edge_mean
    limit = np.inf if r_max is None else float(r_max)

    dist = np.full(nv, np.inf)
    visited = np.zeros(nv, dtype=bool)
    parent = np.full(nv, -1, dtype=np.int64)
    tails = np.zeros((nv, w, 3)) if not full else None
    tail_ids = np.full((nv, w), -1, dtype=np.int64) if not full else None
    dstart = np.zeros(nv)
    normal_cache = mesh.all_vertex_normals

    t1, t2 = _tangent_bases(normal_cache)
    tangent_cache = np.stack([t1, t2], axis=-1)  # (V, 3, 2)

    def normals_of(ids):
        return normal_cache[np.asarray(ids)]

    def tangents_of(ids):
        return tangent_cache[np.asarray(ids)]

    dist[src] = 0.0
    visited[src] = True
    if not full:
        tails[src, :] = V[src]
        tail_ids[src, :] = src
    front = np.array([src], dtype=np.int64)
    pending = np.zeros(0, dtype=np.int64)
    r = 0.0
    done = 1
    while True:
        _, nb = _neighbours(indptr, indices, front)
        cand = np.unique(np.concatenate([pending, nb]))
        cand = cand[~visited[cand]]
        if len(cand) == 0:
            break
        own, nbr = _neighbours(indptr, indices, cand)
        ok = visited[nbr]
        own, nbr = own[ok], nbr[ok]
        el = np.linalg.norm(V[own] - V[nbr], axis=1)
        dest = dist[nbr] + el
        order = np.lexsort((dest, own))
        own, nbr, el, dest = own[order], nbr[order], el[order], dest[order]
        firsts = np.ones(len(own), dtype=bool)
        firsts[1:] = own[1:] != own[:-1]
        grp = np.cumsum(firsts) - 1
        best = dest[firsts]
        lo = best.min()
        if lo > limit:
            break
        r = max(r + _BAND * step, lo)
        accept_mask = best <= r
        # straightest parent among neighbours whose estimate is near the best
        near = dest <= best[grp] + _NEAR * el
        near &= accept_mask[grp]
        if full:
            tan = np.where(
                (parent[nbr] >= 0)[:, None], V[nbr] - V[np.maximum(parent[nbr], 0)], 0.0
            )
        else:
            tan = tails[nbr, -1] - tails[nbr, -2]
        edge = V[own] - V[nbr]
        tn = np.linalg.norm(tan, axis=1)
        cosang = np.where(
            tn > 0, np.einsum("ij,ij->i", tan, edge) / (tn * el + 1e-300), 1.0
        )
        score = np.where(near, -cosang, np.inf)
        o2 = np.lexsort((score, own))
        own2, nbr2, sc2 = own[o2], nbr[o2], score[o2]
        f2 = np.ones(len(own2), dtype=bool)
        f2[1:] = own2[1:] != own2[:-1]
        sel = f2 & np.isfinite(sc2)
        q = own2[sel]
        p = nbr2[sel]
        if len(q):
            parent[q] = p
            visited[q] = True
            if full:
                _solve_full(mesh, q, parent, dist, normals_of)
            else:
                _solve_windowed(
                    mesh, q, p, tails, tail_ids, dstart, dist, normals_of, tangents_of
                )
            done += len(q)
            if progress is not None:
                progress("propagate", done, nv)
        front = q
        pending = cand[~visited[cand]]
        if r > limit and len(q) == 0:
            break
    dist[dist > limit] = np.inf
    return dist


def _solve_windowed(
    mesh, q, p, tails, tail_ids, dstart, dist, normals_of, tangents_of
) -> None:
    V = mesh.vertices
    w = tails.shape[1]
    full_p = tail_ids[p, 0] >= 0
    # shift the parent's window by one and append the new vertex
    new_pts = np.concatenate([tails[p, 1:], V[q][:, None, :]], axis=1)
    new_ids = np.concatenate([tail_ids[p, 1:], q[:, None]], axis=1)
    seg0 = np.linalg.norm(tails[p, 1] - tails[p, 0], axis=1)
    dstart[q] = dstart[p] + np.where(full_p, seg0, 0.0)
    valid = new_ids >= 0
    # pad the unused front slots with the first valid sample
    first = np.argmax(valid, axis=1)
    rows = np.arange(len(q))
    pad = ~valid
    new_pts = np.where(pad[..., None], new_pts[rows, first][:, None, :], new_pts)
    new_ids = np.where(pad, new_ids[rows, first][:, None], new_ids)
    free = valid.copy()
    free[rows, first] = False
    free[:, -1] = False
    if free.any():
        new_ids = _reanchor(mesh, new_pts, new_ids, free)
        flat = new_ids.ravel()
        nrm = normals_of(flat).reshape(len(q), w, 3)
        tng = tangents_of(flat).reshape(len(q), w, 3, 2)
        new_pts = solve_windows(new_pts, nrm, V[new_ids], free, tangents=tng)
    tails[q] = new_pts
    tail_ids[q] = np.where(valid, new_ids, -1)
    seg = np.linalg.norm(np.diff(new_pts, axis=1), axis=2).sum(axis=1)
    dist[q] = dstart[q] + seg


def _reanchor(mesh, pts, ids, free, n_steps: int = 1):
    """Move each free sample's anchor to the nearest vertex of its one ring
    (a local descent, as the samples drift away from their first vertices)."""
    tab = mesh.neighbour_table
    V = mesh.vertices
    sel = np.flatnonzero(free.ravel())
    cur = ids.ravel()[sel]
    x = pts.reshape(-1, 3)[sel]
    for _ in range(n_steps):
        cand = tab[cur]  # (n, D), padded with cur itself
        diff = V[cand] - x[:, None, :]
        d2 = np.einsum("ijk,ijk->ij", diff, diff)
        nxt = cand[np.arange(len(cur)), np.argmin(d2, axis=1)]
        if np.array_equal(nxt, cur):
            break
        cur = nxt
    out = ids.copy().ravel()
    out[sel] = cur
    return out.reshape(ids.shape)


def _solve_full(mesh, q, parent, dist, normals_of) -> None:
    from .flow import lsq_step

    V = mesh.vertices
    for v in q.tolist():
        ids = [v]
        while parent[ids[-1]] >= 0:
            ids.append(int(parent[ids[-1]]))
        ids = np.array(ids[::-1])
        pts = V[ids]
        if len(ids) >= 3:
            nrm = normals_of(ids)
            off = np.einsum("ij,ij->i", pts - V[ids], nrm)
            pts = lsq_step(pts, nrm, pts - off[:, None] * nrm)
        dist[v] = float(np.linalg.norm(np.diff(pts, axis=0), axis=1).sum())
