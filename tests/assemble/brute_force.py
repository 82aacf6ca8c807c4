"""Crossing triangles counted by brute force, independent of the solver's and the report's searches."""

from __future__ import annotations

import numpy as np


def crossing_triangles(x: np.ndarray, faces: np.ndarray, label: np.ndarray | None = None, block: int = 256) -> int:
    """Triangles an edge of another triangle (sharing no vertex with it) passes through, or that are passed.

    Every edge of every triangle against every triangle, in blocks of edges, the plane and the inside tested in
    closed form. ``label`` (V,) welds vertices into one (the two sides of a seam); by default every vertex is its
    own.
    """
    label = np.arange(len(x)) if label is None else np.asarray(label)
    ends = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    owner = np.tile(np.arange(len(faces)), 3)
    a, b, c = (x[faces[:, k]][None] for k in range(3))
    n = np.cross(b - a, c - a)
    lf = label[faces]
    hit = np.zeros(len(faces), dtype=bool)
    for s in range(0, len(ends), block):
        e = ends[s : s + block]
        p, q = x[e[:, 0]][:, None], x[e[:, 1]][:, None]
        dp = np.sum((p - a) * n, axis=2)
        dq = np.sum((q - a) * n, axis=2)
        inside = dp * dq < 0
        m = p + (dp / np.where(inside, dp - dq, 1.0))[:, :, None] * (q - p)
        for u, v in ((a, b), (b, c), (c, a)):
            inside &= np.sum(np.cross(v - u, m - u) * n, axis=2) > 0
        inside &= ~(label[e][:, None, :, None] == lf[None, :, None, :]).any(axis=(2, 3))
        ei, ti = np.nonzero(inside)
        hit[ti] = True
        hit[owner[s + ei]] = True
    return int(np.count_nonzero(hit))
