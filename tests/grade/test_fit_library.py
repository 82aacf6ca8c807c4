"""Grading a library garment to a real character (needs ../shared)."""

from __future__ import annotations

import numpy as np
import pytest

from patternbridge.grade.run import fit_pattern

pytestmark = [pytest.mark.shared, pytest.mark.slow]


def test_trousers_fit_the_cartoon_child(characters_dir):
    from patternbridge.library import load_garment
    from patternbridge.measure.run import measure
    from patternbridge.mesh.load import load_character

    character, _ = load_character(characters_dir / "D_cartoon_child.obj")
    values = measure(character, partial=True).values_cm()
    pattern = load_garment("trousers")
    result = fit_pattern(pattern, values, seed=0, size="D", pop_size=40, n_gen=40)
    s = result.chosen.scores
    assert s.measurement_error <= 0.5
    assert s.max_measurement_error <= 1.5
    assert s.max_seam_mismatch_cm <= 0.1
    assert s.fold_margin > 0 and s.is_simple
    prop = result.baselines["proportional"].scores
    assert s.measurement_error < prop.measurement_error
    assert s.max_seam_mismatch_cm < prop.max_seam_mismatch_cm
    assert s.shape_error < prop.shape_error  # less change of design than scaling, with the fit met
    for piece in result.pattern.pieces:  # straight hems stay straight and level
        if piece.name in ("front", "back"):
            hem = [piece.marks["side_hem"], piece.marks["hem_crease"], piece.marks["inside_hem"]]
            assert np.ptp(piece.outline[hem, 1]) < 0.01, piece.name
    # a child is far smaller than the sample size: the graded waist follows the body, not the chart
    waist = dict(zip(result.data.link_ids, s.achieved_cm, strict=False))["waist_girth"]
    ease = next(lk.ease_cm for lk in pattern.measurements if lk.id == "waist_girth")
    assert waist == pytest.approx(values["waist_girth"] + ease, abs=0.5)
