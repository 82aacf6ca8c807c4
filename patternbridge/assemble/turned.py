"""Cloth worn turned over: its outside facing the body (a twisted strap, a binding worn inside out).

Every garment triangle is wound so that its normal points out of the cloth's
outside, away from the body (the placement lays the pattern's +x round the
body to the right seen from outside and +y along the body's axis, and a
mirror copy is wound the other way round, :func:`.pipeline.prepare`). A
triangle whose outward normal points back into the nearest skin (within 60°,
:data:`TURNED_COS`) is turned over.

A fold turns some cloth under too, and so does a hem rolled in: that cloth
lies under another layer of the garment and its wrong side does not show.
Turned triangles with the garment within :data:`LAYER_CM` over them (along
the direction away from the skin) are *covered* and not counted. And a fold
turns the cloth between two fold lines inside the piece, while a twist, or a
strip worn inside out, turns it all the way to the cloth's edge: the turned
triangles are gathered into patches sharing an edge (across the seams), and
only patches that reach a free edge of the cloth (an edge of one triangle
only, on the welded garment) count. A strap with a half twist is one such
patch a strap wide; a binding sewn on inside out is a patch the length of
the binding.

The pure core (:func:`outward_cos`, :func:`patches`, :func:`free_edge_faces`)
works on arrays; the Open3D queries (closest skin points, rays against the
garment) sit in :func:`turned_cloth`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .collision import triangle_scene

__all__ = ["LAYER_CM", "TURNED_COS", "TurnedCloth", "free_edge_faces", "outward_cos", "patches", "turned_cloth"]

#: a triangle is turned when its outward normal is within 60° of the direction into the skin
TURNED_COS = -0.5
#: a turned triangle with the garment this near over it is under a layer of cloth (a fold, a hem rolled in)
LAYER_CM = 2.0


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class TurnedCloth:
    """The cloth worn turned over.

    cos : (F,) float64 — cosine between each triangle's outward normal and the direction away from the skin
    covered : (F,) bool — turned triangles under another layer of the garment (a fold's, a rolled hem's)
    patch : (F,) int64 — the patch of each counted turned triangle (-1: not turned, covered, or in a
        patch that does not reach a free edge of the cloth)
    area_cm2 : (P,) float64 — the area of each patch
    """

    cos: np.ndarray
    covered: np.ndarray
    patch: np.ndarray
    area_cm2: np.ndarray

    def faces(self, min_area_cm2: float) -> np.ndarray:
        """(F,) bool: the triangles of patches larger than ``min_area_cm2``."""
        big = np.flatnonzero(self.area_cm2 > min_area_cm2)
        return np.isin(self.patch, big)


def outward_cos(x: np.ndarray, faces: np.ndarray, closest: np.ndarray) -> np.ndarray:
    """(F,) float64: cosine between each face's normal and the direction from its nearest skin point to it.

    Parameters
    ----------
    x : (N, 3) float64, cm ; faces : (F, 3) int64, wound with their normal out of the cloth's outside
    closest : (F, 3) float64, cm — the skin point nearest each face's centroid

    A face within 1e-6 cm of the skin has no direction away from it: its cosine is 1 (not turned).
    """
    a, b, c = x[faces[:, 0]], x[faces[:, 1]], x[faces[:, 2]]
    n = np.cross(b - a, c - a)
    away = (a + b + c) / 3.0 - closest
    ln, la = np.linalg.norm(n, axis=1), np.linalg.norm(away, axis=1)
    ok = (ln > 0) & (la > 1e-6)
    out = np.ones(len(faces))
    out[ok] = np.einsum("ij,ij->i", n[ok], away[ok]) / (ln[ok] * la[ok])
    return out


def patches(faces: np.ndarray, weld: np.ndarray, chosen: np.ndarray) -> np.ndarray:
    """(F,) int64: the connected patch of each ``chosen`` face (sharing an edge of welded vertices), -1 elsewhere.

    Patches are numbered from 0 in order of their lowest face id.
    """
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    out = np.full(len(faces), -1, dtype=np.int64)
    ids = np.flatnonzero(chosen)
    if len(ids) == 0:
        return out
    w = weld[faces[ids]]
    e = np.sort(np.stack([w[:, [0, 1]], w[:, [1, 2]], w[:, [2, 0]]], axis=1), axis=2).reshape(-1, 2)
    _, edge = np.unique(e, axis=0, return_inverse=True)
    owner = np.repeat(np.arange(len(ids)), 3)
    n_e = int(edge.max()) + 1
    g = coo_matrix((np.ones(len(owner)), (owner, edge.ravel())), shape=(len(ids), n_e)).tocsr()
    _, label = connected_components(g @ g.T, directed=False)
    _, first = np.unique(label, return_index=True)
    order = np.argsort(np.argsort(first))  # patches numbered by their lowest face
    out[ids] = order[label]
    return out


def free_edge_faces(faces: np.ndarray, weld: np.ndarray) -> np.ndarray:
    """(F,) bool: faces with an edge that no other face shares (on the welded vertices): the cloth's free edges."""
    w = np.sort(weld[faces][:, [[0, 1], [1, 2], [2, 0]]], axis=2).reshape(-1, 2)
    _, inv, count = np.unique(w, axis=0, return_inverse=True, return_counts=True)
    return (count[inv.ravel()] == 1).reshape(-1, 3).any(axis=1)


def _area(x: np.ndarray, faces: np.ndarray) -> np.ndarray:
    a, b, c = x[faces[:, 0]], x[faces[:, 1]], x[faces[:, 2]]
    return 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1)


def _hit_within(scene, origins: np.ndarray, dirs: np.ndarray, reach: float) -> np.ndarray:
    """(n,) bool: rays from ``origins`` along unit ``dirs`` that hit the scene within ``reach``."""
    import open3d as o3d

    if len(origins) == 0:
        return np.zeros(0, dtype=bool)
    rays = np.concatenate([origins, dirs], axis=1).astype(np.float32)
    t = scene.cast_rays(o3d.core.Tensor(rays))["t_hit"].numpy()
    return t <= reach


def turned_cloth(
    x: np.ndarray,
    faces: np.ndarray,
    weld: np.ndarray,
    body_vertices: np.ndarray,
    body_faces: np.ndarray,
    *,
    layer_cm: float = LAYER_CM,
    turned_cos: float = TURNED_COS,
) -> TurnedCloth:
    """The cloth of a finished drape worn turned over (see the module).

    Parameters
    ----------
    x : (N, 3) float64, cm ; faces : (F, 3) int64 — the garment, wound with the normal out of its outside
    weld : (N,) int64 — sewn vertices share an id (patches run across the seams)
    body_vertices : (V, 3) float64, cm ; body_faces : (G, 3) int64 — the skin, in the pose of ``x``
    """
    faces = np.asarray(faces, dtype=np.int64)
    centroid = x[faces].mean(axis=1)
    import open3d as o3d

    body = triangle_scene(body_vertices, body_faces)
    closest = body.compute_closest_points(o3d.core.Tensor(centroid.astype(np.float32)))["points"].numpy()
    cos = outward_cos(x, faces, closest.astype(np.float64))
    turned = cos < turned_cos
    covered = np.zeros(len(faces), dtype=bool)
    ids = np.flatnonzero(turned)
    if len(ids):
        away = centroid[ids] - closest[ids]
        away /= np.maximum(np.linalg.norm(away, axis=1, keepdims=True), 1e-12)
        eps = 1e-3  # start off the triangle itself
        covered[ids] = _hit_within(triangle_scene(x, faces), centroid[ids] + eps * away, away, layer_cm)
    seen = turned & ~covered
    patch = patches(faces, weld, seen)
    at_edge = np.zeros(int(patch.max()) + 2, dtype=bool)  # the last slot, False, is read by patch -1
    at_edge[patch[seen & free_edge_faces(faces, weld)]] = True
    patch = np.where(at_edge[patch], patch, -1)
    _, patch[patch >= 0] = np.unique(patch[patch >= 0], return_inverse=True)
    counted = patch >= 0
    area = np.bincount(patch[counted], weights=_area(x, faces)[counted], minlength=int(patch.max()) + 1)
    return TurnedCloth(cos=cos, covered=covered, patch=patch, area_cm2=area)
