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

from ..errors import MeshError
from .surface import SurfaceMesh

__all__ = ["edge_path"]

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
    a, b = int(a), int(b)
    if a == b:
        return np.array([a], dtype=np.int64), 0.0
    g = mesh.graph
    emax = mesh.edge_max
    chord = float(np.linalg.norm(mesh.vertices[a] - mesh.vertices[b]))
    r = 0.62 * chord + 2.0 * emax
    reached_before = -1
    while True:
        dist, pred = dijkstra(g, directed=True, indices=[a, b], limit=r,
                              return_predecessors=True)
        total = dist[0] + dist[1]
        m = int(np.argmin(total))
        best = float(total[m])
        if np.isfinite(best) and best <= 2.0 * (r - emax):
            break
        reached = int(np.isfinite(dist[0]).sum())
        if reached == reached_before:  # a's component is exhausted
            if np.isfinite(best):
                break
            comp = mesh.components
            raise MeshError(
                f"mesh: vertices {a} and {b} are not connected (components {comp[a]} "
                f"and {comp[b]} of {comp.max() + 1}); pick points on the same piece "
                "of surface")
        reached_before = reached
        r *= 1.6
    left = _trace(pred[0], m)[::-1]
    right = _trace(pred[1], m)[1:]
    return np.array(left + right, dtype=np.int64), best
