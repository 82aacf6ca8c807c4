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

__all__ = ["edge_path", "edge_paths"]

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
    chord = float(np.linalg.norm(V[a] - V[b]))
    cover = (1.0 + _ALT_SLACK) if alternative else 1.0
    r = 0.5 * cover * 1.24 * chord + 2.0 * emax
    reached_before = -1
    while True:
        dist, pred = dijkstra(
            g, directed=True, indices=[a, b], limit=r, return_predecessors=True
        )
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


def _route(pred: np.ndarray, m: int) -> np.ndarray:
    left = _trace(pred[0], m)[::-1]
    right = _trace(pred[1], m)[1:]
    return np.array(left + right, dtype=np.int64)
