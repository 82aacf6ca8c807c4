"""Objectives: analytic values on the skirt, invariances, vectorisation, bad input."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from grade_fixtures import BODY, skirt_pattern

from patternbridge.errors import InputError
from patternbridge.grade.grid import build_grid
from patternbridge.grade.objectives import evaluate, level_slip, link_error, objective_data, residuals
from patternbridge.pattern.model import EdgeRange, Seam


@pytest.fixture
def setup():
    pattern = skirt_pattern()
    grid = build_grid(pattern)
    return pattern, grid, objective_data(grid, BODY)


def test_original_pattern_values(setup):
    pattern, grid, data = setup
    ev = evaluate(data, grid.outlines(grid.x0[None, :]))
    side = np.linalg.norm(np.diff(pattern.piece("front").outline[[2, 3, 4, 5, 6]], axis=0), axis=1).sum()
    np.testing.assert_allclose(ev.achieved_cm[0], [72.0, 96.0, side])
    np.testing.assert_allclose(data.target_cm, [86.0, 108.0, 55.0])
    assert ev.measurement_error[0] == pytest.approx(np.mean(np.abs([72 - 86, 96 - 108, side - 55])))
    np.testing.assert_allclose(ev.seam_mismatch_cm, 0.0, atol=1e-12)
    np.testing.assert_allclose(ev.notch_cm, 0.0, atol=1e-12)
    assert ev.seam_error[0] == pytest.approx(0.0, abs=1e-12)
    assert ev.shape_error[0] == pytest.approx(0.0, abs=1e-12)
    assert len(data.notch_seam) == 2  # one notch pair on each side seam


def test_similarity_keeps_shape_and_seams(setup):
    _, grid, data = setup
    theta = 0.3
    R = np.array([[np.cos(theta), -np.sin(theta)], [np.sin(theta), np.cos(theta)]])
    x = (1.3 * grid.x0.reshape(-1, 2) @ R.T + 5.0).ravel()
    ev = evaluate(data, grid.outlines(x[None, :]))
    ev0 = evaluate(data, grid.outlines(grid.x0[None, :]))
    assert ev.shape_error[0] == pytest.approx(0.0, abs=1e-9)
    assert ev.seam_error[0] == pytest.approx(0.0, abs=1e-9)
    np.testing.assert_allclose(ev.achieved_cm, 1.3 * ev0.achieved_cm)


def test_stretching_one_piece_breaks_seams_by_the_length_difference(setup):
    _, grid, data = setup
    x = grid.x0.copy().reshape(-1, 2)
    n_front = grid.pieces[0].n_control
    x[:n_front, 1] *= 1.1  # front 10 % taller
    pts = grid.outlines(x.reshape(1, -1))
    ev = evaluate(data, pts)
    front = pts[0, : grid.point_offsets[1]]
    back = pts[0, grid.point_offsets[1]:]
    la = np.linalg.norm(np.diff(front[[2, 3, 4, 5, 6]], axis=0), axis=1).sum()
    lb = np.linalg.norm(np.diff(back[[8, 9, 10, 11, 0]], axis=0), axis=1).sum()
    assert ev.seam_mismatch_cm[0, 0] == pytest.approx(lb - la)
    assert ev.seam_error[0] > 0.5
    assert np.all(np.abs(ev.notch_cm[0]) > 0.1)


def test_population_evaluation_matches_one_by_one(setup):
    _, grid, data = setup
    rng = np.random.default_rng(7)
    X = grid.x0 + rng.normal(scale=0.5, size=(9, grid.n_var))
    ev = evaluate(data, grid.outlines(X))
    for i in range(len(X)):
        one = evaluate(data, grid.outlines(X[i:i + 1]))
        np.testing.assert_allclose(one.F[0], ev.F[i], rtol=1e-12, atol=1e-12)
    r = residuals(data, grid.outlines(X))
    assert r.shape[0] == 9 and np.all(np.isfinite(r))


def test_seam_ease_is_the_target(setup):
    pattern, _, _ = setup
    seams = tuple(dataclasses.replace(s, ease_cm=1.5) for s in pattern.seams)
    grid = build_grid(dataclasses.replace(pattern, seams=seams))
    data = objective_data(grid, BODY)
    ev = evaluate(data, grid.outlines(grid.x0[None, :]))
    np.testing.assert_allclose(ev.seam_mismatch_cm[0], [-1.5, -1.5])


def test_no_links_says_how_to_add_them():
    grid = build_grid(skirt_pattern(links=False))
    with pytest.raises(InputError, match="seams infer"):
        objective_data(grid, BODY)


def test_missing_measurements_are_listed():
    grid = build_grid(skirt_pattern())
    with pytest.raises(InputError, match="hip_girth, waist_to_knee"):
        objective_data(grid, {"waist_girth": 80.0})


def test_unknown_mark_in_seam():
    pattern = skirt_pattern()
    bad = Seam(id="bad", a=EdgeRange(piece="front", start="nowhere", end="hem_l"),
               b=EdgeRange(piece="back", start="hem_r", end="waist_r"))
    grid = build_grid(dataclasses.replace(pattern, seams=(*pattern.seams, bad)))
    with pytest.raises(InputError, match="no mark 'nowhere'"):
        objective_data(grid, BODY)


def test_unknown_piece_in_seam():
    pattern = skirt_pattern()
    bad = Seam(id="bad", a=EdgeRange(piece="sleeve", start="a", end="b"),
               b=EdgeRange(piece="back", start="hem_r", end="waist_r"))
    grid = build_grid(dataclasses.replace(pattern, seams=(*pattern.seams, bad)))
    with pytest.raises(InputError, match="unknown piece 'sleeve'"):
        objective_data(grid, BODY)


def test_an_at_least_link_counts_only_when_it_falls_short():
    """The skirt's sample hips are 96 cm: a 108 cm target is 12 short, an 80 cm one is met."""
    hips = dataclasses.replace(skirt_pattern().measurements[1], at_least=True)
    pattern = dataclasses.replace(skirt_pattern(), measurements=(hips,))
    grid = build_grid(pattern)
    points = grid.outlines(grid.x0[None, :])
    short = objective_data(grid, {"hip_girth": 104.0})
    met = objective_data(grid, {"hip_girth": 76.0})
    assert evaluate(short, points).measurement_error[0] == pytest.approx(12.0)
    assert evaluate(met, points).measurement_error[0] == pytest.approx(0.0, abs=1e-12)
    np.testing.assert_allclose(link_error(met, np.array([[70.0], [80.0], [96.0]])), [[-10.0], [0.0], [0.0]])
    assert np.all(residuals(met, points)[:, 0] == 0.0)
    two_sided = objective_data(build_grid(skirt_pattern()), {**BODY, "hip_girth": 76.0})
    assert evaluate(two_sided, points).measurement_error[0] > 0.0


def test_a_girth_across_the_grain_ignores_a_slid_mark_but_counts_the_slide():
    """Sliding the front side hip mark 3 cm down: a chord grows, an across leg keeps 96 cm, 3 cm off level."""
    def with_hips(along):
        pattern = skirt_pattern()
        hips = pattern.measurements[1]
        legs = tuple(dataclasses.replace(g, along=along) for g in hips.legs)
        links = (pattern.measurements[0], dataclasses.replace(hips, legs=legs), pattern.measurements[2])
        grid = build_grid(dataclasses.replace(pattern, measurements=links))
        return grid, objective_data(grid, BODY)

    for along in ("chord", "across"):
        grid, data = with_hips(along)
        points = grid.outlines(grid.x0[None, :]).copy()
        before = evaluate(data, points)
        front = int(np.flatnonzero(data.piece_of_point[data.chord_b] == 0)[0])
        points[0, data.chord_b[front], 1] -= 3.0
        after = evaluate(data, points)
        slip = level_slip(data, points)[0]
        if along == "chord":
            assert after.achieved_cm[0, 1] == pytest.approx(96.0 + np.hypot(48.0, 3.0) - 48.0)
            np.testing.assert_allclose(slip, 0.0)
        else:
            np.testing.assert_allclose(before.achieved_cm, [[72.0, 96.0, before.achieved_cm[0, 2]]])
            assert after.achieved_cm[0, 1] == pytest.approx(96.0)
            np.testing.assert_allclose(np.abs(slip), [3.0, 0.0])
            # the hips were 12 cm short; now also 3 cm off their level, over 3 links
            assert after.measurement_error[0] == pytest.approx(before.measurement_error[0] + 1.0)
