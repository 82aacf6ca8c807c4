"""Notches: type by layer, position on the boundary, direction from the boundary.

Real files put notches as POINTs on layer 4 (slit/V) or 80-83 (T, castle,
check, U) with depth in group 30, width in 39 and an angle in 50 whose meaning
differs per producer; Seamly2D writes short LINEs on layer 4. The reader snaps
each notch to the boundary vertex it sits on (inserting a vertex when it falls
inside an edge) and recomputes its direction as the inward bisector there.
"""

from __future__ import annotations

import numpy as np

from ...pattern.grading import inward_angles
from ...pattern.model import NotchType
from .layers import NOTCH_TYPE_BY_LAYER

__all__ = ["inward_angles", "locate_on_boundary", "notch_type"]


def notch_type(layer: int, width: float = 0.0) -> NotchType:
    """Notch type of a notch on ``layer``; layer 4 with a width is a V notch.

    Examples
    --------
    >>> str(notch_type(4)), str(notch_type(4, 0.3)), str(notch_type(80))
    ('slit', 'V', 'T')
    """
    t = NOTCH_TYPE_BY_LAYER.get(int(layer), NotchType.SLIT)
    if t is NotchType.SLIT and abs(width) > 0:
        return NotchType.V
    return t


def locate_on_boundary(outline: np.ndarray, point: np.ndarray, tol: float) -> tuple[int, float, float]:
    """Where ``point`` sits on a closed outline.

    Returns
    -------
    (edge, t, distance)
        ``edge`` is the index of the edge's first vertex, ``t`` in [0, 1] the
        position along it (0 or 1 when the point is within ``tol`` of a
        vertex), ``distance`` how far the point is from the boundary.
    """
    outline = np.asarray(outline, dtype=np.float64)
    point = np.asarray(point, dtype=np.float64)
    d_vert = np.linalg.norm(outline - point, axis=1)
    i = int(np.argmin(d_vert))
    if d_vert[i] <= tol:
        return i, 0.0, float(d_vert[i])
    a = outline
    b = np.roll(outline, -1, axis=0)
    ab = b - a
    denom = np.einsum("ij,ij->i", ab, ab)
    t = np.where(denom > 0, np.einsum("ij,ij->i", point - a, ab) / np.where(denom > 0, denom, 1), 0.0)
    t = np.clip(t, 0.0, 1.0)
    proj = a + t[:, None] * ab
    dist = np.linalg.norm(proj - point, axis=1)
    e = int(np.argmin(dist))
    return e, float(t[e]), float(dist[e])
