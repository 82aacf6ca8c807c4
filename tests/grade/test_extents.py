"""Extents no link governs keep proportional scaling's, within a slack (issue 19).

The library shirt's yoke carries the shoulder width and part of the neck
girth, both across the grain; nothing measures its height, and the seams
fix only the yoke's height plus the back's. Graded to C_heavy_male, the
final step at the continuation's lowest grid-interval level slid the yoke
seam up and squashed the yoke to 0.52 of its proportional height (0.69 in
the benchmark's chosen grading, 0.36 on I_tall_apple_woman):
:func:`~patternbridge.grade.extents.unlinked_axes` finds that axis from the
links and seams alone and the final step holds it.
"""

from __future__ import annotations

import numpy as np
import pytest

from patternbridge.grade.bands import band_axes
from patternbridge.grade.checks import MIN_EXTENT_RATIO, piece_extents
from patternbridge.grade.extents import axis_spread, unlinked_axes
from patternbridge.grade.grid import build_grid
from patternbridge.grade.objectives import objective_data
from patternbridge.grade.refine import grain_constraints, refine, row_basis, straight_constraints, straight_edges
from patternbridge.grade.run import axis_scaling
from patternbridge.grade.symmetry import mirror_symmetries, symmetry_constraints
from patternbridge.library import load_garment

pytestmark = pytest.mark.shared


@pytest.fixture(scope="module")
def heavy(measured):
    return measured("C_heavy_male")


def _problem(garment: str, values: dict[str, float]):
    grid = build_grid(load_garment(garment), max_lines=6, max_cell_frac=0.2)
    return grid, objective_data(grid, values)


def test_the_spread_of_a_scaled_outline_scales_with_it():
    rng = np.random.default_rng(0)
    pts = rng.normal(size=(1, 40, 2))
    assert np.allclose(axis_spread(pts * [1.0, 2.5], 1), 2.5 * axis_spread(pts, 1))
    assert np.allclose(axis_spread(pts + [3.0, -7.0], 0), axis_spread(pts, 0))


def test_only_the_shirt_yoke_height_is_unlinked_in_the_library(heavy):
    found = {}
    for garment in ("shirt", "tshirt", "trousers", "shorts", "skirt", "dress"):
        grid, data = _problem(garment, heavy)
        ext = unlinked_axes(grid, data, data.points0, skip=band_axes(data).pieces)
        found[garment] = [(grid.pieces[k].name, int(a)) for k, a in zip(ext.pieces, ext.axes, strict=True)]
    # the backs' heights follow the fronts' linked side lengths through the side seams; the yoke's
    # armhole edge is sewn into a sleeve cap no link runs along
    assert found == {"shirt": [("yoke", 1)], "tshirt": [], "trousers": [], "shorts": [], "skirt": [], "dress": []}
    grid, data = _problem("shirt", heavy)
    x0 = axis_scaling(grid, data)
    ext = unlinked_axes(grid, data, grid.outlines(x0[None])[0], skip=band_axes(data).pieces)
    k = grid.piece_index("yoke")
    yoke = grid.outlines(x0[None])[0][data.piece_of_point == k]
    assert np.isclose(ext.spread_ref[0], axis_spread(yoke[None], 1)[0])  # proportional scaling's height


def test_the_final_step_keeps_the_yoke_height(heavy):
    grid, data = _problem("shirt", heavy)
    straight = row_basis(np.concatenate([straight_constraints(grid, straight_edges(grid)), grain_constraints(grid)]))
    x0 = axis_scaling(grid, data)
    symmetric = symmetry_constraints(grid, mirror_symmetries(grid))
    k = grid.piece_index("yoke")

    def yoke_height(w_extent: float) -> float:
        # the continuation's lowest grid-interval level: nothing but the angles and the seams left
        res = refine(
            grid, data, x0, straight=straight, x_design=x0, w_design=0.0, symmetric=symmetric, w_extent=w_extent
        )
        assert res.max_violation_cm < 1e-3
        h, h0 = piece_extents(data, grid.outlines(np.stack([res.x, x0])))[:, k, 1]
        return float(h / h0)

    assert yoke_height(1.0) >= 0.75  # the default: 0.80
    assert yoke_height(0.0) < MIN_EXTENT_RATIO  # without the term: 0.52
