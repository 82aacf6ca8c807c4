"""Limbs touching the torso: a warning and a best-effort dressing (shared character posed with its arms down)."""

from __future__ import annotations

import numpy as np
import pytest

from patternbridge.assemble import assemble
from patternbridge.assemble.bodyparts import segment_body
from patternbridge.assemble.checks import limbs_touching
from patternbridge.mesh.character import Character, Landmark
from patternbridge.report import Report


def _arms_down(character: Character, inward: float) -> Character:
    """The character with both upper arms turned down along the torso (linear blend skinning).

    ``inward`` tilts the arms toward the body (x share of the unit direction),
    so that they press against the hips as in a relaxed stance.
    """
    from patternbridge.mesh.skinning import find_bone, pose_skeleton, pose_vertices, rotation_between

    skel = character.skeleton
    rots = {}
    for side, sx in (("left", 1.0), ("right", -1.0)):
        ua = find_bone(skel, "upperarm", side)
        la = find_bone(skel, "lowerarm", side)
        target = np.array([-sx * inward, -1.0, 0.0])
        rots[skel.names[ua]] = rotation_between(skel.heads[la] - skel.heads[ua], target / np.linalg.norm(target))
    v = pose_vertices(character, rots)
    landmarks = {
        n: Landmark(name=n, position=v[lm.vertex] if lm.vertex is not None else lm.position, vertex=lm.vertex)
        for n, lm in character.landmarks.items()
    }
    return Character(
        vertices=v,
        faces=character.faces,
        name=f"{character.name}-arms-down",
        skeleton=pose_skeleton(skel, rots),
        skin=character.skin,
        landmarks=landmarks,
    )


@pytest.fixture(scope="module")
def arms_down(character_e) -> Character:
    return _arms_down(character_e, inward=0.12)


@pytest.mark.shared
def test_arms_down_against_the_torso_warn_and_the_a_pose_does_not(character_e, arms_down):
    rest = Report()
    assert limbs_touching(np.asarray(character_e.vertices), segment_body(character_e), rest, "E") == 0
    assert not [f for f in rest if f.code == "limbs-touching"]
    report = Report()
    n = limbs_touching(np.asarray(arms_down.vertices), segment_body(arms_down), report, "E-down")
    texts = [str(f) for f in report if f.code == "limbs-touching"]
    assert n >= 2, texts
    assert any("left arm" in t for t in texts) and any("right arm" in t for t in texts)


@pytest.mark.shared
@pytest.mark.slow
def test_trousers_on_arms_down_are_dressed_with_a_warning_and_nothing_inside(arms_down):
    from patternbridge.library import load_garment

    g = assemble(arms_down, load_garment("trousers"), max_edge_cm=5.0, steps=40, seed=2)
    warnings = [w for w in g.report.warnings if "limbs-touching" in w]
    assert warnings, g.report.warnings
    assert g.report.penetrating_vertices == 0
    # a best effort, but still trousers: from the feet to the waist
    assert g.vertices[:, 1].min() < 25.0 and g.vertices[:, 1].max() > 90.0
