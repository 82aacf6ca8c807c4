"""Skin weights of garment vertices, transferred from the nearest body points."""

from __future__ import annotations

import numpy as np

from ..mesh.character import Character

__all__ = ["transfer_weights"]


def transfer_weights(collider, character: Character, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Skin weights at ``points`` from the nearest body surface points.

    The weights of the three corners of the closest body triangle are blended
    with the barycentric coordinates of the closest point; the four largest
    are kept and renormalised.

    Parameters
    ----------
    collider : :class:`~patternbridge.assemble.collision.BodyCollider` of the
        character's body (any pose: only the triangle and the barycentric
        coordinates are used)
    character : the rigged character
    points : (n, 3) float64, cm

    Returns
    -------
    joints : (n, 4) int64 (-1 unused) ; weights : (n, 4) float64, rows sum to 1
    """
    _, _, _, tri, uv = collider.closest(points)
    tri = np.maximum(tri, 0)
    corners = character.faces[tri]  # (n, 3)
    bary = np.stack([1.0 - uv[:, 0] - uv[:, 1], uv[:, 0], uv[:, 1]], axis=1)
    idx = character.skin.bone_indices[corners]  # (n, 3, K)
    w = np.where(idx >= 0, character.skin.weights[corners], 0.0) * bary[:, :, None]
    n, _, k = idx.shape
    idx = idx.reshape(n, 3 * k)
    w = w.reshape(n, 3 * k)
    # merge duplicate bones: sort by bone, sum runs
    order = np.argsort(idx, axis=1, kind="stable")
    idx = np.take_along_axis(idx, order, axis=1)
    w = np.take_along_axis(w, order, axis=1)
    start = np.ones_like(idx, dtype=bool)
    start[:, 1:] = idx[:, 1:] != idx[:, :-1]
    run = np.cumsum(start, axis=1) - 1
    rows = np.repeat(np.arange(n), 3 * k)
    summed = np.zeros_like(w)
    np.add.at(summed, (rows, run.ravel()), w.ravel())
    bones = np.full_like(idx, -1)
    bones[rows[start.ravel()], run[start]] = idx[start]
    summed = np.where(bones >= 0, summed, 0.0)
    top = np.argsort(-summed, axis=1, kind="stable")[:, :4]
    joints = np.take_along_axis(bones, top, axis=1)
    weights = np.take_along_axis(summed, top, axis=1)
    weights = np.where(joints >= 0, weights, 0.0)
    total = weights.sum(axis=1, keepdims=True)
    bad = total[:, 0] <= 0
    weights = weights / np.where(total > 0, total, 1.0)
    if bad.any():  # no weight at all: bind to the root
        joints[bad] = -1
        joints[bad, 0] = 0
        weights[bad] = 0.0
        weights[bad, 0] = 1.0
    return joints.astype(np.int64), weights
