"""Genetic operators of the grader as pymoo operators (thesis §4.2.2–4.2.3).

* :class:`SeedSampling` — the initial population: the seeds (proportional
  scaling per the thesis's Algorithm 4, scaling along and across the grain, the
  nearest graded size, the original) followed by copies of the seeds spread by
  strong mutation.
* :class:`GridCrossover` — uniform crossover piece by piece: for every piece of
  a mating either the whole chromosome (the piece's grid) is exchanged with
  probability ½, or each gene (control point, both coordinates) is exchanged
  with probability ½ (Algorithm 5).
* :class:`GridMutation` — non-uniform mutation (Michalewicz; thesis eqs. 4.3,
  4.4) along one grid direction of a piece at a time: a random row has its
  ``x`` (u) values moved, or a random column its ``y`` (v) values, by
  ``±Δ(gen, t)`` with ``Δ = t·(1 − λ^((1 − gen/Gen_max)^r))``; a draw that
  breaks the order of the control points in that row or column (which would
  fold the piece) is drawn again (Algorithm 6). The share of individuals
  mutated decays linearly with the generations (0.6 down to 0.1 by default).

All randomness comes from the ``random_state`` generator pymoo hands to the
operators, which :func:`pymoo.optimize.minimize` derives from the run's seed.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from pymoo.core.crossover import Crossover
from pymoo.core.mutation import Mutation
from pymoo.core.sampling import Sampling

from .grid import PatternGrid, PieceGrid

__all__ = [
    "GridCrossover",
    "GridMutation",
    "SeedSampling",
    "StepLaw",
    "mutate",
    "mutated_pieces",
    "mutation_rate",
    "non_uniform_delta",
]


def non_uniform_delta(t: np.ndarray, gen: float, n_max_gen: float, r: float, lam: np.ndarray) -> np.ndarray:
    """Michalewicz's non-uniform step ``Δ(gen, t) = t·(1 − λ^((1 − gen/Gen_max)^r))``.

    ``lam`` holds uniform draws in ``[0, 1)``; the step shrinks to 0 as
    ``gen`` reaches ``n_max_gen``. ``r = 0`` makes it uniform on ``[0, t]``.

    Examples
    --------
    >>> float(non_uniform_delta(np.array(2.0), 10, 10, 2.0, np.array(0.3)))
    0.0
    """
    frac = np.clip(1.0 - gen / max(n_max_gen, 1.0), 0.0, 1.0)
    return t * (1.0 - lam ** (frac**r))


def mutation_rate(gen: int, n_max_gen: int, *, rate0: float = 0.6, rate_min: float = 0.1) -> float:
    """Share of individuals mutated at generation ``gen``: linear decay from ``rate0`` to ``rate_min``."""
    frac = min(max(gen / max(n_max_gen, 1), 0.0), 1.0)
    return float(rate0 - (rate0 - rate_min) * frac)


def mutate(
    grid: PatternGrid,
    X: np.ndarray,
    rng: np.random.Generator,
    *,
    gen: float,
    n_max_gen: float,
    rate: float,
    t_frac: float = 0.06,
    r: float = 2.0,
    piece_prob: float = 0.5,
    max_retries: int = 8,
    min_ratio: float = 0.15,
) -> np.ndarray:
    """Mutate a population along one grid direction per piece (pure; returns a copy).

    Parameters
    ----------
    grid : gene layout
    X : (n_pop, n_var) float64
    rng : random generator
    gen, n_max_gen : current and last generation (Δ shrinks with ``gen``)
    rate : probability that an individual is mutated
    t_frac : largest step as a fraction of the piece's extent
    r : non-uniformity exponent
    piece_prob : probability that a given piece of a mutated individual mutates
        (at least one piece always does)
    max_retries : re-draws of a step that breaks the row/column order; a step
        still invalid after that is dropped
    min_ratio : smallest spacing of neighbouring control points, relative to
        the original spacing, that counts as "in order"

    Returns
    -------
    (n_pop, n_var) float64
    """
    X = np.array(X, dtype=np.float64)
    law = StepLaw(t_frac=t_frac, gen=gen, n_max_gen=n_max_gen, r=r, max_retries=max_retries,
                  min_ratio=min_ratio)
    piece_mask = mutated_pieces(rng, len(X), len(grid.pieces), rate=rate, piece_prob=piece_prob)
    for k, g in enumerate(grid.pieces):
        rows = np.flatnonzero(piece_mask[:, k])
        if len(rows) == 0:
            continue
        genes = slice(grid.var_offsets[k], grid.var_offsets[k + 1])
        c = X[rows, genes].reshape(len(rows), g.nv, g.nu, 2)
        X[rows, genes] = _mutate_piece(g, c, rng, law).reshape(len(rows), -1)
    return X


@dataclass(frozen=True, slots=True, kw_only=True)
class StepLaw:
    """How one grid line's step is drawn (:func:`mutate`'s parameters of the step)."""

    t_frac: float
    gen: float
    n_max_gen: float
    r: float
    max_retries: int
    min_ratio: float


def mutated_pieces(rng: np.random.Generator, n_pop: int, n_pieces: int, *, rate: float,
                   piece_prob: float) -> np.ndarray:
    """(n_pop, n_pieces) bool: which pieces of which individuals mutate.

    An individual mutates with probability ``rate``; each piece of a
    mutated individual with ``piece_prob``, and one drawn piece always does.
    """
    chosen = rng.random(n_pop) < rate
    piece_mask = rng.random((n_pop, n_pieces)) < piece_prob
    forced = rng.integers(0, n_pieces, size=n_pop)
    piece_mask[np.arange(n_pop), forced] = True
    return piece_mask & chosen[:, None]


def _mutate_piece(g: PieceGrid, c: np.ndarray, rng: np.random.Generator, law: StepLaw) -> np.ndarray:
    """One piece's control grids ``c (n, nv, nu, 2)`` with one row's x or one column's y moved each.

    Returns a new array.
    """
    c = c.copy()
    along_u = rng.random(len(c)) < 0.5
    t = law.t_frac * g.extent_cm
    for use_u in (True, False):
        sel = np.flatnonzero(along_u == use_u)
        if len(sel) == 0:
            continue
        n_lines = g.nv if use_u else g.nu
        base = np.diff(g.xs if use_u else g.ys)
        line = rng.integers(0, n_lines, size=len(sel))
        if use_u:
            c[sel, line, :, 0] = _mutate_lines(c[sel, line, :, 0], base, t, rng, law)  # (n, nu)
        else:
            c[sel, :, line, 1] = _mutate_lines(c[sel, :, line, 1], base, t, rng, law)  # (n, nv)
    return c


def _mutate_lines(vals: np.ndarray, base: np.ndarray, t: float, rng: np.random.Generator,
                  law: StepLaw) -> np.ndarray:
    """Coordinates ``vals (n, n_along)`` of one grid line each, moved by ``±Δ(gen, t)`` per point.

    A draw that brings neighbours closer than ``min_ratio`` of their
    original spacing ``base (n_along − 1,)`` is drawn again, up to
    ``max_retries`` times; a line still out of order keeps its values.
    """
    new = vals.copy()
    todo = np.ones(len(vals), dtype=bool)
    for _ in range(law.max_retries):
        idx = np.flatnonzero(todo)
        if len(idx) == 0:
            break
        lam = rng.random((len(idx), vals.shape[1]))
        sign = np.where(rng.random((len(idx), vals.shape[1])) >= 0.5, 1.0, -1.0)
        step = sign * non_uniform_delta(t, law.gen, law.n_max_gen, law.r, lam)
        cand = vals[idx] + step
        ok = np.all(np.diff(cand, axis=1) > law.min_ratio * base, axis=1)
        new[idx[ok]] = cand[ok]
        todo[idx[ok]] = False
    new[todo] = vals[todo]  # give up: keep the line as it was
    return new


class GridMutation(Mutation):
    """Non-uniform, order-preserving grid mutation with a decaying rate (see module doc)."""

    def __init__(
        self,
        grid: PatternGrid,
        n_max_gen: int,
        *,
        rate0: float = 0.6,
        rate_min: float = 0.1,
        t_frac: float = 0.06,
        r: float = 2.0,
    ) -> None:
        super().__init__(prob=1.0)
        self.grid = grid
        self.n_max_gen = int(n_max_gen)
        self.rate0 = rate0
        self.rate_min = rate_min
        self.t_frac = t_frac
        self.r = r

    def _do(self, problem, X, *args, random_state=None, algorithm=None, **kwargs):
        gen = 0 if algorithm is None or algorithm.n_gen is None else int(algorithm.n_gen)
        rate = mutation_rate(gen, self.n_max_gen, rate0=self.rate0, rate_min=self.rate_min)
        return mutate(self.grid, X, random_state, gen=gen, n_max_gen=self.n_max_gen, rate=rate,
                      t_frac=self.t_frac, r=self.r)


class GridCrossover(Crossover):
    """Uniform crossover of control points, piece by piece (two parents, two children)."""

    def __init__(self, grid: PatternGrid, *, prob: float = 0.9, piece_swap_prob: float = 0.5) -> None:
        super().__init__(n_parents=2, n_offsprings=2, prob=prob)
        self.grid = grid
        self.piece_swap_prob = piece_swap_prob
        # control point index of every variable
        self._point_of_var = np.repeat(np.arange(grid.n_var // 2), 2)
        self._piece_of_point = np.concatenate([
            np.full(g.n_control, k) for k, g in enumerate(grid.pieces)
        ])

    def _do(self, problem, X, *args, random_state=None, **kwargs):
        rng = random_state
        _, n_matings, n_var = X.shape
        n_points = n_var // 2
        n_pieces = len(self.grid.pieces)
        whole = rng.random((n_matings, n_pieces)) < self.piece_swap_prob
        whole_swap = rng.random((n_matings, n_pieces)) < 0.5
        point_swap = rng.random((n_matings, n_points)) < 0.5
        per_point = np.where(whole[:, self._piece_of_point], whole_swap[:, self._piece_of_point], point_swap)
        swap = per_point[:, self._point_of_var]
        child1 = np.where(swap, X[1], X[0])
        child2 = np.where(swap, X[0], X[1])
        return np.stack([child1, child2])


class SeedSampling(Sampling):
    """Initial population: the seeds, then mutated copies of them.

    Parameters
    ----------
    grid : gene layout
    seeds : (n_seeds, n_var) float64 — kept unchanged as the first individuals
    t_frac : step size of the spreading mutation (fraction of a piece extent)
    n_rounds : mutation rounds applied to each spread copy
    """

    def __init__(self, grid: PatternGrid, seeds: np.ndarray, *, t_frac: float = 0.04, n_rounds: int = 2) -> None:
        super().__init__()
        self.grid = grid
        self.seeds = np.atleast_2d(np.asarray(seeds, dtype=np.float64))
        self.t_frac = t_frac
        self.n_rounds = n_rounds

    def _do(self, problem, n_samples, *args, random_state=None, **kwargs):
        rng = random_state
        n_seeds = len(self.seeds)
        reps = self.seeds[np.arange(n_samples) % n_seeds]
        spread = reps.copy()
        for _ in range(self.n_rounds):
            spread = mutate(self.grid, spread, rng, gen=0, n_max_gen=1, rate=1.0, t_frac=self.t_frac)
        spread[: min(n_seeds, n_samples)] = self.seeds[: min(n_seeds, n_samples)]
        return np.clip(spread, problem.xl, problem.xu)
