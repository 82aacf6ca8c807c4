"""The pattern stood upright for draping: every piece turned as its sidecar's ``orientation`` records.

The sidecar keeps the designer's own drawing (an AccuMark file draws its
pieces sideways, grain along x), so the graded DXF sent back keeps their
layout; the assembler lays a piece with pattern +y up the body. Before
draping, each piece is turned by ``turn_deg`` and moved by ``offset_cm``
(outline, sew lines, internal lines, cut-outs, grain, mirror and reference
lines, drill holes, notch directions). A turn keeps the vertex order, so
marks, seams and the counter-clockwise outline stay valid.
"""

from __future__ import annotations

import dataclasses
import os

import numpy as np

from ..io.json_file import read_json
from ..pattern.model import Pattern, Piece

__all__ = ["turn_piece", "upright_pattern"]


def turn_piece(piece: Piece, turn_rad: float, offset_cm: np.ndarray) -> Piece:
    """``piece`` turned ``turn_rad`` counter-clockwise about the origin, then moved by ``offset_cm`` (2,)."""
    c, s = np.cos(turn_rad), np.sin(turn_rad)
    rot, off = np.array([[c, -s], [s, c]]), np.asarray(offset_cm, dtype=np.float64)

    def move(points: np.ndarray) -> np.ndarray:
        return np.asarray(points, dtype=np.float64) @ rot.T + off

    def line(x):
        return None if x is None else dataclasses.replace(x, points=move(x.points))

    return dataclasses.replace(
        piece,
        outline=move(piece.outline),
        sew_lines=tuple(line(x) for x in piece.sew_lines),
        internal_lines=tuple(line(x) for x in piece.internal_lines),
        cutouts=tuple(line(x) for x in piece.cutouts),
        grain_line=line(piece.grain_line),
        grade_reference=line(piece.grade_reference),
        mirror_line=line(piece.mirror_line),
        drill_holes=tuple(dataclasses.replace(h, position=move(h.position)) for h in piece.drill_holes),
        notches=tuple(dataclasses.replace(n, angle=n.angle + turn_rad) for n in piece.notches),
    )


def upright_pattern(pattern: Pattern, sidecar: str | os.PathLike) -> Pattern:
    """``pattern`` with every piece the sidecar gives an ``orientation`` turned upright (the others as they are)."""
    data = read_json(
        sidecar, hint="give a sidecar written by 'patternbridge seams infer' or 'library export'", what="sidecar file"
    )
    turns = {e["name"]: e["orientation"] for e in data.get("pieces", []) if e.get("orientation")}
    pieces = tuple(
        turn_piece(p, np.radians(turns[p.name]["turn_deg"]), np.array(turns[p.name]["offset_cm"]))
        if p.name in turns
        else p
        for p in pattern.pieces
    )
    return dataclasses.replace(pattern, pieces=pieces)
