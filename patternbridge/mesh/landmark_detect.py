"""Detect the datum points of an upright humanoid from its geometry, one body region at a time.

The body is in cm, +Y up, facing +Z, left = +X (the loader turns it so). Each
region function reads the points found so far (and the ones already known
from a file or a rig, which serve as anchors) and adds its own, each with the
rule that placed it and a confidence:

* :func:`detect_crotch` — scanning horizontal sections down from 62 % of the
  stature, the first level where the body splits into two legs; the lowest
  midline vertex just above.
* :func:`detect_armpits` — scanning up from the crotch, the level where the
  torso section's lateral extent jumps (it meets the arm; a T-pose armpit
  flares gradually, so the scan steps back while the contour is steeper than
  about 60°); the lowest vertex above the gap between torso and arm; the
  axilla folds (front-most / back-most point 1.1 % of S above the armpit) and
  the shoulder point (the convex corner of the shoulder's top contour, from
  the side of the neck down the arm).
* :func:`detect_neck` — the narrowest section between the shoulders and the
  head; the front neck point deepest behind the chord of the front midline
  profile from the upper chest up to the chin, the back neck point where the back midline crosses the level
  2 % of S above the mid-height of the neck base (the section 30 % wider than the neck) and the notch (a
  surface point between the vertex rows), the side neck points at the neck/shoulder corner of
  the frontal section's contour, walked from the narrowest neck to the shoulder point.
* :func:`detect_torso_points` — the waist (narrowest torso section), chest
  (widest above) and hip (widest below) levels of the girth search, and their
  front, back and lateral extreme points.
* :func:`detect_arm` — along the line shoulder point to fingertip, sections
  1 % of it apart: the narrow wrist before the palm, then square to the
  forearm the wrist point where the narrow wrist ends (the last section less
  than 5 % wider than the narrowest; back side), and the elbow where the
  arm's centre line bends most (outer side).
* :func:`detect_leg` — the ankles where the foot section's depth/width ratio
  has dropped to 75 % of the sole's, the heel behind and below them, the knee
  at the knee cap's corner of the leg's front profile (side view).

Confidence: 0.7 for a point found by its rule, lower where the rule fell back
to a default (no bend found at the elbow, no vertex on the crotch midline).
:mod:`patternbridge.mesh.landmark_checks` then checks the whole set.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from ..errors import LandmarkError
from .character import Landmark, LandmarkEvidence, LandmarkSource
from .surface_point import locate_on_surface

__all__ = [
    "detect_arm",
    "detect_armpits",
    "detect_crotch",
    "detect_landmarks",
    "detect_leg",
    "detect_neck",
    "detect_torso_points",
    "level_arm_shoulder",
]

SIDES = {"left": 1.0, "right": -1.0}
FOUND = 0.7  # confidence of a point its rule found
FALLBACK = 0.35  # confidence of a point placed by a rule's fallback
PROVISIONAL = 0.3  # a point a later rule replaces
NO_CORNER = "no shoulder corner: highest vertex 1.2 % of S outside the armpit (provisional)"
CHIN = 1.5  # under the jaw the front midline comes forward more than this (dz / dy) as it rises
NECK_WALL = 1.5  # the side of the neck rises more steeply than this (dy / dx) from the shoulder slope
SHARP = 0.85  # a rule that found a sharp geometric feature (the shoulder corner, the neck base)
LEVEL_ARM_SHARE = 0.53  # a level arm's acromion: this share of the way from the side neck point to the armpit
WRIST_END = 1.1  # the forearm ends where its section is this much wider than the narrowest
FOREARM_WRIST_END = 1.05  # ... and, square to the forearm, where its section is this much wider
STRAIGHT_DEG = 20.0  # an elbow flexed less than this is straight (A-pose elbows: 45°)
KNEE_CORNER = 0.002  # a knee cap's corner stands at least this share of S in front of the profile's chord
NECK_SPINE = 0.44  # the cervical spine's frontal plane: this share of the way from the back to the front neck point
AXILLA_OUT = 0.03  # an axilla fold lies within this share of S outside the armpit (beyond: the raised arm)
ELBOW_SLAB = 0.01  # the olecranon lies within this share of S of the elbow's centre along the upper arm
CERVICALE_RISE = 0.02  # the cervicale: this share of S above the mid-height of the neck base and the notch
NECK_BASE_RISE = 0.006  # ... without a notch: this share of S above the level where the neck has grown 30 % wider
BUST_OUT_DEG = 17.5  # a bust point is the chest front's most prominent point this far out from straight ahead


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class Found:
    """A detected point.

    surface : the rule defines a level or a point between vertices (a
        midline section's point at a level): it is kept where it lies on the
        surface; otherwise it goes to its nearest vertex
    """

    position: np.ndarray
    rule: str
    confidence: float = FOUND
    surface: bool = False


class Scan:
    """The body with horizontal sections on demand and the points found so far.

    Parameters
    ----------
    vertices : (V, 3) float64, cm, +Y up, facing +Z
    faces : (F, 3) int64
    known : name -> (3,) position of landmarks already known (anchors)
    """

    def __init__(self, vertices: np.ndarray, faces: np.ndarray, known: Mapping[str, np.ndarray]) -> None:
        from ..measure.section import SlabIndex

        self.v, self.f = vertices, faces
        self.floor = float(vertices[:, 1].min())
        self.top = float(vertices[:, 1].max())
        self.S = self.top - self.floor
        self.step = self.S / 300.0
        self.slabs = SlabIndex(vertices, faces, axis=1, slab_cm=max(self.S / 200.0, 0.1))
        lo, hi = vertices[:, 0].min(), vertices[:, 0].max()
        self.x_mid = float(0.5 * (lo + hi))
        self.known = {k: np.asarray(p, dtype=np.float64) for k, p in known.items()}
        self.found: dict[str, Found] = {}

    def loops(self, y: float) -> list[np.ndarray]:
        from ..measure.section import plane_loops

        sec = plane_loops(
            self.v,
            self.f,
            np.array([0.0, y, 0.0]),
            np.array([0.0, 1.0, 0.0]),
            candidates=self.slabs.faces_at(y),
        )
        return [lp.points for lp in sec.loops if len(lp.points) >= 3]

    def midline(self, y: float, near: float | None = None) -> np.ndarray:
        """(k, 3) surface points where the horizontal section at ``y`` crosses the mid-sagittal plane.

        Each crossing lies on a section segment, inside a face: the midline
        between the vertex rows. ``near``: only the loops whose points' mean x
        lies within that distance of the midline (the torso, not an arm).
        """
        from ..measure.section import plane_loops

        sec = plane_loops(
            self.v, self.f, np.array([0.0, y, 0.0]), np.array([0.0, 1.0, 0.0]), candidates=self.slabs.faces_at(y)
        )
        out = []
        for lp in sec.loops:
            if near is not None and abs(float(lp.points[:, 0].mean()) - self.x_mid) > near:
                continue
            a, b = lp.points[lp.segments[:, 0]], lp.points[lp.segments[:, 1]]
            da, db = a[:, 0] - self.x_mid, b[:, 0] - self.x_mid
            cut = (da >= 0.0) != (db >= 0.0)
            t = da[cut] / (da[cut] - db[cut])
            out.append(a[cut] + t[:, None] * (b[cut] - a[cut]))
        return np.concatenate(out) if out else np.zeros((0, 3))

    def put(self, name: str, p: np.ndarray, rule: str, confidence: float = FOUND, *, surface: bool = False) -> None:
        self.found[name] = Found(
            position=np.asarray(p, dtype=np.float64), rule=rule, confidence=confidence, surface=surface
        )

    def has(self, name: str) -> bool:
        return name in self.known or name in self.found

    def at(self, name: str) -> np.ndarray:
        """A point: the known one (file, rig) first, else the detected one."""
        if name in self.known:
            return self.known[name]
        return self.found[name].position

    def points(self) -> dict[str, np.ndarray]:
        return {**{k: f.position for k, f in self.found.items()}, **self.known}


def _torso_loop(loops, x_mid: float):
    """The loop spanning the midline (or nearest to it)."""
    if not loops:
        return None
    spanning = [p for p in loops if p[:, 0].min() <= x_mid <= p[:, 0].max()]
    if spanning:
        return max(spanning, key=len)
    return min(loops, key=lambda p: abs(p[:, 0].mean() - x_mid))


def _ray_hit(vertices: np.ndarray, origin: np.ndarray, direction: np.ndarray, radius: float):
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


def _faces_near(vertices, faces, a, b, radius: float) -> np.ndarray:
    ab = b - a
    t = np.clip((vertices - a) @ ab / max(float(ab @ ab), 1e-12), 0.0, 1.0)
    near = np.sum((vertices - (a + t[:, None] * ab)) ** 2, axis=1) <= radius * radius
    return np.flatnonzero(near[faces].any(axis=1))


# --------------------------------------------------------------------------- regions
def detect_crotch(sc: Scan) -> None:
    """Crotch: the first level, going down, where the lower body splits into two legs."""
    v, S, xm = sc.v, sc.S, sc.x_mid
    y_crotch = None
    for y in np.arange(sc.floor + 0.62 * S, sc.floor + 0.30 * S, -sc.step):
        loops = [p for p in sc.loops(y) if abs(p[:, 0].mean() - xm) < 0.12 * S]
        left = [p for p in loops if p[:, 0].min() > xm]
        right = [p for p in loops if p[:, 0].max() < xm]
        if left and right and not any(p[:, 0].min() <= xm <= p[:, 0].max() for p in loops):
            y_crotch = float(y)
            break
    if y_crotch is None:
        raise LandmarkError("geometry: no crotch found (the legs never separate); give landmarks with --landmarks")
    above = (v[:, 1] > y_crotch) & (v[:, 1] < y_crotch + 0.06 * S)
    z_seam = _inseam_depth(sc, y_crotch - 0.01 * S)
    rule = f"legs separate below y = {y_crotch:.1f} cm"
    for tol in (0.001 * S, max(0.004 * S, 0.3)):
        band = above & (np.abs(v[:, 0] - xm) < tol)  # on the midline seam
        if not band.any():
            continue
        cands = np.flatnonzero(band)
        low = cands[np.argmin(v[cands, 1])]
        if z_seam is None:
            sc.put("crotch_point", v[low], f"{rule}; lowest midline vertex above")
            return
        # the midline vertex nearest the inseams' meeting point, level with the lowest one
        target = np.array([v[low, 1], z_seam])
        best = cands[np.argmin(np.sum((v[cands][:, [1, 2]] - target) ** 2, axis=1))]
        sc.put(
            "crotch_point",
            v[best],
            f"{rule}; midline vertex nearest the inseams' meeting point (thighs' mid-depth "
            f"z = {z_seam:.1f} cm, level with the lowest midline vertex)",
            SHARP,
        )
        return
    sc.put("crotch_point", np.array([xm, y_crotch + sc.step, 0.0]), f"{rule}; no midline vertex there", FALLBACK)


def _inseam_depth(sc: Scan, y: float) -> float | None:
    """Mean mid-depth (z, cm) of the two thigh sections at ``y``: where the inseams meet the crotch.

    The bottom of the crotch is a saddle nearly level from front to back, so
    its lowest midline vertex wanders 3 cm forward on some bodies; the inseams
    run up the middle of the thighs' depth, and the crotch point is where they
    meet.
    """
    loops = [p for p in sc.loops(y) if abs(p[:, 0].mean() - sc.x_mid) < 0.12 * sc.S]
    mids = []
    for sg in SIDES.values():
        side = [p for p in loops if np.min(sg * (p[:, 0] - sc.x_mid)) > 0]
        if not side:
            return None
        p = max(side, key=len)
        mids.append(0.5 * float(p[:, 2].min() + p[:, 2].max()))
    return float(np.mean(mids))


def _armpit_profile(sc: Scan, y_crotch: float):
    """Per level from the crotch up: the torso loop's lateral reach and the gap to the next loop out."""
    S, xm = sc.S, sc.x_mid
    # levels on a grid fixed to the floor, so that a crotch a few mm higher or lower moves no level
    k0 = np.ceil((y_crotch + 0.15 * S - sc.floor) / sc.step)
    ys = sc.floor + sc.step * np.arange(k0, np.floor(0.85 * S / sc.step) + 1)
    ext = {s: [] for s in SIDES}
    gap = {s: [] for s in SIDES}
    for y in ys:
        loops = sc.loops(y)
        t = _torso_loop(loops, xm)
        for s, sg in SIDES.items():
            if t is None:
                ext[s].append(np.nan)
                gap[s].append(np.nan)
                continue
            reach = float(np.max(sg * (t[:, 0] - xm)))
            ext[s].append(reach)
            others = [p for p in loops if p is not t and np.mean(sg * (p[:, 0] - xm)) > reach]
            gap[s].append(min((float(np.min(sg * (p[:, 0] - xm))) for p in others), default=reach + 0.05 * S))
    return ys, {s: np.asarray(e) for s, e in ext.items()}, {s: np.asarray(g) for s, g in gap.items()}


def _arm_depth(sc: Scan, y0: float, reach: float, sg: float, fallback: np.ndarray) -> float:
    """Depth (z) of the arm's loop beside the torso at ``y0``, or of the torso for a T-pose."""
    loops0 = sc.loops(y0)
    t = _torso_loop(loops0, sc.x_mid)
    arms0 = [p for p in loops0 if p is not t and np.mean(sg * (p[:, 0] - sc.x_mid)) > reach]
    if arms0:
        return float(np.mean(min(arms0, key=lambda p: np.min(sg * (p[:, 0] - sc.x_mid)))[:, 2]))
    return float(np.mean(t[:, 2])) if t is not None else float(np.median(fallback))


def detect_armpits(sc: Scan) -> None:
    """Armpits where the torso section meets the arm; axilla folds and shoulder points from them."""
    v, S, xm = sc.v, sc.S, sc.x_mid
    ys, ext, gap = _armpit_profile(sc, float(sc.at("crotch_point")[1]))
    for s, sg in SIDES.items():
        if sc.has(f"armpit_point_{s}"):
            arm = sc.at(f"armpit_point_{s}")
            zc = float(arm[2])
        else:
            e = ext[s]
            jump = np.flatnonzero(np.diff(e) > 0.035 * S)
            if not len(jump):
                continue
            k = int(jump[0])
            while k > 0 and e[k] - e[k - 1] > 0.006 * S:  # a T-pose armpit flares gradually
                k -= 1
            y0 = ys[k]
            rel = sg * (v[:, 0] - xm)
            hi_x = min(gap[s][k], e[k] + 0.03 * S) + 0.01 * S  # not out to a T-pose hand
            col = (rel > e[k] - 0.01 * S) & (rel < hi_x) & (v[:, 1] > y0) & (v[:, 1] < y0 + 0.08 * S)
            if not col.any():
                continue
            idx = np.flatnonzero(col)
            zc = _arm_depth(sc, y0, e[k], sg, v[idx, 2])
            close = np.abs(v[idx, 2] - zc) < 0.015 * S
            idx = idx[close] if close.any() else idx
            # the apex of the gap: above the gap itself, not the torso wall just above the level
            bridge = idx[(rel[idx] > e[k]) & (rel[idx] < min(gap[s][k], e[k] + 0.03 * S))]
            idx = bridge if len(bridge) else idx
            arm = v[idx[np.argmin(v[idx, 1])]]
            sc.put(
                f"armpit_point_{s}", arm, f"torso section meets the arm at y = {y0:.1f} cm; lowest vertex above the gap"
            )
        _axillae(sc, s, arm, zc)
        if not sc.has(f"shoulder_point_{s}"):
            _shoulder_point(sc, s, arm, zc)


def _axillae(sc: Scan, s: str, arm: np.ndarray, zc: float) -> None:
    """Axilla folds: the dents between chest (back) and arm in the section 1.1 % of S above the armpit.

    On the torso loop of that section (there it holds the arm), each of its
    front and back halves beside the armpit, seen from the front (back), is
    bridged by its convex hull between the chest's (back's) bulge and the
    arm's; the fold is the point deepest inside the bridging hull edge, where
    a tape laid over the front (back) would leave the skin (the reference
    rule's fold). Only the loop within :data:`AXILLA_OUT` of S outside the
    armpit counts: a raised arm lies along the section, and its underside's
    dent 10 cm out put the T-posed C's front folds 15 cm off. Without a
    dent, the front-most (back-most) point of the section at the armpit's
    x; that point (the rule before) lay 0.7-5.1 cm off the folds.
    """
    S, sg, xm = sc.S, SIDES[s], sc.x_mid
    ya = arm[1] + 0.011 * S
    loops = sc.loops(ya)
    if not loops:
        return
    rule = f"section {ya:.1f} cm high, 1.1 % of S above the armpit"
    t = _torso_loop(loops, xm)
    across = sg * (t[:, 0] - xm)
    beside = (across > 0.011 * S) & (across < sg * (arm[0] - xm) + AXILLA_OUT * S)  # not out along a raised arm
    allp = np.concatenate(loops)
    near = allp[(np.abs(allp[:, 0] - arm[0]) < max(0.006 * S, 0.5)) & (np.abs(allp[:, 2] - zc) < 0.12 * S)]
    for name, side in ((f"axilla_front_{s}", 1.0), (f"axilla_back_{s}", -1.0)):
        q = t[beside & (side * (t[:, 2] - arm[2]) > 0)]
        k = _dent(np.stack([across[beside & (side * (t[:, 2] - arm[2]) > 0)], side * q[:, 2]], axis=1))
        if k is not None:
            sc.put(name, q[k], f"deepest point of the dent between the torso and the arm in the {rule}")
        elif len(near):
            extreme = near[np.argmax(side * near[:, 2])]
            sc.put(name, extreme, f"no dent: {'front' if side > 0 else 'back'}most point of the {rule}", FALLBACK)


def _dent(p: np.ndarray) -> int | None:
    """Index of the point of ``p`` (N, 2: across, out) deepest below its upper convex hull, None if none is."""
    if len(p) < 3:
        return None
    order = np.argsort(p[:, 0], kind="stable")
    q = p[order]
    hull: list[int] = []
    for i in range(len(q)):
        while len(hull) >= 2:
            a, b = q[hull[-2]], q[hull[-1]]
            if (b[0] - a[0]) * (q[i, 1] - a[1]) - (b[1] - a[1]) * (q[i, 0] - a[0]) >= 0:
                hull.pop()
            else:
                break
        hull.append(i)
    h = np.asarray(hull)
    seg = np.clip(np.searchsorted(q[h, 0], q[:, 0], side="right") - 1, 0, len(h) - 2)
    a, b = q[h[seg]], q[h[seg + 1]]
    d = b - a
    below = d[:, 1] * (q[:, 0] - a[:, 0]) - d[:, 0] * (q[:, 1] - a[:, 1])
    depth = below / np.maximum(np.hypot(d[:, 0], d[:, 1]), 1e-12)
    k = int(np.argmax(depth))
    return int(order[k]) if depth[k] > 1e-6 else None


def _shoulder_point(sc: Scan, s: str, arm: np.ndarray, zc: float) -> None:
    """Acromion: the convex corner of the shoulder/arm top contour in the frontal plane of the shoulder.

    The frontal plane is at the median depth of the skin in the column 1.2 %
    of S outside the armpit, above it (up to 12 % of S, below the head). Along
    it, the highest vertex per x bin from 8 % of S inside the armpit to 6 %
    outside gives the top contour (from where it leaves the neck,
    :func:`_clear_of_the_neck`); the corner is the point farthest above the
    chord of that contour (the shoulder slope turning down the arm, which
    falls beyond it by more than 1 in 2), within 2.5 % of S of the column
    1.2 % of S outside the armpit. The chord reaches up the shoulder slope
    toward the neck, as the acromion's definition walks it from the side of
    the neck: from 4 % of S inside the armpit it lay along the top of A's
    massive deltoid, whose lower corner was taken (2.5 cm off the acromion;
    stable from 7 to 10 % on all six test bodies). Without a corner (a level
    T-pose arm) the highest vertex 1.2 % of S outside the armpit is taken,
    with a lower confidence.
    """
    v, S, sg = sc.v, sc.S, SIDES[s]
    xs = arm[0] + sg * 0.012 * S
    shoulder_band = (v[:, 1] > arm[1]) & (v[:, 1] < arm[1] + 0.12 * S)  # below the head
    colm = (np.abs(v[:, 0] - xs) < max(0.004 * S, 0.3)) & shoulder_band & (np.abs(v[:, 2] - zc) < 0.08 * S)
    if not colm.any():
        return
    # the shoulder's frontal mid-plane: the median depth of the column's skin (the mid-depth of
    # its top 3 % of S drifted 2.2 cm back onto the trapezius of the heavy A and C)
    zm = float(np.median(v[colm][:, 2]))
    slab = (np.abs(v[:, 2] - zm) < 0.01 * S) & shoulder_band
    xs_bins = arm[0] + sg * np.linspace(-0.08 * S, 0.06 * S, 36)
    prof = []
    for x in xs_bins:
        sel = slab & (np.abs(v[:, 0] - x) < max(0.002 * S, 0.2))
        if sel.any():
            i = np.flatnonzero(sel)
            prof.append(i[np.argmax(v[i, 1])])
    prof = _clear_of_the_neck(v, np.asarray(prof, dtype=np.int64), arm[0], sg, S)
    if len(prof) > 4:
        p = v[prof][:, [0, 1]]
        ab = p[-1] - p[0]
        n = np.array([-ab[1], ab[0]]) / max(np.linalg.norm(ab), 1e-9)
        if n[1] < 0:
            n = -n  # above the chord
        height = (p - p[0]) @ n
        k = int(np.argmax(height))
        drop = (p[k, 1] - p[-1, 1]) / max(abs(p[-1, 0] - p[k, 0]), 1e-9)  # the arm's fall
        beside = abs(p[k, 0] - xs) < 0.025 * S  # an acromion sits just outside the armpit
        if height[k] > 0.004 * S and 0 < k < len(p) - 1 and drop > 0.5 and beside:
            sc.put(
                f"shoulder_point_{s}",
                v[prof[k]],
                f"convex corner of the shoulder/arm top contour ({height[k]:.1f} cm above its chord)",
                SHARP,
            )
            return
    sel = (
        np.flatnonzero(colm & (np.abs(v[:, 2] - zm) < 0.01 * S))
        if (colm & (np.abs(v[:, 2] - zm) < 0.01 * S)).any()
        else np.flatnonzero(colm)
    )
    sc.put(f"shoulder_point_{s}", v[sel[np.argmax(v[sel, 1])]], NO_CORNER, PROVISIONAL)


def _clear_of_the_neck(v: np.ndarray, prof: np.ndarray, x_armpit: float, sg: float, S: float) -> np.ndarray:
    """The top contour ``prof`` (vertex ids, inside to outside) from where it leaves the neck.

    Walking in from the arm along the contour's upper envelope (bins lower
    than one further out are gaps in the slab, skipped), inside the armpit the
    contour climbs the shoulder slope (less than 1 in 1 on the test bodies, the trapezius of
    the muscular A included) up to the side of the neck, which rises more than
    :data:`NECK_WALL` times as much as it comes in, and by more than 1 % of S;
    the bins from there on inward lie on the neck (an arms-down re-posed
    shoulder slopes gently into a steep neck, and a chord from a point high on
    the neck made a corner of its even slope).
    """
    x = sg * (v[prof, 0] - x_armpit)
    y = v[prof, 1]
    top = len(prof) - 1
    for i in range(len(prof) - 2, -1, -1):
        rise = y[i] - y[top]
        if rise <= 0.0:
            continue
        if x[i] < 0.0 and rise > max(NECK_WALL * (x[top] - x[i]), 0.01 * S):
            return prof[top:]
        top = i
    return prof


def level_arm_shoulder(sc: Scan, s: str) -> None:
    """Shoulder point of a level (T-pose) arm, which has no corner to find.

    Once the side neck point is known, the acromion is taken
    :data:`LEVEL_ARM_SHARE` of the way from it to the armpit (the mean of its
    share on the two T-posed test bodies, 47 % on C and 58 % on B, from their
    detected side neck points and armpits; in an A-pose the acromion lies
    outside the armpit, 109-149 %), at the top of the shoulder in its frontal
    mid-plane. The rule is coarse: the point keeps a low confidence.
    """
    name = f"shoulder_point_{s}"
    f = sc.found.get(name)
    if f is None or f.rule != NO_CORNER or not sc.has(f"neck_shoulder_point_{s}"):
        return
    v, S = sc.v, sc.S
    snp, ap = sc.at(f"neck_shoulder_point_{s}"), sc.at(f"armpit_point_{s}")
    x = snp[0] + LEVEL_ARM_SHARE * (ap[0] - snp[0])
    col = (np.abs(v[:, 0] - x) < max(0.004 * S, 0.3)) & (v[:, 1] > ap[1]) & (v[:, 1] < ap[1] + 0.12 * S)
    if not col.any():
        return
    top = v[col][v[col][:, 1] > v[col][:, 1].max() - 0.03 * S]
    zm = 0.5 * float(top[:, 2].min() + top[:, 2].max())
    near = np.flatnonzero(col & (np.abs(v[:, 2] - zm) < 0.01 * S))
    if len(near):
        sc.put(
            name,
            v[near[np.argmax(v[near, 1])]],
            f"level arm without a shoulder corner: top of the shoulder {LEVEL_ARM_SHARE:.0%} of the way from the side "
            "neck point to the armpit",
            0.45,
        )


def _narrowest_neck(sc: Scan, y_sh: float):
    top = float(sc.at("top_of_head")[1])
    best = None
    for y in np.arange(y_sh, top - 0.05 * (top - sc.floor), sc.step):
        t = _torso_loop(sc.loops(y), sc.x_mid)
        if t is None:
            continue
        width = float(np.ptp(t[:, 0]))
        if best is None or width < best[1]:
            best = (float(y), width, t)
    return best


def _below_the_chin(p: np.ndarray, S: float) -> tuple[np.ndarray, bool]:
    """The front midline profile ``p`` (points from the upper chest up) cut where the chin begins, and
    whether a chin was found.

    Above its most recessed point the profile climbs the front of the neck,
    which comes forward less than it rises; under the jaw the skin comes
    forward :data:`CHIN` times as fast as it rises (and by more than 0.5 % of
    S in one step), and the profile ends before it. The narrowest neck lay
    under the chin on A, E and F, so a chord ending there leaned forward at
    its top and its deepest point rose a vertex row (1.2 cm) up the neck.
    """
    dy, dz = np.diff(p[:, 1]), np.diff(p[:, 2])
    chin = np.flatnonzero((dz > CHIN * np.maximum(dy, 1e-9)) & (dz > 0.005 * S))
    chin = chin[chin >= int(np.argmin(p[:, 2]))]
    return (p[: int(chin[0]) + 1], True) if len(chin) else (p, False)


def detect_neck(sc: Scan) -> None:
    """Front, back and side neck points from the narrowest section between the shoulders and the head."""
    sh = [sc.at(f"shoulder_point_{s}") for s in SIDES if sc.has(f"shoulder_point_{s}")]
    if not sh:
        return
    y_sh = float(np.mean([p[1] for p in sh]))
    best = _narrowest_neck(sc, y_sh)
    if best is None:
        return
    y_neck, w_neck, tn = best
    v, S, xm, step = sc.v, sc.S, sc.x_mid, sc.step
    zc = float(np.mean(tn[:, 2]))
    midv = np.abs(v[:, 0] - xm) < max(0.004 * S, 0.3)
    if not sc.has("front_neck_point"):
        # the chord runs from the upper chest, 8 % of S below the shoulder points, up the neck to the chin
        # (the jugular notch's definition takes it from the upper chest to the neck; from 4 % the
        # notch was 2.4-3.9 cm off on A, C, E, F; the same points from 7 % to 10 %)
        prof = []
        for y in np.arange(y_sh - 0.08 * S, y_neck, step):
            sel = midv & (np.abs(v[:, 1] - y) < step) & (v[:, 2] > zc - 0.02 * S)
            if sel.any():
                i = np.flatnonzero(sel)
                prof.append(i[np.argmax(v[i, 2])])
        if len(prof) > 2:
            p, chin = _below_the_chin(v[np.asarray(list(dict.fromkeys(prof)))], S)
            a, b = p[0], p[-1]
            ab = (b - a)[[1, 2]]
            n2 = np.array([ab[1], -ab[0]]) / np.linalg.norm(ab)
            depth = (p[:, [1, 2]] - a[[1, 2]]) @ n2
            sc.put(
                "front_neck_point",
                p[int(np.argmax(depth))],
                "front midline point deepest behind the chord of the neck/chest profile"
                + (" up to the chin" if chin else ""),
                SHARP if chin else FOUND,
            )
    if not sc.has("back_neck_point"):
        _back_neck_point(sc, y_neck, w_neck, y_sh, zc)
    if sc.has("back_neck_point") and sc.has("front_neck_point"):
        bn, fn = float(sc.at("back_neck_point")[2]), float(sc.at("front_neck_point")[2])
        zc = bn + NECK_SPINE * (fn - bn)
    for s in SIDES:
        if sc.has(f"shoulder_point_{s}") and not sc.has(f"neck_shoulder_point_{s}"):
            _side_neck_point(sc, s, tn, y_neck, zc)


def _neck_base(sc: Scan, y_neck: float, w_neck: float, y_sh: float) -> float | None:
    """Height (cm) where the neck section has grown 30 % wider than the narrowest neck, or None.

    Scanning down from the narrowest neck (to 5 % of S below the shoulder
    points, for raised shoulders) on the scan's grid, then bisecting the step
    where the width crosses, to 1/64 of it: a level between the vertex rows.
    """

    def wider(y: float) -> bool:
        t = _torso_loop(sc.loops(y), sc.x_mid)
        return t is not None and float(np.ptp(t[:, 0])) > 1.3 * w_neck

    for y in np.arange(y_neck, y_sh - 0.05 * sc.S, -sc.step):
        if wider(float(y)):
            lo, hi = float(y), float(y) + sc.step  # wider at lo, not at hi
            for _ in range(6):
                mid = 0.5 * (lo + hi)
                lo, hi = (mid, hi) if wider(mid) else (lo, mid)
            return 0.5 * (lo + hi)
    return None


def _back_neck_point(sc: Scan, y_neck: float, w_neck: float, y_sh: float, zc: float) -> None:
    """Back neck point (cervicale) on the back midline, at a level between the vertex rows.

    The level is :data:`CERVICALE_RISE` of S above the mid-height of the neck
    base (where the neck section has grown 30 % wider than the narrowest
    neck, :func:`_neck_base`) and the jugular notch: the neck base line
    rises from the notch in front over the sides to the cervicale behind, and
    a neck that widens early into a massive trapezius (A) puts the base high
    while its notch stays low. The point is where the section at that level
    crosses the mid-sagittal plane behind the neck (a surface point).
    Measured on the six characters and I: the answer key lies
    1.8-2.4 % of S above that mid-height (spread 0.6 % of S), and
    0.0-1.0 % of S above the neck base alone (spread 1.0 %). The
    back-midline vertex nearest 1 % of S above the base (the rule before)
    took A's row 1.6 cm above the key's: its back length +3.5 %. Without a
    notch, :data:`NECK_BASE_RISE` of S above the base (the median of the
    key's rise).
    """
    y_base = _neck_base(sc, y_neck, w_neck, y_sh)
    if y_base is None:
        level, conf, rule = y_sh, FALLBACK, "back midline at the shoulder height (no neck base found)"
    elif sc.has("front_neck_point"):
        y_fnp = float(sc.at("front_neck_point")[1])
        level, conf = 0.5 * (y_base + y_fnp) + CERVICALE_RISE * sc.S, SHARP
        rule = (
            f"back midline {100 * CERVICALE_RISE:.1f} % of S above the mid-height of the neck base (section 30 % "
            f"wider than the neck, y = {y_base:.1f} cm) and the jugular notch (y = {y_fnp:.1f} cm)"
        )
    else:
        level, conf = y_base + NECK_BASE_RISE * sc.S, SHARP
        rule = (
            f"back midline {100 * NECK_BASE_RISE:.1f} % of S above the neck base (section 30 % wider than the "
            f"neck, y = {y_base:.1f} cm)"
        )
    pts = sc.midline(level, near=0.1 * sc.S)
    back = pts[pts[:, 2] < zc]
    if len(back):
        sc.put("back_neck_point", back[np.argmin(back[:, 2])], rule, conf, surface=True)


def _side_neck_point(sc: Scan, s: str, tn: np.ndarray, y_neck: float, zc: float) -> None:
    """Side neck point: the concave neck/shoulder corner of the frontal section's contour.

    The section is the frontal plane through the cervical spine,
    :data:`NECK_SPINE` of the way from the back to the front neck point (the
    spine lies in the back part of the neck; half-way, A's corner lay 3.2 cm
    down its massive trapezius; every body within 1.2 cm of the answer key for
    shares 0.42-0.46, the T-posed B re-posed arms down 2.6 cm off below 0.42,
    A 2.8 cm above 0.46); along its contour (walked point by point, so the chin, the head
    and the arm never enter) from the side of the narrowest neck to the
    shoulder point, the point deepest below the chord of that stretch. The
    highest skin per x in a slab 1 % of S deep around the plane (the rule
    before) climbed the trapezius behind the plane and made the contour
    between the neck and the shoulder nearly straight: its deepest point
    slid 1.3-3.5 cm out along the shoulder and 0.7-2.9 cm down.
    """
    from ..measure.section import plane_loops

    S, sg = sc.S, SIDES[s]
    spt = sc.at(f"shoulder_point_{s}")
    sec = plane_loops(sc.v, sc.f, np.array([0.0, 0.0, zc]), np.array([0.0, 0.0, 1.0]))
    loops = [lp for lp in sec.loops if lp.closed]
    if not loops:
        return
    lp = min(loops, key=lambda q: float(np.min(np.linalg.norm(q.points[:, :2] - spt[:2], axis=1))))
    P = lp.ordered_points()
    k_sh = int(np.argmin(np.linalg.norm(P[:, :2] - spt[:2], axis=1)))
    off = sg * (P[:, 0] - sc.x_mid)
    on_neck = np.flatnonzero((off > 0.0) & (off < 0.6 * float(np.ptp(tn[:, 0])) + 0.01 * S))
    if not len(on_neck):
        return
    k_n = int(on_neck[np.argmin(np.abs(P[on_neck, 1] - y_neck))])
    n = len(P)
    fwd, back = (k_sh - k_n) % n, (k_n - k_sh) % n
    arc = (k_n + np.arange(fwd + 1)) % n if fwd <= back else (k_n - np.arange(back + 1)) % n
    if len(arc) <= 2:
        return
    p = P[arc]
    a, b = p[0, [0, 1]], p[-1, [0, 1]]
    ab = b - a
    n2 = np.array([-ab[1], ab[0]]) / max(float(np.linalg.norm(ab)), 1e-9)
    if n2[1] > 0:
        n2 = -n2  # below the chord
    depth = (p[:, [0, 1]] - a) @ n2
    sc.put(
        f"neck_shoulder_point_{s}",
        p[int(np.argmax(depth))],
        "concave neck/shoulder corner of the frontal section's contour from the narrowest neck to the shoulder point",
    )


def detect_torso_points(sc: Scan) -> None:
    """Waist, bust, buttock and hip points at the levels of the girth search."""
    from ..measure.girths import BodyFrame, torso_levels

    try:
        levels = torso_levels(BodyFrame(sc.v, sc.f, sc.points()))
    except LandmarkError:
        return
    xm = sc.x_mid
    y, cut = levels["waist"]
    ring = cut.polyline
    if len(ring):
        loops = [p for p in sc.loops(y) if abs(p[:, 0].mean() - xm) < 0.5 * np.ptp(ring[:, 0])]
        allp = np.concatenate(loops) if loops else ring
        midp = allp[np.abs(allp[:, 0] - xm) < max(0.006 * sc.S, 0.5)]
        rule = f"narrowest torso section (waist, y = {y:.1f} cm)"
        if len(midp):
            sc.put("waist_front", midp[np.argmax(midp[:, 2])], f"front midline of the {rule}")
            sc.put("waist_back", midp[np.argmin(midp[:, 2])], f"back midline of the {rule}")
        sc.put("waist_side_left", allp[np.argmax(allp[:, 0])], f"left-most point of the {rule}")
        sc.put("waist_side_right", allp[np.argmin(allp[:, 0])], f"right-most point of the {rule}")
    _bust_points(sc, levels["chest"][0])
    _hip_points(sc, levels["hip"][0], levels["waist"][0])


def _hip_points(sc: Scan, y_wide: float, y_waist: float) -> None:
    """Buttock points (the buttocks' most posterior skin) and hip points (lateral, at their height).

    Each half's buttock prominence is its back-most vertex between the crotch
    and the waist, inside the widest hip section's lateral extent (so the
    hands hanging beside the thighs never count); the hip points are the
    outer-most points of the section at its height. The back-most and
    outer-most points of the widest hip section (the rule before) lay 1.5-3.4
    cm below the prominence, where the thighs flare: buttock points 2.6-3.8 cm
    off on five of the six, waist-to-hip +9 to +13 %.
    """
    S, xm, v = sc.S, sc.x_mid, sc.v
    wide = [p for p in sc.loops(y_wide) if abs(p[:, 0].mean() - xm) < 0.1 * S]
    if not wide:
        return
    wp = np.concatenate(wide)
    y_low = float(sc.at("crotch_point")[1]) if sc.has("crotch_point") else y_wide - 0.05 * S
    for s, sg in SIDES.items():
        off = sg * (v[:, 0] - xm)
        reach = float(np.max(sg * (wp[:, 0] - xm)))
        band = np.flatnonzero((v[:, 1] > y_low) & (v[:, 1] < y_waist) & (off > 0.01 * S) & (off < reach))
        y = float(v[band[np.argmin(v[band, 2])], 1]) if len(band) else y_wide
        loops = [p for p in sc.loops(y) if abs(p[:, 0].mean() - xm) < 0.1 * S]
        if not loops:
            continue
        allp = np.concatenate(loops)
        side = allp[sg * (allp[:, 0] - xm) > 0.01 * S]
        if len(side):
            rule = f"of the section at the buttock prominence (y = {y:.1f} cm)"
            sc.put(f"buttock_point_{s}", side[np.argmin(side[:, 2])], f"back-most point {rule}")
            sc.put(f"hip_side_{s}", side[np.argmax(sg * (side[:, 0] - xm))], f"outer-most point {rule}")


def _bust_points(sc: Scan, y: float) -> None:
    """Bust points: the most prominent point of each half of the chest section's front.

    On the torso loop of the widest chest section, the point of each half
    (beyond 1 % of S from the midline) lying farthest along the direction
    :data:`BUST_OUT_DEG` out from straight ahead: a nipple looks forward and a
    little outward. Straight ahead, a flat or muscular chest's front-most point
    is the pectoral's inner bulge, 3-5 cm toward the sternum; measured square
    to the chord from the front midline to the side's lateral extreme, the
    point slid 3-4 cm out on the men (the chord of a broad back tilts with the
    lats), and the under-bust fold read on the profile through it was 5 cm too
    low on the superhero (under-bust 104 cm against 125).
    """
    t = _torso_loop(sc.loops(y), sc.x_mid)
    if t is None:
        return
    xm, S = sc.x_mid, sc.S
    zc = float(np.mean(t[:, 2]))
    front = t[t[:, 2] > zc]
    out = np.radians(BUST_OUT_DEG)
    for s, sg in SIDES.items():
        side = front[sg * (front[:, 0] - xm) > 0.01 * S]
        if len(side) < 3:
            continue
        along = sg * (side[:, 0] - xm) * np.sin(out) + side[:, 2] * np.cos(out)
        sc.put(
            f"bust_point_{s}",
            side[int(np.argmax(along))],
            f"most prominent point of the chest front {BUST_OUT_DEG:.1f}° out from straight ahead "
            f"(widest chest section, y = {y:.1f} cm)",
        )


def _arm_faces(sc: Scan, spt: np.ndarray, tip: np.ndarray, x_arm: float, sg: float) -> np.ndarray:
    """Faces near the shoulder-fingertip line, wholly beyond the armpit."""
    v, faces = sc.v, sc.f
    arm_faces = _faces_near(v, faces, spt, tip, 0.12 * sc.S)
    beyond = sg * (v[:, 0] - x_arm) > 0
    return arm_faces[beyond[faces[arm_faces]].all(axis=1)]


def _arm_section(sc: Scan, q: np.ndarray, u: np.ndarray, arm_faces: np.ndarray):
    """Centre, width (sum of the two extents) and points of the arm's loop in the plane through ``q`` square to ``u``.

    The closed loop holding ``q``, else the nearest closed loop, else the nearest
    open one; ``(q, inf, None)`` where the plane cuts nothing. Only a closed loop
    can hold ``q``: the side of a heavy bust or belly reaching past the armpit
    is cut open where the arm's faces end, and its fragment, implicitly closed,
    held the line point beside the upper arm (the right elbow of the tall apple
    woman then came out on her bust, 25 cm off).
    """
    from ..measure.section import plane_loops

    sec = plane_loops(sc.v, sc.f, q, u, candidates=arm_faces)
    if not sec.loops:
        return q, np.inf, None
    qq = sec.to_uv(q)
    pool = [lp for lp in sec.loops if lp.closed] or list(sec.loops)
    lp = min(pool, key=lambda lp: -1.0 if lp.closed and lp.contains_uv(qq) else lp.distance_uv(qq))
    return sec.to_xyz(lp.centroid_uv), float(np.sum(np.ptp(lp.uv, axis=0))), lp.points


def _arm_sections(sc: Scan, spt: np.ndarray, tip: np.ndarray, arm_faces: np.ndarray):
    """Centres and widths of sections square to the shoulder-fingertip line, 1 % of it apart."""
    d = tip - spt
    u = d / np.linalg.norm(d)
    ts = np.linspace(0.10, 0.88, 79)
    cut = [_arm_section(sc, spt + t * d, u, arm_faces) for t in ts]
    return ts, np.asarray([c[0] for c in cut]), np.asarray([c[1] for c in cut])


def _wrist_index(ts: np.ndarray, widths: np.ndarray) -> int:
    """The narrowest forearm section before the hand: scanning out from 0.55 of the
    shoulder-fingertip line, the running minimum until the width grows by 30 %
    (the palm), so the narrow fingers beyond are never taken; then out to the
    distal end of the narrow wrist (the last section less than :data:`WRIST_END`
    times wider)."""
    distal = np.flatnonzero((ts > 0.55) & (ts < 0.9))
    best = int(distal[0])
    for k in distal:
        if widths[k] < widths[best]:
            best = int(k)
        elif widths[k] > 1.3 * widths[best]:
            break
    end = best
    while end + 1 < len(widths) and widths[end + 1] < WRIST_END * widths[best]:
        end += 1
    return end


def _forearm_wrist(sc: Scan, ts, cents, k_w: int, arm_faces: np.ndarray, out: np.ndarray):
    """The wrist section square to the forearm, or None: the distal end of the narrow wrist.

    The sections of :func:`_arm_sections` are square to the whole
    shoulder-fingertip line, oblique to a bent forearm, and their widths grow
    into the hand 1-2 cm before the wrist's end. The forearm's axis is the line
    through their centres over the 15 % of that line before the narrow wrist;
    sections square to it, 0.25 % of S apart, from 6 % of S before the wrist
    out: the running minimum until the width grows by 30 % (the palm), then
    the last section less than :data:`FOREARM_WRIST_END` times the narrowest,
    where the hand begins (the ulnar styloid; 0.0-0.6 cm along the arm from the
    reference vertex on the six characters and the two T-poses).
    """
    sel = np.flatnonzero((ts > ts[k_w] - 0.15) & (ts <= ts[k_w]))
    if len(sel) < 3:
        return None
    c = cents[sel]
    axis = np.linalg.svd(c - c.mean(axis=0))[2][0]
    axis = axis if axis @ out > 0 else -axis
    hs = np.arange(-0.06, 0.06, 0.0025) * sc.S
    cut = [_arm_section(sc, cents[k_w] + h * axis, axis, arm_faces) for h in hs]
    widths = np.array([w for _, w, _ in cut])
    best = 0
    for k in range(len(hs)):
        if widths[k] < widths[best]:
            best = k
        elif widths[k] > 1.3 * widths[best]:
            break
    end = best
    while end + 1 < len(hs) and widths[end + 1] < FOREARM_WRIST_END * widths[best]:
        end += 1
    return cut[end][2]


def detect_arm(sc: Scan, s: str) -> None:
    """Wrist (narrowest section before the hand) and elbow (largest bend of the centre line)."""
    sg = SIDES[s]
    if not (sc.has(f"shoulder_point_{s}") and sc.has(f"armpit_point_{s}")):
        return
    v = sc.v
    spt = sc.at(f"shoulder_point_{s}")
    x_arm = float(sc.at(f"armpit_point_{s}")[0])
    # the arm leaves the shoulder sideways: within ~63 degrees of horizontal
    region = (sg * (v[:, 0] - x_arm) > 0) & (sg * (v[:, 0] - spt[0]) > 0.5 * np.abs(v[:, 1] - spt[1]))
    if not region.any():
        return
    idx = np.flatnonzero(region)
    tip = v[idx[np.argmax(np.sum((v[idx] - spt) ** 2, axis=1))]]
    arm_faces = _arm_faces(sc, spt, tip, x_arm, sg)
    ts, cents, widths = _arm_sections(sc, spt, tip, arm_faces)
    on_arm = sg * (cents[:, 0] - x_arm) > 0
    first = int(np.argmax(on_arm & (ts >= 0.15)))
    k_w = _wrist_index(ts, widths)
    if not sc.has(f"wrist_point_{s}"):
        lp = _forearm_wrist(sc, ts, cents, k_w, arm_faces, tip - spt)
        if lp is not None:
            sc.put(
                f"wrist_point_{s}",
                lp[np.argmin(lp[:, 2])],
                "back of the forearm section where the narrow wrist ends (the hand begins)",
            )
    if sc.has(f"elbow_point_{s}"):
        return
    a, b = cents[first], cents[k_w]
    ab = (b - a) / np.linalg.norm(b - a)
    rel = cents - a
    dist = np.linalg.norm(rel - np.outer(rel @ ab, ab), axis=1)
    cand = np.flatnonzero((ts > ts[first] + 0.05) & (ts < ts[k_w] - 0.1))
    if not len(cand):
        return
    k_e = int(cand[np.argmax(dist[cand])])
    u1, u2 = cents[k_e] - a, b - cents[k_e]
    flexion = float(np.degrees(np.arccos(np.clip(u1 @ u2 / (np.linalg.norm(u1) * np.linalg.norm(u2)), -1.0, 1.0))))
    conf = FOUND
    rule = f"largest bend of the arm's centre line ({dist[k_e]:.1f} cm off the chord, flexed {flexion:.0f}°)"
    if flexion < STRAIGHT_DEG:  # a straight arm (biceps and forearm bulges bend its centre line a little): half-way
        k_e = int(cand[np.argmin(np.abs(ts[cand] - 0.5 * (ts[first] + ts[k_w])))])
        conf, rule = 0.5, "straight arm: half-way between the shoulder and the wrist, behind"
    elif sc.has(f"wrist_point_{s}"):  # the bend of a bulging upper arm's centre line lies below the joint
        k_e = _half_way(spt, cents[first : k_w + 1], sc.at(f"wrist_point_{s}")) + first
        rule = f"elbow flexed {flexion:.0f}° (largest bend of the arm's centre line): half-way along the arm"
    c_e = cents[k_e]
    bend = (c_e - a) / np.linalg.norm(c_e - a) - (b - c_e) / np.linalg.norm(b - c_e)
    if np.linalg.norm(bend) < 0.2:
        bend = np.array([0.0, 0.0, -1.0])
    hit = _olecranon(sc, c_e, bend, a, b, widths[k_e], level=conf == FOUND)
    if hit is not None:
        sc.put(f"elbow_point_{s}", v[hit], rule, conf)


def _half_way(spt: np.ndarray, centres: np.ndarray, wrist: np.ndarray) -> int:
    """Index into ``centres`` (the arm's centre line, shoulder to wrist) of the point half-way along the path
    from the shoulder point through them to the wrist point: the upper arm and the forearm are equally long
    from acromion to styloid (the reference olecranon lies 0.48-0.51 of the way on the six test bodies)."""
    path = np.concatenate([spt[None], centres, wrist[None]])
    run = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(path, axis=0), axis=1))])
    half = float(np.interp(0.5 * run[-1], run, np.arange(len(path))))
    return int(np.clip(round(half) - 1, 0, len(centres) - 1))


def _olecranon(
    sc: Scan, c_e: np.ndarray, bend: np.ndarray, a: np.ndarray, b: np.ndarray, width: float, *, level: bool
) -> int | None:
    """The olecranon: the elbow's skin point furthest out along the bend, in the flexion plane.

    Among the vertices within an arm's diameter of the elbow's centre ``c_e`` and
    within 1 % of S of the plane through the shoulder end ``a``, the elbow and
    the wrist end ``b`` (the flexion plane; for a straight arm the plane holding
    the bend direction), the one furthest along ``bend``, the outward bisector
    of upper arm and forearm. The point of a section square to the whole arm's
    line sat 1.5-2.5 cm down the forearm of a bent elbow. A bent elbow's
    (``level``) point lies within :data:`ELBOW_SLAB` of S of ``c_e`` along the
    upper arm: the whole sphere let A's olecranon slide 3.9 cm down its
    forearm (4.1 cm off on the 75° elbows of A_superhero_bent, 0.0 now).
    """
    v, S = sc.v, sc.S
    d = bend / np.linalg.norm(bend)
    n = np.cross(c_e - a, b - c_e)
    if np.linalg.norm(n) < 1e-6 * S * S:
        n = np.cross(b - a, d)
    n = n / max(float(np.linalg.norm(n)), 1e-12)
    rel = v - c_e
    radius = max(0.5 * float(width), 0.02 * S) if np.isfinite(width) else 0.04 * S
    near = (np.sum(rel * rel, axis=1) < radius * radius) & (np.abs(rel @ n) < 0.01 * S)
    if level:  # a bent elbow: level with its centre along the upper arm
        upper = (c_e - a) / max(float(np.linalg.norm(c_e - a)), 1e-12)
        near &= np.abs(rel @ upper) < ELBOW_SLAB * S
    if not near.any():
        return _ray_hit(v, c_e, d, max(0.006 * S, 0.5))
    idx = np.flatnonzero(near)
    return int(idx[np.argmax(rel[idx] @ d)])


def _foot_loop(sc: Scan, y: float, sg: float):
    loops = [
        p for p in sc.loops(y) if sg * (p[:, 0].mean() - sc.x_mid) > 0 and abs(p[:, 0].mean() - sc.x_mid) < 0.15 * sc.S
    ]
    return max(loops, key=len) if loops else None


def detect_leg(sc: Scan, s: str) -> None:
    """Ankles where the foot ends, the heel below and behind, the knee in front."""
    sg = SIDES[s]
    v, S, xm = sc.v, sc.S, sc.x_mid
    y_ank, base = None, None
    for y in np.arange(sc.floor + 0.012 * S, sc.floor + 0.15 * S, sc.step):
        p = _foot_loop(sc, y, sg)
        if p is None:
            continue
        ratio = np.ptp(p[:, 2]) / max(np.ptp(p[:, 0]), 1e-9)
        base = ratio if base is None else base
        if ratio < 0.75 * base:
            y_ank = float(y)
            break
    if y_ank is None:
        return
    p = _foot_loop(sc, y_ank, sg)
    if p is None:
        return
    rule = f"leg section no longer a foot (y = {y_ank:.1f} cm)"
    outside = p[np.argmax(sg * (p[:, 0] - xm))]
    inner = p[sg * (p[:, 0] - p[:, 0].mean()) < 0]
    inside = inner[np.argmin(np.abs(inner[:, 2] - outside[2]))] if len(inner) else p[np.argmin(sg * (p[:, 0] - xm))]
    sc.put(f"ankle_outside_{s}", outside, f"outer-most point of the {rule}")
    sc.put(f"ankle_inside_{s}", inside, f"inner side of the {rule}, across from the outer ankle")
    foot = (sg * (v[:, 0] - xm) > 0) & (v[:, 1] < y_ank) & (np.abs(v[:, 0] - p[:, 0].mean()) < 0.05 * S)
    if foot.any():
        i = np.flatnonzero(foot)
        sc.put(f"heel_point_{s}", v[i[np.argmin(v[i, 2])]], "back-most vertex below the ankle")
    _knee_point(sc, s, y_ank, float(p[:, 0].mean()))


def _knee_point(sc: Scan, s: str, y_ank: float, x_leg: float) -> None:
    """Front of the patella: where the steep front of the knee cap ends, in the side view of the leg.

    The front-most point of the leg's section, level by level from 40 % to 75 %
    of the height from the ankle to the crotch, is the leg's front profile:
    it rises steeply up the knee cap and flattens above it onto the thigh.
    The knee point is that profile's convex corner (the point farthest in
    front of its chord). Where the corner stands less than
    :data:`KNEE_CORNER` of S in front of the chord (a fleshy thigh continues
    the knee cap's rise), it is the front-most point of the section at 60 %
    of that height, with a lower confidence. The front-most leg vertex within
    1.1 % of S of that level (the rule before) took the top of the band, on
    the thigh: 3-4 cm above the patella on A, B and F.
    """
    sg = SIDES[s]
    y_crotch = float(sc.at("crotch_point")[1])
    ys = np.arange(y_ank + 0.40 * (y_crotch - y_ank), y_ank + 0.75 * (y_crotch - y_ank), sc.step)
    fronts = []
    for y in ys:
        loops = [
            q
            for q in sc.loops(float(y))
            if sg * (q[:, 0].mean() - sc.x_mid) > 0 and abs(q[:, 0].mean() - x_leg) < 0.08 * sc.S
        ]
        if loops:
            q = max(loops, key=len)
            fronts.append(q[int(np.argmax(q[:, 2]))])
    if len(fronts) < 3:
        return
    prof = np.asarray(fronts)
    a, b = prof[0, [1, 2]], prof[-1, [1, 2]]
    ab = b - a
    n = np.array([-ab[1], ab[0]]) / max(float(np.linalg.norm(ab)), 1e-9)
    if n[1] < 0:
        n = -n  # in front of the chord
    ahead = (prof[:, [1, 2]] - a) @ n
    k = int(np.argmax(ahead))
    if ahead[k] >= KNEE_CORNER * sc.S:
        sc.put(
            f"knee_point_{s}",
            prof[k],
            f"convex corner of the leg's front profile ({ahead[k]:.1f} cm ahead of its chord)",
        )
        return
    corner = float(ahead[k])
    k = int(np.argmin(np.abs(prof[:, 1] - (y_ank + 0.6 * (y_crotch - y_ank)))))
    sc.put(
        f"knee_point_{s}",
        prof[k],
        f"no knee-cap corner on the leg's front profile ({corner:.1f} cm): front-most point at 60 % of the height "
        "from ankle to crotch",
        0.5,
    )


def detect_landmarks(
    vertices: np.ndarray, faces: np.ndarray, *, known: Mapping[str, np.ndarray] | None = None
) -> dict[str, Landmark]:
    """Detect the datum points of an upright humanoid from its geometry alone.

    Parameters
    ----------
    vertices : (V, 3) float64, cm, +Y up, facing +Z, left = +X
    faces : (F, 3) int64
    known : name -> (3,) position, cm, of landmarks already known (from a
        file or a rig); they anchor the rules that depend on them and are not
        detected again

    Returns
    -------
    name -> Landmark with source ``"detected"``, a confidence and the rule as
    evidence, for the names found (known names are not returned).

    Raises
    ------
    LandmarkError
        The legs never separate (no crotch), so nothing can be placed.
    """
    v = np.asarray(vertices, dtype=np.float64)
    sc = Scan(v, faces, known or {})
    if not sc.has("top_of_head"):
        sc.put("top_of_head", v[int(np.argmax(v[:, 1]))], "highest vertex", 0.9)
    if not sc.has("crotch_point"):
        detect_crotch(sc)
    detect_armpits(sc)
    detect_neck(sc)
    for s in SIDES:
        level_arm_shoulder(sc, s)
    for s in SIDES:
        detect_arm(sc, s)  # before the torso points: the chest level depends on raised arms
    detect_torso_points(sc)
    for s in SIDES:
        detect_leg(sc, s)
    out = {}
    surface = [n for n, f in sc.found.items() if f.surface and n not in sc.known]
    if surface:  # a level's point between the vertex rows, as the rule found it
        at = locate_on_surface(v, faces, np.array([sc.found[n].position for n in surface]))
        for i, name in enumerate(surface):
            f = sc.found[name]
            out[name] = at.landmark(
                i, name, source=LandmarkSource.DETECTED, confidence=f.confidence, evidence=LandmarkEvidence(rule=f.rule)
            )
    for name, f in sc.found.items():
        if name in sc.known or name in out:
            continue
        vid = int(np.argmin(np.sum((v - f.position) ** 2, axis=1)))
        out[name] = Landmark(
            name=name,
            position=v[vid],
            vertex=vid,
            source=LandmarkSource.DETECTED,
            confidence=f.confidence,
            evidence=LandmarkEvidence(rule=f.rule),
        )
    return out
