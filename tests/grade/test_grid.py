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
