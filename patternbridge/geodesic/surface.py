"""The prepared surface: face corners, vertex grid, tangent planes, edge graph.

:class:`SurfaceMesh` does the per-mesh work once so that many paths can be
measured on one character. Everything is vectorised and most of it is lazy:
constructing the object validates, welds and computes face normals and edge
statistics; the corner lists (faces and neighbours of every vertex, one sort)
and the vertex grid are built on the first path; tangent planes are computed
only for the vertices a path needs; the full symmetric edge graph only when
asked for (the single-source propagation uses it, point-to-point paths search
sub-graphs built from the corner lists).
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
# offset from a face corner (3 f + k) to the next / previous corner of face f
_NEXT = np.array([1, 1, -2], dtype=np.int64)
_PREV = np.array([2, -1, -1], dtype=np.int64)
#: bits of the (vertex, corner, next vertex) sort keys; wider keys are split
_PACK_BITS = 63
#: cells of the vertex grid used to pick the vertices near a segment
_GRID_CELLS = 1 << 15


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
        "__weakref__",
        "_cache",
        "_edge_stats",
        "_normal_cols",
        "degenerate",
        "faces",
        "n_faces",
        "n_vertices",
        "rep",
        "vertices",
    )

    def __init__(self, vertices, faces, *, weld: bool = True) -> None:
        try:
            v = np.array(vertices, dtype=np.float64)
            f = np.asarray(faces)
            if f.dtype != np.int64:
                f = f.astype(np.int64)  # a copy: ours
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
        if not np.isfinite(v.sum()) and not np.all(np.isfinite(v)):
            raise MeshError(
                f"mesh: {int((~np.isfinite(v)).any(axis=1).sum())} vertices "
                "have NaN or infinite coordinates; repair the mesh"
            )
        fmin, fmax = int(f.min()), int(f.max())
        if fmin < 0 or fmax >= len(v):
            raise MeshError(
                f"mesh: face indices out of range (min {fmin}, max {fmax}, "
                f"{len(v)} vertices); check the face list"
            )
        self.n_vertices = len(v)
        self.n_faces = len(f)
        self._cache: dict = {}
        rep = _weld_map(v) if weld else None
        if rep is None or not np.any(rep != np.arange(len(v))):
            rep = np.arange(len(v), dtype=np.int64)
            fw = np.array(f, dtype=np.int64, order="C")  # never the caller's
        else:
            fw = rep[f]
        self.rep = rep
        v.flags.writeable = False
        fw.flags.writeable = False
        self.vertices = v
        self.faces = fw
        cols, degenerate, sides = _face_geometry(v, fw)
        if degenerate.all():
            raise MeshError(
                f"mesh: all {len(f)} faces have zero area; "
                "the mesh has no usable surface"
            )
        self._edge_stats = _edge_stats(sides, degenerate)
        self._cache["sides"] = sides  # until the corner lists take them
        degenerate.flags.writeable = False
        self.degenerate = degenerate
        self._normal_cols = cols
        if degenerate.any():
            log.info("mesh: %d zero-area faces ignored", int(degenerate.sum()))

    @property
    def face_normals(self) -> np.ndarray:
        """(F, 3) float64 unit face normals; zero rows for zero-area faces."""
        fn = self._cache.get("fn")
        if fn is None:
            fn = np.zeros((self.n_faces, 3))
            for c in range(3):
                fn[:, c] = self._normal_cols[c]
            fn.flags.writeable = False
            self._cache["fn"] = fn
        return fn

    def normals_of(self, fids) -> np.ndarray:
        """(k, 3) float64 unit normals of faces ``fids`` (no (F, 3) table needed)."""
        if "fn" in self._cache:
            return self._cache["fn"][fids]
        out = np.zeros((len(fids), 3))
        for c in range(3):
            out[:, c] = self._normal_cols[c][fids]
        return out

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

    @property
    def graph(self) -> sp.csr_matrix:
        """Symmetric (V, V) CSR matrix of edge lengths, cm (usable faces only)."""
        if "graph" not in self._cache:
            self._build_graph()
        return self._cache["graph"]

    @property
    def edge_max(self) -> float:
        """Longest edge of a usable face, cm."""
        return self._edge_stats[0]

    @property
    def edge_mean(self) -> float:
        """Mean edge length, cm, over the sides of the usable faces (an edge
        counts once for each usable face it bounds)."""
        return self._edge_stats[1]

    @property
    def corners(self) -> tuple[np.ndarray, np.ndarray]:
        """CSR ``(indptr (V+1,), corners)`` of the usable face corners at each vertex.

        A corner is ``3 * face + k`` (the k-th corner of ``faces[face]``), so
        ``faces.ravel()[corner]`` is the vertex itself and the corners after it
        give its neighbours. Sorted by vertex, then by face. Built on first use
        by one sort of packed (vertex, corner) keys.
        """
        if "corners" not in self._cache:
            self._build_corners()
        return self._cache["corners"]

    def _build_corners(self) -> None:
        nf3 = 3 * self.n_faces
        n = self.n_vertices
        deg = self.degenerate.any()
        if deg:
            good = np.flatnonzero(~self.degenerate)
            j = (good[:, None] * 3 + np.arange(3)).ravel()
            key = self.faces[good].ravel()
            nxt = self.faces[good][:, [1, 2, 0]].ravel()
        else:
            j = np.arange(nf3, dtype=np.int64)
            key = self.faces.ravel().copy()
            nxt = self.faces[:, [1, 2, 0]].ravel()
        sj = max(int(nf3).bit_length(), 1)
        sv = max(int(n).bit_length(), 1)
        packed = sv + sj + sv <= _PACK_BITS
        # sort (vertex, corner) keys; when the bits allow, the next vertex
        # rides along in the low bits and needs no gather afterwards
        low = sj + sv if packed else sj
        key <<= low
        if packed:
            j <<= sv
            key |= nxt
        key |= j
        del j
        key.sort()
        vs = key >> low
        indptr = np.zeros(n + 1, dtype=np.int64)
        np.cumsum(np.bincount(vs, minlength=n), out=indptr[1:])
        del vs
        if packed:
            nxt = key & ((1 << sv) - 1)
            key >>= sv
            key &= (1 << sj) - 1
        else:
            key &= (1 << sj) - 1
            nxt = key % 3
            nxt = _NEXT[nxt]
            nxt += key
            nxt = self.faces.ravel()[nxt]
        sides = self._cache.pop("sides", None)
        if sides is None:
            sides = self._side_lengths()
        length = sides.ravel()[key]
        del sides
        for a in (key, indptr, nxt, length):
            a.flags.writeable = False
        self._cache["corners"] = (indptr, key)
        self._cache["next"] = nxt
        self._cache["length"] = length

    def _side_lengths(self) -> np.ndarray:
        """(F, 3) float64, cm: side k of each face, from corner k to k + 1."""
        v = self.vertices
        out = np.zeros((self.n_faces, 3))
        for k in range(3):
            a = self.faces[:, k]
            b = self.faces[:, (k + 1) % 3]
            for c in range(3):
                col = v[:, c]
                d = col[b] - col[a]
                d *= d
                out[:, k] += d
        return np.sqrt(out, out=out)

    @property
    def corner_next(self) -> np.ndarray:
        """(C,) int64, aligned with :attr:`corners`: the vertex after each
        corner's vertex in its face (the far end of its outgoing half-edge)."""
        if "next" not in self._cache:
            self._build_corners()
        return self._cache["next"]

    def ring_entries(
        self, vids, *, prev: bool = True, lengths: bool = False
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
        """The face corners around vertices ``vids`` and the vertices after them.

        Parameters
        ----------
        vids : (n,) int

        Returns
        -------
        counts : (n,) int64, usable faces around each vertex
        nxt : (sum(counts),) int64, the vertex after ``vids[i]`` in each of its
            faces (in face order, ``vids[0]``'s first)
        prv : (sum(counts),) int64, the vertex before it (None unless ``prev``);
            with ``lengths``, instead the (sum(counts),) float64 lengths, cm,
            of the edges to ``nxt``

        Notes
        -----
        ``nxt`` and ``prv`` together hold every one-ring neighbour; on a closed,
        consistently wound mesh each of them alone does, once per edge.
        """
        indptr, cor = self.corners
        vids = np.asarray(vids, dtype=np.int64)
        starts = indptr[vids]
        counts = indptr[vids + 1] - starts
        idx = np.repeat(starts - np.cumsum(counts) + counts, counts)
        idx += np.arange(len(idx))
        nxt = self.corner_next[idx]
        if lengths:
            return counts, nxt, self._cache["length"][idx]
        if not prev:
            return counts, nxt, None
        j = cor[idx]
        j += _PREV[j % 3]
        return counts, nxt, self.faces.ravel()[j]

    def box_vertices(self, lo, hi, cell_test=None):
        """Vertices in the grid cells that overlap the box ``[lo, hi]``.

        Parameters
        ----------
        lo, hi : (3,) float, cm
        cell_test : optional callable ``(centres (k, 3), margin) -> (k,) bool``
            keeping only the cells that may hold wanted vertices (``margin``:
            the distance from a cell centre to its corners, cm)

        Returns
        -------
        ids : (k,) int64 vertex ids, every vertex inside the box (of the cells
            kept) and some near it
        xyz : tuple of three (k,) float64 coordinate columns, cm

        Notes
        -----
        The grid (about 2^15 cubic cells over the bounding box, vertices sorted
        by cell) is built on first use.
        """
        grid = self._cache.get("grid")
        if grid is None:
            grid = self._cache["grid"] = _cell_grid(self.vertices)
        origin, h, dims, start, order, cols = grid
        lo = np.asarray(lo, dtype=np.float64)
        hi = np.asarray(hi, dtype=np.float64)
        i0 = np.clip(np.floor((lo - origin) / h), 0, dims - 1).astype(np.int64)
        i1 = np.clip(np.floor((hi - origin) / h), -1, dims - 1).astype(np.int64)
        ix, iy, iz = (np.arange(i0[c], i1[c] + 1) for c in range(3))
        cells = (
            (ix[:, None, None] * dims[1] + iy[None, :, None]) * dims[2]
            + iz[None, None, :]
        ).ravel()
        s = start[cells]
        cnt = start[cells + 1] - s
        if cell_test is not None and len(cells):
            busy = cnt > 0
            c3 = np.stack(
                np.broadcast_arrays(
                    ix[:, None, None], iy[None, :, None], iz[None, None, :]
                ),
                axis=-1,
            ).reshape(-1, 3)[busy]
            centres = origin + (c3 + 0.5) * h
            ok = np.zeros(len(cells), dtype=bool)
            ok[busy] = cell_test(centres, 0.5 * np.sqrt(3.0) * h)
            s, cnt = s[ok], cnt[ok]
        idx = np.repeat(s - np.cumsum(cnt) + cnt, cnt)
        idx += np.arange(len(idx))
        return order[idx], tuple(c[idx] for c in cols)

    @property
    def vertex_faces(self) -> tuple[np.ndarray, np.ndarray]:
        """CSR ``(indptr (V+1,), faces)`` of the usable faces around each vertex."""
        if "vf" not in self._cache:
            indptr, cor = self.corners
            fl = cor // 3
            fl.flags.writeable = False
            self._cache["vf"] = (indptr, fl)
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
        nrm = self.normals_of(fidx)
        outer = (nrm[:, :, None] * nrm[:, None, :]).reshape(-1, 9)
        # each vertex's faces are contiguous: segment sums (np.add.at is slow)
        lonely = counts == 0
        both = np.zeros((len(vids), 12))
        if len(nrm):
            first = (np.cumsum(counts) - counts)[~lonely]  # strictly increasing
            both[~lonely] = np.add.reduceat(np.hstack([outer, nrm]), first, axis=0)
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
    order = np.argsort(x)  # ties are grouped whatever the order among them
    xs = x[order]
    if not np.any(xs[1:] == xs[:-1]):  # no two vertices share even an x
        return rep
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


def _face_geometry(v: np.ndarray, fw: np.ndarray):
    """Unit normal columns (3 x (F,)), the zero-area mask (F,) and the side
    lengths (F, 3), cm (None when every face has zero area) of ``fw`` over ``v``.

    Column gathers and in-place products on contiguous columns: several times
    faster than row gathers and ``np.cross`` on (F, 3).
    """
    f0, f1, f2 = fw[:, 0], fw[:, 1], fw[:, 2]
    e1 = []
    e2 = []
    e12 = []
    for c in range(3):
        col = np.ascontiguousarray(v[:, c])
        base = col[f0]
        a = col[f1]
        b = col[f2]
        e12.append(b - a)  # written out, not e2 - e1: exact side lengths
        a -= base
        b -= base
        e1.append(a)
        e2.append(b)
    del base
    nc = []
    for c in range(3):
        i, k = (c + 1) % 3, (c + 2) % 3
        t = e1[i] * e2[k]
        t -= e1[k] * e2[i]
        nc.append(t)
    dbl_area = nc[0] * nc[0]
    dbl_area += nc[1] * nc[1]
    dbl_area += nc[2] * nc[2]
    np.sqrt(dbl_area, out=dbl_area)
    l01 = e1[0] * e1[0]
    l01 += e1[1] * e1[1]
    l01 += e1[2] * e1[2]
    scale = float(np.mean(l01)) or 1.0
    degenerate = dbl_area <= _AREA_EPS * scale
    degenerate |= f0 == f1
    degenerate |= f1 == f2
    degenerate |= f0 == f2
    inv = np.divide(1.0, dbl_area, out=dbl_area, where=~degenerate)
    inv[degenerate] = 0.0
    for t in nc:
        t *= inv
    if degenerate.all():
        return tuple(nc), degenerate, None
    l02 = e2[0] * e2[0]
    l02 += e2[1] * e2[1]
    l02 += e2[2] * e2[2]
    l12 = inv  # reuse
    l12[:] = 0.0
    for d in e12:
        d *= d
        l12 += d
    for t in nc:
        t.flags.writeable = False
    # side lengths, cm, in corner order: side k runs from corner k to k + 1
    sides = np.zeros((len(fw), 3))
    for k, sq in enumerate((l01, l12, l02)):
        np.sqrt(sq, out=sq)
        sides[:, k] = sq
    return tuple(nc), degenerate, sides


def _edge_stats(sides: np.ndarray, degenerate: np.ndarray) -> tuple[float, float]:
    """(longest, mean) side length, cm, of the usable faces."""
    good = sides[~degenerate] if degenerate.any() else sides
    top = float(good.max())
    mean = (
        float(good[:, 0].sum()) + float(good[:, 1].sum()) + float(good[:, 2].sum())
    ) / good.size
    return top, mean


def _cell_grid(v: np.ndarray):
    """A uniform grid over the bounding box of ``v`` (V, 3): origin (3,), cell
    size h, dims (3,) int, CSR start (cells + 1,), the vertex ids ordered by
    cell and their three coordinate columns in that order."""
    cols = [np.ascontiguousarray(v[:, c]) for c in range(3)]
    origin = np.array([c.min() for c in cols])
    ext = np.maximum(np.array([c.max() for c in cols]) - origin, 1e-9)
    h = float(np.cbrt(np.prod(ext) / _GRID_CELLS))
    h = max(h, float(ext.max()) / 256.0)
    dims = np.minimum((ext / h).astype(np.int64) + 1, 256)
    cell = np.zeros(len(v), dtype=np.int64)
    for c in range(3):
        i = cols[c] - origin[c]
        i /= h
        i = i.astype(np.int64)  # >= 0: truncation is floor
        np.minimum(i, dims[c] - 1, out=i)
        cell *= dims[c]
        cell += i
    n_cells = int(np.prod(dims))
    if n_cells <= 1 << 16:  # radix sort
        order = np.argsort(cell.astype(np.uint16), kind="stable")
    else:
        order = np.argsort(cell, kind="stable")
    start = np.zeros(n_cells + 1, dtype=np.int64)
    np.cumsum(np.bincount(cell, minlength=n_cells), out=start[1:])
    return origin, h, dims, start, order, tuple(c[order] for c in cols)
