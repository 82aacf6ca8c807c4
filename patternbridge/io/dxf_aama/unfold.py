"""Unfolding half pieces: a piece drawn to a mirror (fold) line becomes the whole piece.

The half is reflected about its layer-6 mirror line; vertices on the line are
kept once, every other vertex, notch, internal line and drill hole gets its
mirror image, and each graded point's rule gets a mirrored twin, so every size
of the whole piece is the reflection of the same size of the half.
"""

from __future__ import annotations

import dataclasses
import re
from collections.abc import Callable

import numpy as np

from ...pattern.grading import frame_angle, inward_angles
from ...pattern.model import DrillHole, GradeRuleTable, Pattern, Piece, Polyline
from ...report import Report

__all__ = ["unfold_pattern"]


def _reflect(points: np.ndarray, line: np.ndarray) -> np.ndarray:
    a = line[0]
    u = line[1] - line[0]
    u = u / np.hypot(*u)
    d = points - a
    along = d @ u
    return a + 2 * along[:, None] * u - d


def _unfold(piece: Piece, table: GradeRuleTable, report: Report, where: str,
            fresh: Callable[[], str]) -> tuple[Piece, dict[str, np.ndarray]]:
    """Mirror a half piece about its mirror line into the whole piece.

    Returns the whole piece and the new rules (mirrored deltas) to add.
    """
    line = piece.mirror_line.points
    u = line[1] - line[0]
    if np.hypot(*u) == 0:
        report.add("mirror-line-degenerate", "mirror line has zero length; piece not unfolded", where)
        return piece, {}
    outline = piece.outline
    n = len(outline)
    un = u / np.hypot(*u)
    dist = np.abs((outline - line[0]) @ np.array([-un[1], un[0]]))
    tol = max(1e-3, 1e-4 * float(np.ptp(outline, axis=0).max()))
    on = dist <= tol
    if on.sum() < 2 or on.all():
        report.add("mirror-line-off-boundary", "mirror line does not lie on the boundary; piece not unfolded",
                   where)
        return piece, {}
    # the fold is the run of consecutive on-line vertices; the half runs from its end round to its start
    idx = np.flatnonzero(on)
    # find a vertex on the line whose successor is off the line: start of the half
    starts = [i for i in idx if not on[(i + 1) % n]]
    ends = [i for i in idx if not on[(i - 1) % n]]
    if len(starts) != 1 or len(ends) != 1:
        report.add("mirror-line-ambiguous", "boundary touches the mirror line more than once; not unfolded",
                   where)
        return piece, {}
    s, e = starts[0], ends[0]
    half = [(s + k) % n for k in range((e - s) % n + 1)]  # s ... e, CCW, off the line in between
    inner = half[1:-1]
    mirrored_pts = _reflect(outline[inner[::-1]], line)
    new_outline = np.vstack([outline[half], mirrored_pts])
    new_index_of_old = {old: k for k, old in enumerate(half)}
    mirror_index_of_old = {old: len(half) + k for k, old in enumerate(inner[::-1])}
    theta = frame_angle(piece)
    rot = np.array([[np.cos(theta), -np.sin(theta)], [np.sin(theta), np.cos(theta)]])

    def reflect_delta(d: np.ndarray) -> np.ndarray:
        world = d @ rot.T
        along = world @ un
        refl = 2 * along[:, None] * un - world
        return refl @ rot

    new_rules: dict[str, np.ndarray] = {}
    mirrored_rule: dict[str, str] = {}

    def mirror_rule(r: str | None) -> str | None:
        if r is None or r not in table.deltas:
            return None
        if r not in mirrored_rule:
            rid = fresh()
            mirrored_rule[r] = rid
            new_rules[rid] = reflect_delta(np.asarray(table.deltas[r]))
        return mirrored_rule[r]

    kinds = [piece.kinds[i] for i in half] + [piece.kinds[i] for i in inner[::-1]]
    rules = [piece.rules[i] for i in half] + [mirror_rule(piece.rules[i]) for i in inner[::-1]]
    notches = []
    for notch in piece.notches:
        if notch.vertex in new_index_of_old:
            notches.append(dataclasses.replace(notch, vertex=new_index_of_old[notch.vertex]))
        if notch.vertex in mirror_index_of_old:
            notches.append(dataclasses.replace(notch, vertex=mirror_index_of_old[notch.vertex],
                                               rule=mirror_rule(notch.rule)))
    angles = inward_angles(new_outline, [nt.vertex for nt in notches])
    notches = [dataclasses.replace(nt, angle=float(a)) for nt, a in zip(notches, angles, strict=True)]
    internal = list(piece.internal_lines)
    for pl in piece.internal_lines:
        on_fold = np.all(np.abs((pl.points - line[0]) @ np.array([-un[1], un[0]])) <= tol)
        if pl.label == "NM" or on_fold:
            continue
        internal.append(Polyline(points=_reflect(pl.points, line), kinds=pl.kinds,
                                 rules=[mirror_rule(r) for r in pl.rules], closed=pl.closed, label=pl.label))
    holes = list(piece.drill_holes)
    for h in piece.drill_holes:
        p = _reflect(h.position[None], line)[0]
        if np.hypot(*(p - h.position)) > tol:
            holes.append(DrillHole(position=p, diameter_cm=h.diameter_cm, rule=mirror_rule(h.rule), label=h.label))
    whole = dataclasses.replace(
        piece, outline=new_outline, kinds=kinds, rules=rules, notches=tuple(notches),
        internal_lines=tuple(internal), drill_holes=tuple(holes), mirror_line=None, marks={}, landmarks={},
        extra_text={**dict(piece.extra_text), "UNFOLDED FROM MIRROR LINE": "Y"},
    )
    report.add("piece-unfolded", f"half piece mirrored about its mirror line ({n} -> {len(new_outline)} "
               "vertices)", where, fixed=True)
    return whole, new_rules


def unfold_pattern(pattern: Pattern, report: Report) -> Pattern:
    ints = [int(r) for r in pattern.rules.deltas if re.fullmatch(r"-?\d+", r)]
    counter = [max(ints, default=0) + 1]

    def fresh() -> str:
        rid = str(counter[0])
        counter[0] += 1
        return rid

    if all(piece.mirror_line is None for piece in pattern.pieces):
        report.add("nothing-to-unfold", "unfold asked for, but no piece has a mirror line (layer 6); "
                   "pieces kept as drawn", pattern.provenance.source_file, severity="info")
        return pattern
    pieces = []
    extra: dict[str, np.ndarray] = {}
    for piece in pattern.pieces:
        if piece.mirror_line is None:
            pieces.append(piece)
            continue
        whole, new_rules = _unfold(piece, pattern.rules, report, f"{pattern.provenance.source_file}: piece "
                                   f"{piece.name}", fresh)
        pieces.append(whole)
        extra.update(new_rules)
    if not extra:
        return dataclasses.replace(pattern, pieces=tuple(pieces))
    table = dataclasses.replace(pattern.rules, deltas={**dict(pattern.rules.deltas), **extra})
    return dataclasses.replace(pattern, pieces=tuple(pieces), rules=table)
