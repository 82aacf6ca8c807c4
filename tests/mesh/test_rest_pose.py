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


def test_surface_landmarks_ride_their_faces_down_and_back(characters_dir):
    """A landmark inside a face keeps its face and weights through the re-pose: it stays on the skin
    (at the same place of it) and comes back to the given pose exactly; one on a vertex stays on it."""
    from dataclasses import replace

    from patternbridge.mesh.character import Landmark
    from patternbridge.mesh.surface_point import locate_on_surface

    t, _ = load_character(characters_dir / "variants" / "B_slim_female_tpose.glb")
    v, f = t.vertices, t.faces
    shoulder = int(np.argmax(v[:, 0] - 0.2 * np.abs(v[:, 1] - 140.0)))  # on the raised left arm
    face = int(np.flatnonzero((f == shoulder).any(axis=1))[0])
    bary = (0.2, 0.3, 0.5)
    at = locate_on_surface(v, f, np.asarray(bary) @ v[f[face]])
    marks = {
        "inside": at.landmark(0, "inside"),
        "vertex": Landmark(name="vertex", position=v[shoulder], vertex=shoulder),
    }
    assert marks["inside"].face == face and marks["inside"].bary == pytest.approx(bary)
    rest = arms_down(replace(t, landmarks=marks))
    down = rest.character
    for name, lm in down.landmarks.items():
        assert np.linalg.norm(lm.position - marks[name].position) > 5.0  # the arm came down
        np.testing.assert_allclose(lm.position, marks[name].at(down.vertices, f), atol=1e-12)
        np.testing.assert_allclose(lm.moved_to(v, f).position, marks[name].position, atol=1e-9)
    np.testing.assert_allclose(down.landmarks["vertex"].position, down.vertices[shoulder])
