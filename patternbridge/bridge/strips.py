"""Strips binding parts of one opening: where their ends lie, and which ends meet.

A neckline bound by several strips (two front bindings and a back one) is
sewn strip by strip, each along its part of the opening. Seen from outside
every piece's outline runs counter-clockwise, so two edges sewn together run
against each other: a strip's first vertex meets the last vertex of the edge
it binds. The seams already found say which boundary vertices of different
pieces come together on the garment (:func:`vertex_roots`); from them each
strip end gets a place, the ends lying at one place are sewn together, and of
two strips cut alike (mirror twins) the one whose ends fit the ends they meet
binds each part (a front binding's centre-front end is cut with the slant of
the other front's, its shoulder end with the back binding's).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from itertools import combinations

from .edges import Run
from .model import Join, Side
from .openings import run_side

__all__ = ["PartStrip", "chain_order", "place_part_strips", "vertex_roots"]

Vertex = tuple[str, int]
#: two strip ends this close in length are cut to meet
END_TOL_CM = 0.1
#: two strips this close in length may bind each other's part
TWIN_TOL_CM = 0.2


def vertex_roots(joins: Sequence[Join]) -> Callable[[Vertex], Vertex]:
    """The place on the garment of every boundary vertex: vertices two seams bring together share a root.

    A seam between two different pieces joins ``a.start`` with ``b.end`` and
    ``a.end`` with ``b.start`` (its sides run against each other).
    """
    parent: dict[Vertex, Vertex] = {}

    def root(v: Vertex) -> Vertex:
        while parent.get(v, v) != v:
            v = parent[v]
        return v

    for j in joins:
        if j.kind == "fold" or j.a.piece == j.b.piece:
            continue
        for p, q in (((j.a.piece, j.a.start), (j.b.piece, j.b.end)), ((j.a.piece, j.a.end), (j.b.piece, j.b.start))):
            rp, rq = root(p), root(q)
            if rp != rq:
                parent[rp] = rq
    return root


def chain_order(sides: Sequence[Side], root: Callable[[Vertex], Vertex]) -> list[Side] | None:
    """``sides`` in the order they follow each other on the garment (each one's end meets the next one's start).

    None unless one such order exists (checked from every side as the first).
    """
    for first in sides:
        order, rest = [first], [s for s in sides if s is not first]
        while rest:
            here = root((order[-1].piece, order[-1].end))
            nxt = [s for s in rest if root((s.piece, s.start)) == here]
            if len(nxt) != 1:
                break
            order.append(nxt[0])
            rest.remove(nxt[0])
        if not rest:
            return order
    return None


@dataclass(frozen=True, slots=True, kw_only=True)
class PartStrip:
    """A strip sewn along part of an opening: its sewn ``edge``, its end runs and the joins along the opening."""

    name: str
    edge: Run
    ends: tuple[Run, ...]
    joins: tuple[Join, ...]


def _end_places(strip: PartStrip, root: Callable[[Vertex], Vertex]) -> list[tuple[Vertex, Run]]:
    """(place, end run) of the strip's two ends: its edge runs against the opening it binds."""
    out = []
    for j in strip.joins:
        if j.b.start == strip.edge.start:
            out += [(root((j.a.piece, j.a.end)), r) for r in strip.ends if r.end == strip.edge.start]
        if j.b.end == strip.edge.end:
            out += [(root((j.a.piece, j.a.start)), r) for r in strip.ends if r.start == strip.edge.end]
    return out


def _meetings(strips: Sequence[PartStrip], root: Callable[[Vertex], Vertex]) -> list[tuple[str, Run, str, Run]]:
    """Pairs of ends of different strips lying at one place."""
    placed = [(s.name, place, r) for s in strips for place, r in _end_places(s, root)]
    return [(na, ra, nb, rb) for (na, pa, ra), (nb, pb, rb) in combinations(placed, 2) if na != nb and pa == pb]


def _fit(strips: Sequence[PartStrip], root: Callable[[Vertex], Vertex]) -> int:
    return sum(abs(ra.length_cm - rb.length_cm) <= END_TOL_CM for _, ra, _, rb in _meetings(strips, root))


def _swapped(s: PartStrip, t: PartStrip) -> tuple[PartStrip, PartStrip]:
    """``s`` along ``t``'s part and ``t`` along ``s``'s (one join each)."""
    (js,), (jt,) = s.joins, t.joins
    return (
        replace(s, joins=(replace(js, a=jt.a, ease_cm=round(s.edge.length_cm - jt.a.length_cm, 2)),)),
        replace(t, joins=(replace(jt, a=js.a, ease_cm=round(t.edge.length_cm - js.a.length_cm, 2)),)),
    )


def place_part_strips(strips: Sequence[PartStrip], root: Callable[[Vertex], Vertex]) -> list[Join]:
    """The strips' joins along the opening (twins swapped where their ends fit better) and their end joins.

    Returns the joins along the opening followed by one join per pair of
    strip ends lying at one place.
    """
    strips = list(strips)
    for i, k in combinations(range(len(strips)), 2):
        s, t = strips[i], strips[k]
        if len(s.joins) != 1 or len(t.joins) != 1 or abs(s.edge.length_cm - t.edge.length_cm) > TWIN_TOL_CM:
            continue
        s2, t2 = _swapped(s, t)
        trial = [*strips[:i], s2, *strips[i + 1 : k], t2, *strips[k + 1 :]]
        if _fit(trial, root) > _fit(strips, root):
            strips = trial
    out = [j for s in strips for j in s.joins]
    for na, ra, nb, rb in _meetings(strips, root):
        out.append(
            Join(
                id=f"{na}_{nb}_ends",
                a=run_side(ra),
                b=run_side(rb),
                kind="seam",
                confidence=0.8 if abs(ra.length_cm - rb.length_cm) <= END_TOL_CM else 0.5,
                why="ends of two strips binding parts of one opening, at one place",
            )
        )
    return out
