"""Fixtures shared by the grading tests."""

from __future__ import annotations

import pytest


@pytest.fixture(scope="module")
def measured(characters_dir):
    """``measured(name)``: the tape measurements (cm) of the shared character ``name``."""
    from patternbridge.measure.run import measure
    from patternbridge.mesh.load import load_character

    def values(name: str) -> dict[str, float]:
        character, _ = load_character(characters_dir / f"{name}.obj")
        return measure(character, partial=True).values_cm()

    return values


@pytest.fixture(scope="session")
def final_step_from_scaling():
    """``final_step_from_scaling(grid, data, edges)``: (result, straight rows) of the final step from scaling.

    ``edges`` are the straight runs held (``refine.straight_edges``); the
    grain lines and the pieces' mirror symmetries are held as ``fit_pattern`` holds them.
    """
    import numpy as np

    from patternbridge.grade.refine import grain_constraints, refine, row_basis, straight_constraints
    from patternbridge.grade.run import axis_scaling
    from patternbridge.grade.symmetry import mirror_symmetries, symmetry_constraints

    def run(grid, data, edges):
        straight = row_basis(np.concatenate([straight_constraints(grid, edges), grain_constraints(grid)]))
        x0 = axis_scaling(grid, data)
        symmetric = symmetry_constraints(grid, mirror_symmetries(grid))
        res = refine(grid, data, x0, straight=straight, x_design=x0, w_all=3.0, symmetric=symmetric)
        return res, straight

    return run
