"""Curvature flow systems and the projection walk."""

from __future__ import annotations

import numpy as np
import pytest

from patternbridge.geodesic import SurfaceMesh
from patternbridge.geodesic.flow import euler_step, flow_path, lsq_step
from patternbridge.geodesic.initial import edge_path
from patternbridge.geodesic.path import _endpoint
from patternbridge.geodesic.project import project_walk


def _zigzag(m=21):
    t = np.linspace(0.0, 10.0, m)
    p = np.c_[t, np.where(np.arange(m) % 2 == 1, 0.3, 0.0), np.zeros(m)]
    p[-1, 1] = 0.0
    return p, np.tile([0.0, 0.0, 1.0], (m, 1))


def test_lsq_step_straightens_in_the_plane():
    p, n = _zigzag()
    q = lsq_step(p, n, p)
    np.testing.assert_allclose(q[:, 1], 0.0, atol=1e-9)
    np.testing.assert_allclose(q[:, 0], np.linspace(0, 10, len(p)), atol=1e-9)
    np.testing.assert_allclose(q[[0, -1]], p[[0, -1]])


def test_lsq_step_keeps_points_on_tangent_planes():
    p, n = _zigzag()
    pbar = p.copy()
    pbar[:, 2] = 1.0  # planes z = 1 for the inner points
    q = lsq_step(p, n, pbar)
    np.testing.assert_allclose(q[1:-1, 2], 1.0, atol=1e-6)


def test_euler_converges_to_the_lsq_solution():
    p, n = _zigzag()
    q = p.copy()
    for _ in range(60):
        q = euler_step(q, n, p, mu=50.0)
    np.testing.assert_allclose(q, lsq_step(p, n, p), atol=1e-4)
    np.testing.assert_allclose(q[[0, -1]], p[[0, -1]])


def test_flow_and_walk_on_a_sphere(sphere):
    v, f = sphere
    mesh = SurfaceMesh(v, f)
    a, b = 0, 1500
    ea, _ = _endpoint(mesh, mesh.check_point(a, "a"))
    eb, _ = _endpoint(mesh, mesh.check_point(b, "b"))
    vp, graph_len = edge_path(mesh, a, b)
    gc = 10.0 * np.arccos(np.clip(v[a] @ v[b] / 100.0, -1, 1))
    assert graph_len > gc * 1.01
    fl = flow_path(mesh, vp, ea, eb)
    assert np.linalg.norm(np.diff(fl, axis=0), axis=1).sum() == pytest.approx(
        gc, rel=0.01
    )
    walk = project_walk(mesh, fl, ea, eb)
    assert walk is not None
    r = np.linalg.norm(walk.points, axis=1)
    assert r.max() <= 10.0 + 1e-9 and r.min() > 9.9  # on the inscribed mesh
    # consecutive strip faces share an edge
    fv = mesh.faces[walk.strip]
    shared = [len(set(x) & set(y)) for x, y in zip(fv[:-1].tolist(), fv[1:].tolist(), strict=True)]
    assert min(shared) >= 2


def test_tangent_step_equals_the_stacked_least_squares():
    from patternbridge.geodesic.flow import tangent_step

    rng = np.random.default_rng(11)
    p = np.cumsum(rng.normal(size=(30, 3)), axis=0)
    n = rng.normal(size=(30, 3))
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    pbar = p + rng.normal(scale=0.1, size=p.shape)
    np.testing.assert_allclose(
        tangent_step(p, n, pbar), lsq_step(p, n, pbar), atol=1e-7
    )
