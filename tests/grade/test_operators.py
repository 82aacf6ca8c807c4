"""Operators: non-uniform step, order-preserving one-direction mutation, piecewise crossover."""

from __future__ import annotations

import numpy as np
import pytest
from grade_fixtures import BODY, skirt_pattern

from patternbridge.grade.grid import build_grid
from patternbridge.grade.objectives import objective_data
from patternbridge.grade.operators import (
    GridCrossover,
    SeedSampling,
    mutate,
    mutated_pieces,
    mutation_rate,
    non_uniform_delta,
)
from patternbridge.grade.problem import GradingProblem


def test_non_uniform_delta_range_and_decay():
    lam = np.random.default_rng(0).random(1000)
    d0 = non_uniform_delta(2.0, 0, 100, 2.0, lam)
    assert np.all((d0 >= 0) & (d0 <= 2.0))
    np.testing.assert_allclose(non_uniform_delta(2.0, 100, 100, 2.0, lam), 0.0)
    late = non_uniform_delta(2.0, 90, 100, 2.0, lam)
    assert late.mean() < d0.mean()
    np.testing.assert_allclose(non_uniform_delta(2.0, 50, 100, 0.0, lam), 2.0 * (1 - lam))


def test_mutation_rate_decays_linearly():
    assert mutation_rate(0, 200) == pytest.approx(0.6)
    assert mutation_rate(200, 200) == pytest.approx(0.1)
    assert mutation_rate(100, 200) == pytest.approx(0.35)


def test_mutation_keeps_order_and_one_direction_per_piece():
    grid = build_grid(skirt_pattern())
    rng = np.random.default_rng(11)
    X = np.repeat(grid.x0[None, :], 200, axis=0)
    Y = mutate(grid, X, rng, gen=0, n_max_gen=10, rate=1.0, t_frac=0.5, piece_prob=1.0)
    assert np.all(grid.order_ok(Y, min_ratio=0.1))
    assert np.any(Y != X)
    for k in range(len(grid.pieces)):
        d = (grid.control(Y, k) - grid.control(X, k))
        moved_x = np.abs(d[..., 0]) > 0
        moved_y = np.abs(d[..., 1]) > 0
        for i in range(len(Y)):
            assert not (moved_x[i].any() and moved_y[i].any())
            if moved_x[i].any():
                assert len(np.unique(np.nonzero(moved_x[i])[0])) == 1  # one row
            if moved_y[i].any():
                assert len(np.unique(np.nonzero(moved_y[i])[1])) == 1  # one column


def test_mutation_is_reproducible_and_pure():
    grid = build_grid(skirt_pattern())
    X = np.repeat(grid.x0[None, :], 20, axis=0)
    a = mutate(grid, X, np.random.default_rng(5), gen=3, n_max_gen=10, rate=0.5)
    b = mutate(grid, X, np.random.default_rng(5), gen=3, n_max_gen=10, rate=0.5)
    np.testing.assert_array_equal(a, b)
    np.testing.assert_array_equal(X, np.repeat(grid.x0[None, :], 20, axis=0))


def test_crossover_exchanges_whole_control_points():
    grid = build_grid(skirt_pattern())
    problem = GradingProblem(grid, objective_data(grid, BODY))
    rng = np.random.default_rng(2)
    P = np.stack([grid.x0 + rng.normal(size=(6, grid.n_var)), grid.x0 + 100 + rng.normal(size=(6, grid.n_var))])
    C = GridCrossover(grid)._do(problem, P, random_state=np.random.default_rng(9))
    assert C.shape == P.shape
    np.testing.assert_allclose(C[0] + C[1], P[0] + P[1])
    from_first = (C[0] == P[0]).reshape(6, -1, 2)
    assert np.all(from_first[..., 0] == from_first[..., 1])  # x and y of a point travel together
    assert from_first.any() and (~from_first).any()


def test_seed_sampling_starts_with_the_seeds():
    grid = build_grid(skirt_pattern())
    problem = GradingProblem(grid, objective_data(grid, BODY))
    seeds = np.stack([grid.x0, grid.x0 * 1.1])
    X = SeedSampling(grid, seeds)._do(problem, 10, random_state=np.random.default_rng(0))
    assert X.shape == (10, grid.n_var)
    np.testing.assert_array_equal(X[:2], seeds)
    assert np.any(X[2:] != seeds[np.arange(2, 10) % 2])


def test_mutated_pieces_touch_one_piece_at_least_of_every_mutated_individual():
    rng = np.random.default_rng(7)
    every = mutated_pieces(rng, 200, 4, rate=1.0, piece_prob=0.5)
    assert every.shape == (200, 4) and every.any(axis=1).all()
    one = mutated_pieces(rng, 200, 4, rate=1.0, piece_prob=0.0)
    np.testing.assert_array_equal(one.sum(axis=1), np.ones(200))  # only the forced piece
    assert not mutated_pieces(rng, 200, 4, rate=0.0, piece_prob=1.0).any()
    some = mutated_pieces(rng, 2000, 3, rate=0.3, piece_prob=0.0).any(axis=1).mean()
    assert 0.25 < some < 0.35

