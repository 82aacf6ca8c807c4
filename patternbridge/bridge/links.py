"""Measurement links read off the pattern: the girths a garment controls, with their ease.

A bodice controls the chest girth, taken across the grain at the underarm: on
every chosen front and back (bodices, whose tops are scooped), from the
underarm to the centre line — doubled for a half cut on the fold or as a pair —
or, on a piece drawn whole, from one underarm to the other. Legs and skirt
panels control the waist girth across their top. A neckband or neck binding
controls the neck girth along its sewn edge (the strips of a neckline bound
in parts together), so grading keeps the band as long as the neckline needs
even when no applied seam ties it to the neckline. The **ease** is read off the
pattern itself: its girth in the sample size minus the girth of the
**reference body** ``REFERENCE_BODY_CM`` (the men's sample body of the library's
size chart, EN 13402-3 intervals: chest 96, waist 84, neck 39 cm, `docs/library.md`),
used because a file's own size label does not say which chart it follows.
The marks the links need are added as ``v<vertex>``.
"""

from __future__ import annotations

import numpy as np

from ..library.seams import sew_line
from ..pattern.model import Leg, MeasurementLink, Pattern, Piece
from .model import BridgeInference, Orientation, Role
from .openings import shapes_scooped

__all__ = ["REFERENCE_BODY_CM", "measurement_links"]

#: the body whose girths the ease is read against (library men's sample size)
REFERENCE_BODY_CM = {"chest_girth": 96.0, "waist_girth": 84.0, "neck_girth": 39.0}

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


def _span(piece: Piece, leg: Leg) -> float:
    if leg.along == "boundary":
        lines = sew_line(piece)[0]
        n, k, total = len(lines), int(leg.start[1:]), 0.0
        while k != int(leg.end[1:]):
            total += float(np.linalg.norm(lines[(k + 1) % n] - lines[k]))
            k = (k + 1) % n
        return total * leg.factor
    pts = sew_line(piece)[0]
    d = pts[int(leg.end[1:])] - pts[int(leg.start[1:])]
    return float(abs(d @ piece.across_grain)) * leg.factor


def measurement_links(pattern: Pattern, inference: BridgeInference) -> list[MeasurementLink]:
    """The chest (bodices) and waist (legs, skirt panels) links of the chosen garment."""
    chest, waist = [], []
    for name in inference.chosen:
        piece, o, role = pattern.piece(name), inference.orientations[name], inference.roles[name].role
        up = o.apply(sew_line(piece)[0])
        if role in (Role.FRONT, Role.BACK) and (shapes_scooped(up) or o.fold is not None):
            leg = _chest_leg(piece, o)
            chest += [leg] if leg else []
        elif role in _LEGS or role in (Role.FRONT, Role.BACK):
            leg = _waist_leg(piece, o)
            waist += [leg] if leg else []
    links = []
    for measurement, legs in (("chest_girth", chest), ("waist_girth", waist), ("neck_girth", _neck_legs(inference))):
        if not legs:
            continue
        girth = sum(_span(pattern.piece(g.piece), g) for g in legs)
        ease = round(girth - REFERENCE_BODY_CM[measurement], 2)
        links.append(MeasurementLink(id=measurement, measurement=measurement, legs=tuple(legs), ease_cm=ease))
    return links
