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
to the openings left free (:mod:`.bands`). Which pairs may meet at all is
decided by the structural rules of :mod:`.rules`.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ..library.infer import mirror_twins
from ..library.seams import sew_line
from ..pattern.model import Pattern
from .edges import Run, breaks
from .model import Join, Orientation, Role, RoleGuess, Side
from .rules import LEGS, TORSO, PairContext, body_side, is_centre, is_rise, pair_rule

__all__ = ["Candidate", "assign", "body_side", "candidates", "centre_vertices", "crosses", "merge_continuing"]

#: seams agree within this (cm) plus ``LENGTH_TOL_SHARE`` of their length
LENGTH_TOL_CM = 0.3
LENGTH_TOL_SHARE = 0.012
#: a sleeve cap may exceed its armhole by up to this share (crown ease)
CAP_EASE_SHARE = 0.09
#: … or fall short of it by this share (a knit sleeve stretched into its armhole)
CAP_TIGHT_SHARE = 0.02
MIN_RUN_CM = 2.0
#: mirror twins here agree in area and perimeter within this share (stricter than a seam proposal's)
TWIN_TOL_SHARE = 0.003
#: a paired piece's straight centre edge (or a leg's crotch curve) sewn to its mirror copy
CENTRE_SCORE = 0.95
#: a seam whose sides agree in the sample size only scores this share of its score (always "uncertain") …
SAMPLE_ONLY_SCORE = 0.5
#: … and is proposed only when it scored at least this before (equal length, shape and notches: no size backs it)
SAMPLE_ONLY_MIN = 0.85


@dataclass(frozen=True, slots=True, kw_only=True)
class Candidate:
    """A scored pair of runs (``a`` and ``b`` may be the same run: a centre seam)."""

    a: Run
    b: Run
    score: float
    kind: str
    ease_cm: float
    why: str


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


def _centre_candidates(ctx: PairContext, items: list[Run]) -> list[Candidate]:
    """A paired piece's straight centre edge, or a leg's crotch curve, sewn to its mirror copy."""
    out = []
    for r in items:
        role, piece = ctx.roles[r.piece].role, ctx.pattern.piece(r.piece)
        paired = piece.quantity.left > 0 or piece.quantity.right > 1 or piece.quantity.right == 0
        up = ctx.up[r.piece]
        centre = (role in LEGS and is_rise(up, r)) or (role in TORSO and is_centre(up, r))
        if ctx.orientations[r.piece].fold is None and paired and centre:
            why = "centre edge sewn to its mirror copy"
            out.append(Candidate(a=r, b=r, score=CENTRE_SCORE, kind="centre", ease_cm=0.0, why=why))
    return out


def _score_pair(ctx: PairContext, a: Run, b: Run) -> Candidate | None:
    """The candidate seam of two runs the rules allow, or None when their lengths or notches disagree."""
    ra, rb = ctx.roles[a.piece].role, ctx.roles[b.piece].role
    x, y = (a, b) if ra is not Role.SLEEVE or rb is Role.SLEEVE else (b, a)
    capped = ctx.roles[y.piece].role is Role.SLEEVE and ctx.roles[x.piece].role is not Role.SLEEVE
    fit, ease = _length_fit(x, y, -CAP_TIGHT_SHARE if capped else 0.0, CAP_EASE_SHARE if capped else 0.0)
    if fit <= 0.0:
        return None
    # a cap bulges where its armhole is scooped: their shapes differ by design
    straight = np.exp(-abs(a.straightness - b.straightness) / (0.3 if capped else 0.06))
    size = 1.0 - np.exp(-min(a.length_cm, b.length_cm) / 6.0)
    notch = _notch_fit(a, b)
    if _is_pair(ctx.pattern.piece(a.piece)) != _is_pair(ctx.pattern.piece(b.piece)):
        notch = max(notch, _notch_fit(a, _forwards(b)))  # the mirror copy runs the other way
    score = float(fit * straight * size * notch)
    if score <= 0.05:
        return None
    kind = "centre" if frozenset((a.piece, b.piece)) in ctx.twins else "seam"
    why = f"lengths agree in every size (ease {ease:+.2f} cm)"
    return Candidate(a=x, b=y, score=score, kind=kind, ease_cm=ease, why=why)


def _uncertain(cand: Candidate) -> Candidate | None:
    """A candidate scored on the sample size alone, kept only when near certain and then marked uncertain."""
    if cand.score < SAMPLE_ONLY_MIN:
        return None
    why = f"lengths agree in the sample size only (ease {cand.ease_cm:+.2f} cm); the graded sizes disagree"
    return replace(cand, score=cand.score * SAMPLE_ONLY_SCORE, why=why)


def candidates(
    pattern: Pattern,
    runs: dict[str, list[Run]],
    roles: dict[str, RoleGuess],
    orientations: dict[str, Orientation],
    skip: set[str],
    *,
    sample_only: bool = False,
) -> list[Candidate]:
    """Scored candidate seams between the runs of the pieces not in ``skip`` (:func:`.rules.pair_rule` first).

    sample_only : compare lengths in the sample size only (the second pass, for
        edges the file grades unequally): only pairs scoring ``SAMPLE_ONLY_MIN``
        are kept, their scores scaled by ``SAMPLE_ONLY_SCORE`` so every such seam
        stays below the picture's confidence mark.
    """
    ctx = PairContext.of(pattern, roles, orientations, mirror_twins(pattern, tol_share=TWIN_TOL_SHARE))
    items = [r for name, rs in runs.items() if name not in skip for r in rs if r.length_cm >= MIN_RUN_CM]
    if sample_only:
        items = [replace(r, graded_cm=np.array([r.length_cm])) for r in items]
    out = [] if sample_only else _centre_candidates(ctx, items)
    items.sort(key=lambda r: r.length_cm)
    lengths = np.array([r.length_cm for r in items])
    widest = 1 + CAP_EASE_SHARE + LENGTH_TOL_SHARE
    for i, a in enumerate(items):
        # only runs within the widest window a seam allows (crown ease and tolerance) can pair
        stop = int(np.searchsorted(lengths, a.length_cm * widest + LENGTH_TOL_CM, "right"))
        for b in items[i + 1 : stop]:
            if pair_rule(ctx, a, b) is None:
                cand = _score_pair(ctx, a, b)
                if cand is not None and sample_only:
                    cand = _uncertain(cand)
                if cand is not None:
                    out.append(cand)
    return out


#: a vertex of a piece drawn whole this close to its centre line (upright x = 0) is on the centre line
CENTRE_TOL_CM = 0.3


def centre_vertices(pattern: Pattern, orientations: dict[str, Orientation]) -> set[tuple[str, int]]:
    """(piece, vertex) of the marks on the centre line of every piece drawn whole.

    A seam is one per body side: it is not merged, nor matched, across such a mark
    (a waist seam or a neckband meets the front's two halves in two seams).
    """
    out = set()
    for name, o in orientations.items():
        if not o.whole:
            continue
        piece = pattern.piece(name)
        x = o.apply(sew_line(piece)[0])[:, 0]
        out |= {(name, int(v)) for v in breaks(piece) if abs(x[v]) < CENTRE_TOL_CM}
    return out


def crosses(piece: str, start: int, end: int, n: int, marks: set[tuple[str, int]]) -> bool:
    """Whether the range ``start`` → ``end`` of an ``n``-vertex outline has one of ``marks`` strictly inside."""
    span = (end - start) % n
    return any(p == piece and 0 < (v - start) % n < span for p, v in marks)


def _continued_b(j1: Join, j2: Join) -> tuple[Side, int] | None:
    """``j1.b`` continued by ``j2.b`` (either way round) and the vertex where they meet, or None."""
    length = j1.b.length_cm + j2.b.length_cm
    if j2.b.end == j1.b.start and j2.b.start != j1.b.end:  # b runs against a (both pieces seen from one side)
        return Side(piece=j1.b.piece, start=j2.b.start, end=j1.b.end, length_cm=length), j1.b.start
    if j1.b.end == j2.b.start and j1.b.start != j2.b.end:  # b runs along a (one piece drawn mirrored)
        return Side(piece=j1.b.piece, start=j1.b.start, end=j2.b.end, length_cm=length), j1.b.end
    return None


def _continue(j1: Join, j2: Join, keep: set[tuple[str, int]], folded: set[str]) -> Join | None:
    """``j1`` followed by ``j2`` as one seam, when ``j2`` continues both of ``j1``'s sides.

    Also when both sew the same range ``a`` of a half cut on the fold (``folded``:
    its two copies are one piece) and ``b`` continues across the centre line: a
    collar along both halves of a back neck is one seam.
    """
    b = _continued_b(j1, j2)
    if b is None:
        return None
    if j1.a.key == j2.a.key and j1.a.piece in folded:
        a = j1.a
    elif j1.a.end != j2.a.start or j1.a.start == j2.a.end or (j1.a.piece, j1.a.end) in keep:
        return None
    elif (j1.b.piece, b[1]) in keep:
        return None
    else:
        a = Side(piece=j1.a.piece, start=j1.a.start, end=j2.a.end, length_cm=j1.a.length_cm + j2.a.length_cm)
    first, second = (j2, j1) if b[0].start == j2.b.start else (j1, j2)
    return Join(
        id=j1.id,
        a=a,
        b=b[0],
        kind=j1.kind,
        confidence=min(j1.confidence, j2.confidence),
        ease_cm=round(j1.ease_cm + j2.ease_cm, 3),
        why=j1.why + "; continued past a notch",
        spans=chain_spans(first, second),
        copy_a=j1.copy_a,
        copy_b=j1.copy_b,
    )


def chain_spans(first: Join, second: Join) -> tuple[tuple[str, float, float], ...]:
    """The :attr:`Join.spans` of ``first.b`` continued by ``second.b``, on the joined range; () if neither has any.

    Consecutive spans on the same copy become one.
    """
    if not first.spans and not second.spans:
        return ()
    total = first.b.length_cm + second.b.length_cm
    cut = first.b.length_cm / total if total > 0 else 0.5
    spans = [(c, f0 * cut, f1 * cut) for c, f0, f1 in first.spans]
    spans += [(c, cut + f0 * (1 - cut), cut + f1 * (1 - cut)) for c, f0, f1 in second.spans]
    out: list[tuple[str, float, float]] = []
    for c, f0, f1 in spans:
        if out and out[-1][0] == c and abs(out[-1][2] - f0) < 1e-6:
            out[-1] = (c, out[-1][1], f1)
        else:
            out.append((c, f0, f1))
    return tuple((c, round(f0, 6), round(f1, 6)) for c, f0, f1 in out)


def merge_continuing(
    joins: list[Join], keep: set[tuple[str, int]] = frozenset(), folded: set[str] = frozenset()
) -> list[Join]:
    """Join seams that continue each other on the same two pieces (a seam split at a notch).

    Seams, centre seams and band entries merge with their own kind; folds stay as they are.
    keep : (piece, vertex) marks no seam is merged across (:func:`centre_vertices`).
    folded : pieces drawn as a half on the fold.
    """
    out = list(joins)
    changed = True
    while changed:
        changed = False
        for i, j1 in enumerate(out):
            for k, j2 in enumerate(out):
                if i == k or j1.kind not in ("seam", "band", "centre") or j2.kind != j1.kind:
                    continue
                merged = None
                for second in (j2, replace(j2, a=j2.b, b=j2.a)):
                    if merged is None and (j1.a.piece, j1.b.piece) == (second.a.piece, second.b.piece):
                        merged = _continue(j1, second, keep, folded)
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
