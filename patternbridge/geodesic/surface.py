"""The prepared surface: edge graph, vertex-face incidence, tangent planes.

:class:`SurfaceMesh` does the per-mesh work once so that many paths can be
measured on one character. Everything is vectorised and most of it is lazy:
constructing the object validates and welds; the edge graph is built on the
first path, tangent planes are computed only for the vertices a path needs.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from ..errors import MeshError

__all__ = ["SurfaceMesh", "SurfacePoint"]

log = logging.getLogger(__name__)

# a face whose area is below this fraction of (mean edge length)^2 is degenerate
_AREA_EPS = 1e-12


@dataclass(frozen=True, slots=True, kw_only=True)
class SurfacePoint:
    """A point on the surface: a vertex, or a face with barycentric coordinates.

    vertex_id : int or None, the vertex the point sits on
    face : int or None, the face holding the point (when ``vertex_id`` is None)
    bary : (b0, b1, b2) floats summing to 1, weights of ``faces[face]``
    """

    vertex_id: int | None = None
    face: int | None = None
    bary: tuple[float, float, float] | None = None

    def __post_init__(self) -> None:
        if self.vertex_id is None and (self.face is None or self.bary is None):
            raise MeshError(
                "surface point: neither a vertex nor a face with barycentric "
                "coordinates was given; use SurfacePoint.vertex(i) or "
                "SurfacePoint(face=f, bary=(b0, b1, b2))"
            )
        if self.vertex_id is not None:
            object.__setattr__(self, "vertex_id", int(self.vertex_id))
        if self.bary is not None:
            b = tuple(float(x) for x in self.bary)
            s = sum(b)
            if len(b) != 3 or not np.all(np.isfinite(b)) or abs(s) < 1e-12:
                raise MeshError(
                    f"surface point: barycentric coordinates {self.bary!r} are not "
                    "three finite weights with a non-zero sum; pass (b0, b1, b2)"
                )
            object.__setattr__(self, "bary", (b[0] / s, b[1] / s, b[2] / s))
            object.__setattr__(self, "face", int(self.face))

    @classmethod
    def vertex(cls, i: int) -> SurfacePoint:
        """The point at vertex ``i``."""
        return cls(vertex_id=int(i))


class SurfaceMesh:
    """A triangle mesh prepared for geodesic queries.

    Parameters
    ----------
    vertices : (V, 3) float64, cm
    faces : (F, 3) int64
    weld : bool
        Merge vertices at exactly the same position (split seams) so that paths
        can cross them. Vertex ids keep their meaning: a welded vertex is
        represented by the lowest id at its position.

    Raises
    ------
    MeshError
        Wrong shapes, non-finite coordinates, face indices out of range, or no
        face with a non-zero area.

    Notes
    -----
    Zero-area faces are kept in ``faces`` but take no part in paths; edges
    shared by more than two faces (non-manifold) are walked around, never
    through. Connected components are found lazily and a path between two of
    them raises :class:`MeshError`.
    """

    __slots__ = (
        "_cache",
        "degenerate",
        "face_normals",
        "faces",
        "n_faces",
        "n_vertices",
        "rep",
        "vertices",
    )

    def __init__(self, vertices, faces, *, weld: bool = True) -> None:
        try:
            v = np.array(vertices, dtype=np.float64)
            f = np.array(faces, dtype=np.int64)
        except (TypeError, ValueError) as exc:
            raise MeshError(
                f"mesh: vertices/faces are not numeric arrays ({exc}); "
                "pass (V, 3) floats and (F, 3) ints"
            ) from None
        if v.ndim != 2 or v.shape[1] != 3 or len(v) < 3:
            raise MeshError(
                f"mesh: vertices must be (V, 3) with V >= 3 (got {v.shape}); "
                "pass an (V, 3) float array in cm"
            )
        if f.ndim != 2 or f.shape[1] != 3 or len(f) < 1:
            raise MeshError(
                f"mesh: faces must be (F, 3) triangles (got {f.shape}); "
                "triangulate the mesh first"
            )
        if not np.all(np.isfinite(v)):
            raise MeshError(
                f"mesh: {int((~np.isfinite(v)).any(axis=1).sum())} vertices "
                "have NaN or infinite coordinates; repair the mesh"
            )
        if f.min() < 0 or f.max() >= len(v):
            raise MeshError(
                f"mesh: face indices out of range (min {f.min()}, max {f.max()}, "
                f"{len(v)} vertices); check the face list"
            )
        self.n_vertices = len(v)
        self.n_faces = len(f)
        self._cache: dict = {}
        rep = _weld_map(v) if weld else np.arange(len(v), dtype=np.int64)
        self.rep = rep
        fw = rep[f]
        v.flags.writeable = False
        fw.flags.writeable = False
        self.vertices = v
        self.faces = fw
        # column gathers and products: several times faster than row gathers
        # and np.cross on (F, 3)
        f0, f1, f2 = (np.ascontiguousarray(fw[:, c]) for c in range(3))
        e1 = []
        e2 = []
        for c in range(3):
            col = np.ascontiguousarray(v[:, c])
            base = col[f0]
            e1.append(col[f1] - base)
            e2.append(col[f2] - base)
        cr = np.empty((len(fw), 3))
        cr[:, 0] = e1[1] * e2[2] - e1[2] * e2[1]
        cr[:, 1] = e1[2] * e2[0] - e1[0] * e2[2]
        cr[:, 2] = e1[0] * e2[1] - e1[1] * e2[0]
        dbl_area = np.sqrt(np.einsum("ij,ij->i", cr, cr))
        scale = float(np.mean(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2])) or 1.0
        del e1, e2
        degenerate = (
            (dbl_area <= _AREA_EPS * scale) | (f0 == f1) | (f1 == f2) | (f0 == f2)
        )
        if degenerate.all():
            raise MeshError(
                f"mesh: all {len(f)} faces have zero area; "
                "the mesh has no usable surface"
            )
        inv = np.divide(1.0, dbl_area, out=np.zeros_like(dbl_area), where=~degenerate)
        fn = cr
        fn *= inv[:, None]
        degenerate.flags.writeable = False
        fn.flags.writeable = False
        self.degenerate = degenerate
        self.face_normals = fn
        if degenerate.any():
            log.info("mesh: %d zero-area faces ignored", int(degenerate.sum()))

    # ------------------------------------------------------------------ graph
    def _build_graph(self) -> None:
        # few, in-place temporaries: on a 334K-vertex mesh the cost of this
        # function is mostly first-touch page faults of fresh arrays
        f = self.faces if not self.degenerate.any() else self.faces[~self.degenerate]
        n = self.n_vertices
        shift = max(int(n).bit_length(), 1)
        a = f.ravel()
        b = f[:, [1, 2, 0]].ravel()
        fwd = a << shift
        fwd |= b
        fwd.sort()
        rev = b << shift
        rev |= a
        rev.sort()
        if np.array_equal(fwd, rev) and not np.any(fwd[1:] == fwd[:-1]):
            key = fwd  # closed, consistently wound: half-edges already pair up
        else:
            key = np.sort(np.concatenate([fwd, rev]))
            keep = np.ones(len(key), dtype=bool)
            keep[1:] = key[1:] != key[:-1]
            key = key[keep]
        del rev, b
        src = key >> shift
        key &= (1 << shift) - 1
        dst = key
        v = self.vertices
        w = np.zeros(len(dst))
        for c in range(3):  # column gathers are much faster than row gathers
            col = np.ascontiguousarray(v[:, c])
            d = col[src]
            d -= col[dst]
            d *= d
            w += d
        np.sqrt(w, out=w)
        np.maximum(w, 1e-12, out=w)  # a zero weight would read as "no edge"
        indptr = np.zeros(n + 1, dtype=np.int64)
        np.cumsum(np.bincount(src, minlength=n), out=indptr[1:])
        graph = sp.csr_matrix(
            (w, dst.astype(np.int32), indptr.astype(np.int32)), shape=(n, n)
        )
        self._cache["graph"] = graph
        self._cache["edge_max"] = float(w.max()) if len(w) else 0.0
        self._cache["edge_mean"] = float(w.mean()) if len(w) else 0.0

    @property
    def graph(self) -> sp.csr_matrix:
        """Symmetric (V, V) CSR matrix of edge lengths, cm (usable faces only)."""
        if "graph" not in self._cache:
            self._build_graph()
        return self._cache["graph"]

    @property
    def edge_max(self) -> float:
        """Longest edge, cm."""
        if "graph" not in self._cache:
            self._build_graph()
        return self._cache["edge_max"]

    @property
    def edge_mean(self) -> float:
        """Mean edge length, cm."""
        if "graph" not in self._cache:
            self._build_graph()
        return self._cache["edge_mean"]

    @property
    def vertex_faces(self) -> tuple[np.ndarray, np.ndarray]:
        """CSR ``(indptr (V+1,), faces)`` of the usable faces around each vertex."""
        if "vf" not in self._cache:
            m = max(self.n_faces, 1)
            if self.degenerate.any():
                good = np.flatnonzero(~self.degenerate)
                key = self.faces[good].ravel() * m
                key += np.repeat(good, 3)
            else:
                key = self.faces.ravel() * m
                key += np.repeat(np.arange(self.n_faces, dtype=np.int64), 3)
            key.sort()
            vs = key // m
            key -= vs * m
            indptr = np.zeros(self.n_vertices + 1, dtype=np.int64)
            np.cumsum(np.bincount(vs, minlength=self.n_vertices), out=indptr[1:])
            self._cache["vf"] = (indptr, key)
        return self._cache["vf"]

    @property
    def components(self) -> np.ndarray:
        """(V,) int64 connected-component label of each vertex."""
        if "comp" not in self._cache:
            from scipy.sparse.csgraph import connected_components

            _, lab = connected_components(self.graph, directed=False)
            self._cache["comp"] = lab.astype(np.int64)
        return self._cache["comp"]

    @property
    def neighbour_table(self) -> np.ndarray:
        """(V, D) int64 one-ring neighbours, rows padded with the vertex itself."""
        if "nbt" not in self._cache:
            g = self.graph
            deg = np.diff(g.indptr)
            d = int(deg.max()) if len(deg) else 0
            tab = np.repeat(
                np.arange(self.n_vertices, dtype=np.int64)[:, None], max(d, 1), axis=1
            )
            rows = np.repeat(np.arange(self.n_vertices), deg)
            cols = np.arange(len(rows)) - np.repeat(g.indptr[:-1], deg)
            tab[rows, cols] = g.indices
            self._cache["nbt"] = tab
        return self._cache["nbt"]

    @property
    def all_vertex_normals(self) -> np.ndarray:
        """(V, 3) float64 tangent-plane normals of every vertex (cached)."""
        if "vn" not in self._cache:
            self._cache["vn"] = self._pca_normals(np.arange(self.n_vertices))
        return self._cache["vn"]

    def faces_of(self, v: int) -> np.ndarray:
        """Usable faces around vertex ``v`` (int64 array)."""
        indptr, fl = self.vertex_faces
        return fl[indptr[v] : indptr[v + 1]]

    # ---------------------------------------------------------- tangent planes
    def vertex_normals(self, vids) -> np.ndarray:
        """Tangent-plane normals of vertices ``vids`` by PCA of one-ring face normals.

        Parameters
        ----------
        vids : (n,) int

        Returns
        -------
        (n, 3) float64 unit normals: the principal direction of the area-weighted
        scatter of the surrounding face normals, oriented like their mean.

        Notes
        -----
        Computed once per vertex and kept: the flow asks for the same vertices
        at every outer iteration, and paths on one character share vertices.
        """
        vids = np.asarray(vids, dtype=np.int64)
        if "vn" in self._cache:
            return self._cache["vn"][vids]
        if "vn_some" not in self._cache:
            self._cache["vn_some"] = (
                np.zeros((self.n_vertices, 3)),
                np.zeros(self.n_vertices, dtype=bool),
            )
        known, have = self._cache["vn_some"]
        miss = vids[~have[vids]]
        if len(miss):
            miss = np.unique(miss)
            known[miss] = self._pca_normals(miss)
            have[miss] = True
        return known[vids]

    def _pca_normals(self, vids: np.ndarray) -> np.ndarray:
        indptr, fl = self.vertex_faces
        counts = indptr[vids + 1] - indptr[vids]
        owner = np.repeat(np.arange(len(vids)), counts)
        starts = np.repeat(indptr[vids], counts)
        within = np.arange(len(owner)) - np.repeat(np.cumsum(counts) - counts, counts)
        fidx = fl[starts + within]
        nrm = self.face_normals[fidx]
        outer = (nrm[:, :, None] * nrm[:, None, :]).reshape(-1, 9)
        # each vertex's faces are contiguous: segment sums (np.add.at is slow)
        lonely = counts == 0
        if len(nrm):
            first = np.minimum(np.cumsum(counts) - counts, len(nrm) - 1)
            both = np.add.reduceat(np.hstack([outer, nrm]), first, axis=0)
            both[lonely] = 0.0
        else:
            both = np.zeros((len(vids), 12))
        scatter, mean = both[:, :9], both[:, 9:]
        _, vecs = np.linalg.eigh(scatter.reshape(-1, 3, 3) + 1e-15 * np.eye(3))
        n = vecs[:, :, 2]
        sign = np.sign(np.einsum("ij,ij->i", n, mean))
        sign[sign == 0] = 1.0
        n = n * sign[:, None]
        if lonely.any():
            n[lonely] = (0.0, 0.0, 1.0)
        return n

    # --------------------------------------------------------------- points
    def point_position(self, p: SurfacePoint) -> np.ndarray:
        """(3,) float64 position, cm, of a surface point."""
        if p.vertex_id is not None:
            return self.vertices[p.vertex_id].copy()
        return np.asarray(p.bary) @ self.vertices[self.faces[p.face]]

    def check_point(self, p, name: str) -> SurfacePoint:
        """Coerce ``p`` (int or SurfacePoint) and check it against this mesh."""
        if isinstance(p, (int, np.integer)):
            p = SurfacePoint.vertex(int(p))
        if not isinstance(p, SurfacePoint):
            raise MeshError(
                f"{name}: expected a vertex id or SurfacePoint, got "
                f"{type(p).__name__}; pass an int or SurfacePoint"
            )
        if p.vertex_id is not None:
            if not 0 <= p.vertex_id < self.n_vertices:
                raise MeshError(
                    f"{name}: vertex {p.vertex_id} out of range "
                    f"(0..{self.n_vertices - 1}); pick a vertex of this mesh"
                )
            r = int(self.rep[p.vertex_id])
            return p if r == p.vertex_id else SurfacePoint.vertex(r)
        if not 0 <= p.face < self.n_faces:
            raise MeshError(
                f"{name}: face {p.face} out of range "
                f"(0..{self.n_faces - 1}); pick a face of this mesh"
            )
        b = np.asarray(p.bary)
        if b.min() < -1e-9:
            raise MeshError(
                f"{name}: barycentric coordinates {p.bary} leave the face "
                "(negative weight); pass weights >= 0"
            )
        k = int(np.argmax(b))
        if b[k] > 1 - 1e-12 or self.degenerate[p.face]:
            return SurfacePoint.vertex(int(self.faces[p.face, k]))
        return p


def _weld_map(v: np.ndarray) -> np.ndarray:
    """(V,) int64 map to the lowest vertex id at exactly the same position."""
    n = len(v)
    rep = np.arange(n, dtype=np.int64)
    x = np.ascontiguousarray(v[:, 0])
    xs = np.sort(x)
    if not np.any(xs[1:] == xs[:-1]):  # no two vertices share even an x
        return rep
    order = np.argsort(x)  # ties are grouped whatever the order among them
    xs = x[order]
    tie = np.zeros(n, dtype=bool)
    tie[1:] = xs[1:] == xs[:-1]
    tie[:-1] |= tie[1:]
    cand = order[tie]
    if len(cand) == 0:
        return rep
    _, inv = np.unique(v[cand], axis=0, return_inverse=True)
    inv = inv.ravel()
    first = np.full(inv.max() + 1, n, dtype=np.int64)
    np.minimum.at(first, inv, cand)
    rep[cand] = first[inv]
    return rep
