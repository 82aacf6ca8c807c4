"""Which two boundary runs may be sewn together: the structural rules of a garment.

Each rule is a predicate on runs of upright pieces (:mod:`.orient`): where an
edge lies on its piece (hem, waist, neckline, centre line, crotch curve, cap
top, dart leg), which body side a half piece is worn on, and which roles may
meet. :func:`pair_rule` applies them all to a candidate pair and says why a
pair is ruled out; :mod:`.seams` scores the pairs that remain.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..library.seams import sew_line
from ..pattern.model import Pattern
from .edges import Run, turning
from .model import Orientation, Role, RoleGuess, is_band

__all__ = [
    "LEGS",
    "TORSO",
    "PairContext",
    "band_in_place",
    "body_side",
    "is_centre",
    "is_rise",
    "pair_rule",
    "pieces_meet",
    "sleeve_side",
]

#: bodice roles and leg roles
TORSO = {Role.FRONT, Role.BACK, Role.YOKE}
LEGS = {Role.LEG, Role.LEG_FRONT, Role.LEG_BACK}
#: a dart's point turns the outline back on itself (CCW: a right turn sharper than this)
DART_TURN_DEG = 110.0


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class PairContext:
    """What the rules need: roles, turns, the upright sew lines and their turning, mirror twins."""

    pattern: Pattern
    roles: dict[str, RoleGuess]
    orientations: dict[str, Orientation]
    up: dict[str, np.ndarray]
    turns: dict[str, np.ndarray]
    twins: set[frozenset[str]]

    @classmethod
    def of(cls, pattern: Pattern, roles, orientations, twins) -> PairContext:
        up = {p.name: orientations[p.name].apply(sew_line(p)[0]) for p in pattern.pieces}
        return cls(
            pattern=pattern,
            roles=roles,
            orientations=orientations,
            up=up,
            turns={name: turning(points) for name, points in up.items()},
            twins=twins,
        )


def pieces_meet(ra: Role, rb: Role, same_piece: bool) -> bool:
    """Whether pieces of roles ``ra`` and ``rb`` may share a seam (``same_piece``: a self seam)."""
    if same_piece:
        return ra in (Role.SLEEVE, *LEGS) or is_band(ra)
    pair = {ra, rb}
    if pair <= TORSO:
        return ra is not rb or ra is Role.FRONT or ra is Role.BACK
    if Role.SLEEVE in pair:
        return pair - {Role.SLEEVE} <= TORSO or pair == {Role.SLEEVE}
    if pair <= LEGS:
        return True
    if pair & LEGS and pair & {Role.FRONT, Role.BACK}:
        return True  # a dress or a jumpsuit: bodice to leg at the waist
    return False


#: how far (in half-band lengths) a waistband stretch may lie from where the body's stretch puts it
WAISTBAND_PLACE_TOL = 0.12


def _run_points(points: np.ndarray, r: Run) -> np.ndarray:
    n = len(points)
    idx = np.arange(r.start, r.end + 1) if r.end > r.start else np.r_[r.start : n, 0 : r.end + 1]
    return points[idx]


def is_centre(points: np.ndarray, r: Run) -> bool:
    """A straight run along the piece's centre line (x = 0 upright), a fifth of its height or more."""
    seg = _run_points(points, r)
    return bool(
        np.all(np.abs(seg[:, 0]) < 0.3) and np.ptp(seg[:, 1]) > 0.2 * np.ptp(points[:, 1]) and r.straightness > 0.98
    )


def is_rise(points: np.ndarray, r: Run) -> bool:
    """A scooped run that reaches the top of a leg piece: its crotch curve."""
    seg = _run_points(points, r)
    top = points[:, 1].max() - 0.12 * np.ptp(points[:, 1])
    falls = np.ptp(seg[:, 1]) >= 0.4 * r.length_cm  # a rise drops to the fork; a waist runs across
    return bool(r.bend_rad < -0.25 and seg[:, 1].max() >= top and r.straightness < 0.995 and falls)


def _is_hem(points: np.ndarray, r: Run) -> bool:
    """A straight-ish run across the bottom of an upright piece."""
    seg = _run_points(points, r)
    h = np.ptp(points[:, 1])
    return bool(seg[:, 1].max() <= points[:, 1].min() + 0.12 * h and np.ptp(seg[:, 0]) > np.ptp(seg[:, 1]))


def _is_waist(points: np.ndarray, r: Run) -> bool:
    """A nearly level run across the top of an upright piece (a waist; shoulders slope)."""
    seg = _run_points(points, r)
    h = np.ptp(points[:, 1])
    return bool(seg[:, 1].min() >= points[:, 1].max() - 0.1 * h and np.ptp(seg[:, 1]) < 0.15 * np.ptp(seg[:, 0]))


def _wrong_sides(points_a: np.ndarray, a: Run, points_b: np.ndarray, b: Run) -> bool:
    """Two whole pieces seen from outside meet side to opposite side (front's -x to back's +x)."""
    xa, xb = _run_points(points_a, a)[:, 0].mean(), _run_points(points_b, b)[:, 0].mean()
    wa, wb = np.ptp(points_a[:, 0]), np.ptp(points_b[:, 0])
    return bool(abs(xa) > 0.15 * wa and abs(xb) > 0.15 * wb and np.sign(xa) == np.sign(xb))


def _neckline(points: np.ndarray, r: Run) -> bool:
    """A run of a bodice that reaches or crosses the centre line high up: a neckline, sewn only to a band."""
    seg = _run_points(points, r)
    top = points[:, 1].max() - 0.3 * np.ptp(points[:, 1])
    at_centre = (np.abs(seg[:, 0]) < 0.5) | (np.sign(seg[:, 0]) != np.sign(seg[0, 0]))
    return bool(np.any(at_centre & (seg[:, 1] >= top)) and r.straightness < 0.995)


def _across(points_a: np.ndarray, a: Run, points_b: np.ndarray, b: Run, whole: bool) -> bool:
    """Two level runs of pieces of one role (bodice to skirt) at different places across the body."""
    sa, sb = _run_points(points_a, a), _run_points(points_b, b)
    if np.ptp(sa[:, 1]) > 0.3 * np.ptp(sa[:, 0]) or np.ptp(sb[:, 1]) > 0.3 * np.ptp(sb[:, 0]):
        return False
    xa, xb = sa[:, 0].mean(), sb[:, 0].mean()
    wa, wb = np.ptp(points_a[:, 0]), np.ptp(points_b[:, 0])
    if whole:
        return bool(abs(xa / wa - xb / wb) > 0.15)
    return bool(abs(abs(xa) / wa - abs(xb) / wb) > 0.15)


def _waist_fraction(ctx: PairContext, r: Run) -> float | None:
    """Where a leg's or skirt panel's run lies along its waist: 0 at the centre, 1 at the side (None: no waist)."""
    from .landmarks import leg_landmarks, skirt_panel_landmarks
    from .openings import shapes_scooped

    role, up, o = ctx.roles[r.piece].role, ctx.up[r.piece], ctx.orientations[r.piece]
    if role in (Role.LEG_FRONT, Role.LEG_BACK):
        marks = leg_landmarks(up, role).marks
    elif role in (Role.FRONT, Role.BACK) and not shapes_scooped(up) and o.fold is None:
        marks = skirt_panel_landmarks(up, o, role is Role.BACK).marks
    else:
        return None
    # across the body: a piece drawn whole has its two halves on either side of the centre
    c, sd = up[marks["centre_waist"], 0], up[marks["side_waist"], 0]
    mid = _run_points(up, r)[:, 0].mean()
    return float(np.clip(abs(mid - c) / max(abs(sd - c), 1e-9), 0.0, 1.0))


def band_in_place(ctx: PairContext, band: Run, body: Run, middle: str | None = None) -> bool:
    """A waistband's stretch lies where the body's waist stretch lies around the waist.

    Along a waistband drawn whole, its middle is one centre line (``middle``:
    ``front`` or ``back``; None: either), its ends the other and its quarters
    the sides: a body stretch a fraction f of the way from its centre to its
    side belongs f/2 of the half-band from the middle when its centre is the
    middle, else 1 - f/2.
    """
    if ctx.roles[band.piece].role is not Role.WAISTBAND:
        return True
    f = _waist_fraction(ctx, body)
    if f is None:
        return True
    x = ctx.up[band.piece][:, 0]
    pos = (_run_points(ctx.up[band.piece], band)[:, 0].mean() - x.min()) / max(float(np.ptp(x)), 1e-9)
    d = abs(2.0 * pos - 1.0)
    side = "front" if ctx.roles[body.piece].role in (Role.FRONT, Role.LEG_FRONT) else "back"
    wanted = [0.5 * f, 1.0 - 0.5 * f] if middle is None else [0.5 * f if side == middle else 1.0 - 0.5 * f]
    if middle is not None and ctx.orientations[body.piece].whole and not _same_body_half(ctx, band, body, middle):
        return False
    return bool(min(abs(d - w) for w in wanted) < WAISTBAND_PLACE_TOL)


def _same_body_half(ctx: PairContext, band: Run, body: Run, middle: str) -> bool:
    """Whether a stretch of a piece drawn whole and a waistband stretch lie on one body half.

    Seen from outside, the body's right half is a whole front's -x side and a
    whole back's +x side; along a waistband going round the body in its +x
    direction, the half beyond its middle is the body's left when the middle
    is the centre front and the body's right when it is the centre back.
    """
    x_band = _run_points(ctx.up[band.piece], band)[:, 0].mean() - 0.5 * sum(
        (ctx.up[band.piece][:, 0].min(), ctx.up[band.piece][:, 0].max())
    )
    band_right = x_band < 0 if middle == "front" else x_band > 0
    x_body = _run_points(ctx.up[body.piece], body)[:, 0].mean()
    body_right = x_body < 0 if ctx.roles[body.piece].role is Role.FRONT else x_body > 0
    return bool(abs(x_band) < 0.5 or abs(x_body) < 0.5 or band_right == body_right)


def body_side(role: Role, o: Orientation) -> str | None:
    """``right`` or ``left``: the body side a half piece drawn without a fold is worn on (None: both).

    Seen from outside, a right front has its centre front on its right (+x) and
    a right back its centre back on its left.
    """
    if o.fold is not None or o.whole or role not in (Role.FRONT, Role.BACK):
        return None
    right = o.centre_on_right if role is Role.FRONT else not o.centre_on_right
    return "right" if right else "left"


def _other_body_side(oa: Orientation, ob: Orientation) -> bool:
    """A front half and a back half drawn for opposite sides of the body."""
    if oa.fold is not None or ob.fold is not None or oa.whole or ob.whole:
        return False
    return oa.centre_on_right == ob.centre_on_right


def _adjacent(a: Run, b: Run) -> bool:
    return a.end == b.start or b.end == a.start


#: a dart's point turns the outline back on itself (CCW: a right turn sharper than this)
DART_TURN_DEG = 110.0


def _over_cap_top(points: np.ndarray, r: Run) -> bool:
    """Whether a sleeve run passes over the top of its cap (its highest point in the middle 60 % of the run)."""
    seg = _run_points(points, r)
    if seg[:, 1].max() < points[:, 1].max() - 0.05:
        return False
    cum = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(seg, axis=0), axis=1))])
    at = cum[int(np.argmax(seg[:, 1]))] / max(cum[-1], 1e-9)
    return bool(0.2 < at < 0.8)


def sleeve_side(points: np.ndarray, r: Run, partner: Role) -> str:
    """The arm a sleeve is worn on, read from where its cap run lies (a right sleeve has its front on +x)."""
    front_on_right = (_run_points(points, r)[:, 0].mean() > 0) == (partner is Role.FRONT)
    return "right" if front_on_right else "left"


def _at_dart(r: Run, turn: np.ndarray) -> bool:
    """Whether the run ends at a dart's point (it is a dart leg)."""
    return bool(turn[r.start] < -np.radians(DART_TURN_DEG) or turn[r.end] < -np.radians(DART_TURN_DEG))


def _dart(a: Run, b: Run, turn: np.ndarray) -> bool:
    """Two neighbouring runs of one piece meeting at a dart's point (the two legs of a V dart)."""
    for first, second in ((a, b), (b, a)):
        if first.end == second.start and turn[first.end] < -np.radians(DART_TURN_DEG):
            return True
    return False


def _sleeve_rule(ctx: PairContext, x: Run, y: Run) -> str | None:
    """Rules for a bodice run ``x`` against a sleeve run ``y``."""
    up = ctx.up[y.piece]
    if _run_points(up, y)[:, 1].max() < up[:, 1].min() + 0.5 * np.ptp(up[:, 1]):
        return "a sleeve meets a bodice with its cap, not its hem"
    if _over_cap_top(up, y):
        return "the cap top meets the shoulder seam: front and back armholes join there"
    role = ctx.roles[x.piece].role
    worn = body_side(role, ctx.orientations[x.piece])
    if worn and sleeve_side(up, y, role) != worn:
        return "a left sleeve goes into a left armhole"
    return None


def pair_rule(ctx: PairContext, a: Run, b: Run) -> str | None:
    """Why runs ``a`` and ``b`` cannot be sewn together, or None when they may be."""
    ra, rb = ctx.roles[a.piece].role, ctx.roles[b.piece].role
    ua, ub = ctx.up[a.piece], ctx.up[b.piece]
    oa, ob = ctx.orientations[a.piece], ctx.orientations[b.piece]
    same = a.piece == b.piece
    dart = same and _dart(a, b, ctx.turns[a.piece])
    if not dart and (_at_dart(a, ctx.turns[a.piece]) or _at_dart(b, ctx.turns[b.piece])):
        return "a dart's leg sews only to its other leg"
    if same and (set(a.parts) & set(b.parts) or (_adjacent(a, b) and not dart)):
        return "overlapping or neighbouring runs of one piece"
    if not dart and not pieces_meet(ra, rb, same):
        return "these roles do not meet"
    if (ra in LEGS and _is_hem(ua, a)) or (rb in LEGS and _is_hem(ub, b)):
        return "a leg's hem is finished, not sewn"
    if (_is_hem(ua, a) and _is_hem(ub, b)) or (_is_waist(ua, a) and _is_waist(ub, b)):
        return "hem to hem or waist to waist"
    whole = oa.whole and ob.whole and not same
    if whole and {ra, rb} == {Role.FRONT, Role.BACK} and _wrong_sides(ua, a, ub, b):
        return "whole pieces seen from outside meet side to opposite side"
    if ra is rb and not same and _across(ua, a, ub, b, whole):
        return "a waist seam joins the stretch at the same place across the body"
    if (ra in TORSO and _neckline(ua, a)) or (rb in TORSO and _neckline(ub, b)):
        return "a neckline is sewn only to a band"
    if {ra, rb} == {Role.FRONT, Role.BACK} and _other_body_side(oa, ob):
        return "a front and a back half of opposite body sides"
    twin = frozenset((a.piece, b.piece)) in ctx.twins
    if twin and not (is_centre(ua, a) and is_centre(ub, b)):
        if abs(a.length_cm - b.length_cm) < 0.05 * a.length_cm and abs(a.bend_rad - b.bend_rad) < 0.1:
            return "the same edge on a left and a right twin"
    for band, body in ((a, b), (b, a)):
        if not band_in_place(ctx, band, body):
            return "a waistband's stretch lies where the body's waist stretch lies around the waist"
    if rb is Role.SLEEVE and ra is not Role.SLEEVE:
        return _sleeve_rule(ctx, a, b)
    if ra is Role.SLEEVE and rb is not Role.SLEEVE:
        return _sleeve_rule(ctx, b, a)
    return None
