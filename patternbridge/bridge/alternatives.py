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
#: the two halves of a two-piece sleeve add up to the largest sleeve's area within this share
HALVES_TOL_SHARE = 0.15


def copies_cut(piece) -> int:
    """How many copies of the piece are cut: its quantity, else the cutting note.

    The note is ``<count>X <material>`` (``2X FABRIC``, ``1X RIB``) or
    ``<fabric code> X <count>`` (``10 X 1``, ``10X2``: fabric 10, cut once or twice).

    Examples
    --------
    >>> from patternbridge.pattern.model import Piece
    >>> notes = ("2XFABRIC", "10X2", "10 X 1")
    >>> [copies_cut(Piece(name="p", outline=[[0, 0], [1, 0], [0, 1]], annotation=a)) for a in notes]
    [2, 2, 1]
    """
    total = piece.quantity.right + piece.quantity.left
    text = piece.annotation.upper()
    coded = re.match(r"\s*\d+\s*X\s*(\d+)", text)
    note = coded or re.match(r"\s*(\d+)\s*X", text)
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
    """Join two sleeve pieces that are the halves of one sleeve: together about as large as the largest sleeve.

    The upper and under sleeve of a two-piece sleeve add up to a one-piece sleeve
    of the same garment (within ``HALVES_TOL_SHARE`` of its area); either half
    may be over half of it (the T-shirt's back sleeve is 65 % of the one-piece).
    """
    if len(options) < 3:
        return options
    area = [shapes[o[0]].area_share for o in options]
    big = max(area)
    best = None
    for i in range(len(options)):
        for k in range(i + 1, len(options)):
            if big in (area[i], area[k]):
                continue
            miss = abs(area[i] + area[k] - big)
            if miss <= HALVES_TOL_SHARE * big and (best is None or miss < best[0]):
                best = (miss, i, k)
    if best is None:
        return options
    _, i, k = best
    return [o for m, o in enumerate(options) if m not in (i, k)] + [options[i] + options[k]]
