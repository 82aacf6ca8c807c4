"""Bands along openings: bindings, neckbands, cuffs, waistbands and collars.

A band is a strip sewn along an *opening* of the garment: the neckline (the
free edges of the fronts and backs at their centre line, top), an armhole (the
free scooped edges of one front and one back), a sleeve hem or a waist. Each
opening's length counts every copy of its edges (a half piece on the fold or
cut as a pair contributes twice). A band's long edge is matched to the opening
whose length it fits, stretched by up to ``MAX_STRETCH`` or eased by up to
``MAX_EASE`` (bias bindings and rib are cut shorter than the edge they bind);
the band's role follows from the opening when its name does not say. The two
short ends of a loop (binding, neckband, cuff, waistband) are sewn together,
unless the band is longer than its opening by more than ``FLAT_APPLIED``: such
a strip is applied flat and its ends are caught in the next seam.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np

from ..library.seams import sew_line
from ..pattern.model import Pattern
from .alternatives import copies_cut
from .band_spans import FLAT_APPLIED, place_band
from .edges import Run, breaks
from .model import Join, Role, RoleGuess, Side, is_band
from .openings import Opening, run_side
from .seams import crosses
from .strips import PartStrip, chain_order, place_part_strips, vertex_roots

__all__ = ["band_joins", "side_parts"]

MAX_STRETCH = 1.4
MAX_EASE = 0.78
#: two strip ends this close in length are sewn together
END_TOL_CM = 0.1
#: of a band's two long edges the one with more marks is sewn when at least this share of the longer
#: (a collar's neck edge, marked at the shoulders and the centre back, is shorter than its fall edge)
SEWN_EDGE_SHARE = 0.85
#: a loop's ends are its short sides: each at most this share of the sewn edge (a cuff or rib is a wide strip)
END_SHARE = 0.3

_OPENING_ROLES = {
    "neck": (Role.NECK_BINDING, Role.NECKBAND, Role.COLLAR, Role.COLLAR_STAND),
    "armhole": (Role.ARMHOLE_BINDING,),
    "sleeve_hem": (Role.CUFF,),
    "waist": (Role.WAISTBAND,),
}


def _band_edges(rs: list[Run]) -> tuple[Run, Run | None, list[Run]]:
    """The band's longest run, the longest run apart from it, and its end runs."""
    longest = max(rs, key=lambda r: r.length_cm)
    rest = [r for r in rs if not set(r.parts) & set(longest.parts)]
    other = max(rest, key=lambda r: r.length_cm) if rest else None
    if other is None:
        return longest, None, []
    if other.length_cm >= SEWN_EDGE_SHARE * longest.length_cm and len(other.break_fracs) > len(longest.break_fracs):
        longest, other = other, longest  # of two long edges, the one marked for its seams is sewn
    if other.length_cm < 0.5 * longest.length_cm:
        # the other long edge is a fold left out (a rib folded lengthwise): the ends adjoin the sewn edge
        adjoin = [r for r in rs if len(r.parts) == 1 and (r.end == longest.start or r.start == longest.end)]
        return longest, other, [r for r in adjoin if r.key != longest.key]
    ends = [r for r in rs if (r.start, r.end) in ((longest.end, other.start), (other.end, longest.start))]
    return longest, other, ends


def _within(r: Run, side_parts: set[int]) -> bool:
    return set(r.parts) <= side_parts


def side_parts(pattern: Pattern, side: Side) -> set[int]:
    brk = [int(b) for b in breaks(pattern.piece(side.piece))]
    m = len(brk)
    k = brk.index(side.start) if side.start in brk else None
    out: set[int] = set()
    while k is not None and brk[k] != side.end and len(out) < m:
        out.add(k)
        k = (k + 1) % m
    return out


#: a band's stretches sewn one to one must agree within this (cm) plus 2 %
SPLIT_TOL_CM = 0.3


#: whether a band stretch may go on a body stretch where each lies around the body, given which centre line
#: (``front``, ``back`` or either: None) is at the band's middle (``rules.band_in_place``)
PlaceCheck = Callable[[Run, Run, str | None], bool]
#: the place on the garment of a boundary vertex (:func:`.strips.vertex_roots`)
Roots = Callable[[tuple[str, int]], tuple[str, int]]


def _split_band(
    pattern: Pattern,
    runs: dict[str, list[Run]],
    edge: Run,
    op: Opening,
    in_place: PlaceCheck | None = None,
    centres: set[tuple[str, int]] = frozenset(),
    root: Roots | None = None,
) -> list[Join] | None:
    """The band edge sewn stretch by stretch to the opening (a band with marks at the opening's joints).

    Band runs and opening runs of equal length in every size, lying at the same
    place around the body (``in_place``: a waistband's symmetric stretches
    are told apart by where they lie, with the front's or the back's centre at
    the band's middle, whichever sews more of it), are paired one to one,
    longest first (an opening stretch never crosses the centre line of a piece
    drawn whole, ``centres``); None unless they cover 80 % of the band edge.
    """
    band_runs = [r for r in runs[edge.piece] if set(r.parts) <= set(edge.parts)]
    targets = []
    for side in op.sides:
        parts = side_parts(pattern, side)
        n = len(pattern.piece(side.piece).outline)
        own = runs.get(side.piece, [])
        targets += [r for r in own if _within(r, parts) and not crosses(r.piece, r.start, r.end, n, centres)]
    best: tuple[list[Join], float] = ([], -1.0)
    for middle in ("front", "back", None):
        found = _pair_stretches(pattern, band_runs, targets, op, in_place, middle)
        if found[1] > best[1] + 1e-6:
            best = found
    joins, covered = best
    if covered >= 0.8 * edge.length_cm:
        return joins
    return _split_in_proportion(pattern, band_runs, edge, op, root)


def _pair_stretches(
    pattern: Pattern,
    band_runs: list[Run],
    targets: list[Run],
    op: Opening,
    in_place: PlaceCheck | None,
    middle: str | None,
) -> tuple[list[Join], float]:
    """Band and opening stretches equal in every size and in place, paired longest first; the joins and length sewn."""
    pairs = []
    for b in band_runs:
        for t in targets:
            d = np.asarray(b.graded_cm) - np.asarray(t.graded_cm)
            tol = SPLIT_TOL_CM + 0.02 * max(b.length_cm, t.length_cm)
            if np.all(np.abs(d) <= tol) and (in_place is None or in_place(b, t, middle)):
                pairs.append((min(b.length_cm, t.length_cm), float(np.abs(d).max()), b, t))
    pairs.sort(key=lambda p: (-p[0], p[1]))
    used_band: set[int] = set()
    used_target: dict[tuple[str, int], int] = {}
    joins, covered = [], 0.0
    for length, _, b, t in pairs:
        tparts = {(t.piece, k) for k in t.parts}
        piece = pattern.piece(t.piece)
        copies = 2 if piece.quantity.left > 0 or piece.quantity.right > 1 or piece.mirror_line is not None else 1
        if set(b.parts) & used_band or any(used_target.get(k, 0) >= copies for k in tparts):
            continue
        used_band |= set(b.parts)
        for k in tparts:
            used_target[k] = used_target.get(k, 0) + 1
        covered += length
        joins.append(
            Join(
                id=f"{b.piece}_{b.start}_{t.piece}_{t.start}",
                a=run_side(t),
                b=run_side(b),
                kind="seam",
                confidence=0.8,
                ease_cm=round(b.length_cm - t.length_cm, 3),
                why=f"band stretch along the {op.kind}, equal in every size",
            )
        )
    return joins, covered


def _stretch_sides(pattern: Pattern, side: Side) -> list[Side]:
    """``side`` cut at its piece's breaks, in order."""
    piece = pattern.piece(side.piece)
    pts = sew_line(piece)[0]
    n = len(pts)
    seg = np.linalg.norm(np.roll(pts, -1, axis=0) - pts, axis=1)
    brk = set(int(b) for b in breaks(piece))
    out, start, k = [], side.start, side.start
    while k != side.end:
        k = (k + 1) % n
        if k in brk or k == side.end:
            idx = np.arange(start, k) if k > start else np.r_[start:n, 0:k]
            out.append(Side(piece=side.piece, start=start, end=k, length_cm=round(float(seg[idx].sum()), 3)))
            start = k
    return out


def _split_in_proportion(
    pattern: Pattern, band_runs: list[Run], edge: Run, op: Opening, root: Roots | None = None
) -> list[Join] | None:
    """The band edge cut at its own marks where they divide it as the opening's stretches divide the opening.

    A back-neck binding with a mark at its middle sews one half to each back
    half; a neckband marked at its quarters sews a quarter to each half of the
    front and back necklines. Every joint between the opening's sides needs a
    band mark within 5 % of the band; joints inside a side are used where the
    band has a mark. When the seams found say in which order the opening's
    sides follow each other on the garment (``root``, pieces cut once), the
    band runs against them from the chain's end (from anywhere around a closed
    loop). None otherwise.
    """
    units = _loop_units(pattern, op)
    if len(units) < 2:
        return None
    chain = chain_order(op.sides, root) if root is not None and len(op.sides) > 1 and set(op.copies) == {1} else None
    if chain is not None:
        units = [(k, u) for k, side in enumerate(chain) for u in _stretch_sides(pattern, side)]
        closed = root((chain[-1].piece, chain[-1].end)) == root((chain[0].piece, chain[0].start))
        against = units[::-1]
        orders = [against[k:] + against[:k] for k in range(len(against) if closed else 1)]
    else:
        # a band closed into a loop may start anywhere around the opening, in either direction
        orders = [order[k:] + order[:k] for order in (units[::-1], units) for k in range(len(order))]
    for order in orders:  # sewn face to face, a band runs against its opening first
        joins = _split_units(band_runs, edge, op, order)
        if joins:
            return joins
    return None


def _loop_units(pattern: Pattern, op: Opening) -> list[tuple[int, Side]]:
    """The opening's stretches in order around the body, as (side index, stretch).

    A neckline of two sides (front and back) of which a half piece is cut twice
    goes once around the body: each half from its outer end to the centre line
    and back out on its mirror copy (a piece drawn whole crosses once), so a
    collar's marks at the shoulders divide it into front, whole back and front.
    Otherwise each side's stretches once, in the opening's order.
    """
    per_side = [_stretch_sides(pattern, side) for side in op.sides]
    if op.kind != "neck" or len(op.sides) != 2 or 2 not in op.copies or len(op.centre_first) != 2:
        return [(k, u) for k, units in enumerate(per_side) for u in units]
    out = []
    for k, units in enumerate(per_side):
        if op.copies[k] == 2:
            inward = units[::-1] if op.centre_first[k] else units  # outer end -> centre line
            units = inward + inward[::-1]
        out += [(k, u) for u in units]
    return out


def _covering(group: list[Side]) -> Side:
    """The one range the stretches of ``group`` cover (both copies of a stretch count once)."""
    unique = {(g.start, g.end): g for g in group}
    starts = {s for s, _ in unique} - {e for _, e in unique}
    ends = {e for _, e in unique} - {s for s, _ in unique}
    first = group[0]
    return Side(
        piece=first.piece,
        start=starts.pop() if starts else first.start,
        end=ends.pop() if ends else group[-1].end,
        length_cm=round(sum(g.length_cm for g in unique.values()), 3),
    )


def _split_units(band_runs: list[Run], edge: Run, op: Opening, units: list[tuple[int, Side]]) -> list[Join] | None:
    """The proportional split of ``edge`` along ``units`` taken in this order, or None."""
    total = sum(u.length_cm for _, u in units)
    cum = np.cumsum([u.length_cm for _, u in units])[:-1] / total
    marks = np.array(edge.break_fracs)
    if not len(marks):
        return None
    near = np.min(np.abs(marks[None, :] - cum[:, None]), axis=1) < 0.05
    side_joint = np.array([units[m][0] != units[m + 1][0] for m in range(len(units) - 1)])
    if np.any(side_joint & ~near):
        return None
    if sum(near) != len(marks) and len(units) > len(op.sides):
        return None  # every band mark meets a joint of the opening
    # group the stretches between kept joints; each group lies within one side
    groups, current = [], [units[0][1]]
    for m in range(len(units) - 1):
        if near[m]:
            groups.append(current)
            current = []
        current.append(units[m + 1][1])
    groups.append(current)
    fracs = [*cum[near], 1.0]
    joins, start_frac, pos = [], 0.0, edge.start
    for group, frac in zip(groups, fracs, strict=True):
        side = _covering(group)
        run = None
        for r in sorted((r for r in band_runs if r.start == pos), key=lambda r: r.length_cm):
            if abs((start_frac * edge.length_cm + r.length_cm) / edge.length_cm - frac) < 0.05:
                run = r
                break
        if run is None:
            return None
        joins.append(
            Join(
                id=f"{run.piece}_{run.start}_{side.piece}_{side.start}",
                a=side,
                b=run_side(run),
                kind="band",
                confidence=0.7,
                ease_cm=round(run.length_cm - side.length_cm, 2),
                why=f"band cut at its own mark in proportion to the {op.kind}",
            )
        )
        start_frac, pos = frac, run.end
    return joins


def band_joins(
    pattern: Pattern,
    runs: dict[str, list[Run]],
    roles: dict[str, RoleGuess],
    opened: list[Opening],
    folds: dict[str, tuple[int, int]] | None = None,
    in_place: PlaceCheck | None = None,
    centres: set[tuple[str, int]] = frozenset(),
    seams: Sequence[Join] = (),
) -> tuple[list[Join], dict[str, RoleGuess]]:
    """Joins of every band piece to the opening(s) it fits, its closure, and refined band roles.

    folds : piece -> its fold edge; a band folded along it (a rib cuff) is sewn by its other long edge.
    centres : marks on the centre line of pieces drawn whole (:func:`.seams.centre_vertices`).
    seams : the seams found between the pieces; they place the ends of strips binding parts of one
        opening (:mod:`.strips`).

    A band cut twice (two armhole bindings, two cuffs) takes two openings.
    """
    joins: list[Join] = []
    new_roles: dict[str, RoleGuess] = {}
    taken: set[tuple[str, int, int]] = set()
    part_ends: list[tuple[str, Run]] = []
    part_strips: list[PartStrip] = []
    root = vertex_roots(seams) if seams else None
    bands = [n for n, g in roles.items() if is_band(g.role) and runs.get(n)]
    folds = folds or {}
    for name in sorted(bands, key=lambda n: -_band_edges(runs[n])[0].length_cm):
        guess = roles[name]
        fold = folds.get(name)
        edge, _, ends = _band_edges([r for r in runs[name] if fold is None or (r.start, r.end) != fold])
        kind, opening_cm, first = None, [], len(joins)
        for copy_no in range(min(max(copies_cut(pattern.piece(name)), 1), 2)):
            # a second copy binds the twin opening (the other armhole, the other sleeve), never another kind
            kind = _attach(
                pattern,
                runs,
                name,
                guess,
                edge,
                [o if kind in (None, o.kind) else None for o in opened],
                taken,
                joins,
                new_roles,
                in_place,
                opening_cm,
                centres,
                root,
                band_copy="mirror" if copy_no else "primary",
            )
            if kind is None or kind == "neck":
                break
        # a strip longer than its opening is applied flat, its ends caught in the next seam; a collar stays open;
        # a strip binding one part of an opening meets the next strips with its ends
        flat = bool(opening_cm) and edge.length_cm > FLAT_APPLIED * min(abs(c) for c in opening_cm)
        partial = any(c < 0 for c in opening_cm)
        if partial and len(ends) >= 2 and root is not None:
            part_strips.append(PartStrip(name=name, edge=edge, ends=tuple(ends), joins=tuple(joins[first:])))
            del joins[first:]
        elif partial and len(ends) >= 2:
            part_ends += [(name, r) for r in sorted(ends, key=lambda r: -r.length_cm)[:2]]
        loop = guess.role not in (Role.COLLAR, Role.COLLAR_STAND) and not flat and not partial
        joins += _closure(name, edge, ends) if loop else []
    if part_strips:
        joins += place_part_strips(part_strips, root)
    return joins + _join_part_ends(part_ends), new_roles


def _closure(name: str, edge: Run, ends: list[Run]) -> list[Join]:
    """A loop's two short ends sewn together, whatever their slant (a bias binding's ends differ); [] without two."""
    if len(ends) < 2:
        return []
    e1, e2 = sorted(ends, key=lambda r: -r.length_cm)[:2]
    if max(e1.length_cm, e2.length_cm) > END_SHARE * edge.length_cm:
        return []
    return [
        Join(
            id=f"{name}_closure",
            a=run_side(e1),
            b=run_side(e2),
            kind="seam",
            confidence=0.8,
            why="the band's two ends close the loop",
        )
    ]


def _join_part_ends(ends: list[tuple[str, Run]]) -> list[Join]:
    """The ends of strips that bind parts of one opening, sewn to each other: equal ends, longest first.

    Each end is sewn once and two strips meet at one end only (a neckline bound
    by a back strip and two front strips meets at both shoulders and the centre
    front).
    """
    pairs = [
        (min(ra.length_cm, rb.length_cm), i, k)
        for i, (na, ra) in enumerate(ends)
        for k, (nb, rb) in enumerate(ends)
        if i < k and na != nb and abs(ra.length_cm - rb.length_cm) <= END_TOL_CM
    ]
    used: set[int] = set()
    met: set[frozenset[str]] = set()
    joins = []
    for _, i, k in sorted(pairs, key=lambda t: -t[0]):
        (na, ra), (nb, rb) = ends[i], ends[k]
        if i in used or k in used or frozenset((na, nb)) in met:
            continue
        used |= {i, k}
        met.add(frozenset((na, nb)))
        joins.append(
            Join(
                id=f"{na}_{nb}_ends",
                a=run_side(ra),
                b=run_side(rb),
                kind="seam",
                confidence=0.6,
                why="ends of two strips binding parts of one opening",
            )
        )
    return joins


def _attach(
    pattern: Pattern,
    runs: dict[str, list[Run]],
    name: str,
    guess: RoleGuess,
    edge: Run,
    opened: list[Opening | None],
    taken: set[tuple[str, int, int]],
    joins: list[Join],
    new_roles: dict[str, RoleGuess],
    in_place: PlaceCheck | None = None,
    taken_cm: list[float] | None = None,
    centres: set[tuple[str, int]] = frozenset(),
    root: Roots | None = None,
    band_copy: str = "primary",
) -> str | None:
    """Sew band ``name``'s long ``edge`` along the free opening it fits best; its kind, None when none fits.

    ``taken_cm`` receives the length of the opening taken. Band joins along
    several ranges are placed on the band (:func:`.band_spans.place_band`).
    """
    best = None
    for k, op in enumerate(opened):
        if op is None or any(side.key in taken for side in op.sides):
            continue
        ratio = op.length_cm / edge.length_cm
        if not MAX_EASE <= ratio <= MAX_STRETCH:
            continue
        if guess.role not in _OPENING_ROLES[op.kind] and guess.confidence >= 0.7:
            continue  # a band sure of its role binds only its own kind of opening
        cost = abs(np.log(ratio / 1.05))
        centred = any(abs(f - 0.5) < 0.03 for f in edge.break_fracs)
        if centred and len(op.sides) == 1:
            cost += 0.5  # a band marked at its middle crosses a centre line: it spans two halves
        if best is None or cost < best[0]:
            best = (cost, k, op)
    if best is None:
        return None
    cost, k, op = best
    taken.update(side.key for side in op.sides)
    if taken_cm is not None:
        taken_cm.append(-op.length_cm if op.part else op.length_cm)
    conf = round(float(np.clip(1.0 - cost, 0.3, 0.95)), 2)
    if guess.role not in _OPENING_ROLES[op.kind] and name not in new_roles:
        new_roles[name] = RoleGuess(
            role=_OPENING_ROLES[op.kind][0], confidence=conf, why=f"strip {edge.length_cm:.1f} cm along the {op.kind}"
        )
    split = _split_band(pattern, runs, edge, op, in_place, centres, root)
    if split and all(j.kind != "band" for j in split):
        joins.extend(split)
        return op.kind
    # a strip binding one part of an opening (:mod:`.strips` places it) is not placed here
    place = (lambda js: js) if op.part else (lambda js: place_band(pattern, js, edge, op, band_copy))
    if split:
        joins.extend(place(split))
        return op.kind
    along = []
    for side in op.sides:
        along.append(
            Join(
                id=f"{name}_{op.kind}_{side.piece}_{side.start}",
                a=side,
                b=run_side(edge),
                kind="band",
                confidence=conf,
                ease_cm=round(edge.length_cm - op.length_cm, 2),
                why=f"band along the {op.kind}: {op.length_cm:.1f} cm of opening, band {edge.length_cm:.1f} cm",
            )
        )
    joins.extend(place(along))
    return op.kind
