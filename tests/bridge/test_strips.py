"""Where the ends of strips binding parts of one opening lie (``bridge.strips``)."""

from __future__ import annotations

from patternbridge.bridge.edges import Run
from patternbridge.bridge.model import Join, Side
from patternbridge.bridge.strips import PartStrip, chain_order, place_part_strips, vertex_roots


def _join(a: tuple, b: tuple, kind: str = "seam") -> Join:
    side_a, side_b = Side(piece=a[0], start=a[1], end=a[2]), Side(piece=b[0], start=b[1], end=b[2])
    return Join(id=f"{a}{b}", a=side_a, b=side_b, kind=kind)


def _run(piece: str, start: int, end: int, length_cm: float) -> Run:
    return Run(
        piece=piece,
        start=start,
        end=end,
        length_cm=length_cm,
        graded_cm=[length_cm],
        notch_fracs=(),
        bend_rad=0.0,
        chord_cm=length_cm,
        parts=(start,),
    )


# a neckline of a left front L (neck 5 -> 6, centre front at 6), a back B (neck 1 -> 2, centre back at 2, not
# used) and a right front R (neck 3 -> 4, centre front at 3); shoulders L.5 ~ B.1 and the centre fronts L.6 ~ R.3
SEAMS = [_join(("L", 4, 5), ("B", 1, 9)), _join(("L", 6, 7), ("R", 2, 3))]


def test_vertex_roots_join_the_ends_a_seam_brings_together_against_each_other():
    root = vertex_roots([*SEAMS, _join(("L", 0, 1), ("L", 0, 1), kind="fold")])
    assert root(("L", 5)) == root(("B", 1))  # a.end meets b.start
    assert root(("L", 4)) == root(("B", 9))  # a.start meets b.end
    assert root(("L", 6)) == root(("R", 3))
    assert root(("L", 5)) != root(("L", 4))
    assert root(("L", 0)) == ("L", 0)  # a fold brings nothing together
    assert root(("X", 3)) == ("X", 3)


def test_chain_order_follows_the_sides_round_the_garment_or_says_none():
    root = vertex_roots(SEAMS)
    left, right = Side(piece="L", start=5, end=6), Side(piece="R", start=3, end=4)
    assert chain_order([right, left], root) == [left, right]
    assert chain_order([right, Side(piece="B", start=1, end=2)], root) is None


def test_twin_strips_swap_to_the_parts_whose_ends_they_meet():
    """Front bindings P and Q cut alike but turned, a back binding K with 1.6 cm ends at both shoulders.

    A strip runs 0 -> 1 along its sewn edge, against the neck it binds; its
    end (3, 0) lies at its first vertex, (1, 2) at its last. P's 1.9 cm end
    must lie at the centre front: P binds the left front, Q the right.
    """
    root = vertex_roots([*SEAMS, _join(("R", 4, 10), ("B", 7, 8))])  # right shoulder: R.4 meets B.8
    left, right = Side(piece="L", start=5, end=6), Side(piece="R", start=3, end=4)
    back = Side(piece="B", start=8, end=1)
    strips = []
    for name, first, last, side in (("P", 1.9, 1.6, right), ("Q", 1.6, 1.9, left), ("K", 1.6, 1.6, back)):
        edge = _run(name, 0, 1, 30.0 if name == "K" else 15.0)
        ends = (_run(name, 3, 0, first), _run(name, 1, 2, last))
        strips.append(PartStrip(name=name, edge=edge, ends=ends, joins=(_band(side, edge),)))
    joins = place_part_strips(strips, root)
    along = {j.b.piece: j.a.piece for j in joins if j.id.endswith("_band")}
    assert along == {"P": "L", "Q": "R", "K": "B"}
    ends = {frozenset((j.a.piece, j.b.piece)): (j.a.length_cm, j.b.length_cm) for j in joins if j.id.endswith("_ends")}
    assert ends == {
        frozenset("PQ"): (1.9, 1.9),  # centre front
        frozenset("PK"): (1.6, 1.6),  # left shoulder
        frozenset("QK"): (1.6, 1.6),  # right shoulder
    }


def _band(side: Side, edge: Run) -> Join:
    return Join(id=f"{edge.piece}_band", a=side, b=Side(piece=edge.piece, start=edge.start, end=edge.end), kind="band")
