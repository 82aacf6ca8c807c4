"""The arm rig built from landmarks poses a character that has no rig of its own."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from patternbridge.assemble.bodyparts import segment_body
from patternbridge.assemble.landmark_rig import landmark_rig
from patternbridge.assemble.pose import dressing_rotvecs, rotations
from patternbridge.mesh.load import load_character
from patternbridge.mesh.skinning import pose_vertices


@pytest.fixture(scope="module")
def bare(shared_dir):
    character, _ = load_character(shared_dir / "characters" / "E_average_male.obj")
    return dataclasses.replace(character, skeleton=None, skin=None)


def test_the_rig_names_the_body_parts_the_landmarks_cut(bare):
    rig = landmark_rig(bare)
    assert rig is not None and bare.skeleton is None
    by_skin, by_cut = segment_body(rig), segment_body(bare)
    assert by_skin.source == "skin" and by_cut.source == "landmarks"
    assert (by_skin.labels == by_cut.labels).mean() > 0.99
    np.testing.assert_allclose(rig.skin.weights.sum(axis=1), 1.0)
    assert rig.skin.weights.min() >= 0.0


def test_the_rig_raises_the_arms_to_a_t_pose_and_leaves_the_body(bare):
    rig = landmark_rig(bare)
    posed = pose_vertices(rig, rotations(dressing_rotvecs(rig), 1.0))
    rest = np.asarray(bare.vertices)
    for side, sx in (("left", 1.0), ("right", -1.0)):
        shoulder = rest[bare.landmarks[f"shoulder_point_{side}"].vertex]
        wrist = posed[bare.landmarks[f"wrist_point_{side}"].vertex]
        elbow = posed[bare.landmarks[f"elbow_point_{side}"].vertex]
        # the A-pose wrist hangs ~40 cm below the shoulder; in the T-pose it is level with it, straight out
        assert rest[bare.landmarks[f"wrist_point_{side}"].vertex][1] < shoulder[1] - 25.0
        assert abs(wrist[1] - shoulder[1]) < 8.0 and sx * (wrist[0] - shoulder[0]) > 45.0
        assert sx * (wrist[0] - elbow[0]) > 20.0
    legs_and_head = ~segment_body(bare).mask("left_arm") & ~segment_body(bare).mask("right_arm")
    still = legs_and_head & (rest[:, 1] < bare.landmarks["armpit_point_left"].position[1] - 10.0)
    np.testing.assert_allclose(posed[still], rest[still], atol=1e-9)


def test_without_an_elbow_there_is_no_rig(bare):
    marks = {k: v for k, v in bare.landmarks.items() if k != "elbow_point_left"}
    assert landmark_rig(dataclasses.replace(bare, landmarks=marks)) is None
