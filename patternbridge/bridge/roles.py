"""What each piece is: front, back, sleeve, leg, band, … from its geometry first.

Every piece is turned upright (:mod:`.orient`) and described by a few numbers
(:class:`Shape`): its size relative to the largest piece, whether it is a thin
strip, whether the top of the piece bulges out (a sleeve cap) or is scooped
in (neckline and armhole, crotch curves), whether it is cut on the fold, how
deep its neckline drops at the centre line, how wide the hem is against the
widest level. Rules on these give a role and a confidence; the words the file
writes on a piece (:mod:`.hints`) only decide between roles the geometry
leaves open, and raise the confidence when they agree.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..library.seams import sew_line
from ..pattern.geometry import area
from ..pattern.model import Pattern, Piece
from .edges import turning
from .hints import name_hint
from .model import Orientation, Role, RoleGuess, is_band, is_body
from .orient import SMOOTH_DEG, is_strip

__all__ = ["Shape", "infer_roles", "shape_of"]

#: a piece at least this share of the largest piece's area is a body piece
BODY_AREA = 0.3
#: a piece below this share is a small part (placket, interlining, pocket)
SMALL_AREA = 0.12
#: a straight strip at least this wide is a (flat-knit) collar, narrower a neckband
COLLAR_WIDTH_CM = 5.0
#: a leg's hem is narrower than its widest level (the crotch); a bodice's is not
LEG_HEM_SHARE = 0.9


@dataclass(frozen=True, slots=True, kw_only=True)
class Shape:
    """Upright shape numbers of one piece (cm, rad)."""

    height_cm: float
    width_cm: float
    area_share: float
    band: bool
    fold: bool
    n_corners: int
    top_bend_rad: float
    both_sides_scooped: bool
    one_side_scooped: bool
    scoops: tuple[float, float]
    neck_depth_cm: float
    hem_share: float
    paired: bool
    curved_rad: float


def _top(points: np.ndarray, share: float) -> np.ndarray:
    y = points[:, 1]
    return y >= y.max() - share * np.ptp(y)


def _width_at(points: np.ndarray, y: float) -> float:
    """Span (cm) of the closed outline's crossings with the horizontal line at ``y``."""
    a, b = points, np.roll(points, -1, axis=0)
    cross = (a[:, 1] - y) * (b[:, 1] - y) <= 0
    da = b[cross] - a[cross]
    t = np.where(np.abs(da[:, 1]) > 1e-12, (y - a[cross, 1]) / np.where(da[:, 1] == 0, 1, da[:, 1]), 0.0)
    xs = a[cross, 0] + t * da[:, 0]
    return float(np.ptp(xs)) if len(xs) > 1 else 0.0


def shape_of(piece: Piece, o: Orientation, largest_cm2: float) -> Shape:
    """The :class:`Shape` of ``piece`` turned by ``o``."""
    pts = o.apply(sew_line(piece)[0])
    turn = turning(pts)
    smooth = np.abs(turn) < np.radians(SMOOTH_DEG)
    cap = pts[:, 1] >= pts[:, 1].max() - 0.25 * np.ptp(pts[:, 0])
    top_bend = float(turn[cap & smooth].sum())
    xmid = 0.5 * (pts[:, 0].min() + pts[:, 0].max())
    scoop = (turn < -np.radians(2)) & smooth & _top(pts, 0.6)
    left = float(-turn[scoop & (pts[:, 0] < xmid)].sum())
    right = float(-turn[scoop & (pts[:, 0] >= xmid)].sum())
    # neckline depth at the centre line (x = 0 after the turn)
    near = np.abs(pts[:, 0]) < max(0.02 * np.ptp(pts[:, 0]), 0.3)
    neck = float(pts[:, 1].max() - pts[near, 1].max()) if near.any() else 0.0
    y = pts[:, 1]
    hem_w = max(_width_at(pts, y.min() + f * np.ptp(y)) for f in (0.02, 0.08, 0.14, 0.2, 0.25))
    return Shape(
        height_cm=float(np.ptp(y)),
        width_cm=float(np.ptp(pts[:, 0])),
        area_share=float(area(pts)) / max(largest_cm2, 1e-9),
        band=is_strip(piece),
        fold=o.fold is not None,
        n_corners=int(np.sum(np.abs(turn) > np.radians(20))),
        top_bend_rad=top_bend,
        both_sides_scooped=min(left, right) > 0.3,
        one_side_scooped=max(left, right) > 0.3 and min(left, right) < 0.15,
        scoops=(round(left, 2), round(right, 2)),
        neck_depth_cm=neck,
        hem_share=hem_w / max(float(np.ptp(pts[:, 0])), 1e-9),
        paired=piece.quantity.left > 0 or piece.quantity.right > 1,
        curved_rad=float(np.abs(turn[smooth]).sum()),
    )


def _band_role(s: Shape, hint: Role | None) -> tuple[Role, float, str]:
    shaped = s.curved_rad > 0.8 or s.n_corners > 8
    if hint is Role.COLLAR and not shaped and min(s.width_cm, s.height_cm) < COLLAR_WIDTH_CM:
        return Role.NECKBAND, 0.7, "straight strip named collar: a neckband"
    if hint is not None and (is_band(hint) or hint in (Role.PLACKET, Role.INTERLINING)):
        return hint, 0.9, f"strip; named {hint.value}"
    if shaped:
        return Role.COLLAR, 0.6, "strip with a shaped edge"
    if s.n_corners <= 4:
        return Role.NECK_BINDING, 0.6, "plain strip"
    return Role.NECKBAND, 0.6, "strip with shaped ends"


def _small_role(s: Shape, hint: Role | None) -> tuple[Role, float, str]:
    if hint is not None and not is_body(hint) and hint is not Role.SLEEVE:
        return hint, 0.8, f"small piece; named {hint.value}"
    if s.curved_rad > 0.8:
        return Role.COLLAR, 0.5, "small shaped piece"
    return Role.OTHER, 0.4, "small piece"


def _body_role(s: Shape, hint: Role | None) -> tuple[Role, float, str]:
    if s.top_bend_rad > 0.3 and not s.fold:
        return Role.SLEEVE, 0.9, f"top bulges out ({s.top_bend_rad:.2f} rad): a sleeve cap"
    if not s.fold and s.one_side_scooped:
        return Role.LEG, 0.8, "scooped on one side only (the crotch curve): a front or back leg"
    if not s.fold and s.both_sides_scooped and s.hem_share < LEG_HEM_SHARE:
        return Role.LEG, 0.75, "scooped on both sides (two rises), narrow hem: a one-piece leg"
    if not s.fold and hint in (Role.LEG, Role.LEG_FRONT, Role.LEG_BACK):
        return Role.LEG, 0.6, "named a leg; its shape would also fit a bodice"
    return Role.FRONT, 0.5, "body piece"


def _split_front_back(pattern: Pattern, roles: dict[str, RoleGuess], shapes: dict[str, Shape]) -> None:
    """Tell fronts from backs (deeper neckline) and leg fronts from leg backs (larger)."""
    body = [n for n, g in roles.items() if g.role is Role.FRONT]
    tops = [n for n in body if shapes[n].both_sides_scooped or shapes[n].fold]
    for n in set(body) - set(tops):
        hint = name_hint(pattern.piece(n))
        if hint in (Role.FRONT, Role.BACK):
            roles[n] = RoleGuess(role=hint, confidence=0.7, why=f"waist-high piece named {hint.value}")
        else:
            role = Role.BACK if shapes[n].paired else Role.FRONT
            roles[n] = RoleGuess(
                role=role, confidence=0.5, why="waist-high piece: the pair is the back (centre-back seam)"
            )
    if tops:
        depths = {n: shapes[n].neck_depth_cm for n in tops}
        lo, hi = min(depths.values()), max(depths.values())
        for n in tops:
            hint = name_hint(pattern.piece(n))
            if hi - lo > 1.0:
                back = depths[n] < (lo + hi) / 2
                conf = float(min(0.95, 0.6 + (hi - lo) / 20))
                why = f"neckline {depths[n]:.1f} cm deep at the centre (range {lo:.1f}..{hi:.1f})"
            else:
                back = hint is Role.BACK
                conf, why = (0.7, "named") if hint in (Role.FRONT, Role.BACK) else (0.4, "no evidence")
            role = Role.BACK if back else Role.FRONT
            if hint in (Role.FRONT, Role.BACK) and hint is not role:
                conf = min(conf, 0.5)
            roles[n] = RoleGuess(role=role, confidence=round(conf, 2), why=why)
    legs = [n for n, g in roles.items() if g.role is Role.LEG]
    two_piece = [n for n in legs if not shapes[n].both_sides_scooped]
    if len(two_piece) >= 2:
        shares = {n: shapes[n].area_share for n in two_piece}
        mid = (min(shares.values()) + max(shares.values())) / 2
        for n in two_piece:
            role = Role.LEG_BACK if shares[n] > mid else Role.LEG_FRONT
            roles[n] = RoleGuess(role=role, confidence=0.8, why="the larger leg piece is the back")


def infer_roles(
    pattern: Pattern, orientations: dict[str, Orientation]
) -> tuple[dict[str, RoleGuess], dict[str, Shape]]:
    """Role of every piece, and the shape numbers it was read from."""
    largest = max(float(area(sew_line(p)[0])) for p in pattern.pieces)
    shapes = {p.name: shape_of(p, orientations[p.name], largest) for p in pattern.pieces}
    roles = {}
    for p in pattern.pieces:
        s, hint = shapes[p.name], name_hint(p)
        if s.band:
            role, conf, why = _band_role(s, hint)
        elif s.area_share < SMALL_AREA:
            role, conf, why = _small_role(s, hint)
        elif s.area_share < BODY_AREA and s.top_bend_rad <= 0.3 and hint is not None and not is_body(hint):
            role, conf, why = hint, 0.7, f"mid-sized piece; named {hint.value}"
        else:
            role, conf, why = _body_role(s, hint)
        if hint is role:
            conf = min(1.0, conf + 0.1)
        roles[p.name] = RoleGuess(role=role, confidence=round(conf, 2), why=why)
    _split_front_back(pattern, roles, shapes)
    return roles, shapes
