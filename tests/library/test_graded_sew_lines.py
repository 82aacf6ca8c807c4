"""Sew lines in every graded size are graded the way ``grade`` grades a piece."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from patternbridge.io.dxf_aama import read_dxf
from patternbridge.library import load_garment
from patternbridge.library.seams import graded_sew_lines, sew_line
from patternbridge.pattern.grading import grade

TANK = "WM LOOSE SHAPE TANK.DXF"


def _every_fourth_rule(pattern):
    """The pattern with a rule on every fourth vertex only, as a sparse RUL gives it."""
    pieces = tuple(
        dataclasses.replace(p, rules=tuple(r if i % 4 == 0 else None for i, r in enumerate(p.rules)))
        for p in pattern.pieces
    )
    return dataclasses.replace(pattern, pieces=pieces)


@pytest.mark.shared
def test_points_between_rule_points_follow_the_grading_on_a_real_tank(aama_dir):
    # the import keeps this nest exact (a rule on every vertex); thin its rules out
    pattern = _every_fourth_rule(read_dxf(aama_dir / TANK)[0])
    lines = graded_sew_lines(pattern)
    moved_without_rule = 0
    for k, size in enumerate(pattern.rules.sizes):
        graded = grade(pattern, size)
        for piece, want in zip(pattern.pieces, graded.pieces, strict=True):
            np.testing.assert_allclose(lines[piece.name][k], want.outline, atol=1e-9)
            free = np.array([r is None for r in piece.rules])
            moved = np.linalg.norm(lines[piece.name][k] - piece.outline, axis=1) > 0.05
            moved_without_rule += int(np.sum(free & moved))
    # the real file leaves most curve points without a rule: they must move too
    assert moved_without_rule > 100


def test_library_sew_lines_match_the_graded_sew_lines():
    pattern = load_garment("shirt")
    lines = graded_sew_lines(pattern)
    for k, size in enumerate(pattern.rules.sizes):
        graded = grade(pattern, size)
        for piece, want in zip(pattern.pieces, graded.pieces, strict=True):
            np.testing.assert_allclose(
                lines[piece.name][k], sew_line(want)[0], atol=1e-9
            )
