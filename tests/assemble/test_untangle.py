"""Untangling: crossings that exist are undone by the solver, checked by a brute-force triangle test."""

from __future__ import annotations

import numpy as np
import pytest
from cloth_fixtures import sheet

from patternbridge.assemble.cloth import DrapeSettings
from patternbridge.assemble.cloth.untangle import edge_faces, find_crossings
from patternbridge.assemble.drape import build_cloth, drape


def _crossing_pairs(x: np.ndarray, faces: np.ndarray) -> int:
    """Brute force: pairs (edge of a triangle, triangle) sharing no vertex where the edge passes through the inside.

    Every edge of every triangle against every triangle, with the plane
    and the inside tested in closed form (no search structure, nothing of
    the solver's).
    """
    ends = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    p, q = x[ends[:, 0]][:, None], x[ends[:, 1]][:, None]  # (E, 1, 3)
    a, b, c = (x[faces[:, k]][None] for k in range(3))  # (1, F, 3)
    n = np.cross(b - a, c - a)
    dp = np.sum((p - a) * n, axis=2)
    dq = np.sum((q - a) * n, axis=2)
    across = dp * dq < 0
    m = p + (dp / np.where(across, dp - dq, 1.0))[:, :, None] * (q - p)
    inside = across
    for u, v in ((a, b), (b, c), (c, a)):
        inside = inside & (np.sum(np.cross(v - u, m - u) * n, axis=2) > 0)
    shared = (ends[:, None, :, None] == faces[None, :, None, :]).any(axis=(2, 3))
    return int(np.count_nonzero(inside & ~shared))


def _pressed_through(depth_cm: float):
    """A 10 cm sheet 0.8 cm over another, its middle pressed ``depth_cm`` down through the lower one."""
    pts, f = sheet(10, 10.0)
    low = np.c_[pts[:, 0], np.zeros(len(pts)), pts[:, 1]]
    high = low + [0.37, 0.8, 0.21]
    r = np.hypot(high[:, 0] - 5.0, high[:, 2] - 5.0)
    high[:, 1] -= (0.8 + depth_cm) * np.clip(1.0 - r / 3.0, 0.0, 1.0) * 1.5
    high[:, 1] = np.maximum(high[:, 1], -depth_cm)
    return build_cloth([low, high], [pts, pts], [f, f], [])


def test_the_brute_force_check_sees_the_sheets_crossing():
    cloth = _pressed_through(0.8)
    assert _crossing_pairs(cloth.x, cloth.faces) > 10
    # and the solver's search finds the same crossings (its candidates lose none)
    found = find_crossings(cloth.x, cloth.faces, cloth.edges)
    assert len(found) > 0
    x = cloth.x.copy()
    x[len(x) // 2 :, 1] += 2.0  # lifted clear: nothing crosses
    assert _crossing_pairs(x, cloth.faces) == 0
    assert len(find_crossings(x, cloth.faces, cloth.edges)) == 0


def test_edge_faces_lists_the_faces_beside_every_edge():
    from patternbridge.assemble.cloth import edges_and_bends

    _, f = sheet(2, 2.0)
    edges, _ = edges_and_bends(f)
    beside = edge_faces(f, edges)
    for e, (f0, f1) in zip(edges, beside, strict=True):
        assert f0 >= 0 and set(e) <= set(f[f0])
        if f1 >= 0:
            assert set(e) <= set(f[f1]) and f1 != f0
    # a 2 × 2 grid has 8 border edges with one face each
    assert np.count_nonzero(beside[:, 1] < 0) == 8


@pytest.mark.parametrize("depth", [0.5, 1.5, 3.0])
def test_a_sheet_pressed_through_another_is_pulled_back_out(no_body, depth):
    cloth = _pressed_through(depth)
    before = _crossing_pairs(cloth.x, cloth.faces)
    assert before > 0
    drape(cloth, no_body, steps=60, sew_steps=0, gravity_scale=0.0, settings=DrapeSettings(untangle=True))
    assert _crossing_pairs(cloth.x, cloth.faces) == 0
    half = len(cloth.x) // 2
    # pulled back up over the lower sheet, not the lower sheet wrapped round it
    assert np.median(cloth.x[half:, 1]) > np.median(cloth.x[:half, 1])
    # without the untangling the crossing stays (the test can fail)
    cloth = _pressed_through(depth)
    drape(cloth, no_body, steps=60, sew_steps=0, gravity_scale=0.0, settings=DrapeSettings(untangle=False))
    assert _crossing_pairs(cloth.x, cloth.faces) > 0


def test_self_contact_is_off_only_between_the_two_sides_of_a_crossing():
    from patternbridge.assemble.cloth.selfcontact import EdgePairs, SelfPairs
    from patternbridge.assemble.cloth.solver import _without

    faces = np.array([[0, 1, 2], [4, 5, 6]])
    tangled = np.array([0, 1, 2, 3])
    pairs = SelfPairs(vertex=np.array([3, 6, 3]), triangle=np.array([0, 0, 1]), direction=np.ones((3, 3)))
    edges = EdgePairs(edges=np.array([[[0, 1], [2, 3]], [[0, 1], [5, 6]]]), direction=np.ones((2, 3)), key=np.arange(2))
    kept, kept_edges = _without(pairs, edges, faces, tangled, 7)
    # a tangled vertex over a tangled triangle is let through; a third layer on either side still holds
    np.testing.assert_array_equal(kept.vertex, [6, 3])
    np.testing.assert_array_equal(kept.triangle, [0, 1])
    np.testing.assert_array_equal(kept_edges.edges, [[[0, 1], [5, 6]]])
