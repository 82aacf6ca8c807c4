"""The design's split of a waist-to-hip (chest-to-waist) reduction among darts and seams (grade/suppression.py)."""

from __future__ import annotations

import numpy as np
import pytest

from patternbridge.grade.grid import build_grid
from patternbridge.grade.objectives import _edge_lengths, objective_data
from patternbridge.grade.suppression import suppression, suppression_parts, suppression_terms
from patternbridge.library import load_garment


def _problem(name: str):
    pattern = load_garment(name)
    grid = build_grid(pattern)
    data = objective_data(grid, {lk.measurement: 60.0 for lk in pattern.measurements})
    return grid, data


def _pairs(grid, data, sup):
    return {
        (grid.pieces[k].name, data.link_ids[a], data.link_ids[b])
        for k, (a, b) in zip(sup.pair_piece, sup.pair_links, strict=True)
    }


def test_the_skirt_reductions_are_its_darts_and_side_seams():
    grid, data = _problem("skirt")
    sup = suppression(grid, data)
    assert _pairs(grid, data, sup) == {("front", "waist_girth", "hip_girth"), ("back", "waist_girth", "hip_girth")}
    # the library skirt: waist 14 cm under the hip on the front (four darts and two side seams), 7 on the back
    # (two darts, the side seam, the straight centre back)
    assert np.allclose(sorted(sup.r0), [7.0, 14.0], atol=0.05)
    pair = np.concatenate([sup.dart_pair, sup.slope_pair])
    for g in range(len(sup.r0)):
        # a straight level waist: the parts add up to the whole reduction
        assert sup.share0[pair == g].sum() == pytest.approx(1.0, abs=0.01)
    assert np.bincount(sup.dart_pair).tolist() == [4, 2]
    back = int(np.flatnonzero(sup.pair_piece == grid.piece_index("back"))[0])
    assert sorted(np.round(sup.share0[len(sup.dart_pair) :][sup.slope_pair == back], 3)) == [0.0, 0.429]


def test_axis_scaling_keeps_every_share_and_a_straightened_side_seam_does_not():
    grid, data = _problem("skirt")
    sup = suppression(grid, data)
    p0 = data.points0[None]
    scaled = p0 * np.array([1.23, 0.91])  # per-axis scaling: every part scales with the width
    assert np.abs(suppression_terms(sup, data, scaled, _edge_lengths(data, scaled))).max() < 1e-9
    # the back's side waist moved 1.5 cm out: its side seam takes less, the reduction shrinks by as much
    k = grid.piece_index("back")
    moved = p0.copy()
    moved[0, grid.point_offsets[k] + grid.pattern.pieces[k].marks["side_waist"], 0] += 1.5
    r, parts = suppression_parts(sup, data, moved, _edge_lengths(data, moved))
    g = int(np.flatnonzero(sup.pair_piece == k)[0])
    assert r[0, g] == pytest.approx(sup.r0[g] - 1.5, abs=0.05)
    side = len(sup.dart_pair) + int(np.flatnonzero((sup.slope_pair == g) & (sup.share0[len(sup.dart_pair) :] > 0.1))[0])
    assert parts[0, side] == pytest.approx(3.0 - 1.5, abs=0.05)
    assert suppression_terms(sup, data, moved, _edge_lengths(data, moved))[0, side] < -0.1


def test_the_dress_skirt_takes_its_waist_over_the_waist_seam_and_a_neck_is_no_level_of_a_seam():
    grid, data = _problem("dress")
    sup = suppression(grid, data)
    # the skirt pieces carry no waist link: they take its level from the bodice across the waist seams
    assert _pairs(grid, data, sup) == {
        ("bodice_front", "waist_girth", "chest_girth"),
        ("bodice_back", "waist_girth", "chest_girth"),
        ("skirt_front", "waist_girth", "hip_girth"),
        ("skirt_back", "waist_girth", "hip_girth"),
    }
    assert len(sup.dart_rims) == 6  # every dart of the dress, each in one reduction
    grid, data = _problem("tshirt")
    assert not len(suppression(grid, data).r0)  # neck and chest: no seam runs from one to the other


@pytest.mark.shared
@pytest.mark.slow
def test_a_skirt_graded_to_the_superhero_keeps_the_split_and_its_hip_curve_by_default(measured):
    """Her waist-to-hip reduction is about 0.7 of scaling's: held, every dart and seam takes its share of it.

    Without the term the whole grading's back side seam took 0.06 of it
    instead of 0.43 and its hip curve was pulled towards straight (every
    vertex 0.0109 rad against scaling's 0.0004).
    """
    from patternbridge.grade.checks import curve_depth
    from patternbridge.grade.objectives import dart_lengths
    from patternbridge.grade.run import fit_pattern

    one_stage = {"pop_size": 24, "n_gen": 12, "n_refine": 1, "design_levels": (1.0,), "all_levels": (3.0,)}
    body = measured("A_superhero")
    out = {}
    for w in (None, 0.0):  # the default holds the split
        held = {} if w is None else {"w_suppress": w}
        result = fit_pattern(load_garment("skirt"), body, seed=0, size="A", **held, **one_stage)
        grid, data, x = result.grid, result.data, result.chosen.x
        ours, scaling = result.chosen.scores, result.baselines["proportional"].scores
        assert ours.measurement_error <= 0.5 and ours.max_seam_mismatch_cm <= 0.1
        sup = suppression(grid, data)
        pts = grid.outlines(x[None])
        r, parts = suppression_parts(sup, data, pts, _edge_lengths(data, pts))
        pair = np.concatenate([sup.dart_pair, sup.slope_pair])
        k = grid.piece_index("back")
        marks = grid.pattern.pieces[k].marks
        hip = grid.point_offsets[k] + np.arange(marks["side_hip"], marks["side_waist"] + 1)
        depth = curve_depth(pts, hip)[0] / curve_depth(data.points0[None], hip)[0]
        darts = (
            dart_lengths(data, pts)[0] / dart_lengths(data, grid.outlines(result.baselines["proportional"].x[None]))[0]
        )
        out[w] = (np.abs(parts[0] / r[0, pair] - sup.share0).max(), depth, darts, ours, scaling)
    share_err, depth, darts, ours, scaling = out[None]
    assert share_err <= 0.05  # every dart and seam within 5 points of its share
    assert depth >= 0.9  # the back's hip curve keeps its depth
    assert darts.max() <= 1.01  # no dart reaches past its proportional length; they shorten with their intake
    assert ours.shape_error <= scaling.shape_error and ours.shape_error_all <= scaling.shape_error_all
    # not held, the side seams take what is cheapest: at this stage the back's side seam turns at the hip
    # (5.8°) and the shape leaves scaling's
    _, _, _, ours0, scaling0 = out[0.0]
    assert out[0.0][0] > 0.2
    assert ours0.shape_error > scaling0.shape_error


@pytest.mark.shared
@pytest.mark.slow
def test_where_holding_the_split_costs_shape_the_grading_without_it_is_kept(measured):
    """The slim female's waist is 8.3 cm under scaling's: her trousers' back reduction grows to 1.34 of the sample's.

    Held at the same stage, the split turns the dart points and the waists
    (critical points 0.0095 rad against 0.0056 without it, every vertex
    0.0113 against 0.0090): the same stage without the term competes on
    the same standing against scaling (run.split_ladder), so the default
    grading stands no worse than the one that never holds the split.
    """
    from patternbridge.grade.run import fit_pattern, shape_standing

    one_level = {
        "pop_size": 24,
        "n_gen": 12,
        "n_refine": 1,
        "n_trade": 0,
        "design_levels": (1 / 3,),
        "all_levels": (1.0,),
    }
    body = measured("B_slim_female")
    res = {w: fit_pattern(load_garment("trousers"), body, seed=0, w_suppress=w, **one_level) for w in (3.0, 0.0)}
    held, free = res[3.0], res[0.0]
    scaling = held.baselines["proportional"].scores
    assert held.chosen.scores.measurement_error <= 0.5 and held.chosen.scores.max_seam_mismatch_cm <= 0.1
    assert shape_standing(held.chosen.scores, scaling) <= shape_standing(free.chosen.scores, scaling)
    # the split is let go where it costs shape: the chosen grading's settings have no term and no dart ceiling
    assert held.finish_settings["w_suppress"] == 0.0 and not held.finish_settings["dart_cap"]
