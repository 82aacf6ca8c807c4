"""The pieces the drape leaves out: not worn as a layer of their own, or sewn to nothing of the garment.

A pattern file holds every piece the cutting room cuts, and not all of them
hang on the body as cloth of their own:

- an **interlining** (``Role.INTERLINING``) is fused to the piece it
  stiffens (a placket, a collar) and moves with it; draped as a separate
  layer it would lie on the torso with nothing holding it;
- a piece that no seam joins, directly or through other pieces, to the
  garment's body pieces (front, back, legs) has nothing that holds it on the
  body either: a placket or pocket the seam inference could not sew.

:func:`left_out` names them with the reason; :func:`draped_only` removes them
(and their seams and links) from the pattern that is draped. The graded
pattern and the DXF sent back keep every piece.
"""

from __future__ import annotations

import dataclasses
from collections import Counter
from dataclasses import dataclass
from enum import StrEnum

from ..pattern.model import Pattern, Role
from .model import is_body

__all__ = ["LeftOut", "LeftOutReason", "draped_only", "left_out"]


class LeftOutReason(StrEnum):
    """Why the drape leaves a piece out (its value is the report's ``why``)."""

    INTERLINING = "interlining"
    UNSEWN = "unsewn"

    @property
    def words(self) -> str:
        """The reason as the user reads it."""
        return {
            LeftOutReason.INTERLINING: "interlining, fused to the piece it stiffens",
            LeftOutReason.UNSEWN: "sewn to no piece of the garment",
        }[self]


@dataclass(frozen=True, slots=True, kw_only=True)
class LeftOut:
    """A piece the drape leaves out and why."""

    piece: str
    why: LeftOutReason

    def as_dict(self) -> dict[str, str]:
        return {"piece": self.piece, "why": str(self.why)}


def _components(pattern: Pattern) -> dict[str, int]:
    """Piece name -> id of its connected component in the graph of seams between distinct pieces."""
    parent = {p.name: p.name for p in pattern.pieces}

    def root(n: str) -> str:
        while parent[n] != n:
            parent[n] = parent[parent[n]]
            n = parent[n]
        return n

    for s in pattern.seams:
        if s.a.piece != s.b.piece and s.a.piece in parent and s.b.piece in parent:
            parent[root(s.a.piece)] = root(s.b.piece)
    roots = sorted({root(n) for n in parent})
    return {n: roots.index(root(n)) for n in parent}


def left_out(pattern: Pattern) -> tuple[LeftOut, ...]:
    """The pieces of ``pattern`` the drape leaves out, in pattern order.

    Interlinings always; of the rest, the pieces outside every seam-connected
    group holding a body piece (front, back, leg), or outside the largest group
    when no piece has a body role. A pattern without seams between pieces
    (one piece, or nothing sewn yet) keeps all its other pieces.

    Examples
    --------
    >>> from patternbridge.pattern.model import Piece
    >>> sq = [[0, 0], [1, 0], [1, 1], [0, 1]]
    >>> shell, fused = Piece(name="a", outline=sq, role="front"), Piece(name="f", outline=sq, role="interlining")
    >>> p = Pattern(style="s", pieces=(shell, fused))
    >>> [(x.piece, str(x.why)) for x in left_out(p)]
    [('f', 'interlining')]
    """
    out = [LeftOut(piece=p.name, why=LeftOutReason.INTERLINING) for p in pattern.pieces if p.role is Role.INTERLINING]
    gone = {x.piece for x in out}
    comp = _components(pattern)
    if not any(s.a.piece != s.b.piece for s in pattern.seams):
        return tuple(out)
    body = {comp[p.name] for p in pattern.pieces if is_body(p.role) and p.name not in gone}
    if not body:
        body = {Counter(comp[n] for n in comp if n not in gone).most_common(1)[0][0]}
    unsewn = [p.name for p in pattern.pieces if p.name not in gone and comp[p.name] not in body]
    out += [LeftOut(piece=name, why=LeftOutReason.UNSEWN) for name in unsewn]
    order = {p.name: k for k, p in enumerate(pattern.pieces)}
    return tuple(sorted(out, key=lambda x: order[x.piece]))


def draped_only(pattern: Pattern) -> tuple[Pattern, tuple[LeftOut, ...]]:
    """``pattern`` without the pieces :func:`left_out` names (their seams and measurement links dropped too)."""
    out = left_out(pattern)
    if not out:
        return pattern, out
    gone = {x.piece for x in out}
    return (
        dataclasses.replace(
            pattern,
            pieces=tuple(p for p in pattern.pieces if p.name not in gone),
            seams=tuple(s for s in pattern.seams if s.a.piece not in gone and s.b.piece not in gone),
            measurements=tuple(m for m in pattern.measurements if all(g.piece not in gone for g in m.legs)),
        ),
        out,
    )
