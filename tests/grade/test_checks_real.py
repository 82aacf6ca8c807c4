"""Design checks on real tailor's files: a turned piece and a moved girth share are caught; the grader makes neither.

``WM LOOSE SHAPE TANK`` (a front and a back cut on the fold, chest taken across
both), ``GLX0926S16`` (a tank with neck and armhole bindings) and
``GMH1004F15-2`` (a T-shirt, chest and neck over front and back) graded to
``D_cartoon_child``, whose proportions are furthest from the files' sample
size: with nothing holding the back's fold (drawn 0.06° off the axis) the
final step turned it by 10°; the least-squares repair turned the tank's
front and back off their folds and sheared its bindings; the T-shirt's
neck went from a 0.59 / 0.41 front / back split to 0.54 / 0.46.
"""

from __future__ import annotations

import numpy as np
import pytest

from patternbridge.grade.checks import MAX_SHARE_MOVE, MAX_TURN_DEG, design_checks, piece_turn, share_move
from patternbridge.grade.grid import build_grid, pairs_with_outline, reference_line
from patternbridge.grade.objectives import balanced_links, objective_data, piece_axes_turn
from patternbridge.grade.refine import straight_edges
from patternbridge.grade.run import axis_scaling, fit_pattern

pytestmark = pytest.mark.shared

TANK = "WM LOOSE SHAPE TANK.DXF"


@pytest.fixture(scope="module")
def child(characters_dir):
    """D_cartoon_child's measurements (cm)."""
    from patternbridge.workflow import load_subject

    subject, _ = load_subject(characters_dir / "D_cartoon_child.obj")
    return subject.measurements.values_cm()


def _pattern(aama_dir, name, tmp_path_factory):
    from patternbridge.bridge.fit_input import pattern_for_fit

    return pattern_for_fit(aama_dir / name, tmp_path_factory.mktemp("bridge")).pattern


@pytest.fixture(scope="module")
def tank(aama_dir, child, tmp_path_factory):
    """The loose tank's grid and objective data, and its proportional scaling to the child."""
    grid = build_grid(_pattern(aama_dir, TANK, tmp_path_factory), max_lines=6, max_cell_frac=0.2)
    data = objective_data(grid, child)
    return grid, data, axis_scaling(grid, data)


def _turned(grid, x, k, deg):
    """``x`` with piece ``k``'s controls turned by ``deg`` about its centre."""
    out = x.copy()
    sl = slice(grid.var_offsets[k], grid.var_offsets[k + 1])
    c = out[sl].reshape(-1, 2)
    centre = 0.5 * (c.min(axis=0) + c.max(axis=0))
    t = np.radians(deg)
    rot = np.array([[np.cos(t), -np.sin(t)], [np.sin(t), np.cos(t)]])
    out[sl] = ((c - centre) @ rot.T + centre).ravel()
    return out


def _widened(grid, x, k, factor):
    """``x`` with piece ``k`` scaled by ``factor`` about its centre (the AccuMark file draws it sideways)."""
    out = x.copy()
    sl = slice(grid.var_offsets[k], grid.var_offsets[k + 1])
    c = out[sl].reshape(-1, 2)
    centre = 0.5 * (c.min(axis=0) + c.max(axis=0))
    out[sl] = (centre + factor * (c - centre)).ravel()
    return out


def test_turning_a_piece_is_measured_and_caught(tank):
    grid, data, x = tank
    names = tuple(g.name for g in grid.pieces)
    ref = grid.outlines(x[None])[0]
    assert design_checks(data, ref, ref, piece_names=names) == ()
    turned = grid.outlines(_turned(grid, x, 1, 5.0)[None])
    turn = np.degrees(piece_turn(data, turned)[0] - piece_turn(data, ref[None])[0])
    np.testing.assert_allclose(turn, [0.0, 5.0], atol=1e-9)
    found = design_checks(data, turned[0], ref, piece_names=names)
    assert [(f.code, f.where) for f in found if f.code == "piece-turned"] == [("piece-turned", names[1])]
    # a turn below the limit is no finding
    slight = grid.outlines(_turned(grid, x, 1, 0.5 * MAX_TURN_DEG)[None])[0]
    assert not [f for f in design_checks(data, slight, ref, piece_names=names) if f.code == "piece-turned"]


def test_moving_the_chest_from_back_to_front_is_caught(tank):
    grid, data, _ = tank
    names = tuple(g.name for g in grid.pieces)
    chest = data.link_ids.index("chest_girth")
    assert balanced_links(data)[chest]
    # front and back are equal halves of the chest: growing the front by 10 % and
    # shrinking the back by 10 % moves each share by 0.05 (0.55 / 0.45)
    both = _widened(grid, _widened(grid, grid.x0, 0, 1.1), 1, 0.9)
    move = share_move(data, grid.outlines(both[None]))[0]
    assert move[chest] == pytest.approx(0.05, abs=0.002)
    assert move[chest] > MAX_SHARE_MOVE
    found = design_checks(data, grid.outlines(both[None])[0], grid.outlines(grid.x0[None])[0], piece_names=names)
    assert ("share-moved", "chest_girth") in {(f.code, f.where) for f in found}
    # growing both alike keeps the split
    alike = _widened(grid, _widened(grid, grid.x0, 0, 1.1), 1, 1.1)
    assert share_move(data, grid.outlines(alike[None]))[0][chest] == pytest.approx(0.0, abs=1e-9)


def test_a_fold_drawn_off_the_axis_is_a_straight_edge(tank):
    grid = tank[0]
    back = grid.pieces[1]
    pts = back.outline_weights @ back.control
    edge = pts[1] - pts[0]
    assert np.linalg.norm(edge) > 60.0 and 0.0 < abs(np.degrees(np.arctan2(edge[1], edge[0]))) < 0.5
    held = [e for e in straight_edges(grid) if e.piece == back.name and not e.cut]
    assert any(set(e.points.tolist()) == {0, 1} for e in held)
    assert all(abs(np.hypot(*e.direction) - 1.0) < 1e-12 for e in held)


@pytest.mark.parametrize("name", [TANK, "GLX0926S16.DXF", "GMH1004F15-2.DXF"])
def test_the_grader_keeps_folds_and_shares_on_real_files(name, aama_dir, child, tmp_path_factory):
    pattern = _pattern(aama_dir, name, tmp_path_factory)
    result = fit_pattern(pattern, child, seed=0, pop_size=16, n_gen=4)
    data, grid = result.data, result.grid
    assert result.chosen.scores.measurement_error <= 0.5
    pts = grid.outlines(result.chosen.x[None])
    ref = grid.outlines(result.baselines["proportional"].x[None])
    turn = np.degrees(np.abs(piece_turn(data, pts) - piece_turn(data, ref)))[0]
    assert turn.max() <= MAX_TURN_DEG
    assert share_move(data, pts)[0].max() <= MAX_SHARE_MOVE
    assert not {f.code for f in result.findings} & {"piece-turned", "share-moved"}


def test_the_axes_turn_sees_rotation_and_shear_not_scaling(tank):
    grid, data, _ = tank
    x = grid.x0
    c = x.reshape(-1, 2)
    turned = _turned(grid, x, 0, 3.0)
    sheared = c.copy()
    sheared[:, 1] += 0.1 * (c[:, 0] - c[:, 0].mean())  # every piece: y += 0.1 x
    scaled = c * np.array([0.7, 1.3])
    np.testing.assert_allclose(np.degrees(piece_axes_turn(data, grid.outlines(turned[None]))[0, 0]), [3.0, 3.0])
    np.testing.assert_allclose(np.degrees(piece_axes_turn(data, grid.outlines(sheared.ravel()[None]))[0, :, 0]),
                               np.degrees(np.arctan(0.1)), rtol=1e-9)
    np.testing.assert_allclose(piece_axes_turn(data, grid.outlines(sheared.ravel()[None]))[0, :, 1], 0.0, atol=1e-12)
    np.testing.assert_allclose(piece_axes_turn(data, grid.outlines(scaled.ravel()[None]))[0], 0.0, atol=1e-12)


def test_a_sew_line_drawn_the_other_way_round_does_not_carry_the_allowance(aama_dir, tmp_path_factory):
    from patternbridge.library import load_garment

    # GLX0926S16's bindings: the sew line is drawn clockwise against a counter-clockwise cut line,
    # so vertex 1 of one is the far end of the band on the other (the joint vertices the bands'
    # seams insert are inserted into both lines alike)
    pieces = _pattern(aama_dir, "GLX0926S16.DXF", tmp_path_factory).pieces
    bindings = [p for p in pieces if p.role is not None and p.role.value.endswith("_binding")]
    assert len(bindings) == 2
    for piece in bindings:
        assert not pairs_with_outline(reference_line(piece), piece.outline)
    for piece in load_garment("shirt").pieces:
        assert pairs_with_outline(reference_line(piece), piece.outline)
