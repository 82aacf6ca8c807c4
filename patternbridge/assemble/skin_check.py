"""Independent check of cloth against the skin: signed distances of points sampled on every garment triangle.

The solver keeps the cloth out of the body with its own collider
(:mod:`.collision`); the verdict must not trust it. This module builds a
fresh Open3D scene of the body and asks for the signed distance (closest
point on the skin, the sign from a vote of several rays) of points on a
barycentric grid over every garment triangle (corners, edges and inside): a
triangle through a thin limb or over a tip of the skin has points inside
even when its corners are out.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["SkinCheck", "skin_check", "triangle_samples"]

RAY_VOTES = 5  # rays cast per point for the inside/outside sign (odd)
SAMPLE_DIVISIONS = 4  # each triangle is sampled on a barycentric grid of this many divisions (15 points)


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class SkinCheck:
    """Cloth inside the body.

    depth_cm : (F,) float64, cm — how deep the deepest sample of each
        triangle lies inside the skin (0 when all are outside)
    """

    depth_cm: np.ndarray

    def inside(self, tolerance_cm: float) -> np.ndarray:
        """(F,) bool: triangles with a sample deeper than ``tolerance_cm``."""
        return self.depth_cm > tolerance_cm


def signed_distance(body_vertices: np.ndarray, body_faces: np.ndarray, points: np.ndarray) -> np.ndarray:
    """(n,) float64, cm: signed distance of ``points`` (n, 3) to the body, negative inside."""
    import open3d as o3d

    scene = o3d.t.geometry.RaycastingScene()
    scene.add_triangles(
        o3d.core.Tensor(np.asarray(body_vertices, dtype=np.float32)),
        o3d.core.Tensor(np.asarray(body_faces, dtype=np.uint32)),
    )
    query = o3d.core.Tensor(np.asarray(points, dtype=np.float32))
    return scene.compute_signed_distance(query, nsamples=RAY_VOTES).numpy().astype(np.float64)


def triangle_samples(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """(F, s, 3) points on a barycentric grid of :data:`SAMPLE_DIVISIONS` over each triangle (corners, edges and
    inside; s = 15)."""
    k = SAMPLE_DIVISIONS
    i, j = np.meshgrid(np.arange(k + 1), np.arange(k + 1), indexing="ij")
    keep = i + j <= k
    bary = np.stack([i[keep], j[keep], k - i[keep] - j[keep]], axis=1) / k  # (s, 3) barycentric samples
    return np.einsum("sc,fcd->fsd", bary, vertices[faces])


def skin_check(body_vertices: np.ndarray, body_faces: np.ndarray, vertices: np.ndarray, faces: np.ndarray) -> SkinCheck:
    """Depth inside the body of every garment triangle.

    Parameters
    ----------
    body_vertices : (V, 3) float64, cm ; body_faces : (G, 3) int64 — the closed skin
    vertices : (N, 3) float64, cm ; faces : (F, 3) int64 — the garment

    Returns
    -------
    :class:`SkinCheck`
    """
    f = np.asarray(faces, dtype=np.int64)
    samples = triangle_samples(np.asarray(vertices, dtype=np.float64), f)  # (F, s, 3)
    d = signed_distance(body_vertices, body_faces, samples.reshape(-1, 3)).reshape(len(f), -1)
    return SkinCheck(depth_cm=np.maximum(-d.min(axis=1, initial=np.inf), 0.0) if len(f) else np.zeros(0))
