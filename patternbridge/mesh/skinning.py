"""Linear blend skinning: re-pose a character with its skeleton and skin weights.

Conventions
-----------
A rotation given for a bone is a (3, 3) matrix in the **rest-pose frame** (the
character's axes: +X left, +Y up, +Z forward), applied about the bone's rest
head. It is composed down the hierarchy: a child bone is carried by every
rotation of its ancestors, then turned by its own. With ``G_b`` the resulting
4x4 world transform of bone ``b`` (identity at rest), a vertex moves to
``v' = Σ_k w_k G_{b_k} v`` (its four weights sum to 1).

Helpers build the rotations for the two pose changes the project needs: the
upper arms raised from the A-pose to a T-pose, and an elbow bent further.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping

import numpy as np

from ..errors import InputError
from .character import Character, Skeleton, Skin

__all__ = [
    "a_to_t_pose_rotations",
    "bend_elbow_rotations",
    "bone_transforms",
    "find_bone",
    "pose_skeleton",
    "pose_vertices",
    "rotation_about_axis",
    "rotation_between",
]

# candidate names per role, in order (MakeHuman default rig, Mixamo, Rigify/Blender)
_ROLES: dict[str, tuple[str, ...]] = {
    "upperarm": (
        "upperarm01{s}",
        "upper_arm{s}",
        "UpperArm{s}",
        "mixamorig:{side}Arm",
        "{side}Arm",
        "upperarm{s}",
    ),
    "lowerarm": (
        "lowerarm01{s}",
        "forearm{s}",
        "lower_arm{s}",
        "LowerArm{s}",
        "mixamorig:{side}ForeArm",
        "{side}ForeArm",
        "lowerarm{s}",
    ),
    "wrist": ("wrist{s}", "hand{s}", "Hand{s}", "mixamorig:{side}Hand", "{side}Hand"),
    "upperleg": (
        "upperleg01{s}",
        "thigh{s}",
        "UpperLeg{s}",
        "mixamorig:{side}UpLeg",
        "{side}UpLeg",
    ),
    "lowerleg": (
        "lowerleg01{s}",
        "shin{s}",
        "LowerLeg{s}",
        "mixamorig:{side}Leg",
        "{side}Leg",
    ),
    "foot": ("foot{s}", "Foot{s}", "mixamorig:{side}Foot", "{side}Foot"),
    "shoulder": (
        "shoulder01{s}",
        "clavicle{s}",
        "Shoulder{s}",
        "mixamorig:{side}Shoulder",
        "{side}Shoulder",
    ),
    "neck": ("neck01", "neck", "Neck", "mixamorig:Neck"),
    "head": ("head", "Head", "mixamorig:Head"),
    "pelvis": ("root", "pelvis", "Hips", "mixamorig:Hips", "hips"),
}


def find_bone(skeleton: Skeleton, role: str, side: str | None = None) -> int:
    """Index of the bone playing ``role`` (``"upperarm"``, ``"lowerarm"``, ``"wrist"``...).

    ``side`` is ``"left"`` (+X) or ``"right"``. Known rigs: MakeHuman default,
    Mixamo, Rigify-like ``.L/.R`` and ``_L/_R`` names.

    Raises
    ------
    InputError
        No bone of the skeleton matches.
    """
    suffixes = {
        "left": (".L", "_L", ".l", "_l", "Left"),
        "right": (".R", "_R", ".r", "_r", "Right"),
        None: ("",),
    }[side]
    word = {"left": "Left", "right": "Right", None: ""}[side]
    index = {n: i for i, n in enumerate(skeleton.names)}
    for pattern in _ROLES[role]:
        for s in suffixes:
            name = pattern.format(s=s, side=word)
            if name in index:
                return index[name]
    tried = ", ".join(p.format(s=suffixes[0], side=word) for p in _ROLES[role])
    raise InputError(
        f"skeleton: no {side + ' ' if side else ''}{role} bone (tried {tried}); "
        "rename the bones or give landmarks with --landmarks"
    )


def rotation_about_axis(axis, angle: float) -> np.ndarray:
    """(3, 3) rotation by ``angle`` radians about ``axis`` (right-hand rule).

    Examples
    --------
    >>> np.round(rotation_about_axis([0, 0, 1], np.pi / 2) @ [1, 0, 0], 12)
    array([0., 1., 0.])
    """
    a = np.asarray(axis, dtype=np.float64)
    a = a / np.linalg.norm(a)
    k = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * (k @ k)


def rotation_between(a, b) -> np.ndarray:
    """Smallest (3, 3) rotation taking direction ``a`` to direction ``b``."""
    a = np.asarray(a, dtype=np.float64) / np.linalg.norm(a)
    b = np.asarray(b, dtype=np.float64) / np.linalg.norm(b)
    axis = np.cross(a, b)
    s, c = np.linalg.norm(axis), float(np.dot(a, b))
    if s < 1e-12:
        if c > 0:
            return np.eye(3)
        perp = np.cross(a, [1.0, 0, 0] if abs(a[0]) < 0.9 else [0, 1.0, 0])
        return rotation_about_axis(perp, np.pi)
    return rotation_about_axis(axis, np.arctan2(s, c))


def _order(parents: np.ndarray) -> list[int]:
    """Bones ordered so that every parent comes before its children."""
    depth = np.zeros(len(parents), dtype=np.int64)
    for i in range(len(parents)):
        p, d = parents[i], 0
        while p >= 0 and d <= len(parents):
            p, d = parents[p], d + 1
        depth[i] = d
    return list(np.argsort(depth, kind="stable"))


def bone_transforms(
    skeleton: Skeleton, rotations: Mapping[str, np.ndarray]
) -> np.ndarray:
    """World transforms of every bone for the given local rotations.

    Parameters
    ----------
    skeleton : rest skeleton
    rotations : bone name -> (3, 3) rotation in the rest frame about the bone head

    Returns
    -------
    (B, 4, 4) float64, identity for bones neither rotated nor carried.

    Raises
    ------
    InputError
        A rotation names an unknown bone or is not a rotation matrix.
    """
    index = {n: i for i, n in enumerate(skeleton.names)}
    local = np.tile(np.eye(4), (len(index), 1, 1))
    for name, rot in rotations.items():
        if name not in index:
            raise InputError(
                f"skeleton: unknown bone {name!r} in the pose; use one of the skeleton's bone names"
            )
        r = np.asarray(rot, dtype=np.float64)
        if r.shape != (3, 3) or not np.allclose(r @ r.T, np.eye(3), atol=1e-6):
            raise InputError(
                f"skeleton: the rotation of {name!r} is not a 3x3 rotation matrix; fix the pose"
            )
        h = skeleton.heads[index[name]]
        m = np.eye(4)
        m[:3, :3] = r
        m[:3, 3] = h - r @ h
        local[index[name]] = m
    world = local.copy()
    for i in _order(skeleton.parents):
        p = skeleton.parents[i]
        if p >= 0:
            world[i] = world[p] @ local[i]
    return world


def pose_skeleton(skeleton: Skeleton, rotations: Mapping[str, np.ndarray]) -> Skeleton:
    """The skeleton with its heads and tails moved to the pose."""
    g = bone_transforms(skeleton, rotations)
    heads = np.einsum("bij,bj->bi", g[:, :3, :3], skeleton.heads) + g[:, :3, 3]
    tails = np.einsum("bij,bj->bi", g[:, :3, :3], skeleton.tails) + g[:, :3, 3]
    return Skeleton(
        names=skeleton.names, parents=skeleton.parents, heads=heads, tails=tails
    )


def pose_vertices(
    character: Character,
    rotations: Mapping[str, np.ndarray],
    *,
    vertices: np.ndarray | None = None,
    skin: Skin | None = None,
) -> np.ndarray:
    """Linear blend skinning of the character (or of other points weighted to its bones).

    Parameters
    ----------
    character : a rigged character (``skeleton`` and ``skin`` set)
    rotations : bone name -> (3, 3) rotation in the rest frame about the bone head
    vertices : (V, 3) float64, cm; defaults to the character's rest vertices
    skin : weights for ``vertices``; defaults to the character's skin

    Returns
    -------
    (V, 3) float64, cm: the posed positions.

    Raises
    ------
    InputError
        The character has no skeleton or skin weights.
    """
    if character.skeleton is None or (skin is None and character.skin is None):
        raise InputError(
            f"{character.name}: the character has no skeleton or skin weights; load a rigged file "
            "(GLB with a skin, or an OBJ with its JSON sidecar)"
        )
    skin = skin or character.skin
    v = (
        character.vertices
        if vertices is None
        else np.asarray(vertices, dtype=np.float64)
    )
    g = bone_transforms(character.skeleton, rotations)[:, :3, :]  # (B, 3, 4)
    idx = skin.bone_indices
    w = np.where(idx >= 0, skin.weights, 0.0)
    blend = np.einsum("vk,vkij->vij", w, g[np.maximum(idx, 0)])  # (V, 3, 4)
    return np.einsum("vij,vj->vi", blend[:, :, :3], v) + blend[:, :, 3]


def _sides(sides: str | Iterable[str]) -> tuple[str, ...]:
    return (sides,) if isinstance(sides, str) else tuple(sides)


def a_to_t_pose_rotations(
    skeleton: Skeleton, sides: str | Iterable[str] = ("left", "right")
) -> dict[str, np.ndarray]:
    """Rotations raising each upper arm to horizontal, pointing sideways (T-pose).

    The upper arm direction (shoulder joint to elbow joint) is turned by the
    smallest rotation onto ±X; the forearm keeps its bend relative to it.
    """
    out = {}
    for side in _sides(sides):
        ua = find_bone(skeleton, "upperarm", side)
        la = find_bone(skeleton, "lowerarm", side)
        d = skeleton.heads[la] - skeleton.heads[ua]
        target = np.array(
            [np.sign(d[0]) or (1.0 if side == "left" else -1.0), 0.0, 0.0]
        )
        out[skeleton.names[ua]] = rotation_between(d, target)
    return out


def bend_elbow_rotations(
    skeleton: Skeleton, side: str = "left", angle: float = np.pi / 4
) -> dict[str, np.ndarray]:
    """Rotation bending one elbow further by ``angle`` radians (in its flexion plane).

    The axis is normal to the plane of the upper arm and forearm at rest, so the
    angle between them grows by ``angle``. Combine with other rotations by
    merging the dicts (the elbow rotation is carried by the upper arm's).
    """
    ua = find_bone(skeleton, "upperarm", side)
    la = find_bone(skeleton, "lowerarm", side)
    wr = find_bone(skeleton, "wrist", side)
    u = skeleton.heads[la] - skeleton.heads[ua]
    f = skeleton.heads[wr] - skeleton.heads[la]
    axis = np.cross(u, f)
    if np.linalg.norm(axis) < 1e-9 * np.linalg.norm(u) * np.linalg.norm(f):
        axis = np.cross(u, [0.0, 0.0, 1.0])  # straight arm: bend toward the front
    return {skeleton.names[la]: rotation_about_axis(axis, angle)}
