"""Self-contact near on the cloth: the exclusion by the sewn cloth's rest state and the true point-triangle distance."""

from __future__ import annotations

import numpy as np
import pytest
from cloth_fixtures import sheet

from patternbridge.assemble.cloth import DrapeSettings
from patternbridge.assemble.cloth.selfcontact import closest_on_triangles, keep_sides, rest_near_keys
from patternbridge.assemble.drape import build_cloth, drape
from patternbridge.assemble.selfcross import self_crossing


def test_closest_points_match_a_dense_sampling_of_the_triangle():
    # an independent check: the closest of 20 000 points spread over each triangle
    rng = np.random.default_rng(3)
    tri = rng.normal(size=(200, 3, 3)) * [1.0, 1.0, 0.2]
    p = rng.normal(size=(200, 3)) * 1.5
    bary = closest_on_triangles(p, tri)
    np.testing.assert_allclose(bary.sum(axis=1), 1.0)
    assert bary.min() >= 0.0
    got = np.linalg.norm(p - np.einsum("ij,ijk->ik", bary, tri), axis=1)
    u, v = rng.random((2, 20000))
    u, v = np.where(u + v > 1, 1 - u, u), np.where(u + v > 1, 1 - v, v)
    w = np.stack([1 - u - v, u, v], axis=1)
    samples = np.einsum("sk,tkd->tsd", w, tri)
    best = np.linalg.norm(samples - p[:, None], axis=2).min(axis=1)
    assert np.all(got <= best + 1e-9)
    assert np.all(best - got < 0.05)


def test_rest_near_counts_seam_links_as_zero_and_edges_at_their_pattern_lengths():
    # a path 0-1-2-3 of edges 0.2, 1.0, 0.1 cm; vertex 4 sewn to 3
    edges = np.array([[0, 1], [1, 2], [2, 3]])
    keys = rest_near_keys(5, edges, np.array([0.2, 1.0, 0.1]), np.array([[3, 4]]), 0.35)
    near = {(int(k) // 5, int(k) % 5) for k in keys}
    assert {(0, 1), (1, 0), (2, 3), (3, 4), (2, 4), (4, 2)} <= near
    assert all((i, i) in near for i in range(5))
    assert (1, 2) not in near and (0, 2) not in near


def test_a_side_turned_round_within_one_step_is_kept_and_a_slide_round_an_edge_is_not():
    old_keys = np.array([3, 7, 9])
    old = np.array([[0.0, 1.0, 0.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]])
    new = np.array([[0.0, -1.0, 0.0], [0.6, 0.8, 0.0], [0.0, -1.0, 0.0]])
    out = keep_sides(np.array([3, 7, 5]), new, old_keys, old)
    np.testing.assert_array_equal(out, [[0.0, 1.0, 0.0], [0.6, 0.8, 0.0], [0.0, -1.0, 0.0]])


def _narrow_sheet():
    """A 6 x 6 cm sheet of 1 cm edges with one column 0.2 cm wide (slivers), 1e-4 cm out of its plane at random."""
    pts, f = sheet(6, 6.0)
    u = pts[:, 0].copy()
    u = np.where(u > 3.0, u - 0.8, u)  # the column between 3 and 4 cm becomes 0.2 cm wide
    pts = np.c_[u, pts[:, 1]]
    y = np.random.default_rng(0).normal(scale=1e-4, size=len(pts))
    return pts, f, np.c_[pts[:, 0], y, pts[:, 1]]


def test_a_flat_sheet_is_not_pushed_out_of_its_plane_by_its_own_self_contact(no_body):
    # by the plane's distance a neighbour a sliver's width away is inside the thickness (0.35 cm) and
    # is pushed off; by the true distance and the rest-state exclusion nothing in the sheet moves
    pts, f, x = _narrow_sheet()
    cloth = build_cloth([x], [pts], [f], [])
    start = cloth.x.copy()
    solver = drape(cloth, no_body, steps=20, sew_steps=0, gravity_scale=0.0)
    assert np.abs(cloth.x - start).max() < 1e-3
    assert solver.stats["self_pairs"] == 0  # no pair is even within reach at rest


def test_self_contact_without_the_rest_exclusion_would_push_the_sheet(no_body):
    # the check above can fail: with nothing excluded but each vertex's own triangles, the sliver column's
    # vertices, 0.2 cm from their neighbours' triangles, are pushed apart
    pts, f, x = _narrow_sheet()
    cloth = build_cloth([x], [pts], [f], [])
    start = cloth.x.copy()
    drape(cloth, no_body, steps=20, sew_steps=0, gravity_scale=0.0, settings=DrapeSettings(self_rest_cm=1e-6))
    assert np.abs(cloth.x - start).max() > 0.05


def _closing_fold(n: int, tip_speed_cm_s: float):
    """A 6 x 4 cm sheet of n x 4n/6 squares folded up by 150° along u = 4, its 2 cm flap swinging on over the rest."""
    pts, f = sheet(n, 6.0)
    keep = pts[:, 1] <= 4.0 + 1e-9
    idx = np.cumsum(keep) - 1
    f = f[keep[f].all(axis=1)]
    pts, f = pts[keep], idx[f]
    a = np.radians(150.0)
    r = np.maximum(pts[:, 0] - 4.0, 0.0)
    x = np.c_[np.minimum(pts[:, 0], 4.0) + r * np.cos(a), r * np.sin(a), pts[:, 1]]
    cloth = build_cloth([x], [pts], [f], [])
    # rotating about the crease: speed grows with the distance from it, the tip at tip_speed_cm_s
    cloth.v[:] = (tip_speed_cm_s * r / r.max())[:, None] * np.array([-np.sin(a), np.cos(a), 0.0])
    return cloth, r > 0


@pytest.mark.parametrize(("n", "speed"), [(6, 20.0), (6, 60.0), (12, 20.0), (12, 60.0)])
def test_a_sheet_folded_onto_itself_within_a_few_edges_does_not_pass_through(no_body, n, speed):
    # the flap, 2 or 4 edges long, falls over onto the held half of the sheet (gravity twice earth's):
    # where it lies over the sheet it stays above it (it may roll back off past the crease, which is no crossing)
    def run(settings):  # the lowest a flap vertex over the held sheet came at any step, and the crossings at the end
        cloth, flap = _closing_fold(n, speed)
        hold = np.where(cloth.uv[:, 0] <= 4.0, 1000.0, 0.0)  # the sheet under the flap held where it lies
        low = [np.inf]

        def watch(_):
            over = flap & (cloth.x[:, 0] < 3.8) & (np.abs(cloth.uv[:, 1] - 2.0) < 1.5)  # off the sheet's borders
            low[0] = min(low[0], float(cloth.x[over, 1].min(initial=np.inf)))

        drape(cloth, no_body, steps=20, sew_steps=0, gravity_scale=2.0, settings=settings, hold=hold, on_step=watch)
        return low[0], self_crossing(cloth.x, cloth.faces).any()

    low, crossed = run(DrapeSettings(damping=1.0))
    assert low > 0.1 and not crossed
    low, _ = run(DrapeSettings(damping=1.0, self_weight=0.0))  # without self-contact it passes through
    assert low < 0.0
