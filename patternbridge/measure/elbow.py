"""The elbow straightened for its girth: the arms-hanging posture of the size charts.

A tailor takes the elbow girth on a standing body with the arms hanging
straight. A bent elbow (the A-pose's 35-45°, a posed character's 75°) has its
outside skin stretched over the olecranon, and its girth square to the bend
bisector is 5-8 % larger than the same elbow straightened by its own rig (B 22.5
/ 21.5 cm, C 32.2 / 29.8, E 28.0 / 26.1); A's 75° elbow 18 % larger than its 45°. :func:`straighten_elbow` unbends it
from the surface alone, so a rigged and a rigless file measure alike:

* the axes of the upper arm and the forearm are the lines through the centres
  of two sections square to each (``BodyFrame.refine_axis``), the joint is the
  mid-point of their common perpendicular and the flexion the angle between
  them;
* the forearm is the connected part of the skin beyond the plane through the
  joint square to the bend bisector, less one elbow radius (the distance from
  the joint to the elbow point): the hand and forearm only, never the torso or
  the thigh, whatever lies beyond that plane;
* its vertices turn about the joint, by the flexion times a smoothstep weight
  of their height above that plane over two elbow radii (a two-bone linear
  blend skin, the weights a rig paints round an elbow).

The section axes bend 10-14° less than the bones (a straight T-pose arm's
axes are 14° apart on C), so the surface straightening leaves some bend; the
girth is the snug tape over the elbow point, the smallest section through it
within :data:`SNUG_DEG` of square to the arm (:func:`snug_normals`), as a
tailor draws the tape where it lies shortest round the joint.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..mesh.landmark_detect import STRAIGHT_DEG
from ..mesh.skinning import rotation_about_axis

__all__ = ["SNUG_DEG", "StraightElbow", "snug_normals", "straighten_elbow"]

#: the elbow tape is drawn snug: the smallest section through the elbow point
#: whose plane lies within this many degrees of square to the straightened arm
SNUG_DEG = 10.0


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class StraightElbow:
    """One arm with its elbow straightened.

    vertices : (V, 3) float64, cm; the body with this forearm turned
    elbow : (3,) float64, cm; the elbow point carried with the forearm
    axis : (3,) unit vector; the straight arm's axis (the upper arm's)
    centre : (3,) float64, cm; the joint, on that axis
    flexion_deg : how far the elbow was bent
    """

    vertices: np.ndarray
    elbow: np.ndarray
    axis: np.ndarray
    centre: np.ndarray
    flexion_deg: float


def _joint(c0: np.ndarray, u0: np.ndarray, c1: np.ndarray, u1: np.ndarray) -> np.ndarray:
    """Mid-point of the common perpendicular of two lines (point + unit direction)."""
    w = c0 - c1
    b = float(u0 @ u1)
    d, e = float(u0 @ w), float(u1 @ w)
    den = 1.0 - b * b
    s = (b * e - d) / den
    t = (e - b * d) / den
    return 0.5 * ((c0 + s * u0) + (c1 + t * u1))


def _forearm(vertices: np.ndarray, faces: np.ndarray, beyond: np.ndarray, seed: int) -> np.ndarray:
    """Mask of the vertices connected to ``seed`` through vertices where ``beyond`` holds."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    e = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    e = e[beyond[e[:, 0]] & beyond[e[:, 1]]]
    n = len(vertices)
    graph = coo_matrix((np.ones(len(e)), (e[:, 0], e[:, 1])), shape=(n, n))
    _, label = connected_components(graph, directed=False)
    return beyond & (label == label[seed])


def straighten_elbow(
    vertices: np.ndarray,
    faces: np.ndarray,
    *,
    upper: tuple[np.ndarray, np.ndarray],
    lower: tuple[np.ndarray, np.ndarray],
    elbow: np.ndarray,
    wrist: np.ndarray,
) -> StraightElbow | None:
    """The body with one elbow straightened, or None when it is straight already.

    Parameters
    ----------
    vertices : (V, 3) float64, cm
    faces : (F, 3) int64; the arm's faces are enough (only vertices of these move)
    upper, lower : (point, unit direction) of the upper-arm and forearm axes,
        pointing from the shoulder toward the hand
    elbow, wrist : (3,) the elbow point and the wrist point, cm

    Returns
    -------
    :class:`StraightElbow`, or None for an elbow flexed less than
    ``STRAIGHT_DEG`` (its axes' angle is then the biceps and forearm bulges).
    """
    (c_up, u_up), (c_lo, u_lo) = upper, lower
    flex = float(np.arccos(np.clip(u_up @ u_lo, -1.0, 1.0)))
    if np.degrees(flex) < STRAIGHT_DEG:
        return None
    joint = _joint(c_up, u_up, c_lo, u_lo)
    bisector = (u_up + u_lo) / np.linalg.norm(u_up + u_lo)
    radius = max(float(np.linalg.norm(elbow - joint)), 1e-3)
    v = np.asarray(vertices, dtype=np.float64)
    used = np.unique(faces)
    height = np.full(len(v), -np.inf)
    height[used] = (v[used] - joint) @ bisector
    seed = int(used[np.argmin(np.sum((v[used] - wrist) ** 2, axis=1))])
    region = _forearm(v, faces, height > -radius, seed)
    ids = np.flatnonzero(region)
    w = np.clip((height[ids] + radius) / (2.0 * radius), 0.0, 1.0)
    w = w * w * (3.0 - 2.0 * w)
    turn = rotation_about_axis(np.cross(u_lo, u_up), flex)  # takes u_lo onto u_up
    moved = v.copy()
    moved[ids] += w[:, None] * ((v[ids] - joint) @ turn.T + joint - v[ids])
    h_el = float((elbow - joint) @ bisector)
    w_el = float(np.clip((h_el + radius) / (2.0 * radius), 0.0, 1.0))
    w_el = w_el * w_el * (3.0 - 2.0 * w_el)
    el = elbow + w_el * ((elbow - joint) @ turn.T + joint - elbow)
    return StraightElbow(vertices=moved, elbow=el, axis=u_up, centre=joint, flexion_deg=float(np.degrees(flex)))


def snug_normals(normal: np.ndarray, max_deg: float = SNUG_DEG, steps: int = 5) -> np.ndarray:
    """Unit plane normals tilted up to ``max_deg`` from ``normal`` about two axes square to it.

    A ``steps`` x ``steps`` grid of tilts (``normal`` itself in the middle for
    an odd ``steps``); (steps * steps, 3).
    """
    n = np.asarray(normal, dtype=np.float64)
    n = n / np.linalg.norm(n)
    a = np.cross(n, np.eye(3)[int(np.argmin(np.abs(n)))])
    a /= np.linalg.norm(a)
    b = np.cross(n, a)
    t = np.tan(np.radians(np.linspace(-max_deg, max_deg, steps)))
    ta, tb = np.meshgrid(t, t, indexing="ij")
    out = n + ta.reshape(-1, 1) * a + tb.reshape(-1, 1) * b
    return out / np.linalg.norm(out, axis=1, keepdims=True)
