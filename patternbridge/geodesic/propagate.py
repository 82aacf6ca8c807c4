"""Single source, all destinations: the wavefront propagation with curvature flow.

No priority queue: the wavefront grows in bands (each band accepts the
candidate vertices within 1.5 mean edge lengths of the nearest one, so the
radius limit follows the slowest part of the front; ``r_max`` stops it); a new
vertex takes the *straightest* path among its visited neighbours (the smallest
turn between the neighbour's path tangent and the edge towards the new vertex,
among neighbours whose distance estimate is close to the best) and extends it
by the edge; then the path is relaxed by the curvature flow.

* windowed form (``window=w``): only the last ``w`` samples of each path are
  re-solved, the rest is frozen, so each vertex costs a constant and the whole
  propagation is linear in the number of vertices. The windows of one band are
  independent: they are laid end to end and solved as one tridiagonal (or,
  with ``flow="lsq"``, block-tridiagonal) system, one LAPACK call per band.
* full form (``window="full"``): every path is re-solved whole by the
  least-squares flow (slow; small meshes only).

Two flows for the windows. ``flow="lateral"`` (default) keeps the rows of the
geodesic curvature only: each free sample moves in its tangent plane across
the path (along ``b_i = n_i x (p_{i+1} - p_{i-1})``, normalised) until
``b_i . ((p_{i+1} - p_i) / h_i - (p_i - p_{i-1}) / h_{i-1}) = 0``, so the
samples keep their places along the path (one unknown per sample).
``flow="lsq"`` solves both tangential rows of the least-squares system, which
also even out the spacing (two unknowns per sample); samples then slide along
the path and, where it turns round a fold (under the chin, in the armpit),
bridge the fold. The lateral form is both faster and more accurate (see
``docs/geodesic.md``).

``window=None`` (default) sizes the window from the mesh resolution: the
error comes from the kink where a window starts, so the window has to span a
length (``WINDOW_CM``), not a fixed number of samples.
"""

from __future__ import annotations

import logging
from collections.abc import Callable

import numpy as np
from scipy.linalg.lapack import dpbsv as _pbsv
from scipy.linalg.lapack import dptsv as _ptsv

from ..errors import MeshError, SolverError
from .surface import SurfaceMesh, SurfacePoint

__all__ = [
    "FLOWS",
    "WINDOW_CM",
    "auto_window",
    "geodesic_distances",
    "solve_lateral",
    "solve_windows",
]

log = logging.getLogger(__name__)

#: automatic windows span about this much path, cm
WINDOW_CM = 12.0
#: ... and have at least / at most this many samples
_WINDOW_MIN = 8
_WINDOW_MAX = 64
#: candidate parents: distance estimate within this many edge lengths of the best
_NEAR = 0.05
#: wavefront band: candidates this many mean edge lengths beyond the nearest are accepted
_BAND = 1.5
#: window rows kept at least (the buffer grows if the wavefront needs more)
_ROWS_MIN = 16384
#: the window flows
FLOWS = ("lateral", "lsq")


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Row-wise cross product of (..., 3) arrays (faster than ``np.cross``)."""
    out = np.zeros(np.broadcast_shapes(a.shape, b.shape))
    out[..., 0] = a[..., 1] * b[..., 2] - a[..., 2] * b[..., 1]
    out[..., 1] = a[..., 2] * b[..., 0] - a[..., 0] * b[..., 2]
    out[..., 2] = a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]
    return out


def _tangent_bases(normals: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Two unit tangent vectors per normal (..., 3) -> (..., 3), (..., 3)."""
    helper = np.where((np.abs(normals[..., 0]) < 0.9)[..., None], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0])
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
    two tangential rows per sample, ``2 u_i - T_i^T T_{i-1} u_{i-1} -
    T_i^T T_{i+1} u_{i+1} = T_i^T (b_{i-1} - 2 b_i + b_{i+1})`` (``b``: the
    anchors of free samples, the positions of fixed ones): a symmetric
    positive definite block-tridiagonal system (a discrete connection
    Laplacian with fixed ends). The windows are laid end to end as one banded
    matrix (bandwidth 3; fixed samples have identity rows, so the windows do
    not couple) and solved by one banded Cholesky call, in time linear in the
    number of samples.
    """
    B, w, _ = points.shape
    if tangents is None:
        t1, t2 = _tangent_bases(normals)
        tangents = np.stack([t1, t2], axis=-1)  # (B, w, 3, 2)
    S = B * w
    T = tangents.reshape(S, 3, 2)
    fr = free.reshape(S)
    base = np.where(fr[:, None], anchors_xyz.reshape(S, 3), points.reshape(S, 3))
    return _solve_stack(base, T, fr).reshape(B, w, 3)


def _solve_stack(base: np.ndarray, T: np.ndarray, fr: np.ndarray) -> np.ndarray:
    """Relaxed positions (S, 3), ``base + T u``, of samples laid end to end.

    ``base`` (S, 3) are the anchors of free samples and the positions of fixed
    ones, ``T`` (S, 3, 2) the tangent bases, ``fr`` (S,) the free mask; the first
    and last sample of every window must be fixed. Fixed samples get ``u = 0``.
    """
    S = len(base)
    lap = np.zeros((S, 3))
    lap[1:-1] = base[:-2] + base[2:]
    lap[1:-1] -= 2.0 * base[1:-1]
    rhs = np.einsum("ski,sk->si", T, lap)
    rhs *= fr[:, None]
    # C[s, a, b] = t_{s,a} . t_{s+1,b}, zero unless both samples are free
    C = np.einsum("ska,skb->sab", T[:-1], T[1:])
    C *= (fr[:-1] & fr[1:])[:, None, None]
    # lower band storage, unknowns interleaved (s, 0), (s, 1): ab[r, j] = M[j + r, j]
    ab = np.zeros((S, 2, 4))
    ab[:, :, 0] = np.where(fr, 2.0, 1.0)[:, None]
    ab[:-1, 1, 1] = -C[:, 1, 0]
    ab[:-1, 0, 2] = -C[:, 0, 0]
    ab[:-1, 1, 2] = -C[:, 1, 1]
    ab[:-1, 0, 3] = -C[:, 0, 1]
    abf = ab.reshape(2 * S, 4).T  # (4, 2S), Fortran order for LAPACK
    # ab is kept (LAPACK works on a copy): a failed factorisation leaves part
    # of its factor behind, and the fallback needs the matrix itself
    _, x, info = _pbsv(abf, rhs.reshape(2 * S, 1), lower=1, overwrite_ab=0, overwrite_b=1)
    if info != 0:  # not positive definite (degenerate bases): general banded LU
        from scipy.linalg import solve_banded

        full = np.zeros((7, 2 * S))
        full[3:] = ab.reshape(2 * S, 4).T
        for r in range(1, 4):  # mirror the lower band into the upper
            full[3 - r, r:] = full[3 + r, :-r]
        x = solve_banded((3, 3), full, rhs.reshape(2 * S))
    return base + np.einsum("ski,si->sk", T, x.reshape(S, 2))


def solve_lateral(points: np.ndarray, anchors_xyz: np.ndarray, normals: np.ndarray, free: np.ndarray) -> np.ndarray:
    """The lateral curvature flow on windows laid end to end.

    Parameters
    ----------
    points : (S, 3) float64, cm, samples of one or more windows, one after the
        other
    anchors_xyz : (S, 3) float64, a point of each sample's tangent plane
    normals : (S, 3) float64, unit tangent-plane normals
    free : (S,) bool, samples that may move; the first and last sample of
        every window must be fixed (so windows do not couple)

    Returns
    -------
    (S, 3) float64: each free sample projected onto its tangent plane and moved
    across the path only, ``p_i = base_i + b_i v_i`` with ``b_i`` the unit
    vector ``n_i x (base_{i+1} - base_{i-1})``, so that the path has no
    geodesic curvature, ``b_i . ((p_{i+1} - p_i) / h_i - (p_i - p_{i-1}) /
    h_{i-1}) = 0`` (``h``: the spacings of the projected samples); fixed
    samples are returned unchanged.

    Notes
    -----
    These are the geodesic-curvature rows of the least-squares flow
    (:func:`solve_windows` also keeps the rows along the path, which even out
    the spacing), divided by the spacing so that a straight path satisfies
    them however unevenly it is sampled. With one unknown per sample they
    form a symmetric, diagonally dominant tridiagonal matrix (off-diagonal
    ``-(b_i . b_{i+1}) / h_i``), solved for all windows by one LAPACK call
    (``dptsv``) in time linear in ``S``. The bases ``b`` come from the input,
    so one call is one step of a fixed-point iteration: it converges in a few
    steps on a gently bent path (the propagation re-solves every sample at
    each of its ``w - 2`` positions in the sliding window).
    """
    fr = np.asarray(free, dtype=bool)
    out = _lateral_soa(
        np.ascontiguousarray(points.T), np.ascontiguousarray(anchors_xyz.T), np.ascontiguousarray(normals.T), fr
    )
    return np.ascontiguousarray(out.T)


def _lateral_soa(x: np.ndarray, a: np.ndarray, n: np.ndarray, fr: np.ndarray) -> np.ndarray:
    """:func:`solve_lateral` on coordinate rows: ``x``, ``a``, ``n`` (3, S)
    (row-wise products of three long rows are cheaper than per-sample dots)."""
    S = x.shape[1]
    off = x - a
    off *= n
    off = off.sum(axis=0)
    off *= fr
    base = x - off * n
    ch = base[:, 2:] - base[:, :-2]
    m = n[:, 1:-1]
    b = np.zeros((3, S))
    b[0, 1:-1] = m[1] * ch[2] - m[2] * ch[1]
    b[1, 1:-1] = m[2] * ch[0] - m[0] * ch[2]
    b[2, 1:-1] = m[0] * ch[1] - m[1] * ch[0]
    bl = np.sqrt((b * b).sum(axis=0))
    bl[bl <= 0.0] = 1.0
    b /= bl
    # rows b_i . ((p_{i+1} - p_i) / h_i - (p_i - p_{i-1}) / h_{i-1}) = 0 with the
    # spacings h of the projected samples: exact for a straight path however
    # unevenly it is sampled
    seg = base[:, 1:] - base[:, :-1]
    wgt = np.sqrt((seg * seg).sum(axis=0))
    np.maximum(wgt, 1e-9, out=wgt)
    np.divide(1.0, wgt, out=wgt)  # (S-1,) 1 / spacing
    seg *= wgt
    lap = np.zeros((3, S))
    lap[:, 1:-1] = seg[:, 1:] - seg[:, :-1]
    lap *= b
    rhs = lap.sum(axis=0)
    rhs *= fr
    e = (b[:, :-1] * b[:, 1:]).sum(axis=0)
    e *= wgt
    e *= -1.0
    e *= fr[:-1] & fr[1:]
    d = np.ones(S)
    d[1:-1] = np.where(fr[1:-1], wgt[:-1] + wgt[1:], 1.0)
    _, _, v, info = _ptsv(d, e, rhs[:, None], overwrite_d=1, overwrite_e=1, overwrite_b=1)
    if info != 0:  # pragma: no cover - |b_i . b_j| <= 1 keeps the matrix definite
        raise SolverError(
            f"geodesic: lateral window system not definite (LAPACK info {info}); check the mesh for NaN normals"
        )
    b *= v[:, 0]
    base += b
    return base


def _vertex_normals(mesh: SurfaceMesh) -> np.ndarray:
    """(V, 3) unit normals: the area-weighted mean of the surrounding face
    normals (sums of face cross products by ``bincount``, a few milliseconds;
    the per-vertex PCA of the point-to-point flow takes ~30 ms on a 13K mesh,
    and the propagation's error is the same with either)."""
    V, F = mesh.vertices, mesh.faces
    if mesh.degenerate.any():
        F = F[~mesh.degenerate]
    cols = [np.ascontiguousarray(V[:, c]) for c in range(3)]
    f0, f1, f2 = (np.ascontiguousarray(F[:, c]) for c in range(3))
    e1 = [c[f1] - c[f0] for c in cols]
    e2 = [c[f2] - c[f0] for c in cols]
    flat = F.ravel()
    nv = mesh.n_vertices
    n = np.zeros((nv, 3))
    for c, (a, b) in enumerate(((1, 2), (2, 0), (0, 1))):
        cr = e1[a] * e2[b] - e1[b] * e2[a]
        n[:, c] = np.bincount(flat, weights=np.repeat(cr, 3), minlength=nv)
    ln = np.sqrt(np.einsum("ij,ij->i", n, n))
    lonely = ln <= 0.0
    ln[lonely] = 1.0
    n /= ln[:, None]
    n[lonely] = (0.0, 0.0, 1.0)
    return n


def _padded_graph(mesh: SurfaceMesh) -> tuple[np.ndarray, np.ndarray]:
    """(V, D) one-ring neighbours (``mesh.neighbour_table``: rows padded with
    the vertex itself) and (V, D) float64 edge lengths, cm (padding: 1, never used: the padding vertex is
    the unvisited candidate itself)."""
    tab = mesh.neighbour_table
    g = mesh.graph
    deg = np.diff(g.indptr)
    lens = np.ones(tab.shape)
    rows = np.repeat(np.arange(mesh.n_vertices), deg)
    cols = np.arange(len(rows)) - np.repeat(g.indptr[:-1], deg)
    lens[rows, cols] = g.data
    return tab, lens


def auto_window(mesh: SurfaceMesh) -> int:
    """The automatic window of ``mesh``: the samples spanning ``WINDOW_CM`` of
    path at its mean edge length (at least 8, at most 64)."""
    n = np.ceil(WINDOW_CM / max(mesh.edge_mean, 1e-12))
    return int(min(_WINDOW_MAX, max(_WINDOW_MIN, n)))


def _source_vertex(mesh: SurfaceMesh, source) -> int:
    """The source as a vertex id; a face point snaps to its corner of largest weight."""
    sp_ = mesh.check_point(source, "source")
    if sp_.vertex_id is None:
        sp_ = SurfacePoint.vertex(int(mesh.faces[sp_.face, int(np.argmax(sp_.bary))]))
    return sp_.vertex_id


def _check_options(window: int | str, flow: str, r_max: float | None) -> None:
    """Raise MeshError for a window that is not ``"full"`` or >= 3, an unknown flow or a non-positive radius."""
    full = isinstance(window, str)
    if (full and window != "full") or (not full and int(window) < 3):
        raise MeshError(
            f"geodesic: window {window!r} is not a sample count >= 3 or 'full'; "
            "pass window >= 3, 'full' for the full form, or None for automatic"
        )
    if flow not in FLOWS:
        raise MeshError(
            f"geodesic: flow {flow!r} is not one of {', '.join(FLOWS)}; pass flow='lateral' (default) or flow='lsq'"
        )
    if r_max is not None and not r_max > 0:
        raise MeshError(f"geodesic: r_max {r_max} is not a positive length in cm; pass r_max > 0 or None")


def _candidates(
    tab: np.ndarray, front: np.ndarray, pending: np.ndarray, visited: np.ndarray, seen: np.ndarray
) -> np.ndarray:
    """The unvisited neighbours of ``front`` after those left ``pending``, each once.

    ``seen`` is (V,) int64 scratch, overwritten.
    """
    cand = np.take(tab, front, axis=0).ravel()
    cand = np.concatenate([pending, cand[~visited[cand]]])
    seen[cand] = np.arange(len(cand))
    return cand[seen[cand] == np.arange(len(cand))]


def _band(
    cand: np.ndarray,
    tab: np.ndarray,
    tab_len: np.ndarray,
    dist: np.ndarray,
    visited: np.ndarray,
    reach: float,
    limit: float,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray] | None:
    """The candidates accepted this round: those within ``reach`` of the nearest one's estimate.

    The radius limit follows the slowest part of the wavefront: one band
    beyond the nearest candidate (a limit that only grows by a band each round
    lets the side where the triangulation's diagonals point the way run ahead
    past the cut locus, on a cylinder by 45 %).

    Returns
    -------
    acc : (n,) bool over ``cand``; and per accepted candidate its (k, d)
    neighbours (padded with itself), their edge lengths, the estimates through
    each visited neighbour (inf through the others) and the best of them.
    None when the nearest candidate lies beyond ``limit``.
    """
    nbr = np.take(tab, cand, axis=0)
    el = np.take(tab_len, cand, axis=0)
    dest = np.where(visited[nbr], dist[nbr] + el, np.inf)
    best = dest.min(axis=1)
    lo = best.min()
    if lo > limit:
        return None
    acc = best <= lo + reach  # holds for the nearest candidate at least
    return acc, nbr[acc], el[acc], dest[acc], best[acc, None]


def _straightest_parents(
    V: np.ndarray,
    tdir: np.ndarray,
    src: int,
    q: np.ndarray,
    nbr: np.ndarray,
    el: np.ndarray,
    dest: np.ndarray,
    best: np.ndarray,
) -> np.ndarray:
    """(n,) parent of each new vertex ``q``: among the neighbours whose estimate is
    near the best, the one whose path's last direction continues straightest to it."""
    near = dest <= best + _NEAR * el
    edge = np.take(V, q, axis=0)[:, None, :] - np.take(V, nbr, axis=0)
    cosang = np.einsum("ijk,ijk->ij", np.take(tdir, nbr, axis=0), edge)
    cosang /= el
    cosang[nbr == src] = 1.0
    pick = np.where(near, cosang, -np.inf).argmax(axis=1)
    return np.take(nbr.ravel(), np.arange(0, nbr.size, nbr.shape[1]) + pick)


def geodesic_distances(
    mesh: SurfaceMesh,
    source,
    *,
    r_max: float | None = None,
    window: int | str | None = None,
    flow: str = "lateral",
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
        the mesh resolution (:func:`auto_window`: about ``WINDOW_CM`` of path);
        ``"full"`` re-solves whole paths by the least-squares flow (the full
        form: slow, small meshes only).
    flow : ``"lateral"`` or ``"lsq"``
        Window flow: geodesic-curvature rows only (default), or the two
        tangential rows of the least-squares system (:func:`solve_windows`).
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
    src = _source_vertex(mesh, source)
    if window is None:
        window = auto_window(mesh)
    _check_options(window, flow, r_max)
    nv = mesh.n_vertices
    limit = np.inf if r_max is None else float(r_max)
    tab, tab_len = _padded_graph(mesh)

    dist = np.full(nv, np.inf)
    visited = np.zeros(nv, dtype=bool)
    tdir = np.zeros((nv, 3))  # unit direction of each path's last segment
    if isinstance(window, str):
        solver = _FullSolver(mesh, dist, tdir)
    else:
        solver = _WindowSolver(mesh, src, int(window), flow, dist, tdir, visited)

    dist[src] = 0.0
    visited[src] = True
    seen = np.full(nv, -1, dtype=np.int64)  # scratch for de-duplication
    front = np.array([src], dtype=np.int64)
    pending = np.zeros(0, dtype=np.int64)
    done = 1
    while len(cand := _candidates(tab, front, pending, visited, seen)):
        band = _band(cand, tab, tab_len, dist, visited, _BAND * mesh.edge_mean, limit)
        if band is None:
            break
        acc, nbr, el, dest, best = band
        q = cand[acc]
        p = _straightest_parents(mesh.vertices, tdir, src, q, nbr, el, dest, best)
        visited[q] = True
        solver(q, p)
        done += len(q)
        if progress is not None:
            progress("propagate", done, nv)
        front = q
        pending = cand[~acc]
    dist[dist > limit] = np.inf
    return dist


class _WindowSolver:
    """Windowed form: each vertex keeps the last ``w`` samples of its path
    (``tails``, with their anchor vertices); a new vertex shifts its parent's
    window by one, appends itself and re-solves the window."""

    def __init__(self, mesh, src, w, flow, dist, tdir, visited):
        nv = mesh.n_vertices
        V = mesh.vertices
        self.V = V
        self.w = w
        self.dist = dist
        self.tdir = tdir
        self.visited = visited
        self.tab = mesh.neighbour_table
        normals = _vertex_normals(mesh)
        # coordinate rows (3, V): the window arithmetic runs on (3, samples)
        self.VT = np.ascontiguousarray(V.T)
        self.NT = np.ascontiguousarray(normals.T)
        self.tangents = None
        if flow == "lsq":
            t1, t2 = _tangent_bases(normals)
            self.tangents = np.stack([t1, t2], axis=-1)  # (V, 3, 2)
        # the windows are stored in visiting order (vertex v in row ``row[v]``,
        # ``owner[row]`` the other way), so that each band writes one
        # contiguous block; when the buffer is full, the windows of vertices
        # that can no longer be parents (no unvisited neighbour) are dropped, so
        # memory follows the wavefront, not the mesh. Samples of a path shorter
        # than the window repeat the source (fixed).
        cap = min(nv, max(_ROWS_MIN, nv // 16))
        self.tails = np.zeros((cap, 3, w))  # (row, xyz, sample)
        self.tail_ids = np.zeros((cap, w), dtype=np.int64)
        self.owner = np.zeros(cap, dtype=np.int64)
        self.row = np.zeros(nv, dtype=np.int64)
        self.tails[0] = V[src][:, None]
        self.tail_ids[0] = src
        self.owner[0] = src
        self.used = 1
        self.depth = np.zeros(nv, dtype=np.int64)  # edges on the path
        self.dstart = np.zeros(nv)  # frozen length before the window
        self.slots = np.arange(w)

    def __call__(self, q, p):
        w = self.w
        B = len(q)
        rows = self.row[p]
        tp = np.take(self.tails, rows, axis=0)  # (B, 3, w)
        X = np.zeros((3, B, w))
        X[:, :, :-1] = tp[:, :, 1:].transpose(1, 0, 2)
        X[:, :, -1] = np.take(self.VT, q, axis=1)
        ids = np.zeros((B, w), dtype=np.int64)
        ids[:, :-1] = np.take(self.tail_ids, rows, axis=0)[:, 1:]
        ids[:, -1] = q
        d0 = tp[:, :, 1] - tp[:, :, 0]
        dstart = self.dstart[p] + np.sqrt((d0 * d0).sum(axis=1))
        depth = self.depth[p] + 1
        # the first sample of the path (or of the window) and the new one are fixed
        free = self.slots > np.maximum(0, w - 1 - depth)[:, None]
        free[:, -1] = False
        S = B * w
        fr = free.reshape(S)
        flat = ids.reshape(S)
        x = X.reshape(3, S)
        sel = np.flatnonzero(fr)
        if len(sel):
            # one-ring descent of each free sample's anchor vertex
            D = self.tab.shape[1]
            cand = np.take(self.tab, np.take(flat, sel), axis=0).ravel()
            diff = np.take(self.VT, cand, axis=1).reshape(3, len(sel), D)
            diff -= np.take(x, sel, axis=1)[:, :, None]
            diff *= diff
            d2 = diff.sum(axis=0)
            flat[sel] = np.take(cand, np.arange(0, D * len(sel), D) + d2.argmin(axis=1))
            ax = np.take(self.VT, flat, axis=1)
            if self.tangents is None:
                x = _lateral_soa(x, ax, np.take(self.NT, flat, axis=1), fr)
            else:
                T = np.take(self.tangents, flat, axis=0)
                base = np.where(fr[:, None], ax.T, x.T)
                x = _solve_stack(base, T, fr).T
            X = x.reshape(3, B, w)
        if self.used + B > len(self.owner):
            self._compact(B)
        k = self.used
        self.tails[k : k + B] = X.transpose(1, 0, 2)
        self.tail_ids[k : k + B] = ids
        self.owner[k : k + B] = q
        self.row[q] = np.arange(k, k + B)
        self.used = k + B
        self.depth[q] = depth
        self.dstart[q] = dstart
        seg = X[:, :, 1:] - X[:, :, :-1]
        seg *= seg
        seg = np.sqrt(seg.sum(axis=0))  # (B, w - 1)
        self.dist[q] = dstart + seg.sum(axis=1)
        self.tdir[q] = ((X[:, :, -1] - X[:, :, -2]) / np.maximum(seg[:, -1], 1e-300)).T

    def _compact(self, B: int) -> None:
        """Keep the windows of vertices with an unvisited neighbour (the only
        possible parents) and make room for ``B`` more rows."""
        own = self.owner[: self.used]
        keep = np.flatnonzero(~self.visited[np.take(self.tab, own, axis=0)].all(axis=1))
        m = len(keep)
        cap = len(self.owner)
        if m + B > cap // 2:  # grow, so that compactions stay rare
            cap = min(len(self.row), max(2 * cap, 2 * (m + B)))
            tails = np.zeros((cap, 3, self.w))
            ids = np.zeros((cap, self.w), dtype=np.int64)
            owner = np.zeros(cap, dtype=np.int64)
        else:
            tails, ids, owner = self.tails, self.tail_ids, self.owner
        tails[:m] = self.tails[keep]
        ids[:m] = self.tail_ids[keep]
        owner[:m] = own[keep]
        self.tails, self.tail_ids, self.owner = tails, ids, owner
        self.row[owner[:m]] = np.arange(m)
        self.used = m


class _FullSolver:
    """Full form: the whole path of a new vertex (its chain of parents) is
    relaxed by one least-squares flow step."""

    def __init__(self, mesh, dist, tdir):
        self.mesh = mesh
        self.parent = np.full(mesh.n_vertices, -1, dtype=np.int64)
        self.dist = dist
        self.tdir = tdir
        self.normals = mesh.all_vertex_normals

    def __call__(self, q, p):
        from .flow import lsq_step

        V, parent = self.mesh.vertices, self.parent
        parent[q] = p
        for v in q.tolist():
            ids = [v]
            while parent[ids[-1]] >= 0:
                ids.append(int(parent[ids[-1]]))
            ids = np.array(ids[::-1])
            pts = V[ids]
            if len(ids) >= 3:
                nrm = self.normals[ids]
                off = np.einsum("ij,ij->i", pts - V[ids], nrm)
                pts = lsq_step(pts, nrm, pts - off[:, None] * nrm)
            self.dist[v] = float(np.linalg.norm(np.diff(pts, axis=0), axis=1).sum())
        edge = V[q] - V[p]
        self.tdir[q] = edge / np.maximum(np.linalg.norm(edge, axis=1), 1e-300)[:, None]
