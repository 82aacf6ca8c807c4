"""Cloth against itself: where a garment passes through itself (the report's count).

A fold the solver pushed through the cloth beside it (the lower back tucked
under the upper back, a sleeve's underside caught inside itself, a sleeve
cap through the bodice beside the armhole) shows as a jagged line in the
pictures and catches the animator's cloth simulation in a knot.
Vertex-to-vertex layer separation does not see it once the vertices have
passed each other: :func:`self_crossing` counts it from the geometry for
the report (the garment's edges cast against its triangles, the sides of a
seam one vertex), independently of the solver's self-contact
(:mod:`patternbridge.assemble.cloth.selfcontact`). One piece through
another counts as much as a piece through itself: both are the garment
passing through itself.
"""

from __future__ import annotations

import numpy as np

__all__ = ["self_crossing"]

_EPS_CM = 1e-3  # an edge's ends are left out: the triangles round a vertex touch it there


def self_crossing(
    vertices: np.ndarray, faces: np.ndarray, group: np.ndarray | None = None, same: np.ndarray | None = None
) -> np.ndarray:
    """(F,) bool: triangles crossing, or crossed by, a triangle of their group they share no vertex with.

    Parameters
    ----------
    vertices : (V, 3) float64, cm — welded: the two sides of a seam share vertices
    faces : (F, 3) int64
    group : (F,) int64, optional — triangles cross only triangles of their
        own group (None: the whole garment is one group, as the report counts)
    same : (V,) int64, optional — vertices with one label count as one
        (the sides of a seam before welding, see ``drape.weld_groups``)

    Every edge of a group is cast as a ray, from each end, against that
    group's triangles; a hit strictly between its ends on a triangle that
    has neither end as a corner marks both triangles. Only the first hit
    along a ray is seen, so two layers crossing one edge count once.
    """
    import open3d as o3d

    from .collision import triangle_scene

    x = np.asarray(vertices, dtype=np.float64)
    f = np.asarray(faces, dtype=np.int64)
    group = np.zeros(len(f), dtype=np.int64) if group is None else np.asarray(group)
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


def _normals(tri: np.ndarray) -> np.ndarray:
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    return n / np.maximum(np.linalg.norm(n, axis=1), 1e-12)[:, None]
