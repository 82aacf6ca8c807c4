"""Tape girths: convex hulls of plane sections of one body part.

Torso and head girths use horizontal planes (the torso axis of a standing
character is vertical); limb girths use planes perpendicular to the limb axis,
which is estimated from the datum points and refined through the centres of
two sections, so an inclined A-pose arm is cut square. Of all the loops of a
cut, only those of the body part are kept:

* torso: loops whose centre lies between the two armpit points (arms and
  hanging hands fall outside);
* a limb, the neck or the head: the loop that contains the part's axis point,
  or the loop nearest to it.

Chest and hip are the largest girths over a search band, the waist, the wrist
and the ankle the smallest; the elbow is cut with the elbow straightened
(:mod:`patternbridge.measure.elbow`). ``formats/measurements.md`` gives the bands.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass

import numpy as np

from ..errors import LandmarkError
from .elbow import StraightElbow, snug_normals, straighten_elbow
from .model import Measurement
from .section import Section, SlabIndex, hull_girth, plane_loops

__all__ = ["BodyFrame", "GirthError", "measure_girths", "neck_frame", "torso_levels"]


class GirthError(LandmarkError):
    """A girth could not be taken (no section of the body part found)."""


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class _Cut:
    value_cm: float
    polyline: np.ndarray
    origin: np.ndarray
    normal: np.ndarray


def _hull_centroid_uv(uv: np.ndarray) -> np.ndarray:
    from scipy.spatial import ConvexHull, QhullError

    try:
        ring = uv[ConvexHull(uv).vertices]
    except (QhullError, ValueError):
        return uv.mean(axis=0)
    x, y = ring[:, 0], ring[:, 1]
    xn, yn = np.roll(x, -1), np.roll(y, -1)
    cross = x * yn - xn * y
    a = cross.sum() / 2
    if abs(a) < 1e-12:
        return uv.mean(axis=0)
    return np.array([((x + xn) * cross).sum(), ((y + yn) * cross).sum()]) / (6 * a)


def _hull_cut(sec, loops) -> _Cut:
    """Convex-hull girth of ``loops`` of a section; an empty cut when there are none."""
    if not loops:
        return _Cut(value_cm=0.0, polyline=np.zeros((0, 3)), origin=sec.origin, normal=sec.normal)
    g, ring = hull_girth(sec, loops)
    return _Cut(value_cm=g, polyline=ring, origin=sec.origin, normal=sec.normal)


class BodyFrame:
    """The mesh, its datum points and the search helpers shared by all girths.

    Parameters
    ----------
    vertices : (V, 3) float64, cm, +Y up
    faces : (F, 3) int64
    marks : landmark name -> (3,) position, cm
    """

    def __init__(self, vertices: np.ndarray, faces: np.ndarray, marks: Mapping[str, np.ndarray]) -> None:
        self.v = vertices
        self.f = faces
        self.marks = marks
        self.floor = float(vertices[:, 1].min())
        top = self.mark("top_of_head")
        self.stature = float(top[1] - self.floor)
        self.step = max(self.stature / 400.0, 0.05)
        self.slabs = SlabIndex(vertices, faces, axis=1, slab_cm=max(self.stature / 200.0, 0.1))
        self._extent: dict = {}

    def mark(self, name: str) -> np.ndarray:
        try:
            return np.asarray(self.marks[name], dtype=np.float64)
        except KeyError:
            raise LandmarkError(f"landmark {name!r} is missing") from None

    # -- cutting
    def horizontal(self, y: float) -> Section:
        return plane_loops(
            self.v,
            self.f,
            np.array([0.0, y, 0.0]),
            np.array([0.0, 1.0, 0.0]),
            candidates=self.slabs.faces_at(y),
        )

    def near_segment(self, a: np.ndarray, b: np.ndarray, radius: float) -> np.ndarray:
        """Ids of the faces with a vertex within ``radius`` of the segment ab."""
        lo = np.minimum(a, b) - radius
        hi = np.maximum(a, b) + radius
        # cheap box test on the height slabs first, then the exact distance
        box = self.slabs.faces_between(lo[1], hi[1])
        fv = self.f[box]
        used = np.zeros(len(self.v), dtype=bool)
        used[fv.ravel()] = True
        cand = np.flatnonzero(used)
        p = self.v[cand]
        inbox = np.all((p >= lo) & (p <= hi), axis=1)
        cand, p = cand[inbox], p[inbox]
        ab = b - a
        t = np.clip((p - a) @ ab / max(float(ab @ ab), 1e-12), 0.0, 1.0)
        near = np.zeros(len(self.v), dtype=bool)
        near[cand[np.sum((p - (a + t[:, None] * ab)) ** 2, axis=1) <= radius * radius]] = True
        return box[near[fv].any(axis=1)]

    @staticmethod
    def part_loops(section: Section, ref: np.ndarray):
        """The loops containing ``ref`` (its part), else the nearest loop."""
        if not section.loops:
            return ()
        q = section.to_uv(ref)
        closed = [lp for lp in section.loops if lp.closed]
        inside = [lp for lp in closed if lp.contains_uv(q)]
        if inside:
            return tuple(inside)
        pool = closed or list(section.loops)
        return (min(pool, key=lambda lp: lp.distance_uv(q)),)

    def loop_centre(self, section: Section, loops) -> np.ndarray:
        uv = np.concatenate([lp.uv for lp in loops])
        return section.to_xyz(_hull_centroid_uv(uv))

    def torso_loops(self, section: Section):
        left, right = self.mark("armpit_point_left"), self.mark("armpit_point_right")
        mid = 0.5 * (left[0] + right[0])
        half = 0.5 * abs(left[0] - right[0])
        return tuple(lp for lp in section.loops if abs(section.to_xyz(lp.centroid_uv)[0] - mid) < half)

    def torso_cut(self, y: float) -> _Cut:
        sec = self.horizontal(y)
        return _hull_cut(sec, self.torso_loops(sec))

    def crossing(self, candidates: np.ndarray, origin: np.ndarray, normal: np.ndarray) -> np.ndarray:
        """The candidate faces that straddle the plane (cached per normal)."""
        key = (id(candidates), tuple(np.round(normal, 12)))
        if key not in self._extent:
            h = self.v[self.f[candidates]] @ (normal / np.linalg.norm(normal))
            self._extent.clear()
            self._extent[key] = (h.min(axis=1), h.max(axis=1))
        hmin, hmax = self._extent[key]
        level = float(origin @ (normal / np.linalg.norm(normal)))
        return candidates[(hmin <= level) & (hmax >= level)]

    def part_cut(
        self,
        origin: np.ndarray,
        normal: np.ndarray,
        ref: np.ndarray,
        candidates: np.ndarray,
    ) -> _Cut:
        sec = plane_loops(
            self.v,
            self.f,
            origin,
            normal,
            candidates=self.crossing(candidates, origin, normal),
        )
        return _hull_cut(sec, self.part_loops(sec, ref))

    def refine_axis(
        self,
        p0: np.ndarray,
        p1: np.ndarray,
        candidates: np.ndarray,
        fractions=(0.35, 0.7),
    ) -> tuple[np.ndarray, np.ndarray]:
        """Axis line of a limb: through the centres of two perpendicular sections."""
        d = p1 - p0
        centres = []
        for t in fractions:
            q = p0 + t * d
            sec = plane_loops(self.v, self.f, q, d, candidates=self.crossing(candidates, q, d))
            loops = self.part_loops(sec, q)
            if not loops:
                raise GirthError("no limb section found between the datum points")
            if not all(lp.closed for lp in loops):  # merged with the torso: keep the datum axis
                return p0 + fractions[0] * d, d / np.linalg.norm(d)
            centres.append(self.loop_centre(sec, loops))
        c0, c1 = centres
        axis = c1 - c0
        if axis @ d < 0:
            axis = -axis
        return c0, axis / np.linalg.norm(axis)


def _best(cuts: list[tuple[float, _Cut]], pick: Callable) -> tuple[float, _Cut]:
    good = [(t, c) for t, c in cuts if c.value_cm > 0]
    if not good:
        raise GirthError("no section of the body part in the search band")
    return pick(good, key=lambda tc: tc[1].value_cm)


def _scan(lo: float, hi: float, step: float) -> np.ndarray:
    n = max(2, int(np.ceil((hi - lo) / step)) + 1)
    return np.linspace(lo, hi, n)


#: an upper arm (shoulder point to elbow point) less than this below horizontal is raised
RAISED_BELOW_DEG = 30.0
#: how far a raised (T-pose) arm lifts the armpit skin above the chest, fraction of the stature
#: (armpit to bust point: 0.9-3.7 % of S on the six A-poses, 5.0 and 5.6 % on the T-posed C and B)
RAISED_LIFT = 0.04


def arms_raised(body: BodyFrame) -> bool:
    """True when both upper arms (shoulder point to elbow point) are raised (a T-pose)."""
    for s in ("left", "right"):
        try:
            d = body.mark(f"elbow_point_{s}") - body.mark(f"shoulder_point_{s}")
        except LandmarkError:
            return False
        if np.degrees(np.arctan2(d[1], np.hypot(d[0], d[2]))) < -RAISED_BELOW_DEG:
            return False
    return True


def torso_levels(body: BodyFrame) -> dict[str, tuple[float, _Cut]]:
    """Waist (narrowest), chest (widest), hip (widest), high hip and underbust levels.

    Returns
    -------
    name -> (level y in cm, the cut at that level)
    """
    y_crotch = float(body.mark("crotch_point")[1])
    y_arm = float(min(body.mark("armpit_point_left")[1], body.mark("armpit_point_right")[1]))
    if y_arm <= y_crotch:
        raise GirthError("the armpit points lie below the crotch point")
    h = y_arm - y_crotch
    out: dict[str, tuple[float, _Cut]] = {}
    ys = _scan(y_crotch + 0.35 * h, y_crotch + 0.75 * h, body.step)
    out["waist"] = _best([(y, body.torso_cut(y)) for y in ys], min)
    y_waist = out["waist"][0]
    top = y_arm - 0.01 * body.stature
    if "bust_point_left" in body.marks and "bust_point_right" in body.marks:
        # raised arms lift the armpits: stay within reach of the bust points, and
        # below them when the arms are still raised (no rig brought them down)
        y_b = 0.5 * (body.mark("bust_point_left")[1] + body.mark("bust_point_right")[1])
        top = min(top, y_b + (0.0 if arms_raised(body) else 0.02 * body.stature))
    elif arms_raised(body):  # no bust points yet: below the armpit skin a raised arm lifts
        top = y_arm - RAISED_LIFT * body.stature
    ys = _scan(y_waist + 0.5 * (top - y_waist), top, body.step)
    out["chest"] = _best([(y, body.torso_cut(y)) for y in ys], max)
    ys = _scan(
        y_crotch + 0.2 * (y_waist - y_crotch),
        y_waist - 0.2 * (y_waist - y_crotch),
        body.step,
    )
    out["hip"] = _best([(y, body.torso_cut(y)) for y in ys], max)
    y_high = 0.5 * (y_waist + out["hip"][0])
    out["high_hip"] = (y_high, body.torso_cut(y_high))
    # under-bust: on the front profile through the bust points, the point lying
    # deepest behind the chord from the bust point down to the waist level
    y_bust = out["chest"][0]
    try:
        bl, br = body.mark("bust_point_left"), body.mark("bust_point_right")
        y_bust = float(0.5 * (bl[1] + br[1]))
        bx = float(0.5 * (abs(bl[0]) + abs(br[0])))
    except LandmarkError:
        bx = None
    ys = _scan(y_waist, y_bust, body.step)
    level = y_bust - 0.3 * (y_bust - y_waist)  # no fold (flat or male chest)
    if bx is not None:
        front = []
        for y in ys:
            sec = body.horizontal(y)
            pts = np.concatenate([lp.points for lp in body.torso_loops(sec)] or [np.zeros((0, 3))])
            strip = pts[np.abs(np.abs(pts[:, 0]) - bx) < max(1.5, 0.01 * body.stature)] if len(pts) else pts
            front.append(strip[:, 2].max() if len(strip) else np.nan)
        front = np.asarray(front)
        if np.isfinite(front).all() and len(front) > 2:
            chord = front[0] + (front[-1] - front[0]) * (ys - ys[0]) / (ys[-1] - ys[0])
            depth = chord - front
            edge = max(1, len(ys) // 10)
            depth[:edge] = -np.inf  # neither at the waist nor at the bust point
            depth[-edge:] = -np.inf
            if depth.max() > 0.005 * body.stature:
                level = float(ys[int(np.argmax(depth))])
    out["underbust"] = (level, body.torso_cut(level))
    return out


def _girth(mid: str, cut: _Cut, landmarks: tuple[str, ...], **details) -> Measurement:
    return Measurement(
        id=mid,
        value_cm=cut.value_cm,
        kind="girth",
        method="hull",
        polyline=cut.polyline,
        landmarks=landmarks,
        details={"plane_origin": cut.origin, "plane_normal": cut.normal, **details},
    )


def _torso_girths(body: BodyFrame) -> dict[str, Measurement]:
    levels = torso_levels(body)
    used = ("armpit_point_left", "armpit_point_right", "crotch_point")
    names = {
        "chest": "chest_girth",
        "underbust": "underbust_girth",
        "waist": "waist_girth",
        "high_hip": "high_hip_girth",
        "hip": "hip_girth",
    }
    out = {}
    for key, mid in names.items():
        y, cut = levels[key]
        if cut.value_cm <= 0:
            raise GirthError(f"no torso section at the {key} level (y = {y:.1f} cm)")
        extra = ("bust_point_left", "bust_point_right") if key == "underbust" else ()
        out[mid] = _girth(mid, cut, used + extra, level_y_cm=y)
    return out


NECK_POINTS = (
    "front_neck_point",
    "back_neck_point",
    "neck_shoulder_point_left",
    "neck_shoulder_point_right",
)

#: forward tilts of the collar plane tried around the head chord, radians
NECK_TILTS = np.radians(np.arange(-10.0, 35.0 + 1e-9, 1.0))
#: radius of the region searched around the back neck point, fraction of the stature
NECK_REACH = 0.10


def _clip_convex(ring: np.ndarray, d: np.ndarray, lo: float, hi: float) -> np.ndarray:
    """The vertices of the convex polygon ``ring`` (closed, (k + 1, 2)) cut to the band ``lo <= p @ d <= hi``."""
    import shapely

    e = np.array([-d[1], d[0]])
    reach = 2.0 * float(np.abs(ring).max(initial=0.0)) + abs(lo) + abs(hi) + 1.0
    strip = shapely.Polygon([lo * d - reach * e, hi * d - reach * e, hi * d + reach * e, lo * d + reach * e])
    cut = shapely.Polygon(ring).intersection(strip)
    if cut.is_empty or cut.geom_type != "Polygon":
        return np.zeros((0, 2))
    return np.asarray(cut.exterior.coords)[:-1]


def _neck_base_girth(body: BodyFrame) -> Measurement:
    """Neck-base girth: the tape round the neck base over the four neck points.

    The section is the least-squares plane through the front, back and side
    neck points; the tape passes over the side neck points and does not reach
    out along the shoulders beyond them, so the section's hull is cut to the
    band between them (square to the line joining them, in the plane), and
    the four points (projected onto the plane) are on it. The whole hull of
    the section ran 0.1-1.7 cm out beyond the side neck points, down the
    trapezius, and with the arms raised (the trapezius lifted) 1.8 cm: the
    rigless T-posed C measured +4.1 % of its A-pose, +1.6 % with the tape.
    """
    from scipy.spatial import ConvexHull, QhullError

    pts = np.stack([body.mark(n) for n in NECK_POINTS])
    centre = pts.mean(axis=0)
    _, _, vt = np.linalg.svd(pts - centre)
    normal = vt[2] if vt[2][1] >= 0 else -vt[2]
    radius = 0.15 * body.stature
    cands = body.near_segment(centre, centre, radius)
    sec = plane_loops(body.v, body.f, centre, normal, candidates=body.crossing(cands, centre, normal))
    loops = body.part_loops(sec, centre)
    if not loops:
        raise GirthError("no neck section through the neck points")
    _, ring = hull_girth(sec, loops)
    marks_uv = sec.to_uv(pts)
    left, right = marks_uv[2], marks_uv[3]
    d = left - right
    d = d / max(float(np.linalg.norm(d)), 1e-12)
    band = _clip_convex(sec.to_uv(ring), d, float(right @ d), float(left @ d))
    uv = np.concatenate([band, marks_uv])
    try:
        hull = ConvexHull(uv)
    except QhullError:
        raise GirthError("no neck section through the neck points") from None
    tape = uv[np.append(hull.vertices, hull.vertices[0])]
    girth = float(np.sum(np.linalg.norm(np.diff(tape, axis=0), axis=1)))
    cut = _Cut(value_cm=girth, polyline=sec.to_xyz(tape), origin=centre, normal=normal)
    return _girth("neck_base_girth", cut, NECK_POINTS)


def neck_frame(body: BodyFrame) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Head chord and forward direction of the neck (both unit, in the mid-sagittal plane).

    Returns
    -------
    base : (3,) cm, mean of the four neck points (centre of the neck base)
    chord : (3,) unit vector from ``base`` toward ``top_of_head``
    front : (3,) unit vector perpendicular to ``chord``, from the back neck point
        toward the front neck point
    """
    base = np.stack([body.mark(n) for n in NECK_POINTS]).mean(axis=0)
    chord = body.mark("top_of_head") - base
    if np.linalg.norm(chord) < 1e-6:
        raise GirthError("top_of_head coincides with the neck base")
    chord /= np.linalg.norm(chord)
    front = body.mark("front_neck_point") - body.mark("back_neck_point")
    front -= (front @ chord) * chord
    if np.linalg.norm(front) < 1e-6:
        raise GirthError("the front and back neck points lie on the head chord")
    return base, chord, front / np.linalg.norm(front)


def _neck_girth(body: BodyFrame) -> Measurement:
    """EN 13402-1 neck girth: the snuggest neck section through the back neck point (C7).

    The plane passes through ``back_neck_point``; its normal lies in the
    mid-sagittal plane, tilted forward by t from the head chord (neck base
    centre -> top of head), t in ``NECK_TILTS``. Of these planes the one whose
    neck loop has the smallest convex-hull perimeter is kept: a tape held at
    the nape and drawn snug. For a tube this is the section square to its axis
    (any other plane through the same point cuts a longer ellipse), so the
    chosen normal is the neck axis at C7. Lower planes run into the shoulders
    (trapezius), higher ones into the chin, both longer.
    """
    back = body.mark("back_neck_point")
    base, chord, front = neck_frame(body)
    cands = body.near_segment(back, back, NECK_REACH * body.stature)
    # signed distance to the plane of tilt t: cos t * a + sin t * b (per corner)
    corners = body.v[body.f[cands].T] - back  # (3, F', 3): corner-major, contiguous
    a, b = corners @ chord, corners @ front  # (3, F')
    tried: dict[int, tuple] = {}

    def snug(k: int):
        if k in tried:
            return tried[k]
        t = float(NECK_TILTS[k])
        normal = np.cos(t) * chord + np.sin(t) * front
        h = np.cos(t) * a + np.sin(t) * b
        lo = np.minimum(np.minimum(h[0], h[1]), h[2])
        hi = np.maximum(np.maximum(h[0], h[1]), h[2])
        crossing = cands[(lo <= 0.0) & (hi >= 0.0)]
        sec = plane_loops(body.v, body.f, back, normal, candidates=crossing)
        # the neck loop: the one around the chord line where it crosses the plane
        s = float((back - base) @ normal) / float(chord @ normal)
        ref = base + s * chord
        loops = body.part_loops(sec, ref)
        q = sec.to_uv(ref)
        # a neck loop goes round the chord: a plane grazing an ear or a raised
        # shoulder cuts a small loop beside it, which is no neck girth
        if loops and all(lp.closed for lp in loops) and any(lp.contains_uv(q) for lp in loops):
            cut = _hull_cut(sec, loops)
            tried[k] = (t, cut, ref) if cut.value_cm > 0 else None
        else:  # an open arc (the cut leaves the searched region) is no girth
            tried[k] = None
        return tried[k]

    def length(k: int) -> float:
        r = snug(k)
        return np.inf if r is None else r[1].value_cm

    # every 5th tilt, then every tilt within 4 of the best (the curve is smooth)
    coarse = list(range(0, len(NECK_TILTS), 5))
    k0 = min(coarse, key=length)
    fine = range(max(k0 - 4, 0), min(k0 + 5, len(NECK_TILTS)))
    k = min(sorted(set(coarse) | set(fine)), key=length)
    best = tried[k]
    if best is None:
        raise GirthError("no neck section through the back neck point")
    t, cut, ref = best
    ring = cut.polyline[:-1]
    tip = ring[int(np.argmax((ring - ref) @ front))]
    return _girth(
        "neck_girth",
        cut,
        NECK_POINTS + ("top_of_head",),
        tilt_from_chord_deg=float(np.degrees(t)),
        front_y_cm=float(tip[1]),
        front_above_front_neck_cm=float(tip[1] - body.mark("front_neck_point")[1]),
    )


def _head_girth(body: BodyFrame) -> Measurement:
    top = body.mark("top_of_head")
    h = float(top[1] - body.mark("front_neck_point")[1])
    ys = _scan(top[1] - 0.30 * h, top[1] - 0.12 * h, body.step)
    cuts = []
    for y in ys:
        sec = body.horizontal(y)
        loops = body.part_loops(sec, np.array([top[0], y, top[2]]))
        if loops:
            g, ring = hull_girth(sec, loops)
            cuts.append(
                (
                    y,
                    _Cut(value_cm=g, polyline=ring, origin=sec.origin, normal=sec.normal),
                )
            )
    y, cut = _best(cuts, max)
    return _girth("head_girth", cut, ("top_of_head", "front_neck_point"), level_y_cm=y)


#: the wrist girth's search window along the forearm axis, fractions of the stature
#: above (toward the elbow) and below (toward the hand) the wrist point
WRIST_ABOVE = 0.025
WRIST_BELOW = 0.005


def _snug_elbow_cut(
    body: BodyFrame,
    v: np.ndarray,
    point: np.ndarray,
    normal: np.ndarray,
    axis: tuple[np.ndarray, np.ndarray],
    cands: np.ndarray,
) -> _Cut:
    """The smallest arm section through ``point`` (the elbow point) within ``SNUG_DEG`` of square to ``normal``.

    ``v`` are the body's vertices as cut (the straightened arm, or the body
    itself); the loop kept is the arm's, round the point where the arm's
    ``axis`` (point, unit direction) meets the plane.
    """
    f = body.f[cands]
    c, u = axis
    best = None
    for n in snug_normals(normal):
        h = v[f] @ n
        level = float(point @ n)
        crossing = cands[(h.min(axis=1) <= level) & (h.max(axis=1) >= level)]
        sec = plane_loops(v, body.f, point, n, candidates=crossing)
        ref = c + (float((point - c) @ n) / float(u @ n)) * u
        cut = _hull_cut(sec, body.part_loops(sec, ref))
        if cut.value_cm > 0 and (best is None or cut.value_cm < best.value_cm):
            best = cut
    return best if best is not None else _Cut(value_cm=0.0, polyline=np.zeros((0, 3)), origin=point, normal=normal)


def _straight_elbow_cut(body: BodyFrame, straight: StraightElbow, cands: np.ndarray) -> _Cut:
    """The snug elbow girth of the straightened arm, its ring carried back onto the given skin."""
    from scipy.spatial import cKDTree

    v = straight.vertices
    cut = _snug_elbow_cut(body, v, straight.elbow, straight.axis, (straight.centre, straight.axis), cands)
    if len(cut.polyline):
        ids = np.unique(body.f[cands])
        _, near = cKDTree(v[ids]).query(cut.polyline)
        ring = cut.polyline + (body.v[ids[near]] - v[ids[near]])
        cut = _Cut(value_cm=cut.value_cm, polyline=ring, origin=cut.origin, normal=cut.normal)
    return cut


def _arm_girths(body: BodyFrame, side: str) -> dict[str, Measurement]:
    sh = body.mark(f"shoulder_point_{side}")
    el = body.mark(f"elbow_point_{side}")
    wr = body.mark(f"wrist_point_{side}")
    reach = np.linalg.norm(el - sh) + np.linalg.norm(wr - el)
    cands = body.near_segment(sh, el, 0.25 * reach)
    cands = np.union1d(cands, body.near_segment(el, wr, 0.2 * reach))
    c_up, u_up = body.refine_axis(sh, el, cands, fractions=(0.55, 0.85))
    c_lo, u_lo = body.refine_axis(el, wr, cands, fractions=(0.3, 0.7))
    out = {}
    cuts = []
    for t in np.linspace(0.40, 0.65, 6):
        q = sh + t * (el - sh)
        q = c_up + ((q - c_up) @ u_up) * u_up
        cuts.append((float(t), body.part_cut(q, u_up, q, cands)))
    t, cut = _best(cuts, max)
    out[f"upper_arm_girth_{side}"] = _girth(
        f"upper_arm_girth_{side}",
        cut,
        (f"shoulder_point_{side}", f"elbow_point_{side}"),
        axis_fraction=t,
    )
    # taken with the arm hanging straight (a bent elbow unbent from the surface)
    # the arm's faces only: the forearm near the elbow lies among them, and the rest of the body stays put
    straight = straighten_elbow(body.v, body.f[cands], upper=(c_up, u_up), lower=(c_lo, u_lo), elbow=el, wrist=wr)
    if straight is None:
        bis = u_up + u_lo
        bis /= np.linalg.norm(bis)
        cut = _snug_elbow_cut(body, body.v, el, bis, (c_up, u_up), cands)
    else:
        cut = _straight_elbow_cut(body, straight, cands)
    out[f"elbow_girth_{side}"] = _girth(
        f"elbow_girth_{side}",
        cut,
        (f"shoulder_point_{side}", f"elbow_point_{side}", f"wrist_point_{side}"),
        straightened_deg=0.0 if straight is None else straight.flexion_deg,
    )
    # the snug tape at the narrowest wrist, just above the styloid: the section
    # through the wrist point itself grows 3 cm per cm into the hand
    w0 = c_lo + ((wr - c_lo) @ u_lo) * u_lo
    cuts = []
    for d in np.linspace(-WRIST_ABOVE * body.stature, WRIST_BELOW * body.stature, 7):
        q = w0 + d * u_lo
        cuts.append((float(d), body.part_cut(q, u_lo, q, cands)))
    d, cut = _best(cuts, min)
    out[f"wrist_girth_{side}"] = _girth(
        f"wrist_girth_{side}", cut, (f"elbow_point_{side}", f"wrist_point_{side}"), from_wrist_point_cm=d
    )
    for mid, m in out.items():
        if m.value_cm <= 0:
            raise GirthError(f"{mid}: no arm section found")
    return out


def _leg_loop(body: BodyFrame, y: float, x_hint: float):
    sec = body.horizontal(y)
    if not sec.loops:
        raise GirthError(f"no leg section at y = {y:.1f} cm")
    loop = min(sec.loops, key=lambda lp: abs(sec.to_xyz(lp.centroid_uv)[0] - x_hint))
    return sec, loop


def _leg_girths(body: BodyFrame, side: str) -> dict[str, Measurement]:
    crotch = body.mark("crotch_point")
    knee = body.mark(f"knee_point_{side}")
    a_in, a_out = body.mark(f"ankle_inside_{side}"), body.mark(f"ankle_outside_{side}")
    ankle = 0.5 * (a_in + a_out)
    s = body.stature
    y_top = crotch[1] - 0.04 * s
    x_hint = 0.5 * (knee[0] + crotch[0])
    sec, loop = _leg_loop(body, y_top, x_hint)
    hip_c = body.loop_centre(sec, (loop,))
    sec, loop = _leg_loop(body, knee[1], knee[0])
    knee_c = body.loop_centre(sec, (loop,))
    u_th = (knee_c - hip_c) / np.linalg.norm(knee_c - hip_c)
    u_sh = (ankle - knee_c) / np.linalg.norm(ankle - knee_c)
    cands = body.near_segment(hip_c + u_th * (crotch[1] - hip_c[1]) / max(-u_th[1], 1e-6), ankle, 0.12 * s)
    out = {}

    def at_height(y: float) -> np.ndarray:  # point of the thigh axis at height y
        return hip_c + u_th * (hip_c[1] - y) / max(-u_th[1], 1e-6)

    cuts = []
    for frac in np.linspace(0.01, 0.05, 9):
        q = at_height(crotch[1] - frac * s)
        cuts.append((float(frac), body.part_cut(q, u_th, q, cands)))
    frac, cut = _best(cuts, max)
    out[f"thigh_girth_{side}"] = _girth(
        f"thigh_girth_{side}",
        cut,
        ("crotch_point", f"knee_point_{side}"),
        below_crotch_cm=frac * s,
    )
    bis = u_th + u_sh
    bis /= np.linalg.norm(bis)
    cut = body.part_cut(knee, bis, knee_c, cands)
    out[f"knee_girth_{side}"] = _girth(
        f"knee_girth_{side}",
        cut,
        (
            "crotch_point",
            f"knee_point_{side}",
            f"ankle_inside_{side}",
            f"ankle_outside_{side}",
        ),
    )
    length = float(np.linalg.norm(ankle - knee_c))
    cuts = []
    for t in np.linspace(0.15, 0.60, 10):
        q = knee_c + t * length * u_sh
        cuts.append((float(t), body.part_cut(q, u_sh, q, cands)))
    t, cut = _best(cuts, max)
    used = (f"knee_point_{side}", f"ankle_inside_{side}", f"ankle_outside_{side}")
    out[f"calf_girth_{side}"] = _girth(f"calf_girth_{side}", cut, used, axis_fraction=t)
    lo_t = 1.0 - 0.015 * s / length
    cuts = []
    for t in np.linspace(0.70, lo_t, 8):
        q = knee_c + t * length * u_sh
        cuts.append((float(t), body.part_cut(q, u_sh, q, cands)))
    t, cut = _best(cuts, min)
    out[f"ankle_girth_{side}"] = _girth(f"ankle_girth_{side}", cut, used, axis_fraction=t)
    for mid, m in out.items():
        if m.value_cm <= 0:
            raise GirthError(f"{mid}: no leg section found")
    return out


#: girth groups: the ids each computes, and the function
GROUPS: dict[str, tuple[tuple[str, ...], Callable[[BodyFrame], dict[str, Measurement]]]] = {
    "torso": (
        (
            "chest_girth",
            "underbust_girth",
            "waist_girth",
            "high_hip_girth",
            "hip_girth",
        ),
        _torso_girths,
    ),
    "neck": (("neck_girth",), lambda b: {"neck_girth": _neck_girth(b)}),
    "neck_base": (
        ("neck_base_girth",),
        lambda b: {"neck_base_girth": _neck_base_girth(b)},
    ),
    "head": (("head_girth",), lambda b: {"head_girth": _head_girth(b)}),
    **{
        f"arm_{s}": (
            tuple(f"{k}_girth_{s}" for k in ("upper_arm", "elbow", "wrist")),
            (lambda side: lambda b: _arm_girths(b, side))(s),
        )
        for s in ("left", "right")
    },
    **{
        f"leg_{s}": (
            tuple(f"{k}_girth_{s}" for k in ("thigh", "knee", "calf", "ankle")),
            (lambda side: lambda b: _leg_girths(b, side))(s),
        )
        for s in ("left", "right")
    },
}


def measure_girths(body: BodyFrame, *, progress=None, errors: dict[str, str] | None = None) -> dict[str, Measurement]:
    """Every girth; failures go to ``errors`` (id -> reason) when it is given, else raise."""
    out: dict[str, Measurement] = {}
    for i, (_, (ids, fn)) in enumerate(GROUPS.items()):
        try:
            out.update(fn(body))
        except LandmarkError as exc:
            if errors is None:
                raise
            for mid in ids:
                errors[mid] = str(exc)
        if progress is not None:
            progress("girths", i + 1, len(GROUPS))
    return out
