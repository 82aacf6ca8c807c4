"""Points on a mesh surface: the closest point to a query, its face and barycentric weights.

A landmark placed by a rule that defines a level or a point between vertices
lies inside a face; :class:`SurfaceLocation` gives it that face, its weights
and its nearest vertex (:class:`~patternbridge.mesh.character.Landmark`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .character import Landmark

__all__ = ["SurfaceLocation", "closest_point_on_triangles", "locate_on_surface"]


@dataclass(frozen=True, slots=True, eq=False)
class SurfaceLocation:
    """Points on a mesh surface (rows of the query).

    positions : (n, 3) float64, cm, on the surface
    face : (n,) int64, the face holding each point
    bary : (n, 3) float64, its barycentric weights of ``faces[face]``
    vertex : (n,) int64, the nearest corner of that face
    """

    positions: np.ndarray
    face: np.ndarray
    bary: np.ndarray
    vertex: np.ndarray

    def landmark(self, i: int, name: str, **fields) -> Landmark:
        """Row ``i`` as a :class:`Landmark`: the surface point, its nearest vertex, and its face and
        weights unless it is that vertex."""
        b = self.bary[i]
        inside = float(b.max()) < 1.0 - 1e-9
        return Landmark(
            name=name,
            position=self.positions[i],
            vertex=int(self.vertex[i]),
            face=int(self.face[i]) if inside else None,
            bary=tuple(float(x) for x in b) if inside else None,
            **fields,
        )


def locate_on_surface(vertices: np.ndarray, faces: np.ndarray, points: np.ndarray) -> SurfaceLocation:
    """Closest surface points: position, face, barycentric weights and nearest vertex.

    The closest point is searched on the faces around the 16 nearest vertices
    of each query point (exact for points near the surface).

    Parameters
    ----------
    vertices : (V, 3) float64, cm
    faces : (F, 3) int64
    points : (n, 3) float64, cm
    """
    from scipy.spatial import cKDTree

    points = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    k = min(16, len(vertices))
    _, near = cKDTree(vertices).query(points, k=k)
    near = np.asarray(near).reshape(len(points), -1)
    order = np.argsort(faces.ravel(), kind="stable")
    vf_face = order // 3
    starts = np.searchsorted(faces.ravel()[order], np.arange(len(vertices) + 1))
    positions = np.zeros_like(points)
    vids = np.zeros(len(points), dtype=np.int64)
    face = np.zeros(len(points), dtype=np.int64)
    bary = np.zeros((len(points), 3))
    for i, p in enumerate(points):
        cand = np.unique(np.concatenate([vf_face[starts[v] : starts[v + 1]] for v in near[i]]))
        tri = vertices[faces[cand]]
        q = closest_point_on_triangles(np.broadcast_to(p, (len(cand), 3)).copy(), tri[:, 0], tri[:, 1], tri[:, 2])
        j = int(np.argmin(np.sum((q - p) ** 2, axis=1)))
        positions[i] = q[j]
        face[i] = cand[j]
        bary[i] = _barycentric(q[j], tri[j])
        corners = faces[cand[j]]
        vids[i] = corners[np.argmin(np.sum((vertices[corners] - q[j]) ** 2, axis=1))]
    return SurfaceLocation(positions=positions, face=face, bary=bary, vertex=vids)


def _barycentric(q: np.ndarray, tri: np.ndarray) -> np.ndarray:
    """(3,) weights of the triangle's corners (3, 3) for the point ``q`` on it (clipped, summing to 1)."""
    e1, e2, d = tri[1] - tri[0], tri[2] - tri[0], q - tri[0]
    g = np.array([[e1 @ e1, e1 @ e2], [e1 @ e2, e2 @ e2]])
    try:
        b1, b2 = np.linalg.solve(g, [d @ e1, d @ e2])
    except np.linalg.LinAlgError:  # a degenerate face: its nearest corner
        w = np.zeros(3)
        w[int(np.argmin(np.linalg.norm(tri - q, axis=1)))] = 1.0
        return w
    w = np.clip(np.array([1.0 - b1 - b2, b1, b2]), 0.0, 1.0)
    return w / w.sum()


def closest_point_on_triangles(p: np.ndarray, a: np.ndarray, b: np.ndarray, c: np.ndarray) -> np.ndarray:
    """Closest points of triangles (a, b, c) to points p, all (n, 3); vectorised region test."""
    ab, ac, ap = b - a, c - a, p - a
    d1, d2 = np.einsum("ij,ij->i", ab, ap), np.einsum("ij,ij->i", ac, ap)
    bp = p - b
    d3, d4 = np.einsum("ij,ij->i", ab, bp), np.einsum("ij,ij->i", ac, bp)
    cp = p - c
    d5, d6 = np.einsum("ij,ij->i", ab, cp), np.einsum("ij,ij->i", ac, cp)
    va = d3 * d6 - d5 * d4
    vb = d5 * d2 - d1 * d6
    vc = d1 * d4 - d3 * d2
    denom = va + vb + vc
    denom = np.where(np.abs(denom) < 1e-300, 1e-300, denom)
    v = vb / denom
    w = vc / denom
    out = a + ab * v[:, None] + ac * w[:, None]  # inside the face
    with np.errstate(divide="ignore", invalid="ignore"):
        # edges
        t_ab = d1 / (d1 - d3)
        m = (vc <= 0) & (d1 >= 0) & (d3 <= 0)
        out[m] = (a + ab * t_ab[:, None])[m]
        t_ac = d2 / (d2 - d6)
        m = (vb <= 0) & (d2 >= 0) & (d6 <= 0)
        out[m] = (a + ac * t_ac[:, None])[m]
        t_bc = (d4 - d3) / ((d4 - d3) + (d5 - d6))
        m = (va <= 0) & ((d4 - d3) >= 0) & ((d5 - d6) >= 0)
        out[m] = (b + (c - b) * t_bc[:, None])[m]
    # corners
    m = (d1 <= 0) & (d2 <= 0)
    out[m] = a[m]
    m = (d3 >= 0) & (d4 <= d3)
    out[m] = b[m]
    m = (d6 >= 0) & (d5 <= d6)
    out[m] = c[m]
    return out
