"""Cloth test meshes shared by the solver and untangling tests."""

from __future__ import annotations

import numpy as np


def sheet(n: int, size: float) -> tuple[np.ndarray, np.ndarray]:
    """A square sheet of 2n² triangles, ``size`` cm wide: (pattern points (P, 2), faces (F, 3))."""
    s = np.linspace(0.0, size, n + 1)
    u, v = np.meshgrid(s, s, indexing="ij")
    pts = np.stack([u.ravel(), v.ravel()], axis=1)
    idx = np.arange((n + 1) ** 2).reshape(n + 1, n + 1)
    a, b, c, d = idx[:-1, :-1].ravel(), idx[1:, :-1].ravel(), idx[1:, 1:].ravel(), idx[:-1, 1:].ravel()
    return pts, np.concatenate([np.stack([a, b, c], 1), np.stack([a, c, d], 1)])
