"""The final constrained step: straight edges, constraints met, less shape change than scaling."""

from __future__ import annotations

import numpy as np
import pytest
from grade_fixtures import BODY, half_skirt_pattern, skirt_pattern

from patternbridge.grade.blas import single_blas_thread
from patternbridge.grade.grid import build_grid
from patternbridge.grade.objectives import evaluate, objective_data
from patternbridge.grade.refine import (
    _solve_qp,
    refine,
    straight_constraints,
    straight_edges,
)
from patternbridge.grade.run import axis_scaling, fit_pattern

SMALL = {"pop_size": 20, "n_gen": 10}


def test_straight_edges_of_the_half_skirt():
    grid = build_grid(half_skirt_pattern())
    edges = {(e.piece, e.axis): e for e in straight_edges(grid)}
    # centre line x = 0 (axis 0: constant x) and the hem y = 0 (axis 1) on both halves
    assert set(edges) == {("front", 0), ("front", 1), ("back", 0), ("back", 1)}
    np.testing.assert_array_equal(edges["front", 0].points, [7, 8, 9, 0])
    np.testing.assert_array_equal(edges["front", 1].points, [0, 1, 2])
    assert edges["front", 0].length_cm == pytest.approx(60.0)


def test_straight_constraints_hold_for_axis_scaling_but_not_for_a_tilt():
    grid = build_grid(half_skirt_pattern())
    A = straight_constraints(grid, straight_edges(grid))
    assert A.shape[1] == grid.n_var and len(A) > 0
    scaled = (grid.x0.reshape(-1, 2) * [1.2, 0.9]).ravel()
    np.testing.assert_allclose(A @ scaled, 0.0, atol=1e-9)
    sheared = grid.x0.reshape(-1, 2).copy()
    sheared[:, 0] += 0.05 * sheared[:, 1]  # tilts the centre line
    assert np.abs(A @ sheared.ravel()).max() > 0.1


def test_qp_meets_equalities_and_bounds():
    rng = np.random.default_rng(0)
    M = rng.normal(size=(6, 6))
    H = M @ M.T + np.eye(6)
    g = rng.normal(size=6)
    A = rng.normal(size=(2, 6))
    b = rng.normal(size=2)
    Jm = rng.normal(size=(3, 6))
    lo, hi = np.full(3, -0.1), np.full(3, 0.1)
    d = _solve_qp(H, g, A, b, Jm, lo, hi)
    np.testing.assert_allclose(A @ d, b, atol=1e-8)
    assert np.all(Jm @ d <= hi + 1e-8) and np.all(Jm @ d >= lo - 1e-8)
    # the same optimum as a general constrained solver
    from scipy.optimize import minimize

    ref = minimize(lambda z: 0.5 * z @ H @ z + g @ z, np.zeros(6), jac=lambda z: H @ z + g, method="SLSQP",
                   constraints=[{"type": "eq", "fun": lambda z: A @ z - b},
                                {"type": "ineq", "fun": lambda z: hi - Jm @ z},
                                {"type": "ineq", "fun": lambda z: Jm @ z - lo}],
                   options={"ftol": 1e-12, "maxiter": 500})
    assert ref.success
    np.testing.assert_allclose(d, ref.x, atol=1e-5)


def test_refine_closes_the_fit_with_less_shape_change_than_scaling():
    pattern = skirt_pattern()
    grid = build_grid(pattern, max_cell_frac=0.2)
    data = objective_data(grid, BODY)
    A = straight_constraints(grid, straight_edges(grid))
    x_prop = axis_scaling(grid, data)
    with single_blas_thread():
        res = refine(grid, data, x_prop, measure_tol_cm=0.3, straight=A)
    ev = evaluate(data, grid.outlines(np.stack([x_prop, res.x])))
    err = np.abs(ev.achieved_cm[1] - data.target_cm)
    assert err.max() <= 0.3 + 1e-4
    np.testing.assert_allclose(ev.seam_mismatch_cm[1], 0.0, atol=1e-4)
    np.testing.assert_allclose(ev.notch_cm[1], 0.0, atol=1e-4)
    assert res.max_violation_cm < 1e-4
    assert ev.measurement_error[0] > 1.0  # scaling alone misses the fit...
    assert ev.shape_error[1] < ev.shape_error[0]  # ...and still changes the design more
    np.testing.assert_allclose(A @ res.x, 0.0, atol=1e-6)
    assert grid.fold_margin(res.x[None, :])[0] > 0


def test_refine_is_deterministic():
    grid = build_grid(skirt_pattern())
    data = objective_data(grid, BODY)
    x = axis_scaling(grid, data)
    a = refine(grid, data, x, max_iter=5)
    b = refine(grid, data, x, max_iter=5)
    np.testing.assert_array_equal(a.x, b.x)


@pytest.fixture(scope="module")
def half_fit():
    return fit_pattern(half_skirt_pattern(), BODY, seed=1, size="hero", **SMALL)


def test_centre_edge_stays_straight_and_on_the_grain(half_fit):
    s = half_fit.chosen.scores
    assert s.measurement_error <= 0.5 and s.max_seam_mismatch_cm <= 0.1
    assert s.shape_error < half_fit.baselines["proportional"].scores.shape_error
    for piece in half_fit.pattern.pieces:
        centre = piece.outline[[7, 8, 9, 0]]
        # no bend and no tilt: every centre vertex on one vertical line (0.1 mm)
        assert np.ptp(centre[:, 0]) < 0.01, piece.name
        hem = piece.outline[[0, 1, 2]]
        assert np.ptp(hem[:, 1]) < 0.01, piece.name
        # the grain line moved with the piece and is still vertical
        g = piece.grain_line.points
        assert abs(g[1, 0] - g[0, 0]) < 0.01 * abs(g[1, 1] - g[0, 1]) + 1e-6


def test_keep_straight_off_lets_the_centre_edge_move(half_fit):
    free = fit_pattern(half_skirt_pattern(), BODY, seed=1, size="hero", keep_straight=False, **SMALL)
    assert free.chosen.scores.measurement_error <= 0.5
    ptp = max(np.ptp(p.outline[[7, 8, 9, 0], 0]) for p in free.pattern.pieces)
    kept = max(np.ptp(p.outline[[7, 8, 9, 0], 0]) for p in half_fit.pattern.pieces)
    # without the constraint the fit bends the centre line by millimetres,
    # so the straightness test above can fail
    assert ptp > 0.05 and kept < 0.01


def test_single_blas_thread_restores_and_computes():
    M = np.random.default_rng(3).normal(size=(50, 50)) + 50 * np.eye(50)
    b = np.ones(50)
    from threadpoolctl import threadpool_info

    before = [p["num_threads"] for p in threadpool_info() if p["user_api"] == "blas"]
    with single_blas_thread():
        assert all(p["num_threads"] == 1 for p in threadpool_info() if p["user_api"] == "blas")
        x = np.linalg.solve(M, b)
    assert [p["num_threads"] for p in threadpool_info() if p["user_api"] == "blas"] == before
    np.testing.assert_allclose(M @ x, b, atol=1e-9)
    np.testing.assert_allclose(np.linalg.solve(M, b), x, atol=1e-12)


def test_centre_edge_straight_on_the_cut_and_the_sew_line():
    import dataclasses

    from patternbridge.pattern.model import Polyline

    pattern = half_skirt_pattern()
    pieces = []
    for p in pattern.pieces:
        centre = p.outline.mean(axis=0)
        sew = centre + 0.9 * (p.outline - centre)  # stands in for the line inside the allowance
        pieces.append(dataclasses.replace(p, sew_lines=(Polyline(points=sew, closed=True),)))
    pattern = dataclasses.replace(pattern, pieces=tuple(pieces))
    grid = build_grid(pattern, max_cell_frac=0.2)
    found = {(e.piece, e.axis, e.cut) for e in straight_edges(grid)}
    assert ("front", 0, True) in found and ("front", 0, False) in found
    result = fit_pattern(pattern, BODY, seed=2, size="hero", **SMALL)
    assert result.chosen.scores.measurement_error <= 0.5
    for p in result.pattern.pieces:
        assert np.ptp(p.outline[[7, 8, 9, 0], 0]) < 0.01, p.name
        assert np.ptp(p.sew_lines[0].points[[7, 8, 9, 0], 0]) < 0.01, p.name


def test_dart_keeps_its_length_in_the_final_step():
    from patternbridge.grade.grid import reference_line
    from patternbridge.grade.objectives import dart_lengths
    from patternbridge.library import load_garment

    slim = {"waist_girth": 66.631, "hip_girth": 93.234, "thigh_girth_right": 51.828, "knee_girth_right": 34.587,
            "waist_to_hip": 19.609, "crotch_length": 60.111, "inside_leg_right": 71.456,
            "outside_leg_right": 96.981}
    pattern = load_garment("trousers")
    grid = build_grid(pattern, max_lines=6, max_cell_frac=0.2)
    data = objective_data(grid, slim)
    back = pattern.piece("back")
    line = reference_line(back)
    a, x, b = (line[back.marks[m]] for m in ("dart_side", "dart_apex", "dart_cb"))
    length0 = 0.5 * (np.linalg.norm(a - x) + np.linalg.norm(b - x))
    np.testing.assert_allclose(dart_lengths(data, grid.outlines(grid.x0[None, :])), [[length0]], atol=1e-9)
    x_prop = axis_scaling(grid, data)
    with single_blas_thread():
        res = refine(grid, data, x_prop, straight=straight_constraints(grid, straight_edges(grid)),
                     x_design=x_prop, w_design=0.0, max_iter=25)
        free = refine(grid, data, x_prop, straight=straight_constraints(grid, straight_edges(grid)),
                      x_design=x_prop, w_design=0.0, max_iter=25, keep_darts=False)
    lengths = dart_lengths(data, grid.outlines(np.stack([x_prop, res.x, free.x])))[:, 0]
    assert res.max_violation_cm < 1e-3
    assert lengths[1] == pytest.approx(lengths[0], abs=1e-3)
    # without the constraint the waist reduction lengthens the dart (no angle sees it)
    assert abs(lengths[2] - lengths[0]) > 0.5
