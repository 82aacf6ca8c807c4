"""Tailoring paths on the shared 13K-vertex character against exact (MMP) lengths."""

from __future__ import annotations

import json

import numpy as np
import pytest

from patternbridge.geodesic import SurfaceMesh, geodesic_path, geodesic_paths

pytestmark = pytest.mark.shared

# exact polyhedral geodesic lengths (cm) on E_average_male.obj from pygeodesic's MMP
EXACT_E = {
    ("back_neck_point", "waist_back"): 43.3276,
    ("shoulder_point_left", "shoulder_point_right"): 45.2944,  # across the chest,
    # not over the neck where the shortest edge path goes
    ("neck_shoulder_point_left", "shoulder_point_left"): 13.5956,
}


@pytest.fixture(scope="module")
def character_e(characters_dir):
    import trimesh

    m = trimesh.load(characters_dir / "E_average_male.obj", process=False)
    lm = json.loads((characters_dir / "E_average_male.json").read_text())["landmarks"]
    mesh = SurfaceMesh(np.asarray(m.vertices), np.asarray(m.faces))
    return mesh, {k: v["vertex"] for k, v in lm.items()}


def test_lengths_match_exact_geodesics(character_e):
    mesh, lm = character_e
    pairs = [(lm[a], lm[b]) for a, b in EXACT_E]
    for (names, want), path in zip(EXACT_E.items(), geodesic_paths(mesh, pairs), strict=True):
        assert path.length == pytest.approx(want, rel=1e-3), names


def test_tape_is_never_longer_than_the_skin(character_e):
    mesh, lm = character_e
    skin = geodesic_path(mesh, lm["axilla_back_left"], lm["axilla_back_right"])
    tape = geodesic_path(
        mesh, lm["axilla_back_left"], lm["axilla_back_right"], tape=True
    )
    assert tape.length <= skin.length + 1e-9
    assert tape.length >= np.linalg.norm(skin.points[0] - skin.points[-1])
    # the back between the shoulder blades is hollow: the tape bridges part of it
    assert tape.length < skin.length
