"""Where a band meets each range of the opening it binds, and its joints as marks on the band.

A band sewn along an opening made of several ranges (a neckline of a front
and a back, each half cut twice) needs a mark on its edge at every joint of
the opening. A pattern maker puts them in proportion: the band's sewn edge is
divided as the opening's ranges divide the opening, so each range takes the
band's ease in proportion to its length.

The opening is walked once around (:func:`opening_units`): every range on
each copy it is cut in, each traversed the way the garment's surface, seen
from outside, goes round the hole (a range on the drawn copy in outline
order, on the mirror copy against it; the two copies of a half meet at the
centre line). The band, sewn face to face, runs against that direction: on
its drawn copy from its edge's end back to its start, on its mirror copy from
start to end. Of the places round the loop where the band's two ends may
fall, the one whose joints meet the band's own marks (a collar's shoulder
notches) is taken; joints within ``SNAP`` of a mark are moved onto it. A strip
longer than its opening by more than ``FLAT_APPLIED`` is applied flat: it is
sewn at its own length along the opening and the excess is left free at its
two ends, half at each: in the workroom it is sewn from one end and the
excess cut off where the sewing meets its start, so the drape wears it cut
straight across the strip at both ends of its sewn range (:class:`.model.Trim`,
:mod:`.worn`).

:func:`split_bands` turns the placed band joins into one-to-one seams,
inserting a vertex on the band wherever a joint falls between two
(:mod:`..pattern.insert`), and at the two cut lines of a band applied flat,
and renumbers everything that names the band's vertices.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from ..library.seams import sew_line
from ..pattern.insert import insert_vertices
from ..pattern.model import Pattern
from .edges import Run
from .model import BridgeInference, Join, Side, Trim
from .openings import Opening

__all__ = ["SNAP", "opening_units", "place_band", "split_bands"]

#: a joint this close to a band mark (share of the band's edge) is moved onto the mark
SNAP = 0.05
#: a band longer than this times its opening is applied flat (:data:`.bands.FLAT_APPLIED`)
FLAT_APPLIED = 1.05
#: a unit of the opening is sewn to a band join's range when it covers at least this share of it
MIN_SPAN = 0.02
#: a joint this close (cm, along the edge) to a band vertex uses the vertex
VERTEX_TOL_CM = 0.05
#: a band whose sewn range leaves more than this share of its edge free at both ends is applied flat (trimmed)
FLAT_TAIL = 0.01


def opening_units(op: Opening) -> list[tuple[Side, str]] | None:
    """The opening's ranges on each copy, ``(side, copy)``, in order round the hole; None if not known.

    A neckline side cut twice (a half on the fold, a pair) is walked on both
    copies, which meet at the centre line; any other opening (an armhole, a
    sleeve hem) is one copy of the garment's. Two sides close a loop in either
    order; more need the seams' chain order, which is not known here. An
    armhole's ranges are taken on the copies worn on the body's right side
    (:attr:`.openings.Opening.right_copy`), so a band's drawn copy binds one
    armhole, never a left front's and a right back's half of two.
    """
    if not 1 <= len(op.sides) <= 2:
        return None
    units: list[tuple[Side, str]] = []
    for k, side in enumerate(op.sides):
        twice = op.kind == "neck" and k < len(op.copies) and op.copies[k] == 2
        if not twice:
            units.append((side, op.right_copy[k] if k < len(op.right_copy) else "primary"))
            continue
        centre_first = k < len(op.centre_first) and op.centre_first[k]
        # the drawn copy in outline order goes centre -> outer when its range starts at the centre line
        units += [(side, "mirror"), (side, "primary")] if centre_first else [(side, "primary"), (side, "mirror")]
    return units


def _closure_height(op: Opening, units: list[tuple[Side, str]], start: int) -> float:
    """Minus the upright height of the joint where a band started at unit ``start`` closes (0 when not known).

    The walk starts at the unit's start on a drawn copy, at its end on a mirror copy. Of the places its own
    marks leave open, an armhole band closes at its highest joint (the shoulder): both armholes' bands then
    close alike, the band's middle at the underarm.
    """
    if not op.heights or len(op.heights) != len(units):
        return 0.0
    side_start, side_end = op.heights[start]
    return -(side_start if units[start][1] == "primary" else side_end)


def _bounds(lengths: np.ndarray, start: int, band_copy: str, margin: float = 0.0) -> np.ndarray:
    """(m + 1,) positions (share of the band edge from its start) of the unit ends, the loop started at ``start``.

    ``margin``: the share of the edge left free at each end (a strip applied flat).
    """
    order = np.roll(lengths, -start)
    cum = margin + (1.0 - 2.0 * margin) * np.concatenate([[0.0], np.cumsum(order)]) / order.sum()
    return 1.0 - cum if band_copy == "primary" else cum


def place_band(pattern: Pattern, joins: list[Join], edge: Run, op: Opening, band_copy: str) -> list[Join]:
    """``joins`` (one band copy along ``op``) with their :attr:`Join.spans`; unchanged when not placed.

    Each join's ``b`` is the band's whole edge or the part of it the band's
    own marks assign to ``a``; a join gets one span per unit of its side that
    lies on its ``b``.
    """
    units = opening_units(op)
    if not units or not joins:
        return joins

    lengths = np.array([side.length_cm for side, _ in units], dtype=np.float64)
    if lengths.min() <= 0.0:
        return joins
    marks = np.array(edge.break_fracs, dtype=np.float64)
    # a strip longer than its opening by more than FLAT_APPLIED is applied flat: sewn at its own length,
    # the excess left at its two ends, where the next seam catches them
    excess = edge.length_cm - lengths.sum()
    margin = 0.5 * excess / edge.length_cm if edge.length_cm > FLAT_APPLIED * lengths.sum() else 0.0

    def fit(start: int) -> tuple[int, float, float, int]:
        inner = _bounds(lengths, start, band_copy, margin)[1:-1]
        low = _closure_height(op, units, start)
        if not len(marks) or not len(inner):
            return (0, 0.0, low, start)
        d = np.min(np.abs(inner[:, None] - marks[None, :]), axis=1)
        return (-int(np.sum(d < SNAP)), float(np.minimum(d, SNAP).sum()), low, start)

    start = min(fit(k) for k in range(len(units)))[-1]
    pos = _bounds(lengths, start, band_copy, margin)
    for k in range(int(margin == 0.0), len(pos) - int(margin == 0.0)):
        if len(marks) and np.min(np.abs(marks - pos[k])) < SNAP:
            pos[k] = marks[np.argmin(np.abs(marks - pos[k]))]
    ordered = units[start:] + units[:start]
    lo, hi = np.minimum(pos[:-1], pos[1:]), np.maximum(pos[:-1], pos[1:])
    twice = {side.piece for side, copy in units if copy == "mirror"}
    whole = (edge.piece, edge.start, edge.end)
    out = []
    for j in joins:
        if j.b.key != whole and j.a.piece not in twice:
            # cut at the band's own marks onto a range cut once: sewn as it is
            out.append(dataclasses.replace(j, spans=(("primary", 0.0, 1.0),), copy_b=band_copy))
            continue
        g0, g1 = _edge_share(pattern, edge, j.b)
        spans = []
        for (side, copy), a, b in zip(ordered, lo, hi, strict=True):
            inside = min(b, g1) - max(a, g0)
            if side.piece == j.a.piece and inside > MIN_SPAN * (g1 - g0):
                f0, f1 = (max(a, g0) - g0) / (g1 - g0), (min(b, g1) - g0) / (g1 - g0)
                spans.append((copy, round(float(np.clip(f0, 0, 1)), 6), round(float(np.clip(f1, 0, 1)), 6)))
        spans.sort(key=lambda s: s[1])
        if j.b.key != whole and spans:
            # a part cut at the band's own marks: on the copy it mostly lies on, unless it spans both
            # (a collar along both halves of a back neck), then split where the copies meet
            share = max(f1 - f0 for _, f0, f1 in spans)
            if share >= 1.0 - SNAP:
                copy = max(spans, key=lambda s: s[2] - s[1])[0]
                spans = [(copy, 0.0, 1.0)]
            else:
                spans[0], spans[-1] = (spans[0][0], 0.0, spans[0][2]), (spans[-1][0], spans[-1][1], 1.0)
        out.append(dataclasses.replace(j, spans=tuple(spans), copy_b=band_copy))
    return out


def _arc(pattern: Pattern, piece: str, start: int) -> tuple[np.ndarray, float]:
    """(n,) sew-line arc length of every vertex from ``start`` in outline order, and the perimeter."""
    pts = sew_line(pattern.piece(piece))[0]
    seg = np.linalg.norm(np.roll(pts, -1, axis=0) - pts, axis=1)
    cum = np.concatenate([[0.0], np.cumsum(seg)])[:-1]
    total = float(seg.sum())
    return np.mod(cum - cum[start], total), total


def _edge_share(pattern: Pattern, edge: Run, b: Side) -> tuple[float, float]:
    """Where the range ``b`` starts and ends on ``edge``, as shares of the edge's length from its start."""
    arc, _ = _arc(pattern, edge.piece, edge.start)
    length = arc[edge.end] if edge.end != edge.start else _arc(pattern, edge.piece, edge.start)[1]
    g0 = 0.0 if b.start == edge.start else arc[b.start] / length
    g1 = 1.0 if b.end == edge.end else arc[b.end] / length
    return float(g0), float(g1)


def _position(arc: np.ndarray, total: float, seg: np.ndarray, p: float) -> tuple[int, float] | int:
    """The vertex at perimeter position ``p`` (cm from vertex 0), or ``(segment, t)`` between two."""
    d = np.abs(np.mod(arc - p + 0.5 * total, total) - 0.5 * total)
    v = int(np.argmin(d))
    if d[v] <= VERTEX_TOL_CM:
        return v
    k = int(np.searchsorted(arc, p, side="right") - 1) % len(arc)
    return k, float((p - arc[k]) / seg[k])


def _band_ends(pattern: Pattern, j: Join, spans) -> list[tuple[float, float]]:
    """Perimeter positions (cm from vertex 0) of the start and end of each span on the band."""
    arc, total = _arc(pattern, j.b.piece, 0)
    start = arc[j.b.start]
    length = float(np.mod(arc[j.b.end] - start, total)) or total
    return [
        (float(np.mod(start + f0 * length, total)), float(np.mod(start + f1 * length, total))) for _, f0, f1 in spans
    ]


def _remap(side: Side, index: np.ndarray | None) -> Side:
    if index is None:
        return side
    return dataclasses.replace(side, start=int(index[side.start]), end=int(index[side.end]))


def _flat_ends(placed: list[Join], ends: dict[str, list[tuple[float, float]]]) -> dict[str, tuple[float, float]]:
    """Band piece -> perimeter positions (cm from vertex 0) of the start and end of its sewn range, for each band
    applied flat: sewn along its whole edge with more than :data:`FLAT_TAIL` of the edge free at both ends."""
    by_piece: dict[str, list[tuple[float, float]]] = {}
    edges: dict[str, set] = {}
    for j in placed:
        edges.setdefault(j.b.piece, set()).add(j.b.key)
        for (_, f0, f1), (p0, p1) in zip(j.spans, ends[j.id], strict=True):
            by_piece.setdefault(j.b.piece, []).extend([(f0, p0), (f1, p1)])
    out = {}
    for name, marks in by_piece.items():
        lo, hi = min(marks), max(marks)
        if len(edges[name]) == 1 and lo[0] > FLAT_TAIL and hi[0] < 1.0 - FLAT_TAIL:
            out[name] = (lo[1], hi[1])
    return out


def _across(pts: np.ndarray, arc: np.ndarray, total: float, p: float) -> float | None:
    """Perimeter position of the point straight across the strip from perimeter position ``p`` (the first
    crossing of the outline by the inward normal there; the outline runs counter-clockwise), or None."""
    seg_vec = np.roll(pts, -1, axis=0) - pts
    seg = np.linalg.norm(seg_vec, axis=1)
    k = int(np.searchsorted(arc, np.mod(p, total), side="right") - 1) % len(pts)
    t = seg_vec[k] / max(seg[k], 1e-12)
    origin = pts[k] + (np.mod(p, total) - arc[k]) * t
    normal = np.array([-t[1], t[0]])
    # origin + s * normal = pts[i] + u * seg_vec[i]
    det = normal[0] * (-seg_vec[:, 1]) - normal[1] * (-seg_vec[:, 0])
    rel = pts - origin
    with np.errstate(divide="ignore", invalid="ignore"):
        s = (rel[:, 0] * (-seg_vec[:, 1]) - rel[:, 1] * (-seg_vec[:, 0])) / det
        u = (normal[0] * rel[:, 1] - normal[1] * rel[:, 0]) / det
    ok = (np.abs(det) > 1e-12) & (s > 1e-3) & (u >= 0.0) & (u <= 1.0)
    if not ok.any():
        return None
    i = int(np.argmin(np.where(ok, s, np.inf)))
    return float(np.mod(arc[i] + u[i] * seg[i], total))


def split_bands(pattern: Pattern, inference: BridgeInference) -> tuple[Pattern, BridgeInference, dict[str, set[int]]]:
    """Each placed band join as one-to-one seams, with a vertex on the band at every joint.

    Returns the pattern with the new band vertices, the inference with the
    placed band joins replaced, every index on a band renumbered and the
    :attr:`~.model.BridgeInference.trims` of the bands applied flat, and the
    new vertices per piece. Strips binding parts of one opening (the CLO
    shirt's neck strips, :mod:`.strips`) stay ``band`` joins.
    """
    placed = [j for j in inference.joins if j.kind == "band" and j.spans]
    wanted: dict[str, list[float]] = {}
    ends: dict[str, list[tuple[float, float]]] = {}
    for j in placed:
        ends[j.id] = _band_ends(pattern, j, j.spans)
        wanted.setdefault(j.b.piece, []).extend(p for pair in ends[j.id] for p in pair)
    cuts: dict[str, list[tuple[float, float]]] = {}
    for name, (lo, hi) in _flat_ends(placed, ends).items():
        arc, total = _arc(pattern, name, 0)
        pts = sew_line(pattern.piece(name))[0]
        across = [_across(pts, arc, total, p) for p in (lo, hi)]
        if all(a is not None for a in across):
            cuts[name] = [(lo, across[0]), (hi, across[1])]
            wanted[name].extend(across)
    pieces, maps, inserted = {}, {}, {}
    for name, positions in wanted.items():
        arc, total = _arc(pattern, name, 0)
        pts = sew_line(pattern.piece(name))[0]
        seg = np.linalg.norm(np.roll(pts, -1, axis=0) - pts, axis=1)
        at = {}
        for p in positions:
            where = _position(arc, total, seg, p)
            if isinstance(where, tuple):
                at[(where[0], round(where[1], 6))] = where
        piece, index = insert_vertices(pattern.piece(name), list(at.values()))
        pieces[name], maps[name] = piece, index
        inserted[name] = set(range(len(piece.outline))) - set(index.tolist())
    out = dataclasses.replace(pattern, pieces=tuple(pieces.get(p.name, p) for p in pattern.pieces))
    joins: list[Join] = []
    for j in inference.joins:
        mine = next((q for q in placed if q.id == j.id), None)
        if mine is None:
            joins.append(dataclasses.replace(j, a=_remap(j.a, maps.get(j.a.piece)), b=_remap(j.b, maps.get(j.b.piece))))
            continue
        joins += _span_seams(out, mine, ends[mine.id])
    trims = []
    for name, ((s0, a0), (s1, a1)) in cuts.items():
        at = _vertex_at(out, name)
        trims.append(Trim(piece=name, start=at(s0), start_across=at(a0), end=at(s1), end_across=at(a1)))
    orientations = {
        name: o
        if name not in maps or o.fold is None
        else dataclasses.replace(o, fold=(int(maps[name][o.fold[0]]), int(maps[name][o.fold[1]])))
        for name, o in inference.orientations.items()
    }
    new = dataclasses.replace(inference, joins=tuple(joins), orientations=orientations, trims=tuple(trims))
    return out, new, inserted


def _vertex_at(pattern: Pattern, piece: str):
    """The function: perimeter position (cm from vertex 0 of the piece before insertion, the same on its
    sew line after) -> the nearest vertex of ``piece`` in ``pattern``."""
    arc, total = _arc(pattern, piece, 0)

    def at(p: float) -> int:
        return int(np.argmin(np.abs(np.mod(arc - p + 0.5 * total, total) - 0.5 * total)))

    return at


def _span_seams(pattern: Pattern, j: Join, ends: list[tuple[float, float]]) -> list[Join]:
    """The seams of one placed band join: one per span, the band range between its two joint vertices."""
    arc, total = _arc(pattern, j.b.piece, 0)
    out = []
    for n, ((copy, _, _), (p0, p1)) in enumerate(zip(j.spans, ends, strict=True)):
        d0 = np.abs(np.mod(arc - p0 + 0.5 * total, total) - 0.5 * total)
        d1 = np.abs(np.mod(arc - p1 + 0.5 * total, total) - 0.5 * total)
        v0, v1 = int(np.argmin(d0)), int(np.argmin(d1))
        length = float(np.mod(arc[v1] - arc[v0], total))
        b = Side(piece=j.b.piece, start=v0, end=v1, length_cm=round(length, 3))
        out.append(
            dataclasses.replace(
                j,
                id=j.id if len(j.spans) == 1 else f"{j.id}_{n + 1}",
                b=b,
                kind="seam",
                ease_cm=round(length - j.a.length_cm, 3),
                why=f"{j.why}; band marked at the opening's joints in proportion",
                spans=(),
                copy_a=copy,
                copy_b=j.copy_b or "primary",
            )
        )
    return out
