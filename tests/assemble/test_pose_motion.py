"""The arms coming down as a motion: the body moves every cloth step and carries the cloth by contact."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest
from cloth_fixtures import sheet

from patternbridge.assemble.cloth import ClothSolver, DrapeSettings
from patternbridge.assemble.collision import BodyCollider
from patternbridge.assemble.drape import build_cloth
from patternbridge.assemble.phases import PoseKeyframe, run_phases
from patternbridge.assemble.pose import dressing_rotvecs, moved_bones, rotations
from patternbridge.mesh.skinning import find_bone, pose_skeleton, pose_vertices


def winding_numbers(points: np.ndarray, vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """(n,) generalised winding numbers of ``points`` in a closed mesh (1 inside, 0 outside), by solid angles."""
    a, b, c = (vertices[faces[:, k]][None, :, :] - points[:, None, :] for k in range(3))
    la, lb, lc = (np.linalg.norm(v, axis=2) for v in (a, b, c))
    det = np.einsum("pfi,pfi->pf", a, np.cross(b, c))
    dot = lambda u, v: np.einsum("pfi,pfi->pf", u, v)  # noqa: E731
    den = la * lb * lc + dot(a, b) * lc + dot(a, c) * lb + dot(b, c) * la
    return (2.0 * np.arctan2(det, den)).sum(axis=1) / (4.0 * np.pi)


def _under_the_forearm(character, rotvecs, share):
    """The middle of the left forearm posed at ``share``, and the unit direction below it across the arm."""
    skel = pose_skeleton(character.skeleton, rotations(rotvecs, share))
    la, wr = find_bone(character.skeleton, "lowerarm", "left"), find_bone(character.skeleton, "wrist", "left")
    mid = 0.5 * (skel.heads[la] + skel.heads[wr])
    axis = (skel.heads[wr] - skel.heads[la]) / np.linalg.norm(skel.heads[wr] - skel.heads[la])
    down = np.array([0.0, -1.0, 0.0]) - axis * -axis[1]
    return mid, axis, down / np.linalg.norm(down)


@pytest.mark.shared
@pytest.mark.parametrize("attach", [0.0, 1.0])
def test_the_moving_arm_carries_a_patch_under_it_without_entering_it(character_e, attach):
    rotvecs = dressing_rotvecs(character_e)
    body = pose_vertices(character_e, rotations(rotvecs, 1.0))
    mid, axis, _ = _under_the_forearm(character_e, rotvecs, 1.0)
    # a 6 cm patch of cloth lying flat just under the forearm in the dressing pose (arms out sideways)
    near = np.abs((body - mid) @ axis) < 3.0
    low = body[near & (np.linalg.norm(np.cross(body - mid, axis), axis=1) < 8.0), 1].min()
    pts, f = sheet(6, 6.0)
    x = np.c_[pts[:, 0] - 3.0 + mid[0], np.full(len(pts), low - 0.8), pts[:, 1] - 3.0 + mid[2]]
    cloth = build_cloth([x], [pts], [f], [])
    settings = DrapeSettings()
    collider = BodyCollider(body, character_e.faces)
    sim = SimpleNamespace(
        character=character_e,
        cloth=cloth,
        body=body,
        hands=[],
        proxies=(),
        rotvecs=rotvecs,
        settings=settings,
        solver=ClothSolver(cloth, settings),
        collider=collider,
        cloth_collider=collider,
    )
    # the arm turns down by a third of the way to the rest pose (about 16 degrees, the forearm's middle ~12 cm)
    phases = tuple(
        PoseKeyframe(share_from=s0, share_to=s1, steps=8, gravity_scale=0.0, sew_from=1.0, sew_to=1.0, attach=attach)
        for s0, s1 in ((1.0, 5 / 6), (5 / 6, 2 / 3))
    )
    start = cloth.x.mean(axis=0)
    run_phases(sim, phases)
    final = pose_vertices(character_e, rotations(rotvecs, 2 / 3))
    # the collider followed the body (its vertices are the posed body's)
    np.testing.assert_allclose(sim.collider.vertices, final, atol=1e-9)
    # no cloth inside the body, by winding numbers (independent of the collider's queries)
    assert np.abs(winding_numbers(cloth.x, final, np.asarray(character_e.faces))).max() < 0.5
    # and the patch was carried down with the arm: a body that jumped would have passed through it
    # (the patch left above the arm or inside it), one that did not move would not have carried it
    mid1, _, down1 = _under_the_forearm(character_e, rotvecs, 2 / 3)
    carried = (cloth.x.mean(axis=0) - start) @ (mid1 - mid) / np.linalg.norm(mid1 - mid)
    # held on the skin's motion the patch stays under the arm; pushed alone its sides wrap round it, the
    # middle falls behind
    assert carried > (0.7 if attach > 0 else 0.3) * np.linalg.norm(mid1 - mid)
    if attach > 0:
        below = (cloth.x - mid1) @ down1
        assert below.min() > 0.0 and below.max() < 8.0


@pytest.mark.shared
def test_the_pose_moves_the_arms_and_the_bones_below_them(character_e):
    rotvecs = dressing_rotvecs(character_e)
    moved = moved_bones(character_e, rotvecs)
    skel = character_e.skeleton
    for side in ("left", "right"):
        for role in ("upperarm", "lowerarm", "wrist"):
            assert moved[find_bone(skel, role, side)]
    assert not moved[skel.parents < 0].any()  # the root stays
    # a bone is moved exactly when it is turned or its parent is moved
    turned = np.array([n in rotvecs for n in skel.names])
    parent_moved = np.where(skel.parents >= 0, moved[np.maximum(skel.parents, 0)], False)
    np.testing.assert_array_equal(moved, turned | parent_moved)


@pytest.mark.shared
def test_the_mitts_follow_the_hands_and_a_shared_scene_answers_as_a_new_collider(character_e):
    from patternbridge.assemble.bodyparts import hand_masks, segment_body
    from patternbridge.assemble.collision import mitt_hulls

    rotvecs = dressing_rotvecs(character_e)
    body = pose_vertices(character_e, rotations(rotvecs, 1.0))
    hands = hand_masks(character_e, body, segment_body(character_e, vertices=body))
    mitts = mitt_hulls(body, hands)
    assert len(mitts) == 2
    faces = np.asarray(character_e.faces)
    half = pose_vertices(character_e, rotations(rotvecs, 0.5))  # the arms half way down
    proxies = tuple((half[ids], f) for ids, f in mitts)
    moved = BodyCollider(half, faces).with_proxies(proxies)
    fresh = BodyCollider(half, faces, proxies=proxies)
    for (ids, f), hand in zip(mitts, hands, strict=True):
        assert hand[ids].all()  # the mitt's corners are the hand's vertices
        # the hand posed half way down lies within its mitt moved by those corners (within 1 mm of it): the
        # mitt left where it was taken would be some 30 cm away
        v = half[hand]
        assert BodyCollider(half[ids], f).signed_distance(v).max() < 0.1
        assert BodyCollider(body[ids], f).signed_distance(v).max() > 10.0
        probe = v + np.random.default_rng(0).normal(scale=2.0, size=v.shape)
        np.testing.assert_array_equal(moved.inside(probe), fresh.inside(probe))
        np.testing.assert_allclose(moved.closest(probe)[0], fresh.closest(probe)[0], atol=1e-6)
