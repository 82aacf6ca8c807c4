"""The final step's piece-block Jacobian equals the forward differences over every gene."""

from __future__ import annotations

import numpy as np
import pytest
from grade_fixtures import BODY, skirt_pattern

from patternbridge.grade.grid import build_grid
from patternbridge.grade.objectives import across_legs, link_shares, objective_data, piece_axes_turn
from patternbridge.grade.refine import grain_constraints, row_basis, straight_constraints, straight_edges
from patternbridge.grade.run import axis_scaling
from patternbridge.grade.step_terms import StepTerms
from patternbridge.grade.symmetry import mirror_symmetries, symmetry_constraints


def _terms(pattern, body):
    grid = build_grid(pattern, max_cell_frac=0.2)
    data = objective_data(grid, body)
    x = axis_scaling(grid, data)
    straight = row_basis(np.concatenate([straight_constraints(grid, straight_edges(grid)), grain_constraints(grid)]))
    share_ref, shared = link_shares(data, grid.outlines(x[None]))
    terms = StepTerms.build(
        grid,
        data,
        straight=straight,
        symmetric=symmetry_constraints(grid, mirror_symmetries(grid)),
        x_design=x,
        level=across_legs(data),
        dart_ref=None,
        share_ref=share_ref[:, :, shared],
        shared=shared,
        axes_ref=piece_axes_turn(data, grid.outlines(x[None]))[0] + 0.01,
        w_axes=1.0,
        w_rotation=0.05,
        w_shift=0.01,
        w_bend=0.02,
        w_cell=0.3,
        min_cell_ratio=0.4,
        w_design=0.7,
        design_slack=0.0,
        w_share=3.0,
        w_fit=0.02,
        w_interval=0.01,
        w_turn=0.005,
        w_symmetry=3.0,
        w_proportion=0.0,
        w_direction=0.0,
    )
    return grid, data, x, terms


@pytest.mark.parametrize("garment", ["skirt_fixture", "trousers", "shirt"])
def test_the_piece_block_jacobian_is_the_full_forward_difference(garment):
    from patternbridge.library import load_garment

    if garment == "skirt_fixture":
        grid, data, x, terms = _terms(skirt_pattern(), BODY)
    else:
        from patternbridge.library.sizes import MEN

        # a body off the size chart: the sample man, 12 % larger
        body = {k: 1.12 * v for k, v in MEN.body(MEN.sample_size).items()}
        grid, data, x, terms = _terms(load_garment(garment), body)
    rng = np.random.default_rng(3)
    # away from the start, so no term sits at a kink of its own (the squeeze barrier's max)
    x = x + rng.normal(scale=0.05, size=x.shape)
    wc = rng.uniform(0.5, 2.0, size=len(data.critical))
    wa = rng.uniform(0.5, 2.0, size=len(data.angle0))
    wm = rng.uniform(0.5, 2.0, size=len(data.target_cm))
    s, c, m = (a[0] for a in terms.evaluate(x[None], wc, wa, wm))
    h = np.full(len(x), 1e-5)
    Js, Jc, Jm = terms.jacobian(x, s, c, m, h, wc, wa, wm)
    sp, cp, mp = terms.evaluate(x[None, :] + np.diag(h), wc, wa, wm)
    np.testing.assert_allclose(Js, ((sp - s) / h[:, None]).T, atol=1e-6)
    np.testing.assert_allclose(Jc, ((cp - c) / h[:, None]).T, atol=1e-6)
    np.testing.assert_allclose(Jm, ((mp - m) / h[:, None]).T, atol=1e-6)
    # the blocks are not empty: every piece's genes move its own angles and some seam term
    assert np.count_nonzero(np.abs(Js) > 1e-8) > 0
    for k in range(len(grid.pieces)):
        cols = slice(int(grid.var_offsets[k]), int(grid.var_offsets[k + 1]))
        assert np.abs(Js[:, cols]).max() > 0.0
