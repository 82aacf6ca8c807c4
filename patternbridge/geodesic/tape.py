"""Tape correction: a real tape bridges concave stretches instead of following them.

A point of a surface path is concave when its curve normal (the turn of the
unit tangent between ``p_{i-1} -> p_i`` and ``p_i -> p_{i+1}``) agrees with the
outward surface normal: the skin curves away under the tape there. Such points
are moved onto the line through their neighbours until none is left; a run of
consecutive concave points goes at once onto the chord between the points
around it (kept in arc-length order), which reaches the taut state in a few
sweeps. Points of an exempt section (a bent elbow, say) stay on the skin.
"""

from __future__ import annotations

import numpy as np

from ..errors import MeshError

__all__ = ["exempt_mask", "tape_correct"]


def exempt_mask(points: np.ndarray, exempt) -> np.ndarray:
    """(k,) bool mask of exempt points.

    Parameters
    ----------
    points : (k, 3) float64, cm
    exempt : None, a (k,) bool mask, or a sequence of ``(start, stop)`` fractions
        of the path length in [0, 1]
    """
    k = len(points)
    if exempt is None:
        return np.zeros(k, dtype=bool)
    arr = np.asarray(exempt)
    if arr.dtype == bool:
        if arr.shape != (k,):
            raise MeshError(
                f"tape: exempt mask has shape {arr.shape}, expected ({k},); "
                "pass one flag per path point or (start, stop) fractions"
            )
        return arr.copy()
    arr = np.asarray(exempt, dtype=np.float64).reshape(-1, 2) if arr.size else np.zeros((0, 2))
    if np.any(arr < 0) or np.any(arr > 1) or np.any(arr[:, 0] > arr[:, 1]):
        raise MeshError(
            f"tape: exempt sections {arr.tolist()} are not (start, stop) "
            "fractions with 0 <= start <= stop <= 1; fix the sections"
        )
    seg = np.linalg.norm(np.diff(points, axis=0), axis=1)
    s = np.concatenate([[0.0], np.cumsum(seg)])
    t = s / s[-1] if s[-1] > 0 else np.zeros(k)
    mask = np.zeros(k, dtype=bool)
    for a, b in arr:
        mask |= (t >= a) & (t <= b)
    return mask


def _curve_normals(p: np.ndarray) -> np.ndarray:
    """(k, 3) turning of the unit tangents at each point (zero at the ends): the curve normal, free of the spacing.

    Examples
    --------
    >>> _curve_normals(np.array([[0.0, 0, 0], [1, -1, 0], [2, 0, 0]])).round(6).tolist()
    [[0.0, 0.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, 0.0]]
    """
    d = np.diff(p, axis=0)
    ln = np.linalg.norm(d, axis=1)
    u = d / np.where(ln > 0, ln, 1.0)[:, None]
    c = np.zeros_like(p)
    c[1:-1] = (u[1:] - u[:-1]) * np.minimum(ln[1:], ln[:-1])[:, None]
    return c


def _runs(mask: np.ndarray) -> tuple[list[int], list[int]]:
    """Starts and stops (exclusive) of the runs of True in ``mask``.

    Examples
    --------
    >>> _runs(np.array([False, True, True, False, True]))
    ([1, 4], [3, 5])
    """
    edge = np.diff(np.r_[0, mask.astype(np.int8), 0])
    return np.flatnonzero(edge == 1).tolist(), np.flatnonzero(edge == -1).tolist()


def _chord(p: np.ndarray, i: int, j: int) -> np.ndarray:
    """(j - i, 3) points i..j-1 moved onto the chord between points i-1 and j, spaced as along the path."""
    a, b = p[i - 1], p[j]
    s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(p[i - 1 : j + 1], axis=0), axis=1))])
    t = s[1:-1] / s[-1] if s[-1] > 0 else np.zeros(j - i)
    return a + t[:, None] * (b - a)


def _sweep(p: np.ndarray, n: np.ndarray, fixed: np.ndarray, moved: np.ndarray, tol_cm: float) -> bool:
    """One sweep: each run of concave points becomes the chord between the points around it.

    Runs grow over points already on a straight span, so that a span is
    re-straightened as a whole when its ends turn concave. ``p`` and
    ``moved`` are updated in place; False when no point is concave.
    """
    c = _curve_normals(p)
    concave = (np.einsum("ij,ij->i", c, n) > tol_cm) & ~fixed
    if not concave.any():
        return False
    flat = moved & (np.linalg.norm(c, axis=1) <= tol_cm) & ~fixed
    for i, j in zip(*_runs(concave | flat), strict=True):
        if not concave[i:j].any():
            continue
        p[i:j] = _chord(p, i, j)
        moved[i:j] = True
    return True


def _on_straight_spans(p: np.ndarray, moved: np.ndarray, fixed: np.ndarray) -> np.ndarray:
    """(k,) bool, the points to keep: a moved point on the straight span between its neighbours goes."""
    k = len(p)
    keep = np.ones(k, dtype=bool)
    i = 1
    last = 0
    while i < k - 1:
        if moved[i] and not fixed[i]:
            a, b = p[last], p[i + 1]
            d = b - a
            dd = float(d @ d)
            t = float((p[i] - a) @ d) / dd if dd > 0 else 0.0
            if np.linalg.norm(a + t * d - p[i]) < 1e-9:
                keep[i] = False
                i += 1
                continue
        last = i
        i += 1
    return keep


def tape_correct(points, normals, exempt=None, *, tol_cm: float = 1e-6, max_sweeps: int | None = None) -> np.ndarray:
    """Straighten the concave stretches of a path like a taut tape.

    Parameters
    ----------
    points : (k, 3) float64, cm, a path on the surface
    normals : (k, 3) float64, outward unit surface normals at the points
    exempt : None, (k,) bool mask, or sequence of (start, stop) length fractions
        of sections that stay on the skin
    tol_cm : a point is concave when its curve normal has more than this
        component along the surface normal
    max_sweeps : cap on the sweeps (default ``4 k``)

    Returns
    -------
    (k', 3) float64, cm: the corrected path; points left exactly on a straight
    span between their neighbours are dropped (the ends always stay).

    Examples
    --------
    >>> import numpy as np
    >>> p = np.array([[0.0, 0, 0], [1, -1, 0], [2, 0, 0]])
    >>> n = np.tile([0.0, 1, 0], (3, 1))
    >>> tape_correct(p, n).tolist()
    [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0]]
    """
    p = np.array(points, dtype=np.float64)
    n = np.array(normals, dtype=np.float64)
    if p.ndim != 2 or p.shape[1] != 3 or n.shape != p.shape:
        raise MeshError(f"tape: points {p.shape} and normals {n.shape} must both be (k, 3); pass one normal per point")
    fixed = exempt_mask(p, exempt)
    step = np.ones(len(p), dtype=bool)  # drop repeated points
    step[1:] = np.linalg.norm(np.diff(p, axis=0), axis=1) > 0
    step[-1] = True
    p, n, fixed = p[step], n[step], fixed[step]
    k = len(p)
    if k < 3:
        return p
    fixed[[0, -1]] = True
    moved = np.zeros(k, dtype=bool)
    for _ in range(max_sweeps or 4 * k):
        if not _sweep(p, n, fixed, moved, tol_cm):
            break
    return p[_on_straight_spans(p, moved, fixed)]
