"""Which way is up the body for each piece, and the turn that stands it upright.

The grain line gives the body's vertical axis (the principal axis of the
outline without one; bands run around the body, so their long axis is
horizontal). Up is the end of that axis where the outline's smooth curves are:
necklines, armholes, crotch curves and sleeve caps sit at the top of a piece,
hems are straight. A half piece cut on the fold keeps its fold edge, found on
the file's mirror line, as its centre line; the turn puts it at x = 0.
"""

from __future__ import annotations

import numpy as np

from ..library.seams import sew_line
from ..pattern.model import Piece
from .edges import turning
from .model import Orientation

__all__ = ["fold_edge", "is_strip", "is_symmetric", "orient_piece", "vertical_axis"]

#: curvature ratio below which "up" counts as uncertain
CLEAR_RATIO = 1.5
SMOOTH_DEG = 30.0
BAND_ASPECT = 5.0


def _principal(points: np.ndarray) -> np.ndarray:
    centred = points - points.mean(axis=0)
    _, _, vt = np.linalg.svd(centred, full_matrices=False)
    return vt[0]


def is_strip(piece: Piece) -> bool:
    """A long thin strip (binding, rib, band): extent ratio above ``BAND_ASPECT``."""
    pts = piece.outline
    axis = _principal(pts)
    along = pts @ axis
    across = pts @ np.array([-axis[1], axis[0]])
    return float(np.ptp(along)) > BAND_ASPECT * max(float(np.ptp(across)), 1e-9)


def vertical_axis(piece: Piece) -> np.ndarray:
    """Unit (2,) vector along the body's vertical for the piece, sign not yet decided."""
    pts = piece.outline
    if is_strip(piece):
        axis = _principal(pts)
        return np.array([-axis[1], axis[0]])
    if piece.grain_line is not None:
        d = np.diff(piece.grain_line.points, axis=0)[0]
        if np.hypot(*d) > 1e-6:
            return d / np.hypot(*d)
    return _principal(pts)


def fold_edge(piece: Piece, tol_cm: float = 0.05) -> tuple[int, int] | None:
    """(start, end) outline vertices of the longest boundary run on the mirror line, or None."""
    if piece.mirror_line is None:
        return None
    p0, p1 = piece.mirror_line.points
    d = p1 - p0
    length = np.hypot(*d)
    if length < 1e-9:
        return None
    normal = np.array([-d[1], d[0]]) / length
    on = np.abs((piece.outline - p0) @ normal) < tol_cm
    n = len(on)
    best, best_len = None, 0.0
    for s in np.nonzero(on)[0]:
        if on[(s - 1) % n]:
            continue
        e = s
        while on[(e + 1) % n] and (e + 1) % n != s:
            e = (e + 1) % n
        span = float(np.hypot(*(piece.outline[e] - piece.outline[s])))
        if span > best_len:
            best, best_len = (int(s), int(e)), span
    return best if best_len > 1.0 else None


def _end_bend(points: np.ndarray, axis: np.ndarray, top: bool) -> float:
    """Smooth turning (|angle| per vertex below ``SMOOTH_DEG``) in the third of the piece at one end."""
    h = points @ axis
    lo, hi = h.min(), h.max()
    cut = hi - (hi - lo) / 3 if top else lo + (hi - lo) / 3
    inside = h >= cut if top else h <= cut
    turn = np.abs(turning(points))
    smooth = turn < np.radians(SMOOTH_DEG)
    return float(turn[inside & smooth].sum())


def is_symmetric(points: np.ndarray, x_mid: float, tol_cm: float = 0.5) -> bool:
    """Whether the closed outline is its own mirror image across the vertical line ``x = x_mid``."""
    mirrored = points * np.array([-1.0, 1.0]) + np.array([2 * x_mid, 0.0])
    a, b = points, np.roll(points, -1, axis=0)
    ab = b - a
    t = np.clip(
        np.einsum("mkj,kj->mk", mirrored[:, None, :] - a[None], ab) / np.maximum(np.einsum("kj,kj->k", ab, ab), 1e-12),
        0.0,
        1.0,
    )
    near = a[None] + t[..., None] * ab[None]
    dist = np.linalg.norm(mirrored[:, None, :] - near, axis=-1).min(axis=1)
    return bool(np.percentile(dist, 90) < tol_cm)


def _centre_edge_x(turned: np.ndarray) -> tuple[float, bool, bool]:
    """x of the centre line of an upright piece without a fold, whether it is on the right, whether whole.

    A half piece drawn without a fold (a CLO front or back half) has a long
    straight vertical edge at one side: its centre front or back. Otherwise
    the piece is taken as whole and centred on its bounding box.
    """
    x, y = turned[:, 0], turned[:, 1]
    mid = float(x.min() + x.max()) / 2
    if is_symmetric(turned, mid):
        return mid, True, True
    d = np.roll(turned, -1, axis=0) - turned
    vertical = np.abs(d[:, 0]) < 0.02 * np.maximum(np.abs(d[:, 1]), 1e-9)
    lo, hi, height = x.min(), x.max(), np.ptp(y)
    # the longer straight vertical edge at either side is the centre (a side seam curves over the hip)
    spans = {}
    for side, edge_x in ((True, hi), (False, lo)):
        at = vertical & (np.abs(x - edge_x) < 0.01 * np.ptp(x) + 0.05)
        spans[side] = (float(np.abs(d[at, 1]).sum()), float(edge_x))
    side = max(spans, key=lambda k: spans[k][0])
    if spans[side][0] > 0.4 * height:
        return spans[side][1], side, False
    return float(lo + hi) / 2, True, False


def orient_piece(piece: Piece) -> Orientation:
    """The upright turn of one piece (see the module docstring)."""
    pts = sew_line(piece)[0]
    axis = vertical_axis(piece)
    fold = fold_edge(piece)
    if is_strip(piece):
        up, conf, why = axis, 0.9, "band: long axis horizontal"
    else:
        top, bottom = _end_bend(pts, axis, True), _end_bend(pts, axis, False)
        up = axis if top >= bottom else -axis
        ratio = max(top, bottom) / max(min(top, bottom), 1e-3)
        conf = float(np.clip(0.5 + 0.5 * (ratio - 1.0) / (CLEAR_RATIO - 1.0), 0.5, 1.0))
        why = f"curves at the top {max(top, bottom):.2f} rad vs {min(top, bottom):.2f} at the hem"
    turn = float(np.arctan2(up[0], up[1]))  # rotate ``up`` onto +y
    c, s = np.cos(turn), np.sin(turn)
    turned = pts @ np.array([[c, -s], [s, c]]).T
    whole = False
    if fold is not None:
        cx = float(turned[[fold[0], fold[1]], 0].mean())
        centre_on_right = cx >= float(turned[:, 0].mean())
    elif is_strip(piece):
        cx, centre_on_right, whole = float(turned[:, 0].min() + turned[:, 0].max()) / 2, True, True
    else:
        cx, centre_on_right, whole = _centre_edge_x(turned)
    offset = np.array([-cx, -float(turned[:, 1].min())])
    return Orientation(
        turn_rad=turn,
        offset=offset,
        fold=fold,
        centre_on_right=centre_on_right,
        whole=whole,
        confidence=conf,
        why=why,
    )
