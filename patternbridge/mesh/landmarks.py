"""Datum points (landmarks): from a file, from the skeleton's joints, or detected from the geometry.

:func:`resolve_landmarks` fills the table of :data:`LANDMARK_NAMES` in three
passes, each only for names still missing, and records the source of every
point (``"file"``, ``"skeleton"``, ``"detected"``):

1. the character's own landmarks (sidecar JSON or ``--landmarks FILE``);
2. the skeleton, when the character is rigged: each joint is projected to the
   skin along a documented direction (:data:`SKELETON_RULES`);
3. detection from the geometry alone (:func:`detect_landmarks`), for an upright
   humanoid in cm, +Y up, facing +Z, left = +X, arms in A- or T-pose.

The detection rules (``docs/measurements.md`` gives the errors against the
reference tables of the six test characters):

* ``top_of_head``: the highest vertex.
* ``crotch_point``: scanning horizontal sections down from mid-height, the
  first level where the body splits into two legs; the lowest midline vertex
  just above it.
* ``armpit_point_*``: scanning up from the crotch, the level where the torso
  section merges with the arm (its lateral extent jumps); the lowest vertex
  above the gap between torso and arm.
* ``axilla_front_*``/``axilla_back_*``: front-most / back-most point of the
  section 1.1 % of stature above the armpit, at the armpit's x.
* ``shoulder_point_*``: the highest vertex 1.2 % of stature outside the armpit.
* ``front_neck_point``/``back_neck_point``/``neck_shoulder_point_*``: from the
  narrowest section between the shoulders and the head: the midline front
  point deepest behind the chord of the front profile, the midline back point
  at the neck-base level, and the neck/shoulder corner of the frontal contour
  (in the plane half-way between the back and front neck points).
* waist, bust and hip points: the narrowest torso section (waist) and the
  widest above (chest) and below it (hip), with the front / back / lateral
  extreme points of those sections.
* ``wrist_point_*``, ``elbow_point_*``: along the line shoulder point to
  fingertip, the narrowest perpendicular section before the hand (wrist, back
  side of it), and the section where the arm's centre line bends most (elbow,
  outer side of the bend).
* ``knee_point_*``: the front-most leg vertex within 1.1 % of stature of 60 %
  of the height from ankle to crotch.
* ``ankle_*``: the lowest level where the leg section is no longer a foot
  (front-to-back extent below 1.6 times its width), its medial and lateral
  extreme points; ``heel_point_*``: the back-most vertex below it.
"""

from __future__ import annotations

import logging
from collections.abc import Mapping

import numpy as np

from ..errors import InputError, LandmarkError
from .character import Character, Landmark

__all__ = [
    "LANDMARK_NAMES",
    "SKELETON_RULES",
    "detect_landmarks",
    "resolve_landmarks",
    "skeleton_landmarks",
]

log = logging.getLogger(__name__)

#: The landmark vocabulary (as in ``shared/characters/landmarks.json``); left = +X.
LANDMARK_NAMES: tuple[str, ...] = (
    "top_of_head",
    "front_neck_point",
    "back_neck_point",
    "neck_shoulder_point_left",
    "neck_shoulder_point_right",
    "shoulder_point_left",
    "shoulder_point_right",
    "armpit_point_left",
    "armpit_point_right",
    "axilla_front_left",
    "axilla_front_right",
    "axilla_back_left",
    "axilla_back_right",
    "bust_point_left",
    "bust_point_right",
    "waist_front",
    "waist_back",
    "waist_side_left",
    "waist_side_right",
    "buttock_point_left",
    "buttock_point_right",
    "hip_side_left",
    "hip_side_right",
    "crotch_point",
    "elbow_point_left",
    "elbow_point_right",
    "wrist_point_left",
    "wrist_point_right",
    "knee_point_left",
    "knee_point_right",
    "ankle_inside_left",
    "ankle_inside_right",
    "ankle_outside_left",
    "ankle_outside_right",
    "heel_point_left",
    "heel_point_right",
)

_SIGN = {"left": 1.0, "right": -1.0}


def _nearest_vertex(vertices: np.ndarray, p: np.ndarray) -> int:
    return int(np.argmin(np.sum((vertices - p) ** 2, axis=1)))


def _ray_hit(
    vertices: np.ndarray, origin: np.ndarray, direction: np.ndarray, radius: float
) -> int | None:
    """The first vertex met by a thick ray: nearest along it among those within ``radius``."""
    d = direction / np.linalg.norm(direction)
    rel = vertices - origin
    t = rel @ d
    perp2 = np.sum(rel * rel, axis=1) - t * t
    ok = (t > 0) & (perp2 <= radius * radius)
    if not ok.any():
        return None
    idx = np.flatnonzero(ok)
    return int(idx[np.argmin(t[idx])])


def _faces_near(
    vertices: np.ndarray, faces: np.ndarray, a: np.ndarray, b: np.ndarray, radius: float
) -> np.ndarray:
    ab = b - a
    t = np.clip((vertices - a) @ ab / max(float(ab @ ab), 1e-12), 0.0, 1.0)
    near = np.sum((vertices - (a + t[:, None] * ab)) ** 2, axis=1) <= radius * radius
    return np.flatnonzero(near[faces].any(axis=1))


# --------------------------------------------------------------------------- skeleton
#: landmark -> (bone role, side or None, "head"/"tail", projection direction in the rest frame)
SKELETON_RULES: dict[str, tuple[str, str | None, str, tuple[float, float, float]]] = {
    **{
        f"shoulder_point_{s}": ("upperarm", s, "head", (0.0, 1.0, 0.0))
        for s in ("left", "right")
    },
    **{
        f"armpit_point_{s}": ("upperarm", s, "head", (0.0, -1.0, 0.0))
        for s in ("left", "right")
    },
    **{
        f"elbow_point_{s}": ("lowerarm", s, "head", (0.0, 0.0, -1.0))
        for s in ("left", "right")
    },
    **{
        f"wrist_point_{s}": ("wrist", s, "head", (0.0, 0.0, -1.0))
        for s in ("left", "right")
    },
    **{
        f"knee_point_{s}": ("lowerleg", s, "head", (0.0, 0.0, 1.0))
        for s in ("left", "right")
    },
    **{
        f"ankle_inside_{s}": ("foot", s, "head", (-_SIGN[s], 0.0, 0.0))
        for s in ("left", "right")
    },
    **{
        f"ankle_outside_{s}": ("foot", s, "head", (_SIGN[s], 0.0, 0.0))
        for s in ("left", "right")
    },
    **{
        f"heel_point_{s}": ("foot", s, "head", (0.0, -0.5, -1.0))
        for s in ("left", "right")
    },
    "back_neck_point": ("neck", None, "head", (0.0, 0.0, -1.0)),
    "front_neck_point": ("neck", None, "head", (0.0, -0.45, 1.0)),
    "crotch_point": (
        "pelvis",
        None,
        "head",
        (0.0, -1.0, 0.0),
    ),  # from between the hip joints
}


def skeleton_landmarks(character: Character) -> dict[str, Landmark]:
    """Landmarks from the skeleton's joints projected to the skin (:data:`SKELETON_RULES`).

    The elbow point is projected to the outer side of the elbow's bend when the
    arm is bent (the direction from the forearm toward the upper arm), else
    backwards. Joints the skeleton does not have are skipped.
    """
    from .skinning import find_bone

    sk = character.skeleton
    if sk is None:
        return {}
    v = character.vertices
    radius = 0.008 * character.stature_cm
    out: dict[str, Landmark] = {}
    for name, (role, side, end, direction) in SKELETON_RULES.items():
        try:
            b = find_bone(sk, role, side)
        except InputError:
            continue
        joint = sk.heads[b] if end == "head" else sk.tails[b]
        d = np.asarray(direction, dtype=np.float64)
        if name == "crotch_point":  # between the hip joints, not at the pelvis root
            try:
                joint = 0.5 * (
                    sk.heads[find_bone(sk, "upperleg", "left")]
                    + sk.heads[find_bone(sk, "upperleg", "right")]
                )
            except InputError:
                pass
        if name.startswith("elbow_point"):
            try:
                ua = find_bone(sk, "upperarm", side)
                wr = find_bone(sk, "wrist", side)
                u = joint - sk.heads[ua]
                f = sk.heads[wr] - joint
                bend = u / np.linalg.norm(u) - f / np.linalg.norm(f)
                if np.linalg.norm(bend) > 0.2:
                    d = bend
            except InputError:
                pass
        hit = _ray_hit(v, joint, d, radius)
        if hit is not None:
            out[name] = Landmark(
                name=name, position=v[hit], vertex=hit, source="skeleton"
            )
    return out


# --------------------------------------------------------------------------- geometry
class _Scan:
    """Horizontal sections on demand, with cached loops."""

    def __init__(self, vertices: np.ndarray, faces: np.ndarray) -> None:
        from ..measure.section import SlabIndex

        self.v, self.f = vertices, faces
        self.floor = float(vertices[:, 1].min())
        self.top = float(vertices[:, 1].max())
        self.S = self.top - self.floor
        self.slabs = SlabIndex(
            vertices, faces, axis=1, slab_cm=max(self.S / 200.0, 0.1)
        )
        lo, hi = vertices[:, 0].min(), vertices[:, 0].max()
        self.x_mid = float(0.5 * (lo + hi))

    def loops(self, y: float):
        from ..measure.section import plane_loops

        sec = plane_loops(
            self.v,
            self.f,
            np.array([0.0, y, 0.0]),
            np.array([0.0, 1.0, 0.0]),
            candidates=self.slabs.faces_at(y),
        )
        return [lp.points for lp in sec.loops if len(lp.points) >= 3]


def _torso_loop(loops, x_mid: float):
    """The loop spanning the midline (or nearest to it)."""
    if not loops:
        return None
    spanning = [p for p in loops if p[:, 0].min() <= x_mid <= p[:, 0].max()]
    pool = spanning or loops
    return (
        max(pool, key=len)
        if spanning
        else min(pool, key=lambda p: abs(p[:, 0].mean() - x_mid))
    )


def detect_landmarks(vertices: np.ndarray, faces: np.ndarray) -> dict[str, Landmark]:
    """Detect the datum points of an upright humanoid from its geometry alone.

    Parameters
    ----------
    vertices : (V, 3) float64, cm, +Y up, facing +Z, left = +X
    faces : (F, 3) int64

    Returns
    -------
    name -> Landmark with source ``"detected"`` (names that could not be
    found are absent).
    """
    from ..measure.girths import BodyFrame, torso_levels

    v = np.asarray(vertices, dtype=np.float64)
    sc = _Scan(v, faces)
    S, floor, xm = sc.S, sc.floor, sc.x_mid
    step = S / 300.0
    pts: dict[str, np.ndarray] = {}

    def put(name: str, p: np.ndarray) -> None:
        pts[name] = np.asarray(p, dtype=np.float64)

    top_i = int(np.argmax(v[:, 1]))
    put("top_of_head", v[top_i])

    # -- crotch: first level (going down) where the lower body splits into two legs
    y_crotch = None
    for y in np.arange(floor + 0.62 * S, floor + 0.30 * S, -step):
        loops = [p for p in sc.loops(y) if abs(p[:, 0].mean() - xm) < 0.12 * S]
        left = [p for p in loops if p[:, 0].min() > xm]
        right = [p for p in loops if p[:, 0].max() < xm]
        if (
            left
            and right
            and not any(p[:, 0].min() <= xm <= p[:, 0].max() for p in loops)
        ):
            y_crotch = y
            break
    if y_crotch is None:
        raise LandmarkError(
            "geometry: no crotch found (the legs never separate); give landmarks with --landmarks"
        )
    mid = np.abs(v[:, 0] - xm) < max(0.004 * S, 0.3)
    band = mid & (v[:, 1] > y_crotch) & (v[:, 1] < y_crotch + 0.06 * S)
    if band.any():
        cands = np.flatnonzero(band)
        put("crotch_point", v[cands[np.argmin(v[cands, 1])]])
    else:
        put("crotch_point", np.array([xm, y_crotch + step, 0.0]))
    y_crotch = float(pts["crotch_point"][1])

    # -- armpits: the torso section widens suddenly when it meets the arm
    ys = np.arange(y_crotch + 0.15 * S, floor + 0.85 * S, step)
    ext = {"left": [], "right": []}
    gap = {"left": [], "right": []}
    for y in ys:
        loops = sc.loops(y)
        t = _torso_loop(loops, xm)
        if t is None:
            for s in ext:
                ext[s].append(np.nan)
                gap[s].append(np.nan)
            continue
        for s, sg in _SIGN.items():
            reach = float(np.max(sg * (t[:, 0] - xm)))
            ext[s].append(reach)
            others = [
                p for p in loops if p is not t and np.mean(sg * (p[:, 0] - xm)) > reach
            ]
            gap[s].append(
                min(
                    (float(np.min(sg * (p[:, 0] - xm))) for p in others),
                    default=reach + 0.05 * S,
                )
            )
    for s, sg in _SIGN.items():
        e = np.asarray(ext[s])
        jump = np.flatnonzero(np.diff(e) > 0.035 * S)
        if not len(jump):
            continue
        k = int(jump[0])
        # a T-pose armpit flares gradually: step back while the contour stays steeper than ~60 deg
        while k > 0 and e[k] - e[k - 1] > 0.006 * S:
            k -= 1
        y0 = ys[k]
        lo_x, hi_x = e[k] - 0.01 * S, gap[s][k] + 0.01 * S
        rel = sg * (v[:, 0] - xm)
        col = (rel > lo_x) & (rel < hi_x) & (v[:, 1] > y0) & (v[:, 1] < y0 + 0.08 * S)
        if not col.any():
            continue
        idx = np.flatnonzero(col)
        # stay at the depth of the arm (or of the torso for a T-pose)
        loops0 = sc.loops(y0)
        t = _torso_loop(loops0, xm)
        arms0 = [
            p for p in loops0 if p is not t and np.mean(sg * (p[:, 0] - xm)) > e[k]
        ]
        if arms0:
            zc = float(
                np.mean(min(arms0, key=lambda p: np.min(sg * (p[:, 0] - xm)))[:, 2])
            )
        else:
            zc = (
                float(np.mean(t[:, 2]))
                if t is not None
                else float(np.median(v[idx, 2]))
            )
        close = np.abs(v[idx, 2] - zc) < 0.015 * S
        idx = idx[close] if close.any() else idx
        arm = v[idx[np.argmin(v[idx, 1])]]
        put(f"armpit_point_{s}", arm)
        # axilla folds: front-most and back-most points of the section just above
        ya = arm[1] + 0.011 * S
        loops = sc.loops(ya)
        if loops:
            allp = np.concatenate(loops)
            near = allp[np.abs(allp[:, 0] - arm[0]) < max(0.006 * S, 0.5)]
            near = near[np.abs(near[:, 2] - zc) < 0.12 * S]
            if len(near):
                put(f"axilla_front_{s}", near[np.argmax(near[:, 2])])
                put(f"axilla_back_{s}", near[np.argmin(near[:, 2])])
        # shoulder point: highest vertex 1.2 % of stature outside the armpit
        xs = arm[0] + sg * 0.012 * S
        colm = (
            (np.abs(v[:, 0] - xs) < max(0.004 * S, 0.3))
            & (np.abs(v[:, 2] - zc) < 0.06 * S)
            & (v[:, 1] > arm[1])
        )
        if colm.any():
            idx = np.flatnonzero(colm)
            put(f"shoulder_point_{s}", v[idx[np.argmax(v[idx, 1])]])

    # -- neck: narrowest section between the shoulders and the head
    sh = [pts[k] for k in ("shoulder_point_left", "shoulder_point_right") if k in pts]
    if sh:
        y_sh = float(np.mean([p[1] for p in sh]))
        top = pts["top_of_head"][1]
        best = None
        for y in np.arange(y_sh, top - 0.10 * (top - floor) * 0.5, step):
            t = _torso_loop(sc.loops(y), xm)
            if t is None:
                continue
            width = float(np.ptp(t[:, 0]))
            if best is None or width < best[1]:
                best = (y, width, t)
        if best is not None:
            y_neck, _, tn = best
            zc = float(np.mean(tn[:, 2]))
            midv = np.abs(v[:, 0] - xm) < max(0.004 * S, 0.3)
            # front profile between the neck and below the shoulders
            ylo = y_sh - 0.04 * S
            prof = []
            for y in np.arange(ylo, y_neck, step):
                sel = midv & (np.abs(v[:, 1] - y) < step) & (v[:, 2] > zc - 0.02 * S)
                if sel.any():
                    i = np.flatnonzero(sel)
                    prof.append(i[np.argmax(v[i, 2])])
            if len(prof) > 2:
                p = v[prof]
                a, b = p[0], p[-1]
                ab = (b - a)[[1, 2]]
                n2 = np.array([ab[1], -ab[0]]) / np.linalg.norm(
                    ab
                )  # points backward for a rising chord
                depth = (p[:, [1, 2]] - a[[1, 2]]) @ n2
                put("front_neck_point", p[int(np.argmax(depth))])
            # neck base: the section girth grows by 30 % going down from the neck
            y_base = y_sh
            w_neck = best[1]
            for y in np.arange(y_neck, y_sh, -step):
                t = _torso_loop(sc.loops(y), xm)
                if t is not None and np.ptp(t[:, 0]) > 1.3 * w_neck:
                    y_base = y
                    break
            back = (
                midv
                & (np.abs(v[:, 1] - (y_base + 0.01 * S)) < 2 * step)
                & (v[:, 2] < zc)
            )
            if back.any():
                i = np.flatnonzero(back)
                put("back_neck_point", v[i[np.argmin(v[i, 2])]])
            # side neck points: neck/shoulder corner of the frontal contour, in the
            # frontal plane half-way between the back and front neck points
            if "back_neck_point" in pts and "front_neck_point" in pts:
                zc = 0.5 * float(pts["back_neck_point"][2] + pts["front_neck_point"][2])
            for s, sg in _SIGN.items():
                key = f"shoulder_point_{s}"
                if key not in pts:
                    continue
                spt = pts[key]
                x_n = xm + sg * 0.5 * float(np.ptp(tn[:, 0]))
                xs_ = np.linspace(x_n, spt[0], 24)
                prof = []
                for x in xs_:
                    sel = (
                        (np.abs(v[:, 0] - x) < max(0.004 * S, 0.3))
                        & (np.abs(v[:, 2] - zc) < 0.01 * S)
                        & (v[:, 1] < y_neck + 0.02 * S)
                        & (v[:, 1] > spt[1] - 0.02 * S)
                    )
                    if sel.any():
                        i = np.flatnonzero(sel)
                        prof.append(i[np.argmax(v[i, 1])])
                if len(prof) > 2:
                    p = v[prof]
                    a, b = p[0, [0, 1]], p[-1, [0, 1]]
                    ab = b - a
                    n2 = np.array([-ab[1], ab[0]]) / np.linalg.norm(ab)
                    if n2[1] > 0:
                        n2 = -n2  # below the chord
                    depth = (p[:, [0, 1]] - a) @ n2
                    put(f"neck_shoulder_point_{s}", p[int(np.argmax(depth))])

    # -- torso levels: waist (narrowest), chest (widest above), hip (widest below)
    try:
        body = BodyFrame(v, faces, pts)
        levels = torso_levels(body)
    except LandmarkError:
        levels = {}
    if levels:
        for key, names in (("waist", ("waist_front", "waist_back", "waist_side")),):
            ring = levels[key][1].polyline
            near = ring[np.abs(ring[:, 0] - xm) < 0.03 * S] if len(ring) else ring
            y = levels[key][0]
            if len(ring):
                loops = [
                    p
                    for p in sc.loops(y)
                    if abs(p[:, 0].mean() - xm) < 0.5 * np.ptp(ring[:, 0])
                ]
                allp = np.concatenate(loops) if loops else ring
                midp = allp[np.abs(allp[:, 0] - xm) < max(0.006 * S, 0.5)]
                if len(midp):
                    put(names[0], midp[np.argmax(midp[:, 2])])
                    put(names[1], midp[np.argmin(midp[:, 2])])
                put(f"{names[2]}_left", allp[np.argmax(allp[:, 0])])
                put(f"{names[2]}_right", allp[np.argmin(allp[:, 0])])
            del near
        y = levels["chest"][0]
        loops = [p for p in sc.loops(y) if abs(p[:, 0].mean() - xm) < 0.1 * S]
        if loops:
            allp = np.concatenate(loops)
            for s, sg in _SIGN.items():
                side = allp[sg * (allp[:, 0] - xm) > 0.02 * S]
                if len(side):
                    put(f"bust_point_{s}", side[np.argmax(side[:, 2])])
        y = levels["hip"][0]
        loops = [p for p in sc.loops(y) if abs(p[:, 0].mean() - xm) < 0.1 * S]
        if loops:
            allp = np.concatenate(loops)
            for s, sg in _SIGN.items():
                side = allp[sg * (allp[:, 0] - xm) > 0.01 * S]
                if len(side):
                    put(f"buttock_point_{s}", side[np.argmin(side[:, 2])])
                    put(f"hip_side_{s}", side[np.argmax(sg * (side[:, 0] - xm))])

    # -- arms: wrist (narrowest before the hand) and elbow (largest bend)
    from ..measure.section import plane_loops

    for s, sg in _SIGN.items():
        key = f"shoulder_point_{s}"
        if key not in pts or f"armpit_point_{s}" not in pts:
            continue
        spt = pts[key]
        x_arm = pts[f"armpit_point_{s}"][0]
        # the arm leaves the shoulder sideways: within ~63 degrees of horizontal
        region = (sg * (v[:, 0] - x_arm) > 0) & (
            sg * (v[:, 0] - spt[0]) > 0.5 * np.abs(v[:, 1] - spt[1])
        )
        if not region.any():
            continue
        idx = np.flatnonzero(region)
        tip = v[idx[np.argmax(np.sum((v[idx] - spt) ** 2, axis=1))]]
        d = tip - spt
        L = float(np.linalg.norm(d))
        u = d / L
        ts = np.linspace(0.10, 0.88, 40)
        cents, girths = [], []
        arm_faces = _faces_near(v, faces, spt, tip, 0.12 * S)
        beyond = sg * (v[:, 0] - x_arm) > 0
        arm_faces = arm_faces[beyond[faces[arm_faces]].all(axis=1)]
        for t in ts:
            q = spt + t * d
            sec = plane_loops(v, faces, q, u, candidates=arm_faces)
            if not sec.loops:
                cents.append(q)
                girths.append(np.inf)
                continue
            qq = sec.to_uv(q)
            lp = min(
                sec.loops,
                key=lambda lp: lp.distance_uv(qq) if not lp.contains_uv(qq) else -1.0,
            )
            cents.append(sec.to_xyz(lp.centroid_uv))
            girths.append(float(np.sum(np.ptp(lp.uv, axis=0))))
        cents = np.asarray(cents)
        girths = np.asarray(girths)
        on_arm = sg * (cents[:, 0] - x_arm) > 0
        first = int(np.argmax(on_arm & (ts >= 0.15)))
        distal = (ts > 0.55) & (ts < 0.85)
        k_w = int(np.flatnonzero(distal)[np.argmin(girths[distal])])
        q = spt + ts[k_w] * d
        sec = plane_loops(v, faces, q, u, candidates=arm_faces)
        if sec.loops:
            qq = sec.to_uv(q)
            lp = min(
                sec.loops,
                key=lambda lp: lp.distance_uv(qq) if not lp.contains_uv(qq) else -1.0,
            )
            put(f"wrist_point_{s}", lp.points[np.argmin(lp.points[:, 2])])
        # elbow: the centre line's farthest point from the chord shoulder-wrist
        a, b = cents[first], cents[k_w]
        ab = (b - a) / np.linalg.norm(b - a)
        rel = cents - a
        off = rel - np.outer(rel @ ab, ab)
        dist = np.linalg.norm(off, axis=1)
        band = (ts > ts[first] + 0.05) & (ts < ts[k_w] - 0.1)
        if band.any():
            cand = np.flatnonzero(band)
            k_e = int(cand[np.argmax(dist[cand])])
            if dist[k_e] < 0.01 * S:
                k_e = int(
                    cand[np.argmin(np.abs(ts[cand] - 0.5 * (ts[first] + ts[k_w])))]
                )
            c_e = cents[k_e]
            up_dir = c_e - a
            fo_dir = b - c_e
            bend = up_dir / np.linalg.norm(up_dir) - fo_dir / np.linalg.norm(fo_dir)
            if np.linalg.norm(bend) < 0.2:
                bend = np.array([0.0, 0.0, -1.0])
            hit = _ray_hit(v, c_e, bend, max(0.006 * S, 0.5))
            if hit is not None:
                put(f"elbow_point_{s}", v[hit])

    # -- legs: ankles (where the foot ends), heel, knee
    for s, sg in _SIGN.items():
        y_ank = None
        base = None
        for y in np.arange(floor + 0.012 * S, floor + 0.15 * S, step):
            loops = [
                p
                for p in sc.loops(y)
                if sg * (p[:, 0].mean() - xm) > 0
                and abs(p[:, 0].mean() - xm) < 0.15 * S
            ]
            if not loops:
                continue
            p = max(loops, key=len)
            ratio = np.ptp(p[:, 2]) / max(np.ptp(p[:, 0]), 1e-9)
            base = ratio if base is None else base
            if ratio < 0.75 * base:
                y_ank = y
                break
        if y_ank is None:
            continue
        loops = [
            p
            for p in sc.loops(y_ank)
            if sg * (p[:, 0].mean() - xm) > 0 and abs(p[:, 0].mean() - xm) < 0.15 * S
        ]
        if not loops:
            continue
        p = max(loops, key=len)
        put(f"ankle_inside_{s}", p[np.argmin(sg * (p[:, 0] - xm))])
        put(f"ankle_outside_{s}", p[np.argmax(sg * (p[:, 0] - xm))])
        foot = (
            (sg * (v[:, 0] - xm) > 0)
            & (v[:, 1] < y_ank)
            & (np.abs(v[:, 0] - p[:, 0].mean()) < 0.05 * S)
        )
        if foot.any():
            i = np.flatnonzero(foot)
            put(f"heel_point_{s}", v[i[np.argmin(v[i, 2])]])
        y_knee = y_ank + 0.6 * (y_crotch - y_ank)
        leg = (
            (sg * (v[:, 0] - xm) > 0)
            & (np.abs(v[:, 1] - y_knee) < 0.011 * S)
            & (np.abs(v[:, 0] - p[:, 0].mean()) < 0.08 * S)
        )
        if leg.any():
            i = np.flatnonzero(leg)
            put(f"knee_point_{s}", v[i[np.argmax(v[i, 2])]])

    out = {}
    for name, p in pts.items():
        vid = _nearest_vertex(v, p)
        out[name] = Landmark(name=name, position=v[vid], vertex=vid, source="detected")
    return out


def resolve_landmarks(
    character: Character, *, detect: bool = True
) -> dict[str, Landmark]:
    """The character's landmarks, completed from the skeleton and then the geometry.

    Returns
    -------
    name -> Landmark, each with its ``source``.
    """
    marks: dict[str, Landmark] = dict(character.landmarks)
    if any(n not in marks for n in LANDMARK_NAMES) and character.skeleton is not None:
        for name, lm in skeleton_landmarks(character).items():
            marks.setdefault(name, lm)
    if detect and any(n not in marks for n in LANDMARK_NAMES):
        try:
            found = detect_landmarks(character.vertices, character.faces)
        except LandmarkError as exc:
            log.warning("%s: landmark detection failed: %s", character.name, exc)
            found = {}
        for name, lm in found.items():
            marks.setdefault(name, lm)
    return marks


def landmark_errors(
    found: Mapping[str, Landmark], reference: Mapping[str, Landmark]
) -> dict[str, float]:
    """Distance (cm) from each found landmark to the reference one of the same name."""
    return {
        n: float(np.linalg.norm(found[n].position - reference[n].position))
        for n in LANDMARK_NAMES
        if n in found and n in reference
    }
