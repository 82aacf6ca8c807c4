"""Measurement links read off the pattern: the girths and lengths a garment controls, with their ease.

**Girths** (target = body + ease, the ease read off the pattern):

- *chest*, across the grain at the underarm of every chosen bodice (a front
  or back whose top is scooped): underarm to centre line, doubled for a half
  cut on the fold or as a pair; underarm to underarm on a piece drawn whole;
- *waist*, across the top of legs and skirt panels;
- *neck*, along the neckline of the bodices (centre neck to side neck, twice
  per half), and apart along the sewn edge of every neckband or neck binding
  (the strips of a neckline bound in parts together): both follow the body's
  neck with their own ease, so a band's length follows the neckline it is
  sewn to even where no applied seam ties the two;
- *upper arm*, across a sleeve at its underarm;
- *thigh*, across each leg role at its crotch point.

**Lengths** follow the body in proportion (``proportional`` links: target =
sample length × body / reference body), so a garment keeps its design's
proportion to the body: the bodice's centre length to the back length
(nape to waist), the sleeve's length to the arm, the leg's to the outside leg.
A **band's width** (binding, neckband, cuff, collar, waistband) follows the
body height in proportion, so a strip graded to a child stays a strip.

The **ease** and the proportions are read against the **reference body**
``REFERENCE_BODY_CM``: the men's sample body of the library's size chart
(EN 13402-3 intervals with Aldrich's secondary dimensions, `docs/library.md`),
because a file's own size label does not say which chart it follows. The
marks the links need are added as ``v<vertex>``.
"""

from __future__ import annotations

import numpy as np

from ..library.seams import sew_line
from ..pattern.model import Leg, MeasurementLink, Pattern, Piece
from .landmarks import PieceLandmarks, piece_landmarks
from .model import BridgeInference, Orientation, Role, is_band
from .openings import shapes_scooped

__all__ = ["REFERENCE_BODY_CM", "measurement_links"]

#: the body whose girths the ease and whose lengths the proportions are read against (library men's sample size)
REFERENCE_BODY_CM = {
    "chest_girth": 96.0,
    "waist_girth": 84.0,
    "neck_girth": 39.0,
    "upper_arm_girth_right": 31.8,
    "thigh_girth_right": 57.0,
    "back_length": 45.0,
    "arm_length_right": 64.0,
    "outside_leg_right": 105.0,
    "stature": 176.0,
}

_LEGS = (Role.LEG, Role.LEG_FRONT, Role.LEG_BACK)


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


def _neck_legs(inference: BridgeInference) -> list[Leg]:
    """The sewn long edge of every chosen neckband or neck binding, once per band, along its boundary."""
    legs: dict[str, Leg] = {}
    for j in inference.joins:
        band = j.b.piece
        if j.kind != "band" or band not in inference.chosen or band in legs:
            continue
        if inference.roles[band].role in (Role.NECKBAND, Role.NECK_BINDING):
            legs[band] = Leg(piece=band, start=f"v{j.b.start}", end=f"v{j.b.end}", along="boundary", factor=1.0)
    return list(legs.values())


def _across_at(up: np.ndarray, at: int, far_side: bool = True) -> int:
    """The vertex on the other side of the piece from vertex ``at``, nearest its level."""
    x, y = up[:, 0], up[:, 1]
    mid = 0.5 * (x.min() + x.max())
    other = np.nonzero((x - mid) * (x[at] - mid) < 0)[0] if far_side else np.arange(len(up))
    if not len(other):
        return at
    return int(other[np.argmin(np.abs(y[other] - y[at]))])


def _sleeve_legs(piece: Piece, o: Orientation, found: PieceLandmarks) -> tuple[Leg | None, Leg | None]:
    """(upper arm across the underarm, cap top to hem along the sleeve) of a sleeve."""
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
    cap = found.marks.get("cap_top")
    if cap is None:
        return girth, None
    bottom = np.nonzero(y <= y.min() + 0.03 * np.ptp(y))[0]
    hem = int(bottom[np.argmin(np.abs(x[bottom] - x[cap]))])
    return girth, Leg(piece=piece.name, start=f"v{cap}", end=f"v{hem}", along="chord", factor=1.0)


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


def _band_width_leg(piece: Piece, o: Orientation, found: PieceLandmarks) -> Leg | None:
    """A band's width: from the middle of its sewn long edge straight across to its other long edge."""
    mid = found.marks.get("band_middle")
    if mid is None:
        return None
    up = o.apply(sew_line(piece)[0])
    x, y = up[:, 0], up[:, 1]
    top = np.nonzero(y >= y.max() - 0.25 * np.ptp(y))[0]
    if not len(top):
        return None
    other = int(top[np.argmin(np.abs(x[top] - x[mid]))])
    if other == mid:
        return None
    return Leg(piece=piece.name, start=f"v{mid}", end=f"v{other}", along="chord", factor=1.0)


def _span(piece: Piece, leg: Leg) -> float:
    pts = sew_line(piece)[0]
    i, j = int(leg.start[1:]), int(leg.end[1:])
    if leg.along == "boundary":
        return _arc(pts, i, j) * leg.factor
    d = pts[j] - pts[i]
    if leg.along == "chord":
        return float(np.linalg.norm(d)) * leg.factor
    return float(abs(d @ piece.across_grain)) * leg.factor


def _collect(pattern: Pattern, inference: BridgeInference) -> dict[str, list[Leg]]:
    """Legs of every link, keyed ``link id|measurement|kind`` (kind ``girth`` or ``length``)."""
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
            add("chest_girth|chest_girth|girth", _chest_leg(piece, o))
            add("neck_girth|neck_girth|girth", _neckline_leg(piece, o, found[name]))
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
                if "leg_length|outside_leg_right|length" not in legs:
                    add("leg_length|outside_leg_right|length", length)
        elif role is Role.SLEEVE and first:
            girth, length = _sleeve_legs(piece, o, found[name])
            add("upper_arm_girth|upper_arm_girth_right|girth", girth)
            add("sleeve_length|arm_length_right|length", length)
        elif is_band(role):
            add(f"{name}_width|stature|length", _band_width_leg(piece, o, found[name]))
    for leg in _neck_legs(inference):
        add("neckband_girth|neck_girth|girth", leg)
    return legs


def measurement_links(pattern: Pattern, inference: BridgeInference) -> list[MeasurementLink]:
    """The girth and length links of the chosen garment, with ease and proportions read off the pattern."""
    links = []
    for key, legs in _collect(pattern, inference).items():
        link_id, measurement, kind = key.split("|")
        sample = sum(_span(pattern.piece(g.piece), g) for g in legs)
        if sample <= 1e-6:
            continue
        ease = round(sample - REFERENCE_BODY_CM[measurement], 2)
        if kind == "length" and ease >= sample:
            continue
        links.append(
            MeasurementLink(
                id=link_id, measurement=measurement, legs=tuple(legs), ease_cm=ease, proportional=kind == "length"
            )
        )
    return links
