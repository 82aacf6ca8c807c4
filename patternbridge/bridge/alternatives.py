"""Alternative pieces: variants of one another of which a garment uses one.

Two pieces (or piece sets) are alternatives when they have the same role and
would sew to the same partner edges: two sleeves of one role in a garment
whose bodice has one armhole, two neckbands for one neckline, legs of three
lengths. Pieces are grouped by role; a role that a garment needs once (per
side) but that several unrelated-shape pieces claim forms a group, its
largest member first (the default); mirror twins (a left and a right piece
drawn separately) and the two copies of a pair are not alternatives.
"""

from __future__ import annotations

import re
from collections.abc import Iterable

from ..pattern.model import Pattern
from .model import Role, RoleGuess
from .roles import Shape

__all__ = ["choose_garment", "copies_cut"]

#: roles a garment has one kind of (its copies aside); bindings are left out, a neckline is often bound
#: by several strips (the CLO shirt's two front and one back binding)
_SINGLE = (Role.SLEEVE, Role.NECKBAND, Role.COLLAR, Role.LEG, Role.CUFF, Role.COLLAR_STAND)


def copies_cut(piece) -> int:
    """How many copies of the piece are cut: its quantity, else the ``2X FABRIC`` cutting note."""
    total = piece.quantity.right + piece.quantity.left
    note = re.match(r"\s*(\d+)\s*X", piece.annotation.upper())
    return max(total, int(note.group(1)) if note else 0)


def _twin(a: Shape, b: Shape) -> bool:
    return (
        abs(a.area_share - b.area_share) <= 0.01 * max(a.area_share, b.area_share)
        and abs(a.height_cm - b.height_cm) < 0.5
    )


def choose_garment(
    pattern: Pattern,
    roles: dict[str, RoleGuess],
    shapes: dict[str, Shape],
    *,
    pieces: Iterable[str] | None = None,
    exclude: Iterable[str] = (),
) -> tuple[list[tuple[tuple[str, ...], ...]], set[str]]:
    """Groups of alternatives (each a tuple of piece sets, default first) and the chosen pieces."""
    groups: list[tuple[tuple[str, ...], ...]] = []
    for role in _SINGLE:
        names = [n for n in pattern.piece_names if roles[n].role is role]
        options: list[list[str]] = []
        for n in sorted(names, key=lambda n: -shapes[n].area_share):
            twin = next(
                (
                    o
                    for o in options
                    if any(_twin(shapes[n], shapes[m]) for m in o) and copies_cut(pattern.piece(n)) < 2
                ),
                None,
            )
            if twin is not None:
                twin.append(n)
            else:
                options.append([n])
        if role is Role.SLEEVE:
            options = _two_piece_sleeves(options, shapes)
        if len(options) > 1:
            groups.append(tuple(tuple(o) for o in options))
    chosen = set(pattern.piece_names)
    for g in groups:
        for opt in g[1:]:
            chosen -= set(opt)
    if pieces is not None:
        chosen = set(pieces)
    chosen -= set(exclude)
    return groups, chosen


def _two_piece_sleeves(options: list[list[str]], shapes: dict[str, Shape]) -> list[list[str]]:
    """Join the small sleeve pieces that are halves of one sleeve (each under 60 % of the largest)."""
    if len(options) < 3:
        return options
    big = max(shapes[o[0]].area_share for o in options)
    whole = [o for o in options if shapes[o[0]].area_share >= 0.6 * big]
    halves = [n for o in options if shapes[o[0]].area_share < 0.6 * big for n in o]
    return whole + ([halves] if halves else [])
