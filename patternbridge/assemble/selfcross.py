"""Cloth against itself: where a garment passes through itself, and keeping it from doing so.

A fold the solver pushed through the cloth beside it (the lower back tucked
under the upper back, a sleeve's underside caught inside itself) shows as
a jagged line in the pictures and catches the animator's cloth simulation
in a knot. Vertex-to-vertex layer separation does not see it once the
vertices have passed each other: :func:`self_crossing` counts it from the
geometry for the report (a piece's edges cast against the same piece's
triangles), and :func:`keep_sides`, run at every solver step, keeps each
vertex on the side of the nearby triangles it came from.
"""

from __future__ import annotations

import numpy as np

__all__ = ["keep_sides", "keep_uncrossed", "self_crossing"]

_EPS_CM = 1e-3  # an edge's ends are left out: the triangles round a vertex touch it there


def self_crossing(
    vertices: np.ndarray, faces: np.ndarray, group: np.ndarray, same: np.ndarray | None = None
) -> np.ndarray:
    """(F,) bool: triangles crossing, or crossed by, a triangle of the same piece they share no vertex with.

    Parameters
    ----------
    vertices : (V, 3) float64, cm — welded: the two sides of a seam share vertices
    faces : (F, 3) int64
    group : (F,) int64 — the piece of every triangle
    same : (V,) int64, optional — vertices with one label count as one
        (the sides of a seam before welding, see ``drape.weld_groups``)

    Every edge of a piece is cast as a ray, from each end, against that
    piece's triangles; a hit strictly between its ends on a triangle that
    has neither end as a corner marks both triangles. Only the first hit
    along a ray is seen, so two layers crossing one edge count once.
    """
    import open3d as o3d

    from .collision import triangle_scene

    x = np.asarray(vertices, dtype=np.float64)
    f = np.asarray(faces, dtype=np.int64)
    group = np.asarray(group)
    same = np.arange(len(x)) if same is None else np.asarray(same)
    out = np.zeros(len(f), dtype=bool)
    for g in np.unique(group):
        ids = np.flatnonzero(group == g)
        if len(ids) < 2:
            continue
        fg = f[ids]
        scene = triangle_scene(x, fg)
        owner = np.repeat(np.arange(len(fg)), 3)
        ends = (fg.ravel(), np.roll(fg, -1, axis=1).ravel())
        for start, stop in (ends, ends[::-1]):
            d = x[stop] - x[start]
            length = np.linalg.norm(d, axis=1)
            u = d / np.maximum(length, 1e-12)[:, None]
            rays = np.concatenate([x[start] + _EPS_CM * u, u], axis=1).astype(np.float32)
            hit = scene.cast_rays(o3d.core.Tensor(rays))
            t = hit["t_hit"].numpy()
            prim = hit["primitive_ids"].numpy().astype(np.int64)
            ok = (length > 1e-9) & np.isfinite(t) & (t < length - 2 * _EPS_CM)
            other = fg[np.where(ok, prim, 0)]
            mine = same[other]
            ok &= ~((mine == same[start][:, None]).any(axis=1) | (mine == same[stop][:, None]).any(axis=1))
            # the ray caster reports edges lying in a triangle's plane as hits
            # anywhere along their line (a flat stretch of cloth): only an edge
            # going through the triangle counts
            ok[ok] = _through(x[start[ok]], x[stop[ok]], x[other[ok]])
            out[ids[owner[ok]]] = True
            out[ids[prim[ok]]] = True
    return out


def _through(p: np.ndarray, q: np.ndarray, tri: np.ndarray, tol: float = 1e-6) -> np.ndarray:
    """(n,) bool: segments ``p``→``q`` (n, 3) passing through the triangles ``tri`` (n, 3, 3), ends strictly apart."""
    a, b, c = tri[:, 0], tri[:, 1], tri[:, 2]
    n = _normals(tri)
    dp = np.einsum("ij,ij->i", p - a, n)
    dq = np.einsum("ij,ij->i", q - a, n)
    across = (dp * dq < 0) & (np.abs(dp) > tol) & (np.abs(dq) > tol)
    t = dp / np.where(across, dp - dq, 1.0)
    m = p + t[:, None] * (q - p)
    # inside: the hit point is on the inner side of all three edges
    inside = np.ones(len(p), dtype=bool)
    for u, v in ((a, b), (b, c), (c, a)):
        inside &= np.einsum("ij,ij->i", np.cross(v - u, m - u), n) >= -tol
    return across & inside


def keep_sides(
    x: np.ndarray,
    x0: np.ndarray,
    faces: np.ndarray,
    weld: np.ndarray,
    thickness_cm: float,
) -> np.ndarray:
    """(N, 3) positions with every vertex kept on the side of each nearby triangle it was on at ``x0``.

    Parameters
    ----------
    x : (N, 3) float64, cm — the cloth now
    x0 : (N, 3) float64, cm — the cloth at the start of the step
    faces : (F, 3) int64
    weld : (N,) int64 — weld group of every vertex (sewn vertices never push each other)
    thickness_cm : the distance kept between a vertex and a triangle it lies over

    A vertex over (or under) a triangle of the cloth, not one of its
    corners, that has come closer than ``thickness_cm`` to it or gone
    through it, is put back ``thickness_cm`` on the side it came from; the
    vertex and the triangle's corners share the move (by their barycentric
    weights), and the moves of a vertex in several pairs are averaged.
    Vertex-to-vertex repulsion (``separate_layers``) does not see a vertex
    passing through a triangle between its corners; remembering the side
    does. Only pairs where the vertex lies over the triangle's inside both
    at ``x0`` and now are held (a vertex going round a free edge changes
    side legitimately).
    """
    from scipy.spatial import cKDTree

    x = np.asarray(x, dtype=np.float64)
    x0 = np.asarray(x0, dtype=np.float64)
    f = np.asarray(faces, dtype=np.int64)
    tri = x[f]
    centre = tri.mean(axis=1)
    # (a triangle stretched past the 99th percentile is reached from near its centre only)
    radius = np.sqrt(np.max(np.sum((tri - centre[:, None]) ** 2, axis=2), axis=1))
    reach = float(np.percentile(radius, 99)) + thickness_cm
    pairs = cKDTree(x).sparse_distance_matrix(cKDTree(centre), reach, output_type="ndarray")
    if len(pairs) == 0:
        return x
    v, t = pairs["i"].astype(np.int64), pairs["j"].astype(np.int64)
    close = pairs["v"] <= radius[t] + thickness_cm
    v, t = v[close], t[close]
    # cheap plane distances first: most pairs are far from each other's plane and stay on their side
    n0, n1 = _normals(x0[f]), _normals(tri)
    d0 = np.einsum("ij,ij->i", x0[v] - x0[f[t, 0]], n0[t])
    d1 = np.einsum("ij,ij->i", x[v] - x[f[t, 0]], n1[t])
    side = np.sign(d0)
    depth = thickness_cm - side * d1
    near = (side != 0) & (depth > 0) & ~(weld[f[t]] == weld[v][:, None]).any(axis=1)
    v, t, side, depth = v[near], t[near], side[near], depth[near]
    if len(v) == 0:
        return x
    inside0, _ = _over(x0[v], x0[f[t]])
    inside1, bary = _over(x[v], tri[t])
    hold = inside0 & inside1
    if not hold.any():
        return x
    v, t, side, depth, bary = v[hold], t[hold], side[hold], depth[hold], bary[hold]
    push = (side * depth / (1.0 + np.sum(bary**2, axis=1)))[:, None] * n1[t]
    delta = np.zeros_like(x)
    count = np.zeros(len(x))
    np.add.at(delta, v, push)
    np.add.at(count, v, 1.0)
    for k in range(3):
        np.add.at(delta, f[t, k], -bary[:, k, None] * push)
        np.add.at(count, f[t, k], 1.0)
    return x + delta / np.maximum(count, 1.0)[:, None]


def keep_uncrossed(
    x: np.ndarray,
    x0: np.ndarray,
    faces: np.ndarray,
    group: np.ndarray,
    same: np.ndarray,
    crossed0: np.ndarray,
    *,
    rounds: int = 3,
) -> tuple[np.ndarray, np.ndarray]:
    """Send back to ``x0`` the corners of the triangles that cross their piece at ``x`` but did not at ``x0``.

    Parameters
    ----------
    x, x0 : (N, 3) float64, cm — the cloth now and at the start of the step
    faces : (F, 3) int64
    group : (F,) int64 — the piece of every triangle
    same : (N,) int64 — weld group of every vertex (see :func:`self_crossing`)
    crossed0 : (F,) bool — :func:`self_crossing` at ``x0`` (left to the solver to undo)

    :func:`keep_sides` holds a vertex on its side of the triangles under
    it; an edge can still cut through a triangle between its corners where
    the cloth crumples (a sleeve gathered as the arm comes down). The
    triangles that crossed in the step get their corners back where they
    were, and again for those the return makes cross, up to ``rounds``
    times. Corners sewn to another vertex (sharing a label in ``same``)
    stay where the step put them: held back, their seams stayed open
    (armholes 12-19 mm instead of 5 on the shirts). Returns the corrected
    ``x`` and :func:`self_crossing` of it.
    """
    x = np.array(x, dtype=np.float64)
    f = np.asarray(faces, dtype=np.int64)
    same = np.asarray(same)
    sewn = np.bincount(same)[same] > 1
    crossed = self_crossing(x, f, group, same)
    for _ in range(rounds):
        new = crossed & ~crossed0
        if not new.any():
            break
        back = np.unique(f[new])
        back = back[~sewn[back]]
        if not back.size:  # only sewn corners: nothing to send back
            break
        x[back] = x0[back]
        crossed = self_crossing(x, f, group, same)
    return x, crossed


def _normals(tri: np.ndarray) -> np.ndarray:
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    return n / np.maximum(np.linalg.norm(n, axis=1), 1e-12)[:, None]


def _over(p: np.ndarray, tri: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Whether each point of ``p`` (n, 3) lies over the inside of its triangle ``tri`` (n, 3, 3), and the
    barycentric weights (n, 3) of its foot on the triangle's plane."""
    e1, e2, w = tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0], p - tri[:, 0]
    d11, d12, d22 = (np.einsum("ij,ij->i", a, b) for a, b in ((e1, e1), (e1, e2), (e2, e2)))
    w1, w2 = np.einsum("ij,ij->i", w, e1), np.einsum("ij,ij->i", w, e2)
    den = np.maximum(d11 * d22 - d12 * d12, 1e-18)
    b1 = (d22 * w1 - d12 * w2) / den
    b2 = (d11 * w2 - d12 * w1) / den
    bary = np.stack([1.0 - b1 - b2, b1, b2], axis=1)
    return np.all(bary >= 0.0, axis=1), bary
