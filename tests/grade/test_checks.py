"""The design checks fail on the degraded patterns they name: a collapsed yoke, a flat neckline, a lost symmetry."""

from __future__ import annotations

import numpy as np
import pytest
from grade_fixtures import BODY, skirt_pattern

from patternbridge.grade.checks import (
    MIN_CURVE_RATIO,
    curve_depth,
    curve_runs,
    design_checks,
    piece_extents,
    span_sagitta,
)
from patternbridge.grade.grid import build_grid
from patternbridge.grade.objectives import objective_data
from patternbridge.grade.report import fit_report
from patternbridge.grade.run import axis_scaling, fit_pattern
from patternbridge.grade.symmetry import mirror_symmetries, symmetry_error


@pytest.fixture(scope="module", params=["E_average_male", "variants/I_tall_apple_woman"])
def shirt(request, characters_dir):
    """The library shirt on a shared character (measured), proportionally scaled."""
    from patternbridge.library import load_garment
    from patternbridge.measure.run import measure
    from patternbridge.mesh.load import load_character

    character, _ = load_character(characters_dir / f"{request.param}.obj")
    grid = build_grid(load_garment("shirt"), max_lines=6, max_cell_frac=0.2)
    data = objective_data(grid, measure(character, partial=True).values_cm())
    x = axis_scaling(grid, data)
    names = tuple(g.name for g in grid.pieces)
    return grid, data, x, names


def _codes(findings, where):
    return {f.code for f in findings if f.where == where}


@pytest.mark.shared
def test_proportional_scaling_passes_every_check(shirt):
    grid, data, x, names = shirt
    pts = grid.outlines(x[None])[0]
    assert design_checks(data, pts, pts, piece_names=names) == ()


@pytest.mark.shared
def test_a_collapsed_yoke_is_caught(shirt):
    grid, data, x, names = shirt
    k = names.index("yoke")
    squashed = x.copy()
    sl = slice(grid.var_offsets[k], grid.var_offsets[k + 1])
    c = squashed[sl].reshape(-1, 2)
    c[:, 1] = c[:, 1].mean() + 0.48 * (c[:, 1] - c[:, 1].mean())  # 10 cm high -> 4.8 cm
    squashed[sl] = c.ravel()
    ref = grid.outlines(x[None])[0]
    pts = grid.outlines(squashed[None])[0]
    assert piece_extents(data, pts[None])[0, k, 1] == pytest.approx(0.48 * piece_extents(data, ref[None])[0, k, 1])
    found = design_checks(data, pts, ref, piece_names=names)
    # squashed to 0.48 of its height, the neckline keeps about 0.48 of its depth: flattened as a whole too
    assert _codes(found, "yoke") == {"piece-collapsed", "curve-flattened"}
    assert all(f.where == "yoke" for f in found)
    assert all("as a whole" in f.message for f in found if f.code == "curve-flattened")


@pytest.mark.shared
def test_a_flat_neckline_is_caught(shirt):
    grid, data, x, names = shirt
    ref = grid.outlines(x[None])[0]
    depth = span_sagitta(data, data.points0[None])[0]
    k = names.index("yoke")
    span = int(np.argmax(np.where(data.span_piece == k, depth, -1.0)))  # the yoke's deepest curve: the neckline
    pts = ref.copy()
    a, b = ref[data.span_a[span]], ref[data.span_b[span]]
    on = np.flatnonzero(data.span_edges[:, span])
    t = ((pts[on] - a) @ (b - a)) / ((b - a) @ (b - a))
    pts[on] = a + t[:, None] * (b - a)  # every neckline vertex pulled onto the chord
    assert span_sagitta(data, pts[None])[0, span] < 1e-9
    found = design_checks(data, pts, ref, piece_names=names)
    assert "curve-flattened" in _codes(found, "yoke")


@pytest.mark.shared
def test_a_neckline_flattened_as_a_whole_is_caught_though_each_half_keeps_its_depth(shirt):
    grid, data, x, names = shirt
    ref = grid.outlines(x[None])[0]
    k = names.index("yoke")
    runs = [r for r in curve_runs(data) if data.piece_of_point[r[0]] == k]
    neck = max(runs, key=lambda r: curve_depth(data.points0[None], r)[0])  # neck side to neck side
    marks = grid.pattern.pieces[k].marks
    first = int(grid.point_offsets[k])
    assert {int(neck[0]) - first, int(neck[-1]) - first} == {marks["neck_side_left"], marks["neck_side_right"]}
    assert marks["cb_neck"] + first in neck[1:-1]  # the centre-back mark lies inside the curve
    # raise the neckline towards its chord by a tent that peaks at the centre back: linear on
    # each half, so each half keeps its own bulge while the whole loses most of its depth
    a, b = ref[neck[0]], ref[neck[-1]]
    u = (b - a) / np.linalg.norm(b - a)
    normal = np.array([-u[1], u[0]])
    side = np.sign(np.median((ref[neck] - a) @ normal))
    t = (ref[neck] - a) @ u / np.linalg.norm(b - a)
    t_cb = (ref[marks["cb_neck"] + first] - a) @ u / np.linalg.norm(b - a)
    tent = np.where(t <= t_cb, t / t_cb, (1.0 - t) / (1.0 - t_cb))
    depth = float(np.abs((ref[neck] - a) @ normal).max())
    pts = ref.copy()
    pts[neck] -= side * 0.9 * depth * tent[:, None] * normal[None, :]
    whole = curve_depth(pts[None], neck)[0] / curve_depth(ref[None], neck)[0]
    on_neck = [s for s in np.flatnonzero(data.span_piece == k) if data.span_a[s] in neck and data.span_b[s] in neck]
    halves = span_sagitta(data, pts[None])[0, on_neck] / span_sagitta(data, ref[None])[0, on_neck]
    assert len(on_neck) == 2 and (halves >= MIN_CURVE_RATIO).all()
    assert whole < MIN_CURVE_RATIO
    found = [f for f in design_checks(data, pts, ref, piece_names=names) if f.where == "yoke"]
    assert [f.code for f in found] == ["curve-flattened"] and "as a whole" in found[0].message


@pytest.mark.shared
def test_a_lost_symmetry_is_caught(shirt):
    grid, data, x, names = shirt
    sym = mirror_symmetries(grid)
    assert "yoke" in {s.piece for s in sym}
    k = names.index("yoke")
    g = grid.pieces[k]
    lopsided = x.copy()
    right = np.flatnonzero(g.control[:, 0] > np.median(g.control[:, 0]))
    lopsided[grid.var_offsets[k] + 2 * right + 1] += 0.5  # the right half raised 5 mm
    err = dict(zip([s.piece for s in sym], symmetry_error(grid, sym, lopsided[None])[0], strict=True))
    assert err["yoke"] > 0.2
    pts = grid.outlines(lopsided[None])[0]
    found = design_checks(data, pts, grid.outlines(x[None])[0], piece_names=names, symmetry_cm=err)
    assert "symmetry-lost" in _codes(found, "yoke")


def test_the_fit_report_carries_the_checks():
    result = fit_pattern(skirt_pattern(), BODY, seed=0, pop_size=16, n_gen=5, n_refine=1)
    report = fit_report(result)
    assert report["checks"] == [] and report["design_kept"] is True
