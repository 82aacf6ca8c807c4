"""Grading by rules: analytic cases, arc-length following, frames, nests and added sizes."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from patternbridge.pattern.geometry import area
from patternbridge.pattern.grading import (
    add_size,
    derive_rules,
    frame_angle,
    grade,
    grade_piece,
    graded_outlines,
    inward_angles,
    rebase_rules,
    rules_from_nest,
    single_size,
)
from patternbridge.pattern.model import (
    DrillHole,
    GradeRuleTable,
    Line,
    Notch,
    Pattern,
    Piece,
    Polyline,
    VertexKind,
)

SIZES = ("S", "M", "L", "XL")


def _rect_pattern(theta: float = 0.0) -> Pattern:
    """A 20 x 10 rectangle whose corners carry rules that widen it by 2 cm per size.

    Mid-edge vertices carry no rule; a notch sits on vertex 1 (bottom middle).
    ``theta`` rotates the whole piece and its grade reference line.
    """
    pts = np.array([[0, 0], [10, 0], [20, 0], [20, 10], [10, 10], [0, 10]], float)
    rot = np.array([[np.cos(theta), -np.sin(theta)], [np.sin(theta), np.cos(theta)]])
    pts = pts @ rot.T
    ref = np.array([[2, 5], [18, 5]], float) @ rot.T
    k = np.arange(len(SIZES)) - 1  # M is the sample
    grow = lambda sx, sy: np.stack([sx * k, sy * k], axis=1)  # noqa: E731
    table = GradeRuleTable(
        name="T", sizes=SIZES, sample_size="M",
        deltas={"1": grow(-1, -0.5), "2": grow(1, -0.5), "3": grow(1, 0.5), "4": grow(-1, 0.5)},
    )
    piece = Piece(
        name="R", outline=pts,
        kinds=["turn", "plain", "turn", "turn", "plain", "turn"],
        rules=["1", None, "2", "3", None, "4"],
        notches=(Notch(vertex=1, depth_cm=0.5, angle=0.0),),
        grade_reference=Line(points=ref),
        grain_line=Line(points=ref),
        internal_lines=(Polyline(points=np.array([[5, 5], [15, 5]], float) @ rot.T),),
        drill_holes=(DrillHole(position=np.array([10.0, 5.0]) @ rot.T, rule="3"),),
    )
    return Pattern(style="rect", pieces=(piece,), sample_size="M", sizes=SIZES, rules=table)


def test_rule_points_move_by_their_rule_and_areas_are_analytic():
    pat = _rect_pattern()
    for k, size in enumerate(SIZES):
        piece = grade_piece(pat.pieces[0], pat.rules, size)
        w, h = 20 + 2 * (k - 1), 10 + 1 * (k - 1)
        assert float(area(piece.outline)) == pytest.approx(w * h)
        np.testing.assert_allclose(piece.outline[0], [-(k - 1), -0.5 * (k - 1)], atol=1e-12)
        # the unruled mid-edge vertex stays halfway along its edge (arc-length following)
        np.testing.assert_allclose(piece.outline[1], (piece.outline[0] + piece.outline[2]) / 2, atol=1e-12)
        assert piece.size == size


def test_rules_are_in_the_grade_reference_frame():
    theta = np.deg2rad(90.0)
    pat = _rect_pattern(theta)
    assert frame_angle(pat.pieces[0]) == pytest.approx(theta)
    big = grade(pat, "XL").pieces[0]
    # in the piece's own frame the rectangle grew to 24 x 12, whatever the drawing rotation
    rot_back = np.array([[np.cos(-theta), -np.sin(-theta)], [np.sin(-theta), np.cos(-theta)]])
    local = big.outline @ rot_back.T
    np.testing.assert_allclose(local.max(0) - local.min(0), [24, 12], atol=1e-9)


def test_grade_rebases_so_grading_twice_lands_where_grading_once_does():
    pat = _rect_pattern()
    via_l = grade(grade(pat, "L"), "S")
    direct = grade(pat, "S")
    assert via_l.sample_size == "S"
    np.testing.assert_allclose(via_l.pieces[0].outline, direct.pieces[0].outline, atol=1e-12)
    np.testing.assert_array_equal(rebase_rules(pat.rules, "L").deltas["1"][2], [0, 0])
    assert grade(pat, "M").pieces[0] == dataclasses.replace(pat.pieces[0], size="M")


def test_elements_follow_the_boundary_and_notches_keep_their_vertex():
    pat = _rect_pattern()
    piece = grade(pat, "XL").pieces[0]
    # drill hole carries rule 3 (top right corner): moves by (2, 1)
    np.testing.assert_allclose(piece.drill_holes[0].position, [12, 6])
    # the unruled internal line moves with the nearest boundary vertices
    assert piece.internal_lines[0].points.shape == (2, 2)
    assert piece.notches[0].vertex == 1
    assert piece.notches[0].angle == pytest.approx(np.pi / 2)  # into the piece from the bottom edge
    # the grain / grade reference line has no rules: its ends follow the nearest boundary vertex
    assert np.all(np.isfinite(piece.grain_line.points))


def test_graded_outlines_match_grade():
    pat = _rect_pattern()
    nest = graded_outlines(pat)
    assert list(nest) == list(SIZES)
    for size in SIZES:
        np.testing.assert_allclose(nest[size]["R"], grade(pat, size).pieces[0].outline)
    with pytest.raises(KeyError, match="not in the size list"):
        grade(pat, "XXL")


def test_derive_rules_from_a_nest_reproduces_every_size():
    pat = _rect_pattern(np.deg2rad(30))
    nest = graded_outlines(pat)
    bare = dataclasses.replace(pat, rules=GradeRuleTable(), sizes=())
    table = derive_rules(bare, nest)
    assert table.sizes == SIZES and table.sample_size == "M"
    for rid in ("1", "2", "3", "4"):
        np.testing.assert_allclose(table.deltas[rid], pat.rules.deltas[rid], atol=1e-12)
    back = rules_from_nest(bare, nest)
    for size in SIZES:
        np.testing.assert_allclose(grade(back, size).pieces[0].outline, nest[size]["R"], atol=1e-9)


def test_shared_rule_id_that_moves_differently_is_split():
    pat = _rect_pattern()
    piece = dataclasses.replace(pat.pieces[0], rules=["1", None, "1", "1", None, "1"])
    bare = Pattern(style="x", pieces=(piece,), sample_size="M")
    back = rules_from_nest(bare, graded_outlines(pat))
    ids = [r for r in back.pieces[0].rules if r is not None]
    assert ids[0] == "1" and len(set(ids)) == 4
    for size in SIZES:
        np.testing.assert_allclose(grade(back, size).pieces[0].outline, grade(pat, size).pieces[0].outline,
                                   atol=1e-9)


def test_piece_without_rule_points_gets_rules_on_turn_points():
    pat = _rect_pattern()
    piece = dataclasses.replace(pat.pieces[0], rules=None)
    back = rules_from_nest(Pattern(style="x", pieces=(piece,), sample_size="M"), graded_outlines(pat))
    turns = [k == VertexKind.TURN for k in back.pieces[0].kinds]
    assert [r is not None for r in back.pieces[0].rules] == turns


def test_nest_with_wrong_vertex_count_is_rejected():
    pat = _rect_pattern()
    nest = graded_outlines(pat)
    nest["L"]["R"] = nest["L"]["R"][:-1]
    with pytest.raises(ValueError, match="vertices"):
        derive_rules(pat, nest)
    del nest["L"]["R"]
    with pytest.raises(ValueError, match="missing in size"):
        derive_rules(pat, nest)


def test_add_size_reproduces_the_new_shape_and_keeps_the_old_sizes():
    pat = _rect_pattern(np.deg2rad(15))
    before = graded_outlines(pat)
    rng = np.random.default_rng(7)
    free = pat.pieces[0].outline + rng.normal(0, 0.8, size=pat.pieces[0].outline.shape)
    out = add_size(pat, "HERO", {"R": free}, position=2)
    assert out.sizes == ("S", "M", "HERO", "L", "XL") and out.rules.sizes == out.sizes
    assert all(r is not None for r in out.pieces[0].rules)
    np.testing.assert_allclose(grade(out, "HERO").pieces[0].outline, free, atol=1e-9)
    for size in SIZES:
        np.testing.assert_allclose(grade(out, size).pieces[0].outline, before[size]["R"], atol=1e-9)
    for d in out.rules.deltas.values():
        assert d.shape == (5, 2)
        np.testing.assert_array_equal(d[1], [0, 0])  # sample column stays zero


def test_add_size_errors():
    pat = _rect_pattern()
    with pytest.raises(ValueError, match="already in the size list"):
        add_size(pat, "L", {"R": pat.pieces[0].outline})
    with pytest.raises(ValueError, match="no outline for pieces"):
        add_size(pat, "N", {})
    with pytest.raises(ValueError, match="vertices"):
        add_size(pat, "N", {"R": pat.pieces[0].outline[:-1]})
    with pytest.raises(ValueError, match="position"):
        add_size(pat, "N", {"R": pat.pieces[0].outline}, position=9)


def test_add_size_on_a_pattern_without_rules():
    pat = _rect_pattern()
    bare = dataclasses.replace(pat, rules=GradeRuleTable(), sizes=("M",))
    out = add_size(bare, "HERO", {"R": pat.pieces[0].outline * 1.1})
    assert out.sizes == ("M", "HERO")
    np.testing.assert_allclose(grade(out, "HERO").pieces[0].outline, pat.pieces[0].outline * 1.1, atol=1e-9)
    np.testing.assert_allclose(grade(out, "M").pieces[0].outline, pat.pieces[0].outline)


def test_single_size_keeps_geometry_and_drops_every_rule():
    from patternbridge.pattern.json import pattern_from_dict, pattern_to_dict
    from patternbridge.testing import example_pattern

    pat = example_pattern()
    assert any(r is not None for p in pat.pieces for r in (p.rules or ()))
    one = single_size(pat, "HERO")
    assert one.sizes == ("HERO",) and one.sample_size == "HERO" and not one.rules.deltas
    for before, after in zip(pat.pieces, one.pieces, strict=True):
        assert after.size == "HERO" and not any(after.rules or ())
        np.testing.assert_array_equal(after.outline, before.outline)
        assert [n.vertex for n in after.notches] == [n.vertex for n in before.notches]
        assert all(n.rule is None for n in after.notches)
        assert all(h.rule is None for h in after.drill_holes)
        for pl in (*after.internal_lines, *after.cutouts, *after.sew_lines):
            assert not any(pl.rules or ())
        for line in (after.grain_line, after.grade_reference, after.mirror_line):
            assert line is None or not any(line.rules)
    # still a valid canonical pattern: it round trips through JSON unchanged
    assert pattern_to_dict(pattern_from_dict(pattern_to_dict(one))) == pattern_to_dict(one)
    assert grade(one, "HERO").pieces[0].outline.shape == pat.pieces[0].outline.shape


def test_inward_angles_on_a_square_and_with_repeated_vertices():
    sq = np.array([[0, 0], [2, 0], [2, 0], [2, 2], [0, 2]], float)
    ang = inward_angles(sq, [0, 1, 3, 4])
    np.testing.assert_allclose(ang, np.deg2rad([45, 135, -135, -45]))
