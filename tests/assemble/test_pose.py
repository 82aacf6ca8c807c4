"""The dressing pose of tops: arms straight, at a chosen angle below the horizontal."""

from __future__ import annotations

import numpy as np
import pytest

from patternbridge.assemble.pose import dressing_rotvecs, rotations
from patternbridge.mesh.skinning import find_bone, pose_skeleton


@pytest.mark.shared
@pytest.mark.parametrize("drop_deg", [0.0, 35.0])
def test_dressing_pose_straightens_the_arms_at_the_angle(character_e, drop_deg):
    skel = character_e.skeleton
    posed = pose_skeleton(skel, rotations(dressing_rotvecs(character_e, drop_deg), 1.0))
    for side, sx in (("left", 1.0), ("right", -1.0)):
        ua, la, wr = (find_bone(skel, role, side) for role in ("upperarm", "lowerarm", "wrist"))
        upper = posed.heads[la] - posed.heads[ua]
        fore = posed.heads[wr] - posed.heads[la]
        want = np.array([sx * np.cos(np.radians(drop_deg)), -np.sin(np.radians(drop_deg)), 0.0])
        np.testing.assert_allclose(upper / np.linalg.norm(upper), want, atol=1e-9)
        np.testing.assert_allclose(fore / np.linalg.norm(fore), want, atol=1e-9)  # the elbow unbent
        # bones keep their lengths, and the shoulder does not move
        np.testing.assert_allclose(np.linalg.norm(upper), np.linalg.norm(skel.heads[la] - skel.heads[ua]))
        np.testing.assert_allclose(posed.heads[ua], skel.heads[ua], atol=1e-9)
    # in the rest pose the arms hang about 48 degrees below the horizontal: the
    # half-share pose lies between
    half = pose_skeleton(skel, rotations(dressing_rotvecs(character_e, 0.0), 0.5))
    ua, la = find_bone(skel, "upperarm", "left"), find_bone(skel, "lowerarm", "left")
    d = half.heads[la] - half.heads[ua]
    assert 15.0 < np.degrees(np.arctan2(-d[1], np.hypot(d[0], d[2]))) < 35.0
