"""Points on a mesh surface: the closest point to a query, its face and barycentric weights.

:func:`closest_on_triangles` is the one closest-point-on-triangle test of the package (the landmarks here,
the cloth's self-contact in :mod:`patternbridge.assemble.cloth.selfcontact`).

A landmark placed by a rule that defines a level or a point between vertices
lies inside a face; :class:`SurfaceLocation` gives it that face, its weights
and its nearest vertex (:class:`~patternbridge.mesh.character.Landmark`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .character import Landmark

__all__ = ["SurfaceLocation", "closest_on_triangles", "locate_on_surface", "point_on_triangles"]


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
        q = point_on_triangles(closest_on_triangles(np.broadcast_to(p, (len(cand), 3)), tri), tri)
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


def closest_on_triangles(p: np.ndarray, tri: np.ndarray) -> np.ndarray:
    """(k, 3) barycentric weights of the points of the triangles ``tri`` (k, 3, 3) closest to ``p`` (k, 3).

    The region tests of Ericson (Real-Time Collision Detection, 5.1.5): the
    closest point is a corner, a point of an edge or the foot inside.
    """
    a, b, c = tri[:, 0], tri[:, 1], tri[:, 2]
    ab, ac = b - a, c - a

    def dot(u, v):
        return np.einsum("ij,ij->i", u, v)

    ap, bp, cp = p - a, p - b, p - c
    d1, d2, d3, d4, d5, d6 = dot(ab, ap), dot(ac, ap), dot(ab, bp), dot(ac, bp), dot(ab, cp), dot(ac, cp)
    va, vb, vc = d3 * d6 - d5 * d4, d5 * d2 - d1 * d6, d1 * d4 - d3 * d2

    def ratio(num, den):
        return num / np.where(np.abs(den) > 1e-18, den, 1e-18)

    v, w = ratio(vb, va + vb + vc), ratio(vc, va + vb + vc)
    out = np.stack([1.0 - v - w, v, w], axis=1)
    one, zero = np.ones(len(p)), np.zeros(len(p))
    t_bc, t_ac, t_ab = ratio(d4 - d3, (d4 - d3) + (d5 - d6)), ratio(d2, d2 - d6), ratio(d1, d1 - d3)
    regions = (  # lowest priority first: a later region overrides an earlier one
        ((va <= 0) & (d4 - d3 >= 0) & (d5 - d6 >= 0), (zero, 1.0 - t_bc, t_bc)),  # edge bc
        ((vb <= 0) & (d2 >= 0) & (d6 <= 0), (1.0 - t_ac, zero, t_ac)),  # edge ac
        ((d6 >= 0) & (d5 <= d6), (zero, zero, one)),  # corner c
        ((vc <= 0) & (d1 >= 0) & (d3 <= 0), (1.0 - t_ab, t_ab, zero)),  # edge ab
        ((d3 >= 0) & (d4 <= d3), (zero, one, zero)),  # corner b
        ((d1 <= 0) & (d2 <= 0), (one, zero, zero)),  # corner a
    )
    for mask, weights in regions:
        out[mask] = np.stack(weights, axis=1)[mask]
    return np.clip(out, 0.0, 1.0)


def point_on_triangles(bary: np.ndarray, tri: np.ndarray) -> np.ndarray:
    """(k, 3) points of the barycentric weights ``bary`` (k, 3) on the triangles ``tri`` (k, 3, 3).

    A weight of 1 is its corner itself and a point with one zero weight is
    found along the edge of the other two from its first corner, so a point on
    a corner or an edge lies there to the last bit (as a sum of all three
    weighted corners it would not).
    """
    a, b, c = tri[:, 0], tri[:, 1], tri[:, 2]
    out = a + (b - a) * bary[:, 1, None] + (c - a) * bary[:, 2, None]  # inside, and on the edges from a
    on_bc = bary[:, 0] == 0.0
    out[on_bc] = (b + (c - b) * bary[:, 2, None])[on_bc]
    for k in range(3):
        corner = bary[:, k] == 1.0
        out[corner] = tri[corner, k]
    return out
