"""Seams at the edge level: a one-to-one assignment of boundary runs.

Two runs are a candidate seam when their sew-line lengths agree in **every
graded size** (their difference stays constant over the sizes and within a
tolerance of zero, or of the ease the roles allow: a sleeve cap may be longer
than its armhole), their notches match, and their pieces' roles may meet
(front and back, sleeve and bodice, a leg with itself …). A run may also be
sewn to itself on the piece's mirror copy (a crotch curve, a centre-back seam)
or to the same edge of a separately drawn mirror twin (a centre front closure)
when it lies on the piece's centre line. Candidates are taken greedily, surest
and longest first, each elementary stretch at most once; fold edges are folds.
Bands (bindings, neckbands, cuffs, waistbands, collars) are matched afterwards
to the openings left free (:mod:`.bands`).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ..library.seams import sew_line
from ..pattern.model import Pattern
from .edges import Run, turning
from .model import Join, Orientation, Role, RoleGuess, Side, is_band

__all__ = ["Candidate", "assign", "candidates", "pieces_meet"]

#: seams agree within this (cm) plus ``LENGTH_TOL_SHARE`` of their length
LENGTH_TOL_CM = 0.3
LENGTH_TOL_SHARE = 0.012
#: a sleeve cap may exceed its armhole by up to this share (crown ease)
CAP_EASE_SHARE = 0.09
#: … or fall short of it by this share (a knit sleeve stretched into its armhole)
CAP_TIGHT_SHARE = 0.02
MIN_RUN_CM = 2.0
#: a paired piece's straight centre edge (or a leg's crotch curve) sewn to its mirror copy
CENTRE_SCORE = 0.95

_TORSO = {Role.FRONT, Role.BACK, Role.YOKE}
_LEGS = {Role.LEG, Role.LEG_FRONT, Role.LEG_BACK}


def pieces_meet(ra: Role, rb: Role, same_piece: bool) -> bool:
    """Whether pieces of roles ``ra`` and ``rb`` may share a seam (``same_piece``: a self seam)."""
    if same_piece:
        return ra in (Role.SLEEVE, *_LEGS) or is_band(ra)
    pair = {ra, rb}
    if pair <= _TORSO:
        return ra is not rb or ra is Role.FRONT or ra is Role.BACK
    if Role.SLEEVE in pair:
        return pair - {Role.SLEEVE} <= _TORSO or pair == {Role.SLEEVE}
    if pair <= _LEGS:
        return True
    if pair & _LEGS and pair & {Role.FRONT, Role.BACK}:
        return True  # a dress or a jumpsuit: bodice to leg at the waist
    return False


@dataclass(frozen=True, slots=True, kw_only=True)
class Candidate:
    """A scored pair of runs (``a`` and ``b`` may be the same run: a centre seam)."""

    a: Run
    b: Run
    score: float
    kind: str
    ease_cm: float
    why: str


def _upright(pattern: Pattern, orientations: dict[str, Orientation]) -> dict[str, np.ndarray]:
    return {p.name: orientations[p.name].apply(sew_line(p)[0]) for p in pattern.pieces}


def _run_points(points: np.ndarray, r: Run) -> np.ndarray:
    n = len(points)
    idx = np.arange(r.start, r.end + 1) if r.end > r.start else np.r_[r.start : n, 0 : r.end + 1]
    return points[idx]


def _is_centre(points: np.ndarray, r: Run) -> bool:
    """A straight run along the piece's centre line (x = 0 upright), a fifth of its height or more."""
    seg = _run_points(points, r)
    return bool(
        np.all(np.abs(seg[:, 0]) < 0.3) and np.ptp(seg[:, 1]) > 0.2 * np.ptp(points[:, 1]) and r.straightness > 0.98
    )


def _is_rise(points: np.ndarray, r: Run) -> bool:
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


def _length_fit(a: Run, b: Run, ease_lo: float, ease_hi: float) -> tuple[float, float]:
    """(score 0..1, ease_cm) of ``b`` against ``a`` over every graded size."""
    d = np.asarray(b.graded_cm) - np.asarray(a.graded_cm)
    longer = max(a.length_cm, b.length_cm)
    tol = LENGTH_TOL_CM + LENGTH_TOL_SHARE * longer
    # graded evidence: the difference must stay put over the sizes (robust to a few bad sizes)
    if len(d) > 1:
        drift = float(np.percentile(np.abs(d - d[np.argmin(np.abs(d))]), 75))
        if drift > tol:
            return 0.0, 0.0
    ease = float(np.median(d))
    lo, hi = ease_lo * longer - tol, ease_hi * longer + tol
    if not lo <= ease <= hi:
        return 0.0, 0.0
    off = (
        0.0
        if ease_lo * longer <= ease <= ease_hi * longer
        else min(abs(ease - ease_lo * longer), abs(ease - ease_hi * longer))
    )
    # crown ease is allowed, not wanted: the less a cap needs, the likelier the match
    eased = 1.0 if ease_hi == 0 else 0.9 * float(np.exp(-abs(ease) / (0.15 * longer)))
    return float(np.exp(-((off / (0.5 * tol)) ** 2))) * eased, ease


def _is_pair(piece) -> bool:
    return piece.quantity.left > 0 or piece.quantity.right > 1


def _forwards(r: Run) -> Run:
    """``r`` with its notch and break fractions measured from the other end."""
    return replace(
        r,
        notch_fracs=tuple(1.0 - f for f in reversed(r.notch_fracs)),
        break_fracs=tuple(1.0 - f for f in reversed(r.break_fracs)),
    )


def _notch_fit(a: Run, b: Run) -> float:
    """1 when every notch of each side meets a notch or a turn point of the other (b runs backwards)."""
    if not a.notch_fracs and not b.notch_fracs:
        return 0.9

    def met(notches, marks):
        marks = np.asarray(marks)
        return all(len(marks) and np.min(np.abs(marks - f)) < 0.04 for f in notches)

    back = [1.0 - f for f in b.break_fracs]
    ok = met(a.notch_fracs, back) and met([1.0 - f for f in b.notch_fracs], a.break_fracs)
    return 1.0 if ok else 0.4


def _twins(pattern: Pattern) -> set[frozenset[str]]:
    from ..pattern.geometry import area, perimeter

    stats = [(p.name, float(area(sew_line(p)[0])), float(perimeter(sew_line(p)[0]))) for p in pattern.pieces]
    return {
        frozenset((na, nb))
        for i, (na, aa, pa) in enumerate(stats)
        for nb, ab, pb in stats[i + 1 :]
        if abs(aa - ab) <= 0.003 * max(aa, ab) and abs(pa - pb) <= 0.003 * max(pa, pb)
    }


def candidates(
    pattern: Pattern,
    runs: dict[str, list[Run]],
    roles: dict[str, RoleGuess],
    orientations: dict[str, Orientation],
    skip: set[str],
) -> list[Candidate]:
    """Scored candidate seams between the runs of the pieces not in ``skip``."""
    up = _upright(pattern, orientations)
    turns = {name: turning(points) for name, points in up.items()}
    twins = _twins(pattern)
    items = [r for name, rs in runs.items() if name not in skip for r in rs if r.length_cm >= MIN_RUN_CM]
    out = []
    for r in items:
        role = roles[r.piece].role
        piece = pattern.piece(r.piece)
        paired = piece.quantity.left > 0 or piece.quantity.right > 1 or piece.quantity.right == 0
        if (
            orientations[r.piece].fold is None
            and paired
            and ((role in _LEGS and _is_rise(up[r.piece], r)) or (role in _TORSO and _is_centre(up[r.piece], r)))
        ):
            out.append(
                Candidate(
                    a=r, b=r, score=CENTRE_SCORE, kind="centre", ease_cm=0.0, why="centre edge sewn to its mirror copy"
                )
            )
    items.sort(key=lambda r: r.length_cm)
    lengths = np.array([r.length_cm for r in items])
    for i, a in enumerate(items):
        ra = roles[a.piece].role
        # only runs within the widest window a seam allows (crown ease and tolerance) can pair
        stop = int(
            np.searchsorted(lengths, a.length_cm * (1 + CAP_EASE_SHARE + LENGTH_TOL_SHARE) + LENGTH_TOL_CM, "right")
        )
        for b in items[i + 1 : stop]:
            rb = roles[b.piece].role
            same = a.piece == b.piece
            dart = same and _dart(a, b, turns[a.piece])
            if not dart and (_at_dart(a, turns[a.piece]) or _at_dart(b, turns[b.piece])):
                continue  # a dart's leg sews only to its other leg
            if same and (set(a.parts) & set(b.parts) or (_adjacent(a, b) and not dart)):
                continue
            if not dart and not pieces_meet(ra, rb, same):
                continue
            if (ra in _LEGS and _is_hem(up[a.piece], a)) or (rb in _LEGS and _is_hem(up[b.piece], b)):
                continue  # a leg's hem is finished, not sewn
            if (_is_hem(up[a.piece], a) and _is_hem(up[b.piece], b)) or (
                _is_waist(up[a.piece], a) and _is_waist(up[b.piece], b)
            ):
                continue
            whole = orientations[a.piece].whole and orientations[b.piece].whole and not same
            if whole and {ra, rb} == {Role.FRONT, Role.BACK} and _wrong_sides(up[a.piece], a, up[b.piece], b):
                continue
            if ra is rb and not same and _across(up[a.piece], a, up[b.piece], b, whole):
                continue  # a waist seam joins the stretch at the same place across the body
            if (ra in _TORSO and _neckline(up[a.piece], a)) or (rb in _TORSO and _neckline(up[b.piece], b)):
                continue
            if {ra, rb} == {Role.FRONT, Role.BACK} and _other_body_side(orientations[a.piece], orientations[b.piece]):
                continue
            twin = frozenset((a.piece, b.piece)) in twins
            if twin and not (_is_centre(up[a.piece], a) and _is_centre(up[b.piece], b)):
                if abs(a.length_cm - b.length_cm) < 0.05 * a.length_cm and abs(a.bend_rad - b.bend_rad) < 0.1:
                    continue  # the same edge on a left and a right twin
            x, y = (a, b) if ra is not Role.SLEEVE or rb is Role.SLEEVE else (b, a)
            capped = roles[y.piece].role is Role.SLEEVE and roles[x.piece].role is not Role.SLEEVE
            if capped and _run_points(up[y.piece], y)[:, 1].max() < up[y.piece][:, 1].min() + 0.5 * np.ptp(
                up[y.piece][:, 1]
            ):
                continue  # a sleeve meets a bodice with its cap, not its hem
            if capped and _over_cap_top(up[y.piece], y):
                continue  # the cap top meets the shoulder seam: front and back armholes join there
            worn = body_side(roles[x.piece].role, orientations[x.piece]) if capped else None
            if worn and sleeve_side(up[y.piece], y, roles[x.piece].role) != worn:
                continue  # a left sleeve goes into a left armhole
            fit, ease = _length_fit(x, y, -CAP_TIGHT_SHARE if capped else 0.0, CAP_EASE_SHARE if capped else 0.0)
            if fit <= 0.0:
                continue
            # a cap bulges where its armhole is scooped: their shapes differ by design
            straight = np.exp(-abs(a.straightness - b.straightness) / (0.3 if capped else 0.06))
            size = 1.0 - np.exp(-min(a.length_cm, b.length_cm) / 6.0)
            notch = _notch_fit(a, b)
            if _is_pair(pattern.piece(a.piece)) != _is_pair(pattern.piece(b.piece)):
                notch = max(notch, _notch_fit(a, _forwards(b)))  # the mirror copy runs the other way
            score = float(fit * straight * size * notch)
            if score > 0.05:
                kind = "centre" if twin else "seam"
                out.append(
                    Candidate(
                        a=x,
                        b=y,
                        score=score,
                        kind=kind,
                        ease_cm=ease,
                        why=f"lengths agree in every size (ease {ease:+.2f} cm)",
                    )
                )
    return out


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


def _continue(j1: Join, j2: Join) -> Join | None:
    """``j1`` followed by ``j2`` as one seam, when ``j2`` continues both of ``j1``'s sides."""
    if j1.a.end != j2.a.start or j1.a.start == j2.a.end:
        return None
    if j2.b.end == j1.b.start:  # b runs against a (both pieces seen from one side)
        b = Side(piece=j1.b.piece, start=j2.b.start, end=j1.b.end, length_cm=j1.b.length_cm + j2.b.length_cm)
    elif j1.b.end == j2.b.start:  # b runs along a (one piece drawn mirrored)
        b = Side(piece=j1.b.piece, start=j1.b.start, end=j2.b.end, length_cm=j1.b.length_cm + j2.b.length_cm)
    else:
        return None
    return Join(
        id=j1.id,
        a=Side(piece=j1.a.piece, start=j1.a.start, end=j2.a.end, length_cm=j1.a.length_cm + j2.a.length_cm),
        b=b,
        kind="seam",
        confidence=min(j1.confidence, j2.confidence),
        ease_cm=round(j1.ease_cm + j2.ease_cm, 3),
        why=j1.why + "; continued past a notch",
    )


def merge_continuing(joins: list[Join]) -> list[Join]:
    """Join seams that continue each other on the same two pieces (a seam split at a notch)."""
    out = list(joins)
    changed = True
    while changed:
        changed = False
        for i, j1 in enumerate(out):
            for k, j2 in enumerate(out):
                if i == k or j1.kind != "seam" or j2.kind != "seam":
                    continue
                merged = None
                for second in (j2, replace(j2, a=j2.b, b=j2.a)):
                    if merged is None and (j1.a.piece, j1.b.piece) == (second.a.piece, second.b.piece):
                        merged = _continue(j1, second)
                if merged is not None:
                    out = [j for m, j in enumerate(out) if m not in (i, k)] + [merged]
                    changed = True
                    break
            if changed:
                break
    return out


def assign(
    cands: list[Candidate],
    used: set[tuple[str, int]],
    parts_of,
    sides: dict[str, str | None] | None = None,
    twice: set[str] | None = None,
    whole: set[str] = frozenset(),
) -> list[Join]:
    """Greedy one-to-one choice of candidates, best first (longer seams first among equals).

    sides : piece -> body side of half pieces (:func:`body_side`); a piece sewn
        to a half piece of one side is not sewn to a half piece of the other.
    twice, whole : pieces cut as a pair, and pieces drawn whole; an edge of the
        first may be sewn twice to edges of the second (once per copy).
    """
    sides = sides or {}
    twice = twice or set()
    order = sorted(cands, key=lambda c: -(c.score * (1.0 + 0.05 * min(c.a.length_cm, 40.0) / 10.0)))
    joins = []
    worn: dict[str, str] = {}
    second: set[tuple[str, int]] = set()
    for c in order:
        pa, pb = parts_of(c.a), parts_of(c.b)
        # a paired piece sewn to a piece drawn whole meets it once per copy (both sleeves, both armholes)
        again = set()
        if c.a.piece != c.b.piece:
            if c.a.piece in twice and c.b.piece in whole:
                again = pa & used - second
            elif c.b.piece in twice and c.a.piece in whole:
                again = pb & used - second
        if ((pa | pb) & used) - again:
            continue
        second |= again
        sa, sb = sides.get(c.a.piece), sides.get(c.b.piece)
        if c.a.piece != c.b.piece and c.kind != "centre":
            if (sb and worn.get(c.a.piece, sb) != sb) or (sa and worn.get(c.b.piece, sa) != sa):
                continue
            if sb and not sa:
                worn[c.a.piece] = sb
            if sa and not sb:
                worn[c.b.piece] = sa
        used |= pa | pb
        joins.append(
            Join(
                id=f"{c.a.piece}_{c.a.start}_{c.b.piece}_{c.b.start}",
                a=Side(piece=c.a.piece, start=c.a.start, end=c.a.end, length_cm=round(c.a.length_cm, 3)),
                b=Side(piece=c.b.piece, start=c.b.start, end=c.b.end, length_cm=round(c.b.length_cm, 3)),
                kind=c.kind,
                confidence=round(min(1.0, c.score), 3),
                ease_cm=round(c.ease_cm, 3),
                why=c.why,
            )
        )
    return joins
