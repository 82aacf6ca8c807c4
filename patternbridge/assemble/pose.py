"""The pose used for dressing tops, and the linear-blend-skinning round trip back to the rest pose.

A rigged character is dressed for tops with its arms straight (elbows
unbent) and :data:`DRESS_ARM_DROP_DEG` below the horizontal, 0: a T-pose,
the arms clear of the torso's bounding cylinder. (Lower arms let the
sleeve caps sew in with less pull on the sleeves, but at 15 and 35 degrees
the sleeves of the thin and the heavy body bunched up to the elbows and
the superhero's cloth caught between arm and torso; docs/assembly.md.)
After draping, the cloth follows the skin of the nearest body points back
to the rest pose (each garment vertex carries the blended bone transform of
its skin weights).
"""

from __future__ import annotations

import numpy as np

from ..mesh.character import Character

__all__ = [
    "DRESS_ARM_DROP_DEG",
    "apply_transforms",
    "blend_transforms",
    "dressing_rotvecs",
    "moved_bones",
    "rotations",
    "unapply_transforms",
]

DRESS_ARM_DROP_DEG = 0.0  # arms below the horizontal in the dressing pose (0: a T-pose)


def dressing_rotvecs(character: Character, drop_deg: float = DRESS_ARM_DROP_DEG) -> dict[str, np.ndarray]:
    """Rotation vectors (rad) per bone name taking the rest pose to the dressing pose.

    Both arms straight (elbows unbent), pointing sideways ``drop_deg``
    below the horizontal (0 gives a T-pose).

    Raises
    ------
    InputError
        The skeleton lacks an upper arm, lower arm or wrist bone
        (:func:`patternbridge.mesh.skinning.find_bone`).
    """
    from ..mesh.skinning import find_bone, rotation_between

    skel = character.skeleton
    out: dict[str, np.ndarray] = {}
    for side, sx in (("left", 1.0), ("right", -1.0)):
        ua = find_bone(skel, "upperarm", side)
        la = find_bone(skel, "lowerarm", side)
        wr = find_bone(skel, "wrist", side)
        a = np.radians(drop_deg)
        target = np.array([sx * np.cos(a), -np.sin(a), 0.0])
        r_up = rotation_between(skel.heads[la] - skel.heads[ua], target)
        # the forearm turns in the world frame after the upper arm did; its
        # rotation is given in the rest frame and carried by the upper arm's
        fore = r_up @ (skel.heads[wr] - skel.heads[la])
        r_fore = rotation_between(fore, target)
        out[skel.names[ua]] = _rotvec(r_up)
        out[skel.names[la]] = _rotvec(r_up.T @ r_fore @ r_up)
    return out


def _rotvec(r: np.ndarray) -> np.ndarray:
    from scipy.spatial.transform import Rotation

    return Rotation.from_matrix(r).as_rotvec()


def moved_bones(character: Character, rotvecs: dict[str, np.ndarray]) -> np.ndarray:
    """(B,) bool: the bones a pose of ``rotvecs`` moves (those it turns and every bone below them)."""
    from .bodyparts import first_ancestor

    skel = character.skeleton
    turned = {i for i, name in enumerate(skel.names) if name in rotvecs}
    return first_ancestor(skel.parents, turned) >= 0


def rotations(rotvecs: dict[str, np.ndarray], share: float) -> dict[str, np.ndarray]:
    """Bone name -> (3, 3) rotation matrix of ``share`` (0 = rest, 1 = full pose) of each rotation vector."""
    from scipy.spatial.transform import Rotation

    return {k: Rotation.from_rotvec(share * v).as_matrix() for k, v in rotvecs.items()}


def blend_transforms(
    character: Character, rots: dict[str, np.ndarray], joints: np.ndarray, weights: np.ndarray
) -> np.ndarray:
    """(N, 3, 4) per-vertex blended bone transforms (linear blend skinning).

    Parameters
    ----------
    rots : bone name -> (3, 3) local rotation (see :func:`rotations`)
    joints, weights : (N, K) int64 / float64 skin weights (-1 / 0 unused)
    """
    from ..mesh.skinning import bone_transforms

    g = bone_transforms(character.skeleton, rots)[:, :3, :]
    w = np.where(joints >= 0, weights, 0.0)
    return np.einsum("vk,vkij->vij", w, g[np.maximum(joints, 0)])


def apply_transforms(b: np.ndarray, x: np.ndarray) -> np.ndarray:
    """(N, 3) points ``x`` moved by the per-vertex transforms ``b`` (N, 3, 4)."""
    return np.einsum("vij,vj->vi", b[:, :, :3], x) + b[:, :, 3]


def unapply_transforms(b: np.ndarray, x: np.ndarray) -> np.ndarray:
    """(N, 3) points ``x`` moved back by the inverse of the per-vertex transforms ``b`` (N, 3, 4)."""
    return np.einsum("vij,vj->vi", np.linalg.inv(b[:, :, :3]), x - b[:, :, 3])
