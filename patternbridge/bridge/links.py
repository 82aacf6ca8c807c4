"""Measurement links read off the pattern: the girths and lengths a garment controls, with their ease.

**Girths** (target = body + ease, the ease read off the pattern):

- *chest*, across the grain at the underarm of every chosen bodice (a front
  or back whose top is scooped): underarm to centre line, doubled for a half
  cut on the fold or as a pair; underarm to underarm on a piece drawn whole;
- *waist*, across the top of legs and skirt panels;
- *neck*, along the neckline of the bodices (centre neck to side neck, twice
  per half), when the neckline sits at the neck: at most ``NECK_AT_NECK``
  times the reference neck (a crew or polo neckline is 2–10 cm over the neck;
  a tank's scoop, 52–66 cm on the real files, is a style line that the neck
  does not control: its ``neckline`` link keeps its proportion to the chest
  girth, as the bodice does);
- *hip*, across the hem of every chosen bodice whose hem falls at or below
  the hip: its body length (centre neck to centre hem) at least the sample
  body's back length plus its waist-to-hip height; the hem's side corner to
  the centre line, doubled as the chest is; an ``at_least`` link: a top
  whose hem passes over the hips must reach the hips plus its ease, and may
  be wider (a straight hem over narrow hips is the design, not an error);
- *upper arm*, across a sleeve at its underarm;
- *thigh*, across each leg role at its crotch point;
- *knee*, *calf* and *ankle*, across each leg role at the level the body's
  girth is measured at (:data:`.size_chart.LEG_LEVELS`: its share of the
  sample body's inside leg below the leg's crotch point), from the outline's
  vertex nearest that level on one side of the leg to the one on the other;
  a level below the hem is not measured, unless it lies within
  ``HEM_REACH_CM`` of it (a full-length leg's ankle girth is its hem). The
  ease is the pattern's width there minus the sample body's girth (the calf
  of :data:`.size_chart.CALF_UNDER_KNEE_CM`, which no chart states). Without
  them nothing below the thigh follows the body: the lower leg is graded
  with the width alone (the leggings' knee and hem 1.9 cm wider than
  the pattern's ease on the child, 2.1–2.4 cm on the average man). Only
  a leg that fits is linked there: a width over ``LEG_AT_BODY`` times the
  body's girth is a style width (the library trousers' knee is 1.26 times
  the knee, their hem 1.86 times the ankle), which the body does not
  control; it keeps its proportion to the rest of the leg, as the width
  grading gives it (held to the body with an adult's ease, a child's
  trousers narrowed below the knee and their pieces turned 3.9–4.3°).

**Lengths** follow the body in proportion (``proportional`` links: target =
sample length × body / sample body), so a garment keeps its design's
proportion to the body: the bodice's centre length to the back length
(nape to waist), the sleeve's underarm seam to the arm, the leg's length to
the outside leg.
A **band's width** (binding, neckband, cuff, collar, waistband) follows the
body height in proportion, so a strip graded to a child stays a strip; so
does a **strap's width** (``<piece>_strap``: a bodice's shoulder, side neck
to shoulder point, straight) when the neckline is a scoop (a ``neckline``
link) and the shoulder is a strap, at most ``STRAP_SHARE`` of the bodice's
half chest span: nothing else holds the strip of cloth between a scoop and
the armhole, and graded to a child it would vanish. A neckline at the neck,
or a shoulder as wide as a T-shirt's, is held with the chest and the neck. A
band sewn along an opening of several ranges (``band`` entries, not applied
as seams) keeps its **length to the opening**: the link ``<band>_length``
is its sewn edge minus the opening's ranges (each copy of a half at a centre
line counted), a difference that follows the body height in proportion, so a
binding 1 cm shorter than its armhole stays about that much shorter.

A **girth drafted under the body** (negative ease: leggings, a fitted
jersey) follows the body in proportion too: such a garment goes on only by
stretching, and what its designer drafts is the stretch it is worn at, a
share of the body's girth (the leggings' calf 15.6 % under the sample's,
worn stretched 18.5 %), not a number of centimetres. With the ease added in
centimetres a child's calf (26.7 cm) would be worn stretched 24.9 % by the
same 5.3 cm, and a large calf less than drafted. A girth with ease (a
shirt's chest) keeps its ease in centimetres: the room a body moves in does
not scale with it.

The **ease** and the proportions are read against the **sample body**: the
body of the file's sample size in the size system its labels belong to
(:mod:`.size_chart`: a women's file's size 36 against a bust of 84 cm, a
men's size 50 against a chest of 100 cm; a file in no recognised system
against the library's men's sample body, ``REFERENCE_BODY_CM``). The marks
the links need are added as ``v<vertex>``.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from ..library.seams import sew_line
from ..pattern.model import Leg, MeasurementLink, Pattern, Piece
from .landmarks import PieceLandmarks, piece_landmarks
from .model import BridgeInference, Orientation, Role, is_band
from .openings import shapes_scooped
from .size_chart import LEG_LEVELS, REFERENCE_BODY_CM, ChartChoice, choose_chart

__all__ = ["REFERENCE_BODY_CM", "measurement_links"]

#: a neckline longer than this many reference necks is a style line (scoop, boat), not a neck fit
NECK_AT_NECK = 1.3
#: a knee, calf or ankle width over this many body girths is a style width (a trouser's), not a fit (the leggings':
#: 0.84-0.98; the library trousers' knee 1.26, hem 1.86)
LEG_AT_BODY = 1.2
#: a shoulder at most this share of the bodice's half chest span is a strap (tanks: 0.12-0.31 on the shared
#: files; a T-shirt's or a shirt's shoulder: 0.5-0.64)
STRAP_SHARE = 0.4

#: a bodice's hem: its lowest share of the piece's height (a shirt-tail's side corner sits above its centre hem)
HEM_BAND = 0.2

_LEGS = (Role.LEG, Role.LEG_FRONT, Role.LEG_BACK)

#: a leg level at most this far below the hem (cm) is measured at the hem (a full-length leg's ankle)
HEM_REACH_CM = 3.0


def _copies(piece: Piece, o: Orientation) -> float:
    return 2.0 if o.fold is not None or piece.quantity.left > 0 or piece.quantity.right > 1 else 1.0


def _chest_leg(piece: Piece, o: Orientation) -> Leg | None:
    """Underarm to centre line (a half) or underarm to underarm (a whole piece), across the grain."""
    up = o.apply(sew_line(piece)[0])
    y, h = up[:, 1], np.ptp(up[:, 1])
    band = (y >= y.min() + 0.45 * h) & (y <= y.min() + 0.85 * h)
    if not band.any():
        return None
    idx = np.nonzero(band)[0]
    if o.whole:
        lo, hi = int(idx[np.argmin(up[idx, 0])]), int(idx[np.argmax(up[idx, 0])])
        return Leg(piece=piece.name, start=f"v{lo}", end=f"v{hi}", along="across", factor=1.0)
    under = int(idx[np.argmax(np.abs(up[idx, 0]))])
    centre = np.nonzero(np.abs(up[:, 0]) < 0.5)[0]
    if not len(centre):
        return None
    mid = int(centre[np.argmin(np.abs(up[centre, 1] - up[under, 1]))])
    return Leg(piece=piece.name, start=f"v{under}", end=f"v{mid}", along="across", factor=_copies(piece, o))


def _hem_leg(piece: Piece, o: Orientation, found: PieceLandmarks) -> Leg | None:
    """Across a bodice's hem: its side corner (the widest vertex of the lowest ``HEM_BAND``) to the centre line.

    A piece drawn whole is taken from its left to its right hem corner.
    """
    up = o.apply(sew_line(piece)[0])
    y = up[:, 1]
    idx = np.nonzero(y <= y.min() + HEM_BAND * np.ptp(y))[0]
    if o.whole:
        lo, hi = int(idx[np.argmin(up[idx, 0])]), int(idx[np.argmax(up[idx, 0])])
        return Leg(piece=piece.name, start=f"v{lo}", end=f"v{hi}", along="across", factor=1.0)
    side = int(idx[np.argmax(np.abs(up[idx, 0]))])
    centre = found.marks.get("centre_hem")
    if centre is None:
        on_centre = np.nonzero(np.abs(up[:, 0]) < 0.5)[0]
        if not len(on_centre):
            return None
        centre = int(on_centre[np.argmin(y[on_centre])])
    if centre == side:
        return None
    return Leg(piece=piece.name, start=f"v{side}", end=f"v{centre}", along="across", factor=_copies(piece, o))


def _waist_leg(piece: Piece, o: Orientation) -> Leg | None:
    """Across the top of a leg or skirt panel, from its left to its right top corner."""
    up = o.apply(sew_line(piece)[0])
    y, h = up[:, 1], np.ptp(up[:, 1])
    top = np.nonzero(y >= y.max() - 0.1 * h)[0]
    if len(top) < 2:
        return None
    lo, hi = int(top[np.argmin(up[top, 0])]), int(top[np.argmax(up[top, 0])])
    return Leg(piece=piece.name, start=f"v{lo}", end=f"v{hi}", along="across", factor=_copies(piece, o))


def _arc(points: np.ndarray, start: int, end: int) -> float:
    """Length along a closed polyline from ``start`` to ``end`` in outline order."""
    n, k, total = len(points), start, 0.0
    while k != end:
        total += float(np.linalg.norm(points[(k + 1) % n] - points[k]))
        k = (k + 1) % n
    return total


def _neckline_leg(piece: Piece, o: Orientation, found: PieceLandmarks) -> Leg | None:
    """A bodice's neckline from its centre neck to its side neck (the shorter way round), twice per half."""
    a, b = found.marks.get("centre_neck"), found.marks.get("neck_side")
    if a is None or b is None or a == b:
        return None
    pts = sew_line(piece)[0]
    start, end = (a, b) if _arc(pts, a, b) <= _arc(pts, b, a) else (b, a)
    factor = 2.0 if o.whole else _copies(piece, o)
    return Leg(piece=piece.name, start=f"v{start}", end=f"v{end}", along="boundary", factor=factor)


def _strap_leg(piece: Piece, found: PieceLandmarks) -> Leg | None:
    """A bodice's strap: straight across its shoulder, from the side neck to the shoulder point."""
    a, b = found.marks.get("neck_side"), found.marks.get("shoulder_point")
    if a is None or b is None or a == b:
        return None
    return Leg(piece=piece.name, start=f"v{a}", end=f"v{b}", along="chord", factor=1.0)


def _opening_factor(pattern: Pattern, inference: BridgeInference, side) -> float:
    """How often a band runs along an opening range: each copy at a centre line (neck, waist), else once.

    An armhole range is bound once per binding (each armhole has its own copy
    of the binding; a piece drawn whole has an armhole on each side, so each
    of its two ranges counts half); a neckline or waist range of a half cut on
    the fold or as a pair is bound on both halves by the one band.
    """
    piece, o = pattern.piece(side.piece), inference.orientations[side.piece]
    up = o.apply(sew_line(piece)[0])
    n = len(up)
    idx = np.arange(side.start, side.end + 1) if side.end >= side.start else np.r_[side.start : n, 0 : side.end + 1]
    at_centre = bool(np.abs(up[idx, 0]).min() < 0.5) or inference.roles[side.piece].role in _LEGS
    if at_centre:
        return _copies(piece, o)
    return 0.5 if o.whole else 1.0


def _band_length_legs(pattern: Pattern, inference: BridgeInference) -> dict[str, list[Leg]]:
    """Per band along an opening: its sewn edge (+1) and the opening's ranges (-copies), so the band follows them."""
    legs: dict[str, list[Leg]] = {}
    sewn: set[tuple[str, int, int]] = set()
    for j in inference.joins:
        band = j.b.piece
        if j.kind != "band" or band not in inference.chosen or j.a.piece not in inference.chosen:
            continue
        if (band, j.b.start, j.b.end) not in sewn:  # a band cut at its own marks sews several ranges
            sewn.add((band, j.b.start, j.b.end))
            legs.setdefault(band, []).append(
                Leg(piece=band, start=f"v{j.b.start}", end=f"v{j.b.end}", along="boundary", factor=1.0)
            )
        factor = -_opening_factor(pattern, inference, j.a)
        legs[band].append(
            Leg(piece=j.a.piece, start=f"v{j.a.start}", end=f"v{j.a.end}", along="boundary", factor=factor)
        )
    return legs


def _across_at(up: np.ndarray, at: int, far_side: bool = True) -> int:
    """The vertex on the other side of the piece from vertex ``at``, nearest its level."""
    x, y = up[:, 0], up[:, 1]
    mid = 0.5 * (x.min() + x.max())
    other = np.nonzero((x - mid) * (x[at] - mid) < 0)[0] if far_side else np.arange(len(up))
    if not len(other):
        return at
    return int(other[np.argmin(np.abs(y[other] - y[at]))])


def _sleeve_legs(piece: Piece, o: Orientation) -> tuple[Leg | None, Leg | None]:
    """(upper arm across the underarm, underarm seam from the underarm to the hem) of a sleeve."""
    up = o.apply(sew_line(piece)[0])
    x, y = up[:, 0], up[:, 1]
    if o.fold is not None:
        under = int(np.argmax(np.abs(x)))
        centre = np.nonzero(np.abs(x) < 0.5)[0]
        mid = int(centre[np.argmin(np.abs(y[centre] - y[under]))]) if len(centre) else under
        girth = Leg(piece=piece.name, start=f"v{under}", end=f"v{mid}", along="across", factor=2.0)
    else:
        lo, hi = int(np.argmin(x)), int(np.argmax(x))
        girth = Leg(piece=piece.name, start=f"v{lo}", end=f"v{hi}", along="across", factor=1.0)
    # the length along the underarm seam, underarm to hem corner: a seam edge, not one hem vertex the grader
    # could move alone
    under = int(np.argmin(x))
    bottom = np.nonzero(y <= y.min() + 0.03 * np.ptp(y))[0]
    corner = int(bottom[np.argmin(x[bottom])])
    if under == corner:
        return girth, None
    pts = sew_line(piece)[0]
    start, end = (under, corner) if _arc(pts, under, corner) <= _arc(pts, corner, under) else (corner, under)
    return girth, Leg(piece=piece.name, start=f"v{start}", end=f"v{end}", along="boundary", factor=1.0)


def _leg_legs(piece: Piece, o: Orientation, found: PieceLandmarks) -> tuple[Leg | None, Leg | None]:
    """(thigh across the crotch point, side waist to hem) of a leg piece."""
    up = o.apply(sew_line(piece)[0])
    crotch, side = found.marks.get("crotch_point"), found.marks.get("side_waist")
    if crotch is None or side is None:
        return None, None
    other = _across_at(up, crotch)
    thigh = Leg(piece=piece.name, start=f"v{crotch}", end=f"v{other}", along="across", factor=1.0)
    y = up[:, 1]
    bottom = np.nonzero(y <= y.min() + 0.03 * np.ptp(y))[0]
    hem = int(bottom[np.argmin(np.abs(up[bottom, 0] - up[side, 0]))])
    return thigh, Leg(piece=piece.name, start=f"v{side}", end=f"v{hem}", along="chord", factor=1.0)


def _pair_at_level(up: np.ndarray, level: float) -> tuple[int, int] | None:
    """The outline vertices nearest height ``level`` on its leftmost and rightmost crossing of that height."""
    n = len(up)
    ya, yb = up[:, 1], np.roll(up[:, 1], -1)
    cross = np.nonzero(((ya - level) * (yb - level) <= 0) & (ya != yb))[0]
    if len(cross) < 2:
        return None
    nxt = (cross + 1) % n
    t = (level - ya[cross]) / (yb[cross] - ya[cross])
    x = up[cross, 0] + t * (up[nxt, 0] - up[cross, 0])
    ends = np.where(np.abs(ya[cross] - level) <= np.abs(yb[cross] - level), cross, nxt)
    left, right = int(ends[np.argmin(x)]), int(ends[np.argmax(x)])
    return None if left == right else (left, right)


def _leg_level_legs(piece: Piece, o: Orientation, found: PieceLandmarks, inside_leg: float) -> dict[str, Leg]:
    """Per leg girth of :data:`.size_chart.LEG_LEVELS` (measurement id): the leg across the piece at its level.

    The level lies ``share × inside_leg`` (the sample body's) below the
    piece's crotch point; a level below the hem by more than ``HEM_REACH_CM``
    is left out, one within it is taken at the hem. Two levels that meet the
    same pair of vertices keep the first (the outline has no vertex between).
    """
    crotch = found.marks.get("crotch_point")
    if crotch is None:
        return {}
    up = o.apply(sew_line(piece)[0])
    hem = float(up[:, 1].min())
    out: dict[str, Leg] = {}
    used: set[tuple[int, int]] = set()
    for measurement, share in LEG_LEVELS.items():
        level = float(up[crotch, 1]) - share * inside_leg
        if level < hem - HEM_REACH_CM:
            continue
        pair = _pair_at_level(up, max(level, hem + 1e-6))
        if pair is None or pair in used:
            continue
        used.add(pair)
        out[measurement] = Leg(piece=piece.name, start=f"v{pair[0]}", end=f"v{pair[1]}", along="across", factor=1.0)
    return out


def _level_leg(piece: Piece, up: np.ndarray, found: PieceLandmarks, girth: Leg) -> Leg | None:
    """The height of a leg girth's level: the chord from the hem up the inseam to the girth's vertex there, or None.

    A girth link holds the leg's width between its two vertices, not where
    they sit along the leg: graded to a calf larger than its knee
    (E_average_male: 39.5 against 37.6 cm) the least-change grading slid the
    calf's vertices up the taper to 1.6 cm under the knee's, and the narrow
    rows below them came to lie round the calf. This length, proportional to
    the inside leg, keeps the level at its share of the leg above the hem
    (which the leg's length holds; measured from the crotch point instead, the
    grader met it by moving the crotch down). None for a level at the hem, or
    without a crotch point (which says where the inseam is).
    """
    crotch = found.marks.get("crotch_point")
    if crotch is None:
        return None
    near = lambda k: float(np.linalg.norm(up[k] - up[crotch]))  # noqa: E731
    inseam = min((int(girth.start[1:]), int(girth.end[1:])), key=near)
    low = float(up[:, 1].min())
    if up[inseam, 1] <= low + HEM_REACH_CM:
        return None
    hem = min(np.flatnonzero(up[:, 1] <= low + 0.5).tolist(), key=near)
    return Leg(piece=piece.name, start=f"v{hem}", end=f"v{inseam}", along="chord")


def _band_width_leg(piece: Piece) -> Leg | None:
    """A band's width: straight across its short axis, near the middle of its length.

    The long axis is the principal axis of the sew line (a band may be drawn
    or stood up either way); the leg joins the vertex of the long edge with
    fewer vertices nearest the band's middle (a corner, on a plain edge) to
    the vertex of the other long edge nearest it along the band.
    """
    pts = sew_line(piece)[0]
    c = pts - pts.mean(axis=0)
    _, _, vt = np.linalg.svd(c, full_matrices=False)
    along, across = c @ vt[0], c @ vt[1]
    tol = 0.1 * np.ptp(across)
    low = np.nonzero(across <= across.min() + tol)[0]
    high = np.nonzero(across >= across.max() - tol)[0]
    if not len(low) or not len(high):
        return None
    if len(high) < len(low):  # start on the edge with fewer vertices (a plain edge has only its corners)
        low, high = high, low
    i = int(low[np.argmin(np.abs(along[low]))])
    j = int(high[np.argmin(np.abs(along[high] - along[i]))])
    if i == j:
        return None
    return Leg(piece=piece.name, start=f"v{i}", end=f"v{j}", along="chord", factor=1.0)


def _span(piece: Piece, leg: Leg) -> float:
    pts = sew_line(piece)[0]
    i, j = int(leg.start[1:]), int(leg.end[1:])
    if leg.along == "boundary":
        return _arc(pts, i, j) * leg.factor
    d = pts[j] - pts[i]
    if leg.along == "chord":
        return float(np.linalg.norm(d)) * leg.factor
    return float(abs(d @ piece.across_grain)) * leg.factor


def _collect(pattern: Pattern, inference: BridgeInference, body: Mapping[str, float]) -> dict[str, list[Leg]]:
    """Legs of every link, keyed ``link id|measurement|kind`` (kind ``girth`` or ``length``).

    ``body`` is the sample body (it places the leg levels).
    """
    found = piece_landmarks(pattern, inference)
    legs: dict[str, list[Leg]] = {}

    def add(key: str, leg: Leg | None) -> None:
        if leg is not None:
            legs.setdefault(key, []).append(leg)

    seen_roles: set[Role] = set()
    for name in inference.chosen:
        piece, o, role = pattern.piece(name), inference.orientations[name], inference.roles[name].role
        up = o.apply(sew_line(piece)[0])
        first = role not in seen_roles  # lengths and limb girths: one piece of each role
        seen_roles.add(role)
        if role in (Role.FRONT, Role.BACK) and (shapes_scooped(up) or o.fold is not None):
            chest = _chest_leg(piece, o)
            add("chest_girth|chest_girth|girth", chest)
            add("neck_girth|neck_girth|girth", _neckline_leg(piece, o, found[name]))
            add("hip_girth|hip_girth|girth", _hem_leg(piece, o, found[name]))
            strap = _strap_leg(piece, found[name])
            if strap is not None and chest is not None:
                half_chest = _span(piece, chest) / (2.0 if o.whole else chest.factor)
                if _span(piece, strap) <= STRAP_SHARE * half_chest:
                    add(f"{name}_strap|stature|length", strap)
            if role is Role.BACK or Role.BACK not in {inference.roles[n].role for n in inference.chosen}:
                if first and "centre_neck" in found[name].marks and "centre_hem" in found[name].marks:
                    m = found[name].marks
                    add(
                        "body_length|back_length|length",
                        Leg(piece=name, start=f"v{m['centre_neck']}", end=f"v{m['centre_hem']}", along="chord"),
                    )
        elif role in _LEGS or role in (Role.FRONT, Role.BACK):
            add("waist_girth|waist_girth|girth", _waist_leg(piece, o))
            if role in _LEGS and first:
                thigh, length = _leg_legs(piece, o, found[name])
                add("thigh_girth|thigh_girth_right|girth", thigh)
                levels = _leg_level_legs(piece, o, found[name], body["inside_leg_right"])
                for measurement, leg in levels.items():
                    add(f"{measurement.removesuffix('_right')}|{measurement}|girth", leg)
                    level = _level_leg(piece, up, found[name], leg)
                    add(f"{measurement.removesuffix('_girth_right')}_level|inside_leg_right|length", level)
                if "leg_length|outside_leg_right|length" not in legs:
                    add("leg_length|outside_leg_right|length", length)
        elif role is Role.SLEEVE and first:
            girth, length = _sleeve_legs(piece, o)
            add("upper_arm_girth|upper_arm_girth_right|girth", girth)
            add("sleeve_length|arm_length_right|length", length)
        elif is_band(role):
            add(f"{name}_width|stature|length", _band_width_leg(piece))
    for band, band_legs in _band_length_legs(pattern, inference).items():
        for leg in band_legs:
            add(f"{band}_length|stature|length", leg)
    return legs


def measurement_links(
    pattern: Pattern, inference: BridgeInference, chart: ChartChoice | None = None
) -> list[MeasurementLink]:
    """The girth and length links of the chosen garment, with ease and proportions read off the pattern.

    Ease and proportions are read against the body of the file's sample size
    in ``chart`` (default: :func:`.size_chart.choose_chart` of the file's sizes).
    """
    body = (chart or choose_chart(pattern.sizes, pattern.sample_size)).body_cm
    links = []
    collected = _collect(pattern, inference, body)
    neck = sum(_span(pattern.piece(g.piece), g) for g in collected.get("neck_girth|neck_girth|girth", ()))
    length = sum(_span(pattern.piece(g.piece), g) for g in collected.get("body_length|back_length|length", ()))
    if length < body["back_length"] + body["waist_to_hip"]:
        collected.pop("hip_girth|hip_girth|girth", None)  # the hem sits above the hip: the hips do not pass it
    girth_ids = {
        k.split("|")[0]
        for k, legs in collected.items()
        if k.split("|")[1] in LEG_LEVELS
        and sum(_span(pattern.piece(g.piece), g) for g in legs) <= LEG_AT_BODY * body[k.split("|")[1]]
    }
    for key, legs in collected.items():
        if key.split("|")[0].endswith("_strap") and neck <= NECK_AT_NECK * body["neck_girth"]:
            continue  # a neckline at the neck holds the shoulder with the chest; only a scoop leaves a strap free
        link_id, measurement, kind = key.split("|")
        sample = sum(_span(pattern.piece(g.piece), g) for g in legs)
        if kind == "girth" and sample <= 1e-6:
            continue
        if link_id == "neck_girth" and sample > NECK_AT_NECK * body["neck_girth"]:
            # a style line: it keeps its proportion to the bodice's girth
            link_id, measurement, kind = "neckline", "chest_girth", "length"
        if measurement in LEG_LEVELS and sample > LEG_AT_BODY * body[measurement]:
            continue  # a style width (a trouser's knee or hem): the body does not control it
        if link_id.endswith("_level") and f"{link_id.removesuffix('_level')}_girth" not in girth_ids:
            continue  # the level of a width the body does not control
        ease = round(sample - body[measurement], 2)
        if kind == "length" and ease >= sample:
            continue
        links.append(
            MeasurementLink(
                id=link_id,
                measurement=measurement,
                legs=tuple(legs),
                ease_cm=ease,
                proportional=kind == "length" or ease < 0.0,
                at_least=link_id == "hip_girth",
            )
        )
    return links
