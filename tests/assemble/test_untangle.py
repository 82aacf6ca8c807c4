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


def _halves_pressed_through(depth_cm: float):
    """As :func:`_pressed_through`, the upper sheet cut in two halves sewn along its middle (x = 5 cm)."""
    s = np.linspace(0.0, 10.0, 11)
    u, v = np.meshgrid(s, s, indexing="ij")
    low2d = np.stack([u.ravel(), v.ravel()], axis=1)
    _, low_f = sheet(10, 10.0)
    half2d, half_f = sheet(5, 5.0)
    half2d = half2d * [1.0, 2.0]  # 5 cm wide, 10 cm long
    parts, flats = [np.c_[low2d[:, 0], np.zeros(len(low2d)), low2d[:, 1]]], [low2d]
    for dx in (0.0, 5.0):
        flat = half2d + [dx, 0.0]
        up = np.c_[flat[:, 0] + 0.37, np.full(len(flat), 0.8), flat[:, 1] + 0.21]
        r = np.hypot(up[:, 0] - 5.0, up[:, 2] - 5.0)
        up[:, 1] -= (0.8 + depth_cm) * np.clip(1.0 - r / 3.0, 0.0, 1.0) * 1.5
        up[:, 1] = np.maximum(up[:, 1], -depth_cm)
        parts.append(up)
        flats.append(flat)
    seam_left = np.flatnonzero(np.isclose(half2d[:, 0], 5.0))  # the left half's right edge
    seam_right = np.flatnonzero(np.isclose(half2d[:, 0], 0.0))  # the right half's left edge
    order_l, order_r = np.argsort(half2d[seam_left, 1]), np.argsort(half2d[seam_right, 1])
    seams = [(1, 2, seam_left[order_l], seam_right[order_r])]
    return build_cloth(parts, flats, [low_f, half_f, half_f], seams)


def test_the_untangling_moves_the_two_sides_of_a_seam_as_one_point():
    from patternbridge.assemble.cloth import weld_groups
    from patternbridge.assemble.cloth.untangle import untangle_targets

    cloth = _halves_pressed_through(1.5)
    assert _crossing_pairs(cloth.x, cloth.faces) > 0
    label = weld_groups(len(cloth.x), cloth.seams)
    ids, moves, n = untangle_targets(
        cloth.x, cloth.faces, cloth.edges, edge_faces(cloth.faces, cloth.edges), label, 0.5
    )
    assert n > 0
    move = np.full((len(cloth.x), 3), np.nan)
    move[ids] = moves
    sewn_moved = cloth.seams[~np.isnan(move[cloth.seams[:, 0], 0])]
    assert len(sewn_moved) >= 2  # the seam runs through the crossing
    # both sides of every sewn pair are moved, and by the same vector: the untangling cannot open a seam
    np.testing.assert_allclose(move[sewn_moved[:, 0]], move[sewn_moved[:, 1]], atol=1e-12)


def _welded(cloth) -> tuple[np.ndarray, np.ndarray]:
    """Positions and faces with every sewn pair made one vertex at its midpoint (a seam is one line of cloth)."""
    rep = np.arange(len(cloth.x))
    rep[cloth.seams[:, 1]] = cloth.seams[:, 0]
    x = cloth.x.copy()
    x[cloth.seams[:, 0]] = 0.5 * (cloth.x[cloth.seams[:, 0]] + cloth.x[cloth.seams[:, 1]])
    return x, rep[cloth.faces]


def test_a_sewn_sheet_pressed_through_another_comes_back_out_with_its_seam_closed(no_body):
    cloth = _halves_pressed_through(1.5)
    assert _crossing_pairs(*_welded(cloth)) > 0
    drape(cloth, no_body, steps=60, sew_steps=0, gravity_scale=0.0, settings=DrapeSettings(untangle=True))
    assert _crossing_pairs(*_welded(cloth)) == 0
    gaps = np.linalg.norm(cloth.x[cloth.seams[:, 0]] - cloth.x[cloth.seams[:, 1]], axis=1)
    assert gaps.max() < 0.05  # cm


def test_the_untangling_acts_only_in_the_steps_a_phase_gives_it(no_body):
    settings = DrapeSettings(untangle=True)
    # given no step, the solver keeps the crossing whatever the settings say
    cloth = _pressed_through(1.5)
    drape(cloth, no_body, steps=40, sew_steps=0, gravity_scale=0.0, settings=settings, untangle_steps=(0, 0))
    assert _crossing_pairs(cloth.x, cloth.faces) > 0
    # given the last 30 steps of 40, it undoes it
    cloth = _pressed_through(1.5)
    solver = drape(cloth, no_body, steps=40, sew_steps=0, gravity_scale=0.0, settings=settings, untangle_steps=(10, 40))
    assert _crossing_pairs(cloth.x, cloth.faces) == 0
    assert solver.stats["crossings"] > 0


def test_crossings_round_a_held_vertex_are_left_alone():
    from patternbridge.assemble.cloth.untangle import untangle_targets

    cloth = _pressed_through(1.5)
    beside = edge_faces(cloth.faces, cloth.edges)
    label = np.arange(len(cloth.x))
    ids, _, n = untangle_targets(cloth.x, cloth.faces, cloth.edges, beside, label, 0.5)
    assert n > 0 and len(ids) > 0
    # the upper sheet held: every crossing has an end or a corner there, nothing moves
    held = np.zeros(len(cloth.x), dtype=bool)
    held[len(cloth.x) // 2 :] = True
    ids, moves, n = untangle_targets(cloth.x, cloth.faces, cloth.edges, beside, label, 0.5, held)
    assert n == 0 and len(ids) == 0 and len(moves) == 0


def test_the_untangling_aims_the_sides_of_a_seam_at_one_point():
    from patternbridge.assemble.cloth import ClothSolver
    from patternbridge.assemble.cloth.selfcontact import EdgePairs, SelfPairs

    cloth = _halves_pressed_through(1.5)
    x = cloth.x.copy()
    right = np.unique(cloth.seams[:, 1])
    x[right, 0] += 0.3  # the seam 3 mm open (under untangle_open_cm: not held)
    cloth.x = x
    solver = ClothSolver(cloth, DrapeSettings(untangle=True))
    none = SelfPairs(vertex=np.zeros(0, np.int64), triangle=np.zeros(0, np.int64), direction=np.zeros((0, 3)))
    enone = EdgePairs(edges=np.zeros((0, 2, 2), np.int64), direction=np.zeros((0, 3)), key=np.zeros(0, np.int64))
    ids, targets, _, _ = solver._untangle(x, x, none, enone)
    target = np.full((len(x), 3), np.nan)
    target[ids] = targets
    sewn = cloth.seams[~np.isnan(target[cloth.seams[:, 0], 0])]
    assert len(sewn) >= 2
    # both sides aim at one point: the untangling closes the gap instead of holding it against the seam's spring
    np.testing.assert_allclose(target[sewn[:, 0]], target[sewn[:, 1]], atol=1e-9)
