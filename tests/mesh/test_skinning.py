"""Linear blend skinning and the pose helpers."""

from __future__ import annotations

import numpy as np
import pytest

from patternbridge.errors import InputError
from patternbridge.mesh.character import Character, Skeleton, Skin
from patternbridge.mesh.skinning import (
    a_to_t_pose_rotations,
    bend_elbow_rotations,
    pose_skeleton,
    pose_vertices,
    rotation_about_axis,
    rotation_between,
)


def _chain() -> Character:
    """Two bones along +X; vertex 0 on bone 0, vertex 1 on bone 1, vertex 2 half-half."""
    sk = Skeleton(
        names=("upper", "lower"),
        parents=[-1, 0],
        heads=[[0, 0, 0], [10, 0, 0]],
        tails=[[10, 0, 0], [20, 0, 0]],
    )
    skin = Skin(
        bone_indices=[[0, -1], [1, -1], [0, 1]], weights=[[1, 0], [1, 0], [0.5, 0.5]]
    )
    v = np.array([[5.0, 1, 0], [15.0, 1, 0], [10.0, 1, 0]])
    return Character(vertices=v, faces=[[0, 1, 2]], skeleton=sk, skin=skin)


def test_rest_pose_is_identity():
    c = _chain()
    np.testing.assert_allclose(pose_vertices(c, {}), c.vertices)


def test_rotation_about_the_head_and_hierarchy():
    c = _chain()
    r = rotation_about_axis([0, 0, 1], np.pi / 2)
    out = pose_vertices(c, {"upper": r})
    # the whole chain turns rigidly about the origin
    np.testing.assert_allclose(out, c.vertices @ r.T, atol=1e-12)
    out = pose_vertices(c, {"lower": r})
    np.testing.assert_allclose(out[0], c.vertices[0])
    np.testing.assert_allclose(
        out[1], [9.0, 5.0, 0.0], atol=1e-12
    )  # (15,1) about (10,0)
    # composed: the lower bone is carried by the upper one
    both = pose_vertices(c, {"upper": r, "lower": r})
    np.testing.assert_allclose(both[1], r @ [9.0, 5.0, 0.0], atol=1e-12)
    # blended vertex: average of the two transforms
    np.testing.assert_allclose(
        out[2], 0.5 * (c.vertices[2] + (r @ (c.vertices[2] - [10, 0, 0]) + [10, 0, 0]))
    )


def test_pose_skeleton_moves_children():
    c = _chain()
    r = rotation_about_axis([0, 0, 1], np.pi / 2)
    sk = pose_skeleton(c.skeleton, {"upper": r})
    np.testing.assert_allclose(sk.heads[1], [0, 10, 0], atol=1e-12)
    np.testing.assert_allclose(sk.tails[1], [0, 20, 0], atol=1e-12)


def test_rotation_between():
    for a, b in [
        ([1, 0, 0], [0, 1, 0]),
        ([1, 2, 3], [-3, 1, 0.5]),
        ([0, 0, 1], [0, 0, -1]),
    ]:
        r = rotation_between(a, b)
        np.testing.assert_allclose(r @ r.T, np.eye(3), atol=1e-12)
        np.testing.assert_allclose(
            r @ (np.array(a) / np.linalg.norm(a)),
            np.array(b) / np.linalg.norm(b),
            atol=1e-12,
        )


def test_bad_poses():
    c = _chain()
    with pytest.raises(InputError, match="unknown bone 'femur'"):
        pose_vertices(c, {"femur": np.eye(3)})
    with pytest.raises(InputError, match="not a 3x3 rotation"):
        pose_vertices(c, {"upper": np.eye(3) * 2})
    bare = Character(vertices=c.vertices, faces=c.faces)
    with pytest.raises(InputError, match="no skeleton"):
        pose_vertices(bare, {})


@pytest.mark.shared
def test_a_to_t_and_elbow_on_a_character(characters_dir):
    from patternbridge.mesh.load import load_character

    c, _ = load_character(characters_dir / "E_average_male.obj")
    sk = c.skeleton
    rot = a_to_t_pose_rotations(sk)
    posed = pose_skeleton(sk, rot)
    ua, la, wr = (sk.index(n) for n in ("upperarm01.L", "lowerarm01.L", "wrist.L"))
    d = posed.heads[la] - posed.heads[ua]
    assert abs(d[1]) < 1e-9 and abs(d[2]) < 1e-9 and d[0] > 0  # horizontal, sideways
    # the elbow bends by exactly 45 degrees more
    bend = {**rot, **bend_elbow_rotations(sk, "left", np.pi / 4)}
    posed2 = pose_skeleton(sk, bend)

    def elbow_angle(s):
        u = s.heads[la] - s.heads[ua]
        f = s.heads[wr] - s.heads[la]
        return np.arccos(u @ f / np.linalg.norm(u) / np.linalg.norm(f))

    assert elbow_angle(posed2) - elbow_angle(posed) == pytest.approx(
        np.pi / 4, abs=1e-9
    )
    v = pose_vertices(c, bend)
    assert v.shape == c.vertices.shape and np.all(np.isfinite(v))
    # legs do not move
    knee = c.landmarks["knee_point_left"].vertex
    np.testing.assert_allclose(v[knee], c.vertices[knee], atol=1e-9)
