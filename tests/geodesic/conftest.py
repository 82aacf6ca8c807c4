"""Small analytic meshes for the geodesic tests (planes, cylinders, spheres)."""

from __future__ import annotations

import numpy as np
import pytest


def grid(n: int = 21, size: float = 20.0, jitter: float = 0.0, seed: int = 0):
    """Triangulated square [0, size]^2 at z = 0: (V, 3), (F, 3), index grid."""
    rng = np.random.default_rng(seed)
    t = np.linspace(0.0, size, n)
    x, y = np.meshgrid(t, t)
    v = np.c_[x.ravel(), y.ravel(), np.zeros(n * n)]
    if jitter:
        inner = (
            (x.ravel() > 0) & (x.ravel() < size) & (y.ravel() > 0) & (y.ravel() < size)
        )
        step = size / (n - 1)
        v[inner, :2] += rng.uniform(-jitter, jitter, (int(inner.sum()), 2)) * step
    idx = np.arange(n * n).reshape(n, n)
    a, b = idx[:-1, :-1].ravel(), idx[:-1, 1:].ravel()
    c, d = idx[1:, :-1].ravel(), idx[1:, 1:].ravel()
    f = np.r_[np.c_[a, b, d], np.c_[a, d, c]]
    return v, f, idx


def cylinder(
    radius: float = 5.0, height: float = 20.0, n_around: int = 48, n_up: int = 25
):
    """Open cylinder around the z axis: (V, 3), (F, 3), index grid (up, around)."""
    th = np.linspace(0.0, 2 * np.pi, n_around, endpoint=False)
    z = np.linspace(0.0, height, n_up)
    tt, zz = np.meshgrid(th, z)
    v = np.c_[radius * np.cos(tt.ravel()), radius * np.sin(tt.ravel()), zz.ravel()]
    idx = np.arange(n_up * n_around).reshape(n_up, n_around)
    a = idx[:-1, :].ravel()
    b = np.roll(idx, -1, axis=1)[:-1, :].ravel()
    c = idx[1:, :].ravel()
    d = np.roll(idx, -1, axis=1)[1:, :].ravel()
    f = np.r_[np.c_[a, b, d], np.c_[a, d, c]]
    return v, f, idx


@pytest.fixture(scope="session")
def shapes():
    """Builders of analytic meshes: ``shapes.grid(...)``, ``shapes.cylinder(...)``."""
    from types import SimpleNamespace

    return SimpleNamespace(grid=grid, cylinder=cylinder)


@pytest.fixture(scope="module")
def sphere():
    """Icosphere of radius 10 cm (2562 vertices) projected exactly onto the sphere."""
    import trimesh

    s = trimesh.creation.icosphere(subdivisions=4, radius=10.0)
    v = np.asarray(s.vertices, dtype=np.float64)
    v = 10.0 * v / np.linalg.norm(v, axis=1)[:, None]
    return v, np.asarray(s.faces, dtype=np.int64)
