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

from ...pattern.grading import frame_angle, graded_outlines, inward_angles
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


class _MirrorRules:
    """Rules of mirror images: each size's image is the reflection about that size's own fold.

    The fold of a size is the line through the graded positions of the half's
    two fold-end vertices, so a fold that moves, tilts or turns between sizes
    (a nest may draw a size flipped) is followed exactly. Images of points
    that share a rule share a mirrored rule when their motions agree.
    """

    def __init__(self, table: GradeRuleTable, rot: np.ndarray, folds: np.ndarray, fresh: Callable[[], str]):
        self.table, self.rot, self.folds, self.fresh = table, rot, folds, fresh  # folds: (n_sizes, 2, 2)
        self.new: dict[str, np.ndarray] = {}
        self._made: dict[str, list[tuple[np.ndarray, str]]] = {}

    def __call__(self, rule: str | None, point: np.ndarray) -> str | None:
        if rule is None or rule not in self.table.deltas or len(self.folds) == 0:
            return None
        moved = point + np.asarray(self.table.deltas[rule]) @ self.rot.T  # (n_sizes, 2) world
        images = np.array([_reflect(m[None], fold)[0] for m, fold in zip(moved, self.folds, strict=True)])
        k = int(np.argmin(np.linalg.norm(moved - point, axis=1)))  # the sample size (zero motion)
        delta = (images - images[k]) @ self.rot
        for known, rid in self._made.get(rule, []):
            if np.allclose(known, delta, atol=1e-7):
                return rid
        rid = self.fresh()
        self._made.setdefault(rule, []).append((delta, rid))
        self.new[rid] = delta
        return rid


def _half(piece: Piece, report: Report, where: str) -> tuple[list[int], float] | None:
    """Indices of the half from one fold end round to the other (CCW), and the on-line tolerance."""
    line = piece.mirror_line.points
    u = line[1] - line[0]
    if np.hypot(*u) == 0:
        report.add("mirror-line-degenerate", "mirror line has zero length; piece not unfolded", where)
        return None
    outline = piece.outline
    n = len(outline)
    un = u / np.hypot(*u)
    dist = np.abs((outline - line[0]) @ np.array([-un[1], un[0]]))
    tol = max(1e-3, 1e-4 * float(np.ptp(outline, axis=0).max()))
    on = dist <= tol
    if on.sum() < 2 or on.all():
        report.add("mirror-line-off-boundary", "mirror line does not lie on the boundary; piece not unfolded",
                   where)
        return None
    idx = np.flatnonzero(on)
    starts = [i for i in idx if not on[(i + 1) % n]]  # on the line, successor off it
    ends = [i for i in idx if not on[(i - 1) % n]]
    if len(starts) != 1 or len(ends) != 1:
        report.add("mirror-line-ambiguous", "boundary touches the mirror line more than once; not unfolded",
                   where)
        return None
    s, e = starts[0], ends[0]
    return [(s + k) % n for k in range((e - s) % n + 1)], tol


def _unfold(piece: Piece, table: GradeRuleTable, graded: np.ndarray, report: Report, where: str,
            fresh: Callable[[], str]) -> tuple[Piece, dict[str, np.ndarray]]:
    """Mirror a half piece about its mirror line into the whole piece.

    ``graded`` holds the half's boundary in every size of ``table``
    (``(n_sizes, n, 2)``, cm). Returns the whole piece and the new rules
    (each size's image reflected about that size's fold) to add.
    """
    found = _half(piece, report, where)
    if found is None:
        return piece, {}
    half, tol = found
    line, outline, n = piece.mirror_line.points, piece.outline, len(piece.outline)
    inner = half[1:-1]
    new_outline = np.vstack([outline[half], _reflect(outline[inner[::-1]], line)])
    new_index_of_old = {old: k for k, old in enumerate(half)}
    mirror_index_of_old = {old: len(half) + k for k, old in enumerate(inner[::-1])}
    theta = frame_angle(piece)
    rot = np.array([[np.cos(theta), -np.sin(theta)], [np.sin(theta), np.cos(theta)]])
    mirror_rule = _MirrorRules(table, rot, graded[:, [half[0], half[-1]]], fresh)
    kinds = [piece.kinds[i] for i in half] + [piece.kinds[i] for i in inner[::-1]]
    rules = [piece.rules[i] for i in half] + [mirror_rule(piece.rules[i], outline[i]) for i in inner[::-1]]
    notches = []
    for notch in piece.notches:
        if notch.vertex in new_index_of_old:
            notches.append(dataclasses.replace(notch, vertex=new_index_of_old[notch.vertex]))
        if notch.vertex in mirror_index_of_old:
            notches.append(dataclasses.replace(notch, vertex=mirror_index_of_old[notch.vertex],
                                               rule=mirror_rule(notch.rule, outline[notch.vertex])))
    angles = inward_angles(new_outline, [nt.vertex for nt in notches])
    notches = [dataclasses.replace(nt, angle=float(a)) for nt, a in zip(notches, angles, strict=True)]
    whole = dataclasses.replace(
        piece, outline=new_outline, kinds=kinds, rules=rules, notches=tuple(notches),
        **_mirror_inside(piece, line, tol, mirror_rule), mirror_line=None, marks={}, landmarks={},
        extra_text={**dict(piece.extra_text), "UNFOLDED FROM MIRROR LINE": "Y"},
    )
    report.add("piece-unfolded", f"half piece mirrored about its mirror line ({n} -> {len(new_outline)} "
               "vertices)", where, fixed=True)
    return whole, mirror_rule.new


def _mirror_inside(piece: Piece, line: np.ndarray, tol: float, mirror_rule: _MirrorRules) -> dict:
    """Internal lines (except ``NM`` and those on the fold) and drill holes with their mirror images."""
    u = (line[1] - line[0]) / np.hypot(*(line[1] - line[0]))
    normal = np.array([-u[1], u[0]])
    internal = list(piece.internal_lines)
    for pl in piece.internal_lines:
        if pl.label == "NM" or np.all(np.abs((pl.points - line[0]) @ normal) <= tol):
            continue
        rules = [mirror_rule(r, q) for r, q in zip(pl.rules, pl.points, strict=True)] if pl.rules else pl.rules
        internal.append(Polyline(points=_reflect(pl.points, line), kinds=pl.kinds, rules=rules,
                                 closed=pl.closed, label=pl.label))
    holes = list(piece.drill_holes)
    for h in piece.drill_holes:
        p = _reflect(h.position[None], line)[0]
        if np.hypot(*(p - h.position)) > tol:
            holes.append(DrillHole(position=p, diameter_cm=h.diameter_cm, rule=mirror_rule(h.rule, h.position),
                                   label=h.label))
    return {"internal_lines": tuple(internal), "drill_holes": tuple(holes)}


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
    graded = graded_outlines(pattern) if pattern.rules.sizes else {}
    for piece in pattern.pieces:
        if piece.mirror_line is None:
            pieces.append(piece)
            continue
        stack = np.array([graded[s][piece.name] for s in pattern.rules.sizes]).reshape(-1, len(piece.outline), 2)
        whole, new_rules = _unfold(piece, pattern.rules, stack, report, f"{pattern.provenance.source_file}: piece "
                                   f"{piece.name}", fresh)
        pieces.append(whole)
        extra.update(new_rules)
    if not extra:
        return dataclasses.replace(pattern, pieces=tuple(pieces))
    table = dataclasses.replace(pattern.rules, deltas={**dict(pattern.rules.deltas), **extra})
    return dataclasses.replace(pattern, pieces=tuple(pieces), rules=table)
