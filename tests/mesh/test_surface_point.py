"""The one closest-point-on-triangle test of the package and the surface location built on it."""

from __future__ import annotations

import numpy as np
import trimesh

from patternbridge.mesh.surface_point import closest_on_triangles, locate_on_surface, point_on_triangles


def _dense_min_distance(p: np.ndarray, tri: np.ndarray, n: int = 20000, seed: int = 0) -> np.ndarray:
    """(k,) the distance from ``p`` (k, 3) to the nearest of ``n`` points spread over each triangle (k, 3, 3)."""
    u, v = np.random.default_rng(seed).random((2, n))
    u, v = np.where(u + v > 1, 1 - u, u), np.where(u + v > 1, 1 - v, v)
    w = np.stack([1 - u - v, u, v], axis=1)
    samples = np.einsum("sk,tkd->tsd", w, tri)
    return np.linalg.norm(samples - p[:, None], axis=2).min(axis=1)


def test_the_closest_point_is_no_farther_than_any_point_of_a_dense_sampling():
    rng = np.random.default_rng(11)
    tri = rng.normal(size=(150, 3, 3)) * [1.0, 1.0, 0.3]
    p = rng.normal(size=(150, 3)) * 2.0
    bary = closest_on_triangles(p, tri)
    assert bary.min() >= 0.0
    np.testing.assert_allclose(bary.sum(axis=1), 1.0)
    got = np.linalg.norm(p - point_on_triangles(bary, tri), axis=1)
    best = _dense_min_distance(p, tri)
    assert np.all(got <= best + 1e-9)
    assert np.all(best - got < 0.05)


def test_every_voronoi_region_of_a_triangle_gives_its_feature():
    # the right triangle (0,0,0), (4,0,0), (0,4,0): one query over each corner, edge and the inside, 1 cm up
    tri = np.repeat(np.array([[[0.0, 0.0, 0.0], [4.0, 0.0, 0.0], [0.0, 4.0, 0.0]]]), 7, axis=0)
    p = np.array(
        [
            [-1.0, -1.0, 1.0],  # corner a
            [5.0, -1.0, 1.0],  # corner b
            [-1.0, 5.0, 1.0],  # corner c
            [2.0, -1.0, 1.0],  # edge ab at x = 2
            [-1.0, 3.0, 1.0],  # edge ac at y = 3
            [3.0, 3.0, 1.0],  # edge bc at its middle
            [1.0, 1.0, 1.0],  # inside
        ]
    )
    q = point_on_triangles(closest_on_triangles(p, tri), tri)
    want = np.array(
        [
            [0.0, 0.0, 0.0],
            [4.0, 0.0, 0.0],
            [0.0, 4.0, 0.0],
            [2.0, 0.0, 0.0],
            [0.0, 3.0, 0.0],
            [2.0, 2.0, 0.0],
            [1.0, 1.0, 0.0],
        ]
    )
    np.testing.assert_allclose(q, want, atol=1e-12)
    # a corner is the corner to the last bit, on a triangle whose corners do not add up exactly
    skew = np.array([[[0.1, 0.7, 0.3], [4.3, 0.2, 0.9], [0.6, 4.1, 0.05]]])
    for k in range(3):
        away = skew[0, k] + 3.0 * (skew[0, k] - skew[0].mean(axis=0))
        got = point_on_triangles(closest_on_triangles(away[None], skew), skew)[0]
        assert np.array_equal(got, skew[0, k])


def test_a_location_on_a_mesh_is_the_closest_point_of_all_its_faces():
    # independent reference: open3d's closest point over every face (a BVH, in float32) of a bumpy sphere
    import open3d as o3d

    mesh = trimesh.creation.icosphere(subdivisions=3, radius=20.0)
    rng = np.random.default_rng(5)
    v = mesh.vertices * (1.0 + 0.05 * rng.standard_normal((len(mesh.vertices), 1)))
    d = rng.normal(size=(200, 3))
    points = 20.0 * d / np.linalg.norm(d, axis=1, keepdims=True) * rng.uniform(0.9, 1.1, (200, 1))
    at = locate_on_surface(v, np.asarray(mesh.faces, np.int64), points)
    scene = o3d.t.geometry.RaycastingScene()
    scene.add_triangles(o3d.core.Tensor(v.astype(np.float32)), o3d.core.Tensor(mesh.faces.astype(np.uint32)))
    ref = scene.compute_closest_points(o3d.core.Tensor(points.astype(np.float32)))["points"].numpy()
    np.testing.assert_allclose(
        np.linalg.norm(points - at.positions, axis=1), np.linalg.norm(points - ref, axis=1), atol=1e-4
    )
    # the weights rebuild the position on the face, and the nearest vertex is a corner of it
    rebuilt = np.einsum("ij,ijk->ik", at.bary, v[mesh.faces[at.face]])
    np.testing.assert_allclose(rebuilt, at.positions, atol=1e-9)
    assert np.all((mesh.faces[at.face] == at.vertex[:, None]).any(axis=1))
