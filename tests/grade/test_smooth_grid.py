"""The C1 cubic grid deformation: exact reproduction, no kinks at grid lines, the interior fold check."""

from __future__ import annotations

import numpy as np
import pytest
from grade_fixtures import BODY, skirt_pattern

from patternbridge.grade.grid import (
    bilinear_weights,
    build_grid,
    cubic_weights,
    deform_pattern,
    map_weights,
    piece_grid,
)


def _controls(xs: np.ndarray, ys: np.ndarray, fx=lambda x: x, fy=lambda y: y) -> np.ndarray:
    gx, gy = np.meshgrid(fx(xs), fy(ys))
    return np.stack([gx.ravel(), gy.ravel()], axis=1)


def _turning(points: np.ndarray) -> np.ndarray:
    """Signed turning angle at every vertex of a closed polygon, rad."""
    d_in = points - np.roll(points, 1, axis=0)
    d_out = np.roll(points, -1, axis=0) - points
    cross = d_in[:, 0] * d_out[:, 1] - d_in[:, 1] * d_out[:, 0]
    return np.arctan2(cross, (d_in * d_out).sum(axis=1))


def test_cubic_weights_reproduce_points_and_interpolate_the_controls():
    xs = np.array([0.0, 1.0, 3.0, 3.5, 6.0])
    ys = np.array([0.0, 2.0, 5.0, 5.5])
    rng = np.random.default_rng(7)
    pts = rng.uniform([-2.0, -2.0], [8.0, 7.0], size=(300, 2))  # some outside the grid
    uv, w = cubic_weights(pts, xs, ys)
    np.testing.assert_allclose(w.sum(axis=1), 1.0, atol=1e-12)
    np.testing.assert_allclose(w @ _controls(xs, ys), pts, atol=1e-12)
    # local support: at most 4 × 4 control points per point
    assert (np.abs(w) > 1e-14).sum(axis=1).max() <= 16
    # a grid intersection is its control point
    _, w_nodes = cubic_weights(_controls(xs, ys), xs, ys)
    np.testing.assert_allclose(w_nodes, np.eye(len(xs) * len(ys)), atol=1e-12)
    # inside the grid u, v lie in the cell ranges, as for the bilinear map
    inside = (pts[:, 0] >= 0) & (pts[:, 0] <= 6) & (pts[:, 1] >= 0) & (pts[:, 1] <= 5.5)
    np.testing.assert_allclose(uv[inside], bilinear_weights(pts[inside], xs, ys)[0])


def test_cubic_map_continues_linearly_outside_the_grid():
    xs = np.array([0.0, 2.0, 3.0, 7.0])
    ys = np.array([0.0, 1.0, 4.0])
    rng = np.random.default_rng(1)
    control = _controls(xs, ys) + rng.normal(scale=0.2, size=(12, 2))
    # along a ray leaving the grid the mapped points lie on one straight line
    ray = np.stack([np.linspace(7.5, 12.0, 6), np.full(6, 2.5)], axis=1)
    mapped = map_weights(ray, xs, ys, "cubic") @ control
    d = np.diff(mapped, axis=0)
    cross = d[:-1, 0] * d[1:, 1] - d[:-1, 1] * d[1:, 0]
    np.testing.assert_allclose(cross, 0.0, atol=1e-9)


def test_unknown_deformation_is_rejected():
    with pytest.raises(ValueError, match="unknown grid deformation"):
        map_weights(np.zeros((1, 2)), np.array([0.0, 1.0]), np.array([0.0, 1.0]), "quintic")
    with pytest.raises(ValueError, match="unknown grid deformation"):
        piece_grid(skirt_pattern().pieces[0], deformation="nurbs")


def test_circle_crossing_a_moved_grid_line_keeps_no_kink_under_the_cubic_map():
    """Stretch the right half of a grid (x > 0 moved out by 1.6): a circle crossing x = 0 obliquely.

    The bilinear map's x slope jumps from 1 to 1.6 at the line, so the mapped
    circle turns by about 0.2 rad at the crossing; the C1 map's turning there
    stays near the original's 2π / n.
    """
    xs = np.linspace(-4.0, 4.0, 9)
    ys = np.linspace(-3.0, 3.0, 7)
    control = _controls(xs, ys, fx=lambda x: np.where(x > 0, 1.6 * x, x))
    n = 720
    t = 2 * np.pi * (np.arange(n) + 0.5) / n
    circle = np.stack([-1.0 + 1.5 * np.cos(t), 1.5 * np.sin(t)], axis=1)
    turn0 = _turning(circle)
    crossing = np.abs(circle[:, 0]) < 0.05  # the vertices around the two crossings of x = 0
    assert crossing.sum() >= 4
    bent = {}
    for name in ("bilinear", "cubic"):
        mapped = map_weights(circle, xs, ys, name) @ control
        bent[name] = np.abs(_turning(mapped) - turn0)
    assert bent["bilinear"][crossing].max() > 0.1
    assert bent["cubic"][crossing].max() < 0.01
    # and everywhere else along the curve
    assert bent["cubic"].max() < 0.01
    # the identity grid maps the circle onto itself under both
    for name in ("bilinear", "cubic"):
        np.testing.assert_allclose(map_weights(circle, xs, ys, name) @ _controls(xs, ys), circle, atol=1e-12)


@pytest.mark.parametrize("deformation", ["bilinear", "cubic"])
def test_identity_reproduces_every_point_exactly(deformation):
    pattern = skirt_pattern()
    grid = build_grid(pattern, deformation=deformation, max_cell_frac=0.2)
    assert grid.deformation == deformation
    np.testing.assert_allclose(grid.outlines(grid.x0[None, :])[0],
                               np.concatenate([p.outline for p in pattern.pieces]), atol=1e-9)
    out = deform_pattern(grid, grid.x0)
    for a, b in zip(pattern.pieces, out.pieces, strict=True):
        np.testing.assert_allclose(a.outline, b.outline, atol=1e-9)
        np.testing.assert_allclose(a.grain_line.points, b.grain_line.points, atol=1e-9)
        assert [m.angle for m in a.notches] == pytest.approx([m.angle for m in b.notches], abs=1e-9)
    assert grid.fold_margin(grid.x0[None, :])[0] == pytest.approx(1.0)


def test_affine_controls_move_points_affinely_under_the_cubic_map():
    pattern = skirt_pattern()
    grid = build_grid(pattern, deformation="cubic", max_cell_frac=0.2)
    A = np.array([[1.2, 0.1], [-0.05, 0.9]])
    b = np.array([3.0, -2.0])
    x = grid.x0.reshape(-1, 2) @ A.T + b
    np.testing.assert_allclose(grid.outlines(x.reshape(1, -1))[0],
                               np.concatenate([p.outline for p in pattern.pieces]) @ A.T + b, atol=1e-9)
    # an affine map has the same Jacobian everywhere: the fold check sees its determinant
    np.testing.assert_allclose(grid.jacobian_ratio(x.reshape(1, -1)), np.linalg.det(A), atol=1e-9)
    # and the bilinear grids have no interior samples to check
    assert build_grid(pattern).jacobian_ratio(x.reshape(1, -1)).shape == (1, 0)


def test_fold_check_catches_a_fold_inside_cells_whose_corners_are_fine():
    """The middle column squeezed to a tenth, its neighbours stretched threefold: the cubic map overshoots.

    The slope at the middle column's lines comes from the steep neighbours,
    so the cubic in the squeezed column runs backwards between them. Every
    corner cross product stays at 10 % or more of the original (above the
    5 % margin), so the corner check alone passes; the sampled Jacobian does
    not, and the mapped row really runs backwards.
    """
    pattern = skirt_pattern()
    cubic = build_grid(pattern, deformation="cubic")
    bilinear = build_grid(pattern)
    g = cubic.pieces[0]
    np.testing.assert_allclose(g.xs, [0.0, 7.0, 43.0, 50.0])
    new_xs = np.array([0.0, 21.0, 21.0 + 0.1 * 36.0, 21.0 + 0.1 * 36.0 + 21.0])
    x = cubic.x0.copy()
    for k, gk in enumerate(cubic.pieces):
        c = _controls(gk.xs, gk.ys, fx=lambda _x: new_xs)
        x[cubic.var_offsets[k]:cubic.var_offsets[k + 1]] = c.ravel()
    assert bilinear.fold_margin(x[None, :])[0] == pytest.approx(0.1)
    assert cubic.fold_margin(x[None, :])[0] < 0
    assert cubic.jacobian_ratio(x[None, :]).min() < 0
    row = np.stack([np.linspace(0.0, 50.0, 501), np.full(501, 20.0)], axis=1)
    mapped = map_weights(row, g.xs, g.ys, "cubic") @ x[:2 * g.n_control].reshape(-1, 2)
    assert np.diff(mapped[:, 0]).min() < 0  # the piece folds over itself
    # a moderate narrowing (60 %) is no fold under either map
    mild = np.array([0.0, 7.0, 7.0 + 0.6 * 36.0, 7.0 + 0.6 * 36.0 + 7.0])
    y = cubic.x0.copy()
    for k, gk in enumerate(cubic.pieces):
        y[cubic.var_offsets[k]:cubic.var_offsets[k + 1]] = _controls(gk.xs, gk.ys, fx=lambda _x: mild).ravel()
    assert cubic.fold_margin(y[None, :])[0] > 0.05


def test_fit_controls_recovers_scaled_outlines_under_the_cubic_map():
    pattern = skirt_pattern()
    grid = build_grid(pattern, deformation="cubic")
    target = [p.outline * 1.1 for p in pattern.pieces]
    x = grid.fit_controls(target)
    np.testing.assert_allclose(grid.outlines(x[None, :])[0], np.concatenate(target), atol=1e-3)


def test_fit_pattern_with_the_cubic_map_meets_the_fit():
    from patternbridge.grade.report import fit_report
    from patternbridge.grade.run import fit_pattern

    result = fit_pattern(skirt_pattern(), BODY, seed=0, pop_size=20, n_gen=10, deformation="cubic")
    assert result.grid.deformation == "cubic"
    sc = result.chosen.scores
    assert sc.measurement_error <= 0.5 and sc.max_seam_mismatch_cm <= 0.1
    assert sc.fold_margin > 0.05 and sc.is_simple
    assert fit_report(result)["settings"]["deformation"] == "cubic"
