"""Initial vertex paths: Dijkstra over the edge graph, limited to the neighbourhood.

Two searches, one from each end, each stopped at a radius ``r``; the best
meeting vertex gives the shortest edge path as soon as ``r`` exceeds half its
length plus the longest edge. ``r`` starts from the straight-line distance and
grows until that holds, so the work stays local to the path.
"""

from __future__ import annotations

import logging

import numpy as np
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
    """
    a, b = int(a), int(b)
    if a == b:
        return [(np.array([a], dtype=np.int64), 0.0)]
    g = mesh.graph
    emax = mesh.edge_max
    V = mesh.vertices
    cover = (1.0 + _ALT_SLACK) if alternative else 1.0
    r = start_radius(mesh, a, b, alternative=alternative)
    reached_before = -1
    rows = mesh._cache.get("search_rows")  # kept searches, see geodesic_paths
    while True:
        dist, pred = _searches(g, (a, b), r, rows)
        total = dist[0] + dist[1]
        m = int(np.argmin(total))
        best = float(total[m])
        if np.isfinite(best) and cover * best <= 2.0 * (r - emax):
            break
        reached = int(np.isfinite(dist[0]).sum())
        if reached == reached_before:  # a's component is exhausted
            if np.isfinite(best):
                break
            comp = mesh.components
            raise MeshError(
                f"mesh: vertices {a} and {b} are not connected (components {comp[a]} "
                f"and {comp[b]} of {comp.max() + 1}); pick points on the same piece "
                "of surface"
            )
        reached_before = reached
        r *= 1.6
    out = [(_route(pred, m), best)]
    if alternative and best > 0:
        near = np.flatnonzero(total <= cover * best)
        tree = cKDTree(V[out[0][0]])
        away, _ = tree.query(V[near], distance_upper_bound=_ALT_AWAY * best)
        far = near[np.isinf(away)]
        if len(far):
            m2 = int(far[np.argmin(total[far])])
            out.append((_route(pred, m2), float(total[m2])))
    return out


def start_radius(mesh: SurfaceMesh, a: int, b: int, *, alternative: bool) -> float:
    """First search radius, cm, of :func:`edge_paths` between vertices a and b:
    enough when the edge path is at most 1.24 times the chord."""
    cover = (1.0 + _ALT_SLACK) if alternative else 1.0
    chord = float(np.linalg.norm(mesh.vertices[a] - mesh.vertices[b]))
    return 0.5 * cover * 1.24 * chord + 2.0 * mesh.edge_max


def _searches(g, ends: tuple[int, int], r: float, rows: dict | None):
    """Dijkstra rows (distances, predecessors) from both ends within ``r``.

    ``rows`` (or None) maps a vertex to ``(radius, dist, pred)`` of a search
    kept for a later path from the same vertex, plus ``"keep"``: a map from
    the vertices worth keeping to the least radius to search them with (the
    largest first radius of their paths). A kept search of at least radius
    ``r`` is exact within ``r``; it is cut to ``r`` and reused, so the result
    is the same as searching again.
    """
    if rows is None:
        return dijkstra(
            g, directed=True, indices=list(ends), limit=r, return_predecessors=True
        )
    keep = rows["keep"]
    got: dict[int, tuple] = {}
    plain = []
    for x in dict.fromkeys(ends):
        kept = rows.get(x)
        if kept is None and x in keep:
            rx = max(r, keep[x])
            d, p = dijkstra(
                g, directed=True, indices=x, limit=rx, return_predecessors=True
            )
            kept = rows[x] = (rx, d, p)
        if kept is not None and kept[0] >= r:
            d = kept[1] if kept[0] == r else np.where(kept[1] <= r, kept[1], np.inf)
            got[x] = (d, kept[2])
        else:
            plain.append(x)
    if plain:
        d, p = dijkstra(
            g, directed=True, indices=plain, limit=r, return_predecessors=True
        )
        for k, x in enumerate(plain):
            got[x] = (d[k], p[k])
    (da, pa), (db, pb) = got[ends[0]], got[ends[1]]
    return (da, db), (pa, pb)


def _route(pred: np.ndarray, m: int) -> np.ndarray:
    left = _trace(pred[0], m)[::-1]
    right = _trace(pred[1], m)[1:]
    return np.array(left + right, dtype=np.int64)
