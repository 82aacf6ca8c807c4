"""The grade reference line (layer 5) written wherever rules are: the pattern's own, or one along +x.

Rules of a piece without a reference line are in the drawing axes, so the
line added for them points along +x: the grain line itself when that does
(what AccuMark writes), otherwise a line of the grain line's length from its
tail, or across the middle of the piece. Reading, a layer-5 line that is
exactly this line carries nothing the writer would not write again, so it is
not kept; a graded round trip leaves the model unchanged.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from ...pattern.model import Line, Pattern, Piece

__all__ = ["drop_implied_references", "implied_reference", "reference_line"]

_SAME_CM = 1e-4  # the writer's 4 decimals of a millimetre


def implied_reference(piece: Piece) -> Line:
    """The +x line written for a graded piece that has no grade reference line."""
    grain = piece.grain_line
    if grain is not None:
        d = grain.points[1] - grain.points[0]
        length = float(np.hypot(*d))
        if length > 0 and abs(d[1]) <= 1e-9 * length and d[0] > 0:
            return Line(points=grain.points)
        if length > 0:
            return Line(points=[grain.points[0], grain.points[0] + [length, 0.0]])
    lo, hi = piece.outline.min(axis=0), piece.outline.max(axis=0)
    mid = 0.5 * (lo + hi)
    half = 0.25 * (hi[0] - lo[0])
    return Line(points=[mid - [half, 0.0], mid + [half, 0.0]])


def reference_line(piece: Piece, graded: bool) -> Line | None:
    """The layer-5 line of a block: the piece's own, or the implied one where rules are written."""
    if piece.grade_reference is not None or not graded:
        return piece.grade_reference
    return implied_reference(piece)


def drop_implied_references(pattern: Pattern) -> Pattern:
    """``pattern`` without grade reference lines that are exactly the implied one (regenerated in every size)."""
    if len(pattern.sizes) < 2:
        return pattern
    pieces = []
    for piece in pattern.pieces:
        ref = piece.grade_reference
        if ref is not None:
            implied = implied_reference(dataclasses.replace(piece, grade_reference=None))
            if np.max(np.abs(implied.points - ref.points)) <= _SAME_CM:
                piece = dataclasses.replace(piece, grade_reference=None)
        pieces.append(piece)
    return dataclasses.replace(pattern, pieces=tuple(pieces))
