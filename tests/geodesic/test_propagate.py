"""Single source, all destinations (wavefront propagation with curvature flow)."""

from __future__ import annotations

import numpy as np
import pytest

from patternbridge.errors import MeshError
from patternbridge.geodesic import SurfaceMesh, geodesic_distances
from patternbridge.geodesic.propagate import solve_windows


def test_full_form_is_exact_on_a_plane(shapes):
    v, f, idx = shapes.grid(15, size=14.0, jitter=0.2, seed=7)
    mesh = SurfaceMesh(v, f)
    src = int(idx[7, 7])
    d = geodesic_distances(mesh, src, window="full")
    np.testing.assert_allclose(d, np.linalg.norm(v - v[src], axis=1), atol=1e-9)


def test_windowed_error_on_a_plane(shapes):
    v, f, idx = shapes.grid(31, size=30.0, jitter=0.2, seed=8)
    mesh = SurfaceMesh(v, f)
    src = int(idx[15, 15])
    exact = np.linalg.norm(v - v[src], axis=1)
    far = exact > 3.0
    errs = {}
    for w in (4, 16):
        d = geodesic_distances(mesh, src, window=w)
        errs[w] = np.mean(np.abs(d[far] - exact[far]) / exact[far])
        assert np.all(d[far] >= exact[far] - 1e-9)  # paths on the plane are never short
    assert errs[16] < errs[4]
    assert errs[16] < 0.015


def test_windowed_error_on_a_sphere(sphere):
    v, f = sphere
    mesh = SurfaceMesh(v, f)
    gc = 10.0 * np.arccos(np.clip(v @ v[0] / 100.0, -1, 1))
    d = geodesic_distances(mesh, 0)
    ok = gc > 1.0
    assert d[0] == 0.0
    assert np.mean(np.abs(d[ok] - gc[ok]) / gc[ok]) < 0.02


def test_r_max_limits_the_propagation(sphere):
    v, f = sphere
    mesh = SurfaceMesh(v, f)
    d = geodesic_distances(mesh, 0, r_max=5.0, window=6)
    gc = 10.0 * np.arccos(np.clip(v @ v[0] / 100.0, -1, 1))
    assert np.all(np.isinf(d[gc > 6.0]))
    assert np.all(np.isfinite(d[gc < 4.5]))


def test_other_component_is_unreached(shapes):
    v, f, _ = shapes.grid(6)
    mesh = SurfaceMesh(np.r_[v, v + [0, 0, 5.0]], np.r_[f, f + len(v)])
    d = geodesic_distances(mesh, 0, window=5)
    assert np.all(np.isfinite(d[: len(v)])) and np.all(np.isinf(d[len(v) :]))


def test_bad_arguments(shapes):
    v, f, _ = shapes.grid(5)
    mesh = SurfaceMesh(v, f)
    with pytest.raises(MeshError, match="window"):
        geodesic_distances(mesh, 0, window=2)
    with pytest.raises(MeshError, match="window"):
        geodesic_distances(mesh, 0, window="half")
    with pytest.raises(MeshError, match="r_max"):
        geodesic_distances(mesh, 0, r_max=-1.0)
    with pytest.raises(MeshError, match="SurfaceMesh"):
        geodesic_distances((v, f), 0)
    with pytest.raises(MeshError, match="out of range"):
        geodesic_distances(mesh, 10_000)


def test_batched_window_solve_matches_lsq():
    from patternbridge.geodesic.flow import lsq_step

    rng = np.random.default_rng(9)
    w = 7
    pts = np.cumsum(rng.normal(size=(3, w, 3)), axis=1)
    nrm = rng.normal(size=(3, w, 3))
    nrm /= np.linalg.norm(nrm, axis=2, keepdims=True)
    free = np.ones((3, w), dtype=bool)
    free[:, [0, -1]] = False
    out = solve_windows(pts, nrm, pts, free)
    for b in range(3):
        np.testing.assert_allclose(out[b], lsq_step(pts[b], nrm[b], pts[b]), atol=1e-8)


@pytest.mark.parametrize("w", [7, 30])
def test_block_solvers_agree_and_match_lsq(w):
    """Short windows are solved densely, long ones by block elimination: both
    give the least-squares flow step, with given or derived tangent bases."""
    from patternbridge.geodesic import propagate
    from patternbridge.geodesic.flow import lsq_step

    rng = np.random.default_rng(w)
    pts = np.cumsum(rng.normal(size=(4, w, 3)), axis=1)
    nrm = rng.normal(size=(4, w, 3))
    nrm /= np.linalg.norm(nrm, axis=2, keepdims=True)
    free = np.ones((4, w), dtype=bool)
    free[:, [0, -1]] = False
    free[1, : w // 2] = False  # a window still filling up
    t1, t2 = propagate._tangent_bases(nrm)
    tng = np.stack([t1, t2], axis=-1)
    out = solve_windows(pts, nrm, pts, free)
    np.testing.assert_allclose(solve_windows(pts, nrm, pts, free, tangents=tng), out)
    old = propagate._DENSE_W
    try:
        propagate._DENSE_W = 0 if w <= old else 10_000  # the other solver
        other = solve_windows(pts, nrm, pts, free)
    finally:
        propagate._DENSE_W = old
    np.testing.assert_allclose(other, out, atol=1e-9)
    np.testing.assert_allclose(out[0], lsq_step(pts[0], nrm[0], pts[0]), atol=1e-8)
    np.testing.assert_array_equal(out[1, : w // 2], pts[1, : w // 2])  # fixed stay
