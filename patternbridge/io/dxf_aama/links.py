"""AccuMark's notch links: ATTDEF ``Link:<layer>`` records that place each notch in every size.

AccuMark ASTM writes, in every block of a piece, one ATTDEF per linked notch:
10/20 the boundary vertex before the notch, 11/21 where the notch sits in that
size. In a graded nest a notch need not follow a boundary vertex (it keeps its
distance along the edge), so the reader turns the positions into the notch's
own grade rule when they move differently from its vertex, and the writer
writes each size's ATTDEF at the notch graded by that rule. Grading inside
PatternBridge keeps notches on their vertex; the rule carries the CAD's
placement back out.
"""

from __future__ import annotations

import dataclasses
import re

import numpy as np

from ...pattern.grading import frame_angle, graded_outlines
from ...pattern.model import Pattern, Piece
from ...report import Report

__all__ = ["LINK_MATCH_CM", "link_rules", "notch_positions"]

LINK_MATCH_CM = 1e-3
"""A sample-size link sits on its notch within this (0.01 mm)."""


def _rotation(piece: Piece) -> np.ndarray:
    theta = frame_angle(piece)
    return np.array([[np.cos(theta), -np.sin(theta)], [np.sin(theta), np.cos(theta)]])


def link_rules(pattern: Pattern, links: dict[str, dict[str, np.ndarray]], report: Report) -> Pattern:
    """Notch rules of a pattern graded from a nest: its vertex's, or its own where a link places it elsewhere.

    ``links`` : piece name -> size -> ``(k, 2)`` cm, the 11/21 points of the
    piece's ``Link:`` ATTDEFs in file order (the same order in every size).
    """
    table = pattern.rules
    if len(table.sizes) < 2:
        return pattern
    # rules derived from a nest move every notch with its vertex: the vertex's rule is the notch's
    pattern = dataclasses.replace(pattern, pieces=tuple(
        dataclasses.replace(p, notches=tuple(dataclasses.replace(n, rule=p.rules[n.vertex]) for n in p.notches))
        for p in pattern.pieces))
    if not any(len(a) for sizes in links.values() for a in sizes.values()):
        return pattern
    graded = graded_outlines(pattern)
    ints = [int(r) for r in table.deltas if re.fullmatch(r"-?\d+", r)]
    next_id = max(ints, default=0) + 1
    deltas = dict(table.deltas)
    pieces, moved = [], 0
    for piece in pattern.pieces:
        by_size = links.get(piece.name) or {}
        sample = by_size.get(pattern.sample_size)
        if sample is None or not len(sample) or any(len(by_size.get(s, ())) != len(sample) for s in table.sizes):
            pieces.append(piece)
            continue
        at = piece.outline[[n.vertex for n in piece.notches]].reshape(-1, 2)
        notches = list(piece.notches)
        rot = _rotation(piece)
        for k, point in enumerate(sample):
            d = np.hypot(*(at - point).T) if len(at) else np.array([np.inf])
            j = int(np.argmin(d))
            if d[j] > LINK_MATCH_CM:
                continue
            world = np.array([by_size[s][k] - point for s in table.sizes])
            vertex = np.array([graded[s][piece.name][notches[j].vertex] - at[j] for s in table.sizes])
            if np.max(np.abs(world - vertex)) <= LINK_MATCH_CM:
                continue  # the notch follows its vertex: nothing to keep
            rid = str(next_id)
            next_id += 1
            deltas[rid] = world @ rot
            notches[j] = dataclasses.replace(notches[j], rule=rid)
            moved += 1
        pieces.append(dataclasses.replace(piece, notches=tuple(notches)))
    if not moved:
        return pattern
    report.add("notch-links-kept", f"{moved} notches placed by ATTDEF links away from their vertex in other "
               "sizes; their positions are kept as the notches' own rules", pattern.provenance.source_file)
    return dataclasses.replace(pattern, pieces=tuple(pieces), rules=dataclasses.replace(table, deltas=deltas))


def notch_positions(sample: Piece, graded: Piece, rules, size: str) -> np.ndarray:
    """``(n_notches, 2)`` cm: each notch of ``graded`` (a size of ``sample``) where its link puts it.

    A notch with a rule of its own (not its vertex's) sits at its sample
    position moved by that rule; the others on their graded vertex.
    """
    out = graded.outline[[n.vertex for n in graded.notches]].reshape(-1, 2).copy()
    if size not in rules.sizes:
        return out
    rot = _rotation(sample)
    k = rules.size_index(size)
    for j, notch in enumerate(sample.notches):
        if notch.rule is not None and notch.rule != sample.rules[notch.vertex] and notch.rule in rules.deltas:
            out[j] = sample.outline[notch.vertex] + rot @ rules.deltas[notch.rule][k]
    return out
