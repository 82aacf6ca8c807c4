"""The front handed to the user: distinct gradings within tolerance, thumbnails, ``fit --choose K``."""

from __future__ import annotations

import numpy as np
import pytest
from grade_fixtures import BODY, skirt_pattern

from patternbridge.errors import InputError
from patternbridge.grade.run import choose_member, fit_pattern, front_members


@pytest.fixture(scope="module")
def result():
    return fit_pattern(skirt_pattern(), BODY, seed=0, pop_size=16, n_gen=8, n_refine=1)


def test_the_front_offers_distinct_gradings_within_tolerance(result):
    members = front_members(result)
    rows = [k for k, _ in members]
    assert len(rows) >= 2
    assert all(result.front_within[k] for k in rows)
    F = result.front_F[rows]
    # distinct: no two shown rows share their measurement and shape error
    key = {(round(f[0] / 0.005), round(f[2] / 5e-5)) for f in F}
    assert len(key) == len(rows)
    # they trade fit against shape: a looser fit shown beside the chosen one changes the shape less
    c = result.chosen_index
    assert any(result.front_F[k, 0] > result.front_F[c, 0] and result.front_F[k, 2] < result.front_F[c, 2]
               for k in rows)
    # while the default choice keeps every measurement within the final step's band
    assert result.chosen.scores.max_measurement_error <= 0.151


def test_choose_member_re_runs_the_finish_from_that_row(result):
    members = front_members(result)
    k = max(members, key=lambda m: result.front_F[m[0], 0])[0]  # the loosest fit shown
    picked = choose_member(result, k)
    assert picked.chosen_index == k
    s = picked.chosen.scores
    assert s.measurement_error <= 0.5 and s.max_seam_mismatch_cm <= 0.1
    assert np.array_equal(picked.front_F, result.front_F)
    with pytest.raises(InputError, match="rows 0 to"):
        choose_member(result, len(result.front_F))


def test_pareto_png_draws_the_members(result, tmp_path):
    from patternbridge.io.plot_fit import plot_pareto

    members = [(k, p.pieces) for k, p in front_members(result)]
    path = plot_pareto(result.front_F, tmp_path / "pareto.png", final=result.chosen.scores.F,
                       refined=result.front_refined, within=result.front_within, members=members)
    assert path.stat().st_size > 10_000
