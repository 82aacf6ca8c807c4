"""Control grids: bilinear weights, exact reproduction, folds, deformation of the whole piece."""

from __future__ import annotations

import numpy as np
import pytest
from grade_fixtures import skirt_pattern

from patternbridge.grade.grid import (
    bilinear_weights,
    build_grid,
    deform_pattern,
    grid_lines,
)


def test_grid_lines_keep_ends_and_gap():
    xs = grid_lines(np.array([1.0, 1.05, 5.0, 9.5, 3.0]), 0.0, 10.0, max_lines=4, min_gap_cm=0.5)
    assert xs[0] == 0.0 and xs[-1] == 10.0
    assert len(xs) <= 4
    assert np.all(np.diff(xs) >= 0.5)


def test_grid_lines_without_interior_values():
    lines = grid_lines(np.array([0.0, 10.0]), 0.0, 10.0, max_lines=6, min_gap_cm=0.1)
    np.testing.assert_array_equal(lines, [0.0, 10.0])


def test_bilinear_weights_partition_of_unity_and_reproduction():
    xs = np.array([0.0, 1.0, 3.0])
    ys = np.array([0.0, 2.0])
    rng = np.random.default_rng(3)
    pts = rng.uniform([0, 0], [3, 2], size=(50, 2))
    uv, w = bilinear_weights(pts, xs, ys)
    np.testing.assert_allclose(w.sum(axis=1), 1.0)
    gx, gy = np.meshgrid(xs, ys)
    control = np.stack([gx.ravel(), gy.ravel()], axis=1)
    np.testing.assert_allclose(w @ control, pts, atol=1e-12)
    assert np.all((uv[:, 0] >= 0) & (uv[:, 0] <= 2) & (uv[:, 1] >= 0) & (uv[:, 1] <= 1))


def test_affine_control_map_moves_points_affinely():
    pattern = skirt_pattern()
    grid = build_grid(pattern)
    A = np.array([[1.2, 0.1], [-0.05, 0.9]])
    b = np.array([3.0, -2.0])
    x = grid.x0.reshape(-1, 2) @ A.T + b
    pts = grid.outlines(x.reshape(1, -1))[0]
    orig = np.concatenate([p.outline for p in pattern.pieces])
    np.testing.assert_allclose(pts, orig @ A.T + b, atol=1e-9)


def test_identity_reproduces_pattern_exactly():
    pattern = skirt_pattern()
    grid = build_grid(pattern)
    out = deform_pattern(grid, grid.x0)
    for a, b in zip(pattern.pieces, out.pieces, strict=False):
        np.testing.assert_allclose(a.outline, b.outline, atol=1e-9)
        np.testing.assert_allclose(a.grain_line.points, b.grain_line.points, atol=1e-9)
        assert [n.angle for n in a.notches] == pytest.approx([n.angle for n in b.notches], abs=1e-9)
    assert out.seams == pattern.seams


def test_deform_moves_grain_line_and_renames_size():
    grid = build_grid(skirt_pattern())
    x = grid.x0.reshape(-1, 2) * np.array([1.0, 2.0])
    out = deform_pattern(grid, x.ravel(), size="hero")
    front = out.piece("front")
    assert front.size == "hero"
    np.testing.assert_allclose(front.grain_line.points[:, 1], [20.0, 100.0])


def test_fold_margin_and_order():
    grid = build_grid(skirt_pattern())
    assert grid.fold_margin(grid.x0[None, :])[0] == pytest.approx(1.0)
    flipped = (grid.x0.reshape(-1, 2) * np.array([-1.0, 1.0])).ravel()
    assert grid.fold_margin(flipped[None, :])[0] < 0
    assert grid.order_ok(np.stack([grid.x0, flipped])).tolist() == [True, False]


def test_fit_controls_recovers_scaled_outlines():
    pattern = skirt_pattern()
    grid = build_grid(pattern)
    target = [p.outline * 1.1 for p in pattern.pieces]
    x = grid.fit_controls(target)
    np.testing.assert_allclose(grid.outlines(x[None, :])[0], np.concatenate(target), atol=1e-3)


def test_seams_are_measured_on_the_sew_line():
    import dataclasses

    from patternbridge.pattern.model import Polyline

    pattern = skirt_pattern()
    pieces = []
    for p in pattern.pieces:
        centre = p.outline.mean(axis=0)
        sew = centre + 0.9 * (p.outline - centre)  # a stand-in for the line inside the allowance
        pieces.append(dataclasses.replace(p, sew_lines=(Polyline(points=sew, closed=True),)))
    pattern = dataclasses.replace(pattern, pieces=tuple(pieces))
    grid = build_grid(pattern)
    ref = grid.outlines(grid.x0[None, :])[0]
    np.testing.assert_allclose(ref, np.concatenate([p.sew_lines[0].points for p in pieces]), atol=1e-9)
    out = deform_pattern(grid, grid.x0)
    for a, b in zip(pattern.pieces, out.pieces, strict=False):
        np.testing.assert_allclose(a.outline, b.outline, atol=1e-9)
        np.testing.assert_allclose(a.sew_lines[0].points, b.sew_lines[0].points, atol=1e-9)


def test_pattern_darts_finds_the_trouser_back_dart_once():
    from patternbridge.grade.grid import pattern_darts
    from patternbridge.library import load_garment

    pattern = load_garment("trousers")
    back = pattern.piece("back")
    # the dart is sewn on both cut copies (two seams) and listed once; the front
    # and back rises join a piece to its mirror copy and are no darts
    expected = (back.marks["dart_side"], back.marks["dart_apex"], back.marks["dart_cb"])
    assert pattern_darts(pattern) == {"back": (expected,)}
    assert pattern_darts(skirt_pattern()) == {}


def test_dart_gets_grid_lines_through_its_rims_and_point():
    from patternbridge.grade.grid import reference_line
    from patternbridge.library import load_garment

    pattern = load_garment("trousers")
    back = pattern.piece("back")
    line = reference_line(back)
    rims = line[[back.marks["dart_side"], back.marks["dart_cb"]]]
    apex = line[back.marks["dart_apex"]]
    with_lines = build_grid(pattern, max_cell_frac=0.2)
    without = build_grid(pattern, max_cell_frac=0.2, dart_lines=False)
    g = with_lines.pieces[with_lines.piece_index("back")]
    g0 = without.pieces[without.piece_index("back")]
    # the rims are 2.1 cm apart, under the 6 % merge gap: one cell holds the whole dart without them
    assert abs(rims[0, 0] - rims[1, 0]) < 0.06 * g0.extent_cm
    between = (g0.xs > rims[:, 0].min() - 1e-9) & (g0.xs < rims[:, 0].max() + 1e-9)
    assert not between.any()
    for x in rims[:, 0]:
        assert np.min(np.abs(g.xs - x)) < 1e-9
    assert np.min(np.abs(g.ys - apex[1])) < 1e-9
    # the other pieces' grids are unchanged, and the original is still reproduced exactly
    for a, b in zip(with_lines.pieces, without.pieces, strict=True):
        if a.name != "back":
            np.testing.assert_array_equal(a.xs, b.xs)
            np.testing.assert_array_equal(a.ys, b.ys)
    np.testing.assert_allclose(with_lines.outlines(with_lines.x0[None, :])[0],
                               without.outlines(without.x0[None, :])[0], atol=1e-9)



def _mitre_inset(outline: np.ndarray, width: float) -> np.ndarray:
    """Each vertex where the two edges beside it, moved ``width`` inward, cross (a CCW outline)."""
    out = []
    n = len(outline)
    for k in range(n):
        p, q, r = outline[k - 1], outline[k], outline[(k + 1) % n]
        d1, d2 = (q - p) / np.linalg.norm(q - p), (r - q) / np.linalg.norm(r - q)
        n1, n2 = np.array([-d1[1], d1[0]]), np.array([-d2[1], d2[0]])
        det = d1[0] * -d2[1] + d2[0] * d1[1]
        if abs(det) < 1e-9:
            out.append(q + width * n1)
            continue
        rhs = (q + width * n2) - (q + width * n1)
        s = (rhs[0] * -d2[1] + d2[0] * rhs[1]) / det
        out.append(q + width * n1 + s * d1)
    return np.array(out)


def test_graded_cut_line_keeps_the_allowance_around_the_sew_line():
    import dataclasses

    import shapely

    from patternbridge.pattern.model import Polyline

    pattern = skirt_pattern()
    pieces = [dataclasses.replace(p, sew_lines=(Polyline(points=_mitre_inset(p.outline, 1.0), closed=True),))
              for p in pattern.pieces]
    pattern = dataclasses.replace(pattern, pieces=tuple(pieces))
    grid = build_grid(pattern)
    stretched = (grid.x0.reshape(-1, 2) * np.array([1.5, 1.0])).ravel()
    for piece in deform_pattern(grid, stretched).pieces:
        sew = piece.sew_lines[0].points
        # shapely's mitred buffer is the independent reference for a 1 cm allowance
        allowance = shapely.Polygon(sew).buffer(1.0, join_style="mitre", mitre_limit=10.0)
        assert shapely.hausdorff_distance(shapely.LinearRing(piece.outline), allowance.exterior) < 1e-6
        # moving the cut line with the grid would have widened the side allowance to 1.5 cm
        moved = grid.pieces[0].cut_weights @ stretched[: 2 * grid.pieces[0].n_control].reshape(-1, 2)
        if piece.name == pattern.pieces[0].name:
            assert shapely.hausdorff_distance(shapely.LinearRing(moved), allowance.exterior) > 0.3
