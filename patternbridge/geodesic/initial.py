"""Initial vertex paths: Dijkstra over the edge graph, limited to the neighbourhood.

Two searches, one from each end, each stopped at a radius ``r``; the best
meeting vertex gives the shortest edge path as soon as ``r`` exceeds half its
length plus the longest edge. ``r`` starts from the straight-line distance and
grows until that holds, so the work stays local to the path. Both searches run
on a sub-graph: the vertices within ``r`` of an end that also lie inside the
ellipsoid with the two ends as foci that every edge path short enough to
matter stays in (picked through the vertex grid, edge lengths computed for
that sub-graph only).
"""

from __future__ import annotations

import logging

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import dijkstra
from scipy.spatial import cKDTree

from ..errors import MeshError
from .surface import SurfaceMesh

__all__ = ["edge_path", "edge_paths", "start_radius"]

#: graph routes up to this much longer than the best one are searched for a
#: second way around (e.g. front or back of the neck)
_ALT_SLACK = 0.07
#: a route counts as another way when it passes this fraction of the best
#: length away from the best route
_ALT_AWAY = 0.2

log = logging.getLogger(__name__)


def _trace(pred: np.ndarray, v: int) -> list[int]:
    out = [v]
    while pred[v] >= 0:
        v = int(pred[v])
        out.append(v)
    return out


def edge_path(mesh: SurfaceMesh, a: int, b: int) -> tuple[np.ndarray, float]:
    """Shortest path along mesh edges from vertex ``a`` to vertex ``b``.

    Parameters
    ----------
    mesh : SurfaceMesh
    a, b : int
        Vertex ids.

    Returns
    -------
    vertices : (k,) int64, ``a`` first and ``b`` last
    length : float, cm, along the edges

    Raises
    ------
    MeshError
        When ``a`` and ``b`` lie on different connected components.
    """
    return edge_paths(mesh, a, b, alternative=False)[0]


def edge_paths(
    mesh: SurfaceMesh, a: int, b: int, *, alternative: bool = True
) -> list[tuple[np.ndarray, float]]:
    """The shortest edge path, and the best edge path that goes another way.

    The second route (when ``alternative``) passes through the vertex of least
    ``d(a, x) + d(x, b)`` among those at least ``_ALT_AWAY`` times the best
    length away from the best route, if that sum is within ``_ALT_SLACK`` of
    the best. Two such routes can straighten into different geodesics (over
    the front or the back of the neck), and only straightening tells which is
    shorter.

    Returns
    -------
    list of ``(vertices (k,) int64, length cm)``, the shortest first.

    Notes
    -----
    Both searches run on the sub-graph of the vertices within ``r`` of an end
    and inside the ellipsoid ``|x - a| + |x - b| <= 2 (r - e)`` (``e``: the
    longest edge). Every edge path no longer than that bound stays inside it,
    so the shortest route and every route within ``_ALT_SLACK`` of it are
    found exactly once the bound covers them; the radius grows until it does.
    """
    a, b = int(a), int(b)
    if a == b:
        return [(np.array([a], dtype=np.int64), 0.0)]
    emax = mesh.edge_max
    V = mesh.vertices
    cover = (1.0 + _ALT_SLACK) if alternative else 1.0
    r = start_radius(mesh, a, b, alternative=alternative)
    reached_before = -1
    bounded = True  # False: the whole balls, no ellipsoid
    while True:
        bound = 2.0 * (r - emax) if bounded else np.inf
        keep, g, la, lb = _sub_graph(mesh, a, b, r, bound)
        # half-edges: undirected, so that boundary edges and flipped faces
        # are walked both ways
        dist, pred = dijkstra(
            g, directed=False, indices=[la, lb], limit=r, return_predecessors=True
        )
        total = dist[0] + dist[1]
        m = int(np.argmin(total))
        best = float(total[m])
        if np.isfinite(best) and cover * best <= 2.0 * (r - emax):
            break
        reached = int(np.isfinite(dist[0]).sum())
        if reached == reached_before:
            if bounded:  # perhaps only the ellipsoid stops it: search it all
                bounded = False
                continue
            if np.isfinite(best):  # a's component is exhausted
                break
            comp = mesh.components
            raise MeshError(
                f"mesh: vertices {a} and {b} are not connected (components {comp[a]} "
                f"and {comp[b]} of {comp.max() + 1}); pick points on the same piece "
                "of surface"
            )
        reached_before = reached
        r *= 1.6
    out = [(keep[_route(pred, m)], best)]
    if alternative and best > 0:
        near = np.flatnonzero(total <= cover * best)
        tree = cKDTree(V[out[0][0]])
        away, _ = tree.query(V[keep[near]], distance_upper_bound=_ALT_AWAY * best)
        far = near[np.isinf(away)]
        if len(far):
            m2 = int(far[np.argmin(total[far])])
            out.append((keep[_route(pred, m2)], float(total[m2])))
    return out


def start_radius(mesh: SurfaceMesh, a: int, b: int, *, alternative: bool) -> float:
    """First search radius, cm, of :func:`edge_paths` between vertices a and b:
    enough when the edge path is at most 1.24 times the chord."""
    cover = (1.0 + _ALT_SLACK) if alternative else 1.0
    chord = float(np.linalg.norm(mesh.vertices[a] - mesh.vertices[b]))
    return 0.5 * cover * 1.24 * chord + 2.0 * mesh.edge_max


def _sub_graph(mesh: SurfaceMesh, a: int, b: int, r: float, bound: float):
    """The edge graph on the vertices within ``r`` of ``a`` or ``b`` and with
    ``|x - a| + |x - b| <= bound``.

    Returns
    -------
    keep : (n,) int64 vertex ids of the sub-graph's vertices
    graph : (n, n) CSR edge lengths, cm: the half-edges of the usable faces
        leaving each vertex (search it as undirected)
    la, lb : local ids of ``a`` and ``b``
    """
    V = mesh.vertices
    pa, pb = V[a], V[b]
    lo = np.minimum(pa, pb) - r
    hi = np.maximum(pa, pb) + r
    finite = bool(np.isfinite(bound))
    if finite:
        # bounding box of the ellipsoid with foci a, b and major axis ``bound``
        half = 0.5 * bound
        c = 0.5 * float(np.linalg.norm(pb - pa))
        u = (pb - pa) / (2.0 * c) if c > 0 else np.zeros(3)
        minor2 = max(half * half - c * c, 0.0)
        ext = np.sqrt(half * half * u * u + minor2 * (1.0 - u * u))
        mid = 0.5 * (pa + pb)
        lo = np.maximum(lo, mid - ext)
        hi = np.minimum(hi, mid + ext)

    def cell_test(centres, margin):
        da = np.linalg.norm(centres - pa, axis=1)
        db = np.linalg.norm(centres - pb, axis=1)
        ok = (da <= r + margin) | (db <= r + margin)
        if finite:
            ok &= da + db <= bound + 2.0 * margin
        return ok

    cand, (x, y, z) = mesh.box_vertices(lo, hi, cell_test)
    da = _dist(x, y, z, pa)
    db = _dist(x, y, z, pb)
    ok = (da <= r) | (db <= r)
    if finite:
        da += db
        ok &= da <= bound
    keep = cand[ok]
    n = len(keep)
    # int64 (intp) indices throughout: numpy converts other index types on
    # every gather
    # map vertex -> sub-graph id: a (V,) scratch array of -1 taken from the
    # mesh and handed back clean (a concurrent search makes its own)
    local = mesh._cache.pop("search_ids", None)
    if local is None:
        local = np.full(mesh.n_vertices, -1, dtype=np.int64)
    local[keep] = np.arange(n)
    if local[a] < 0 or local[b] < 0:  # never by construction; keep the ends anyway
        keep = np.union1d(keep, [a, b])
        n = len(keep)
        local[keep] = np.arange(n)
    la, lb = int(local[a]), int(local[b])
    counts, nxt, w = mesh.ring_entries(keep, lengths=True)
    cols = local[nxt]
    local[keep] = -1
    mesh._cache["search_ids"] = local
    inside = cols >= 0
    cols = cols[inside]
    w = w[inside]
    # kept entries per row (rows come in vertex order)
    kept = np.zeros(len(inside) + 1, dtype=np.int64)
    np.cumsum(inside, out=kept[1:])
    ends = np.cumsum(counts)
    per_row = kept[ends] - kept[ends - counts]
    np.maximum(w, 1e-12, out=w)  # a zero weight would read as "no edge"
    indptr = np.zeros(n + 1, dtype=np.int32)
    np.cumsum(per_row, out=indptr[1:])
    g = sp.csr_matrix((w, cols.astype(np.int32), indptr), shape=(n, n))
    return keep, g, la, lb


def _dist(x, y, z, p) -> np.ndarray:
    """Distances, cm, of the points with coordinate columns x, y, z to p (3,)."""
    d = x - p[0]
    d *= d
    t = y - p[1]
    t *= t
    d += t
    t = z - p[2]
    t *= t
    d += t
    return np.sqrt(d, out=d)


def _route(pred: np.ndarray, m: int) -> np.ndarray:
    left = _trace(pred[0], m)[::-1]
    right = _trace(pred[1], m)[1:]
    return np.array(left + right, dtype=np.int64)
