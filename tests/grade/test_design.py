"""Design preservation in the final step: free dimensions follow the design, not the angles alone.

The superhero's measurements (chest 141 cm over a 77.8 cm waist) are far from
the shirt's sample size. Without the design terms the final step collapsed the
cuff to a 0.4 cm sliver (the arm length fixes sleeve + cuff, not their split,
and a taller sleeve keeps the sleeve's angles better) and narrowed the front
hem to 76 % of its share of the back's.
"""

from __future__ import annotations

import numpy as np
import pytest

from patternbridge.grade.blas import single_blas_thread
from patternbridge.grade.grid import deform_pattern
from patternbridge.grade.objectives import link_shares
from patternbridge.grade.refine import design_deviation, refine, straight_constraints, straight_edges
from patternbridge.grade.run import axis_scaling, build_grid, objective_data

SUPERHERO = {
    "chest_girth": 141.027, "waist_girth": 77.77, "neck_girth": 60.715, "shoulder_width": 66.043,
    "back_width": 56.577, "shoulder_length_right": 21.324, "front_length": 41.401,
    "arm_length_right": 64.651, "upper_arm_girth_right": 46.083, "wrist_girth_right": 18.028,
    "hip_girth": 96.295, "waist_to_hip": 16.745, "side_length": 28.381,
}


@pytest.fixture(scope="module")
def shirt_fit():
    from patternbridge.io.load import load_pattern

    pattern, _ = load_pattern("shirt")
    grid = build_grid(pattern, max_lines=6, max_cell_frac=0.2)
    data = objective_data(grid, SUPERHERO)
    x_prop = axis_scaling(grid, data)
    with single_blas_thread():
        # from the proportional seed, as fit_pattern's first start does
        res = refine(grid, data, x_prop, measure_tol_cm=0.45,
                     straight=straight_constraints(grid, straight_edges(grid)), x_design=x_prop)
    return grid, data, x_prop, res


def _hem_ratio(grid, x):
    """Front hem width (half front, cut twice) times two over the back hem width."""
    pieces = {p.name: p for p in deform_pattern(grid, x).pieces}
    f, b = pieces["front"], pieces["back"]
    fw = abs(f.outline[f.marks["side_hem"], 0] - f.outline[f.marks["cf_hem"], 0])
    bw = abs(b.outline[b.marks["side_hem_right"], 0] - b.outline[b.marks["side_hem_left"], 0])
    return 2.0 * fw / bw


def test_cuff_keeps_its_height(shirt_fit):
    grid, _data, x_prop, res = shirt_fit
    assert res.max_violation_cm < 1e-3
    k = grid.piece_index("cuff")
    height = np.ptp(grid.piece_outline(res.x[None, :], k)[0, :, 1])
    height_prop = np.ptp(grid.piece_outline(x_prop[None, :], k)[0, :, 1])
    height0 = np.ptp(grid.piece_outline(grid.x0[None, :], k)[0, :, 1])
    assert height >= 0.7 * height_prop and height >= 0.7 * height0


def test_front_back_hem_split_kept(shirt_fit):
    grid, _data, _x_prop, res = shirt_fit
    ratio0 = _hem_ratio(grid, grid.x0)
    assert 0.8 <= _hem_ratio(grid, res.x) / ratio0 <= 1.25


def test_link_shares_split_a_girth():
    from grade_fixtures import BODY, skirt_pattern

    grid = build_grid(skirt_pattern())
    data = objective_data(grid, BODY)
    shares, shared = link_shares(data, grid.outlines(grid.x0[None, :]))
    # waist and hip over identical front and back panels: half each; the
    # waist-to-knee link lies on the front only
    np.testing.assert_array_equal(shared, [True, True, False])
    np.testing.assert_allclose(shares[0, :, :2], 0.5, atol=1e-12)
    np.testing.assert_allclose(shares[0].sum(axis=0), 1.0, atol=1e-12)


def test_design_deviation_zero_under_translation_and_grows_with_collapse():
    from grade_fixtures import skirt_pattern

    grid = build_grid(skirt_pattern())
    moved = (grid.x0.reshape(-1, 2) + np.array([3.0, -2.0])).ravel()
    np.testing.assert_allclose(design_deviation(grid, moved[None, :], grid.x0), 0.0, atol=1e-12)
    squashed = (grid.x0.reshape(-1, 2) * [1.0, 0.5]).ravel()
    flat = (grid.x0.reshape(-1, 2) * [1.0, 0.1]).ravel()
    n_sq = np.linalg.norm(design_deviation(grid, squashed[None, :], grid.x0))
    n_flat = np.linalg.norm(design_deviation(grid, flat[None, :], grid.x0))
    assert 0 < n_sq < n_flat


SLIM_FEMALE_LEGS = {
    "waist_girth": 66.631, "hip_girth": 93.234, "crotch_length": 60.111, "waist_to_hip": 19.609,
    "outside_leg_right": 96.981, "inside_leg_right": 71.456, "thigh_girth_right": 51.828, "knee_girth_right": 34.587,
}


def _trouser_balance(pattern):
    """Front share of the waist and back rise / front rise of the trousers."""
    from patternbridge.pattern.geometry import range_length

    pieces = {p.name: p for p in pattern.pieces}
    f, b = pieces["front"], pieces["back"]

    def chord(pc, a, c):
        return float(np.linalg.norm(pc.outline[pc.marks[a]] - pc.outline[pc.marks[c]]))

    def rise(pc, top):
        i, j = pc.marks[top], pc.marks["crotch_point"]
        return float(min(range_length(pc.outline, i, j), range_length(pc.outline, j, i)))

    fw, bw = chord(f, "side_waist", "cf_waist"), chord(b, "side_waist", "cb_waist")
    return fw / (fw + bw), rise(b, "cb_waist") / rise(f, "cf_waist")


@pytest.fixture(scope="module")
def slim_trousers():
    """The slim female's trousers graded by ``fit_pattern`` (full budget, as the benchmark; about 18 s)."""
    from patternbridge.grade.run import fit_pattern
    from patternbridge.io.load import load_pattern

    pattern, _ = load_pattern("trousers")
    return pattern, fit_pattern(pattern, SLIM_FEMALE_LEGS, seed=0, size="slim")


def test_trousers_keep_their_balance_on_a_slim_body(slim_trousers):
    # A slim waist over full hips: the angle terms alone would take the waist out of the
    # front (front 16 cm, back 25 cm) and give the back a shorter rise than the front,
    # a pattern no tailor would cut and the assembler cannot sew.
    pattern, res = slim_trousers
    share0, rise0 = _trouser_balance(pattern)
    share, rise = _trouser_balance(res.pattern)
    sc = res.chosen.scores
    assert np.abs(sc.achieved_cm - sc.target_cm).max() <= 0.2 and np.abs(sc.seam_mismatch_cm).max() <= 0.01
    assert abs(share - share0) <= 0.25 * share0
    assert rise > 1.0 and abs(rise - rise0) <= 0.25 * rise0


def _dart(pattern):
    """Intake (chord between the rims) and length (mean leg) of the back dart on the sewing line, cm."""
    from patternbridge.grade.grid import reference_line

    back = pattern.piece("back")
    line = reference_line(back)
    a, x, b = (line[back.marks[m]] for m in ("dart_side", "dart_apex", "dart_cb"))
    return float(np.linalg.norm(a - b)), 0.5 * float(np.linalg.norm(a - x) + np.linalg.norm(b - x))


def test_slim_trousers_change_the_design_less_than_scaling(slim_trousers):
    # issue 6's shape target on the hardest trouser case: a waist 26.6 cm under the hip.
    # Before the dart had grid lines of its own the least corner change the final step
    # found was 0.0065 rad against scaling's 0.0027 (the waist came out of the centre
    # front and back corners); with them the waist reduction goes partly into the dart.
    pattern, res = slim_trousers
    prop = res.baselines["proportional"]
    assert res.chosen.scores.shape_error < prop.scores.shape_error
    assert res.chosen.x is not None and res.front_within[res.chosen_index]
    # the dart keeps the length it has under proportional scaling, its intake is free
    _, length_prop = _dart(prop.pattern)
    intake, length = _dart(res.pattern)
    intake0, _ = _dart(pattern)
    assert length == pytest.approx(length_prop, abs=0.01)
    assert 0.3 * intake0 < intake < 4.0 * intake0
