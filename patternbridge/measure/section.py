"""Plane sections of a triangle mesh, split into closed loops, and their convex hulls.

A tape measure laid around a body part in a plane follows the convex hull of
the part's cross-section: it bridges every hollow. :func:`plane_loops` cuts
the mesh and returns each closed loop of the cut; :func:`hull_girth` gives the
perimeter of the convex hull of a chosen set of loops.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["Loop", "Section", "SlabIndex", "hull_girth", "plane_basis", "plane_loops"]


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class Loop:
    """One connected piece of a plane section.

    points : (n, 3) float64, cm, unordered points of the cut (one per cut edge)
    uv : (n, 2) float64, cm, the same points in the plane's basis
    segments : (m, 2) int64, pairs of rows of ``points`` joined by a face
    """

    points: np.ndarray
    uv: np.ndarray
    segments: np.ndarray

    @property
    def closed(self) -> bool:
        """True when every point joins exactly two segments (a closed curve)."""
        if len(self.segments) < 3:
            return False
        deg = np.bincount(self.segments.ravel(), minlength=len(self.points))
        return bool(np.all(deg == 2))

    def ordered_points(self) -> np.ndarray:
        """(n, 3) the points of a closed loop in their order along it (:attr:`closed` must hold)."""
        n = len(self.points)
        ends = np.concatenate([self.segments, self.segments[:, ::-1]])
        ends = ends[np.argsort(ends[:, 0], kind="stable")]
        nbr = ends[:, 1].reshape(n, 2)  # every point of a closed loop joins exactly two segments
        order = np.zeros(n, dtype=np.int64)
        for i in range(1, n):
            prev = order[i - 2] if i > 1 else -1
            order[i] = nbr[order[i - 1], 0] if nbr[order[i - 1], 0] != prev else nbr[order[i - 1], 1]
        return self.points[order]

    @property
    def centroid_uv(self) -> np.ndarray:
        return self.uv.mean(axis=0)

    def contains_uv(self, q: np.ndarray) -> bool:
        """Even-odd rule: is the 2D point ``q`` inside the loop?"""
        a = self.uv[self.segments[:, 0]]
        b = self.uv[self.segments[:, 1]]
        straddle = (a[:, 1] > q[1]) != (b[:, 1] > q[1])
        t = (q[1] - a[:, 1]) / np.where(straddle, b[:, 1] - a[:, 1], 1.0)
        x = a[:, 0] + t * (b[:, 0] - a[:, 0])
        return bool(np.count_nonzero(straddle & (x > q[0])) % 2)

    def distance_uv(self, q: np.ndarray) -> float:
        """Distance from the 2D point ``q`` to the nearest point of the loop."""
        return float(np.min(np.linalg.norm(self.uv - q, axis=1)))


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class Section:
    """A plane cut: origin (3,), normal (3,), basis (2, 3) and its loops."""

    origin: np.ndarray
    normal: np.ndarray
    basis: np.ndarray
    loops: tuple[Loop, ...]

    def to_uv(self, p: np.ndarray) -> np.ndarray:
        return (np.asarray(p, dtype=np.float64) - self.origin) @ self.basis.T

    def to_xyz(self, uv: np.ndarray) -> np.ndarray:
        return self.origin + np.asarray(uv, dtype=np.float64) @ self.basis


def plane_basis(normal: np.ndarray) -> np.ndarray:
    """(2, 3) orthonormal in-plane axes; the first is as close to +X as possible."""
    n = np.asarray(normal, dtype=np.float64)
    n = n / np.linalg.norm(n)
    ref = np.array([1.0, 0.0, 0.0]) if abs(n[0]) < 0.9 else np.array([0.0, 0.0, 1.0])
    u = ref - n * np.dot(ref, n)
    u /= np.linalg.norm(u)
    return np.stack([u, np.cross(n, u)])


class SlabIndex:
    """Faces bucketed by height, so horizontal cuts only look at nearby faces.

    Parameters
    ----------
    vertices : (V, 3) float64, cm
    faces : (F, 3) int64
    axis : coordinate index of the slabs (1 = y)
    slab_cm : slab thickness
    """

    def __init__(
        self,
        vertices: np.ndarray,
        faces: np.ndarray,
        axis: int = 1,
        slab_cm: float = 1.0,
    ) -> None:
        h = vertices[faces, axis]
        self.lo = float(h.min())
        self.slab_cm = slab_cm
        first = np.floor((h.min(axis=1) - self.lo) / slab_cm).astype(np.int64)
        last = np.floor((h.max(axis=1) - self.lo) / slab_cm).astype(np.int64)
        count = last - first + 1
        face_ids = np.repeat(np.arange(len(faces)), count)
        slab = np.repeat(first, count) + (
            np.arange(count.sum()) - np.repeat(np.cumsum(count) - count, count)
        )
        order = np.argsort(slab, kind="stable")
        self.face_ids = face_ids[order]
        slab = slab[order]
        self.n_slabs = int(last.max()) + 1
        self.n_faces = len(faces)
        self.starts = np.searchsorted(slab, np.arange(self.n_slabs + 1))

    def faces_between(self, lo: float, hi: float) -> np.ndarray:
        """Ids of the faces in the slabs covering heights lo..hi (unique)."""
        k0 = max(int(np.floor((lo - self.lo) / self.slab_cm)), 0)
        k1 = min(int(np.floor((hi - self.lo) / self.slab_cm)), self.n_slabs - 1)
        if k1 < k0:
            return np.zeros(0, dtype=np.int64)
        mark = np.zeros(self.n_faces, dtype=bool)
        mark[self.face_ids[self.starts[k0] : self.starts[k1 + 1]]] = True
        return np.flatnonzero(mark)

    def faces_at(self, level: float) -> np.ndarray:
        k = int(np.floor((level - self.lo) / self.slab_cm))
        if k < 0 or k >= self.n_slabs:
            return np.zeros(0, dtype=np.int64)
        return self.face_ids[self.starts[k] : self.starts[k + 1]]


def plane_loops(
    vertices: np.ndarray,
    faces: np.ndarray,
    origin: np.ndarray,
    normal: np.ndarray,
    *,
    candidates: np.ndarray | None = None,
) -> Section:
    """Cut the mesh with a plane and split the cut into connected loops.

    Parameters
    ----------
    vertices : (V, 3) float64, cm
    faces : (F, 3) int64
    origin : (3,) a point of the plane
    normal : (3,) plane normal (any length)
    candidates : optional face ids to consider (others are known not to cross)

    Returns
    -------
    Section; a vertex lying exactly on the plane counts as above it, so every
    crossing face contributes exactly one segment.
    """
    origin = np.asarray(origin, dtype=np.float64)
    n = np.asarray(normal, dtype=np.float64)
    n = n / np.linalg.norm(n)
    basis = plane_basis(n)
    f = faces if candidates is None else faces[candidates]
    d_f = (vertices[f] - origin) @ n  # (F', 3)
    above = d_f >= 0
    n_above = above.sum(axis=1)
    cross = (n_above == 1) | (n_above == 2)
    f, d_f, above = f[cross], d_f[cross], above[cross]
    if len(f) == 0:
        return Section(origin=origin, normal=n, basis=basis, loops=())
    # the odd corner (alone on its side) and the two others
    odd_is_above = n_above[cross] == 1
    lone = np.where(odd_is_above, np.argmax(above, axis=1), np.argmin(above, axis=1))
    i0 = f[np.arange(len(f)), lone]
    i1 = f[np.arange(len(f)), (lone + 1) % 3]
    i2 = f[np.arange(len(f)), (lone + 2) % 3]
    # edge keys of the two cut edges
    n_v = len(vertices)
    e1 = np.minimum(i0, i1) * n_v + np.maximum(i0, i1)
    e2 = np.minimum(i0, i2) * n_v + np.maximum(i0, i2)
    keys, inverse = np.unique(np.concatenate([e1, e2]), return_inverse=True)
    a = keys // n_v
    b = keys % n_v
    da = (vertices[a] - origin) @ n
    db = (vertices[b] - origin) @ n
    t = da / np.where(da - db == 0, 1.0, da - db)
    pts = vertices[a] + t[:, None] * (vertices[b] - vertices[a])
    seg = inverse.reshape(2, -1).T
    # connected components of the cut graph
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    m = len(keys)
    graph = coo_matrix((np.ones(len(seg)), (seg[:, 0], seg[:, 1])), shape=(m, m))
    n_comp, label = connected_components(graph, directed=False)
    uv = (pts - origin) @ basis.T
    order = np.argsort(label, kind="stable")
    bounds = np.searchsorted(label[order], np.arange(n_comp + 1))
    local = np.zeros(m, dtype=np.int64)
    local[order] = np.arange(m) - np.repeat(bounds[:-1], np.diff(bounds))
    seg_label = label[seg[:, 0]]
    seg_order = np.argsort(seg_label, kind="stable")
    seg_bounds = np.searchsorted(seg_label[seg_order], np.arange(n_comp + 1))
    loops = []
    for c in range(n_comp):
        idx = order[bounds[c] : bounds[c + 1]]
        s = seg[seg_order[seg_bounds[c] : seg_bounds[c + 1]]]
        loops.append(Loop(points=pts[idx], uv=uv[idx], segments=local[s]))
    return Section(origin=origin, normal=n, basis=basis, loops=tuple(loops))


def hull_girth(section: Section, loops) -> tuple[float, np.ndarray]:
    """Perimeter of the convex hull of the given loops and the closed hull polyline.

    Returns
    -------
    girth : float, cm
    polyline : (k + 1, 3) float64, the hull corners in 3D, first repeated last
    """
    from scipy.spatial import ConvexHull, QhullError

    uv = np.concatenate([lp.uv for lp in loops])
    if len(uv) < 3:
        return 0.0, section.to_xyz(uv)
    try:
        hull = ConvexHull(uv)
    except QhullError:
        return 0.0, section.to_xyz(uv)
    ring = uv[np.append(hull.vertices, hull.vertices[0])]
    girth = float(np.sum(np.linalg.norm(np.diff(ring, axis=0), axis=1)))
    return girth, section.to_xyz(ring)
