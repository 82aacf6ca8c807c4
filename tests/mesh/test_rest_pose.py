"""The measuring rest pose: raised arms brought down by the character's own rig."""

from __future__ import annotations

import numpy as np
import pytest

from patternbridge.mesh.load import load_character
from patternbridge.mesh.rest_pose import REST_BELOW_DEG, arm_elevations_deg, arms_down

pytestmark = pytest.mark.shared


def test_t_pose_glb_is_brought_down_to_the_a_pose(characters_dir):
    t, _ = load_character(characters_dir / "variants" / "B_slim_female_tpose.glb")
    assert all(abs(e) < 1e-6 for e in arm_elevations_deg(t).values())  # level arms
    rest = arms_down(t)
    assert rest is not None and set(rest.lowered_deg) == {"left", "right"}
    for e in arm_elevations_deg(rest.character).values():
        assert e == pytest.approx(-REST_BELOW_DEG, abs=1e-6)
    a, _ = load_character(characters_dir / "B_slim_female.obj")  # the body it was posed from
    torso = np.abs(a.vertices[:, 0]) < 8.0  # away from the arms and the shoulders the skin is back
    torso &= a.vertices[:, 1] < 110.0
    d = np.linalg.norm(rest.character.vertices - a.vertices, axis=1)
    assert np.max(d[torso]) < 1e-3  # float32 glTF positions
    assert rest.character.faces is t.faces or np.array_equal(rest.character.faces, t.faces)


def test_arms_already_down_or_no_rig_is_left_alone(characters_dir):
    a, _ = load_character(characters_dir / "E_average_male.obj")
    assert arm_elevations_deg(a)["left"] < -40.0
    assert arms_down(a) is None
    bare, _ = load_character(characters_dir / "variants" / "C_heavy_male_tpose_remesh.obj")
    assert bare.skeleton is None and arms_down(bare) is None
