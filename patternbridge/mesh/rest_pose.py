"""The measuring rest pose: raised arms brought down by the character's own rig.

Size charts and tailors measure a body standing with its arms down. A T-posed
character lifts the armpit skin, the latissimus and the trapezius with its arms,
so its chest, under-bust and neck sections are not those of the chart (the
T-posed B measures a chest 4 % larger). :func:`arms_down` re-poses a rigged
character whose upper arms are raised (less than :data:`RAISED_BELOW_DEG`
below horizontal) so that each upper arm points :data:`REST_BELOW_DEG` below
horizontal, keeping its direction in the horizontal plane and the elbow's
bend. The lowering is shared between the clavicle, shoulder and upper-arm bones
(those of them the rig has) as MPFB2 shares a T-pose lift (10 : 8 : 30), so the
shoulder and trapezius skin come down with the arm instead of folding.

Linear blend skinning is approximate: posing back and forth does not return
the exact skin, and the skin of the armpit region follows the rig's weights.
The vertex order is kept, so landmarks found on the rest body carry back to
the given pose by vertex id.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ..errors import InputError
from .character import Character
from .skinning import find_bone, pose_skeleton, pose_vertices, rotation_about_axis

__all__ = ["RAISED_BELOW_DEG", "REST_BELOW_DEG", "RestPose", "arm_elevations_deg", "arms_down"]

RAISED_BELOW_DEG = 30.0  # upper arms less than this below horizontal count as raised
REST_BELOW_DEG = 45.0  # the measuring rest pose: upper arms this far below horizontal
#: shares of the lowering per bone of the shoulder chain (MPFB2's T-pose lift split)
LIFT_SHARES = {"clavicle": 10.0, "shoulder": 8.0, "upperarm": 30.0}


def _shoulder_chain(sk, ua: int) -> list[tuple[str, int]]:
    """(role, bone) of the upper arm and of its ancestors named clavicle or shoulder."""
    chain = [("upperarm", ua)]
    b = int(sk.parents[ua])
    for _ in range(3):
        if b < 0:
            break
        name = sk.names[b].lower()
        role = "clavicle" if "clavicle" in name else ("shoulder" if "shoulder" in name else None)
        if role is None or any(r == role for r, _ in chain):
            break
        chain.append((role, b))
        b = int(sk.parents[b])
    return chain


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class RestPose:
    """A character brought to the measuring rest pose.

    character : the re-posed character (same vertex order, landmarks moved with their vertices)
    lowered_deg : side -> how far each upper arm was lowered
    """

    character: Character
    lowered_deg: dict[str, float]


def _upper_arm(character: Character, side: str) -> tuple[int, np.ndarray]:
    sk = character.skeleton
    ua = find_bone(sk, "upperarm", side)
    la = find_bone(sk, "lowerarm", side)
    return ua, sk.heads[la] - sk.heads[ua]


def arm_elevations_deg(character: Character) -> dict[str, float]:
    """Side -> elevation of the upper arm (shoulder joint to elbow joint) above horizontal, degrees."""
    out = {}
    for side in ("left", "right"):
        try:
            _, d = _upper_arm(character, side)
        except InputError:
            continue
        out[side] = float(np.degrees(np.arctan2(d[1], np.hypot(d[0], d[2]))))
    return out


def arms_down(character: Character) -> RestPose | None:
    """The character with raised upper arms lowered to the rest pose, or None when nothing is to do.

    None when the character has no skeleton or skin, no upper-arm bones, or
    arms already down.
    """
    if character.skeleton is None or character.skin is None:
        return None
    sk = character.skeleton
    rotations: dict[str, np.ndarray] = {}
    lowered: dict[str, float] = {}
    for side, elevation in arm_elevations_deg(character).items():
        if elevation < -RAISED_BELOW_DEG:
            continue
        ua, d = _upper_arm(character, side)
        horizontal = np.array([d[0], 0.0, d[2]])
        axis = np.cross([0.0, 1.0, 0.0], horizontal)  # turning about it lowers the arm
        angle = np.radians(elevation + REST_BELOW_DEG)
        chain = _shoulder_chain(sk, ua)
        total = sum(LIFT_SHARES[role] for role, _ in chain)
        for role, b in chain:
            rotations[sk.names[b]] = rotation_about_axis(axis, angle * LIFT_SHARES[role] / total)
        lowered[side] = float(np.degrees(angle))
    if not rotations:
        return None
    v = pose_vertices(character, rotations)
    marks = {k: lm.moved_to(v, character.faces) for k, lm in character.landmarks.items()}
    posed = replace(
        character,
        vertices=v,
        skeleton=pose_skeleton(sk, rotations),
        landmarks=marks,
        assumed={**character.assumed, "pose": "upper arms lowered to 45° below horizontal for measuring"},
    )
    return RestPose(character=posed, lowered_deg=lowered)
