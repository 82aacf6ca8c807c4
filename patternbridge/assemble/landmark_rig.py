"""An arm rig from landmarks, so a character without one can still be dressed with its arms raised.

Tops are sewn in a T-pose and brought down to the rest pose by linear
blend skinning (``pose.py``). A mesh without a skeleton would be dressed in
its rest pose, where the sleeves cannot be laid round arms that hang beside
the torso (E's OBJ alone: armholes 16 cm open before welding). The rig here
has a root bone for the torso, a still bone for each leg and the head, and, per arm, an upper arm
(from the shoulder joint, between the shoulder point and the armpit, to the
elbow point), a forearm (elbow to wrist point) and a hand; arm vertices
(cut at the landmarks, :func:`~patternbridge.assemble.bodyparts.segment_body`)
blend between neighbouring bones over a few centimetres at the shoulder,
elbow and wrist. It is used for posing only: the written garment carries no
skin weights, since the character has no skeleton to bind them to.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..errors import LandmarkError
from ..mesh.character import Character, Skeleton, Skin
from ..pattern.model import BodyPart

__all__ = ["ARM_LANDMARKS", "landmark_rig"]

ARM_LANDMARKS = ("shoulder_point_{s}", "armpit_point_{s}", "elbow_point_{s}", "wrist_point_{s}")
"""Landmarks each arm needs (``{s}`` is ``left`` or ``right``)."""

SHOULDER_JOINT = 0.4  # the joint lies this share of the way from the shoulder point to the armpit
BLEND_CM = {"shoulder": 5.0, "elbow": 4.0, "wrist": 2.0}  # half-widths of the blends along the arm


def _ramp(d: np.ndarray, half: float) -> np.ndarray:
    """0 before ``-half``, 1 after ``+half``, smooth in between (smoothstep)."""
    t = np.clip(0.5 + d / (2.0 * half), 0.0, 1.0)
    return t * t * (3.0 - 2.0 * t)


def landmark_rig(character: Character) -> Character | None:
    """``character`` with a skeleton and skin weights built from its arm landmarks, or None when it lacks any.

    Bone names follow the ``upperarm_L`` / ``forearm_L`` / ``hand_L`` pattern
    :func:`patternbridge.mesh.skinning.find_bone` knows; the root is
    ``root``, the still ones ``thigh_L``, ``thigh_R`` and ``neck``. Every
    vertex has two weights.
    """
    from .bodyparts import segment_body

    names = [f.format(s=s) for s in ("left", "right") for f in ARM_LANDMARKS]
    if any(n not in character.landmarks for n in names) or "crotch_point" not in character.landmarks:
        return None
    v = np.asarray(character.vertices, dtype=np.float64)
    try:
        parts = segment_body(character, vertices=v)
    except LandmarkError:  # landmarks the cut planes need are missing: no rig
        return None
    p = character.landmark_position
    bone_names = ["root"]
    parents = [-1]
    heads = [p("crotch_point")]
    top = p("front_neck_point") if "front_neck_point" in character.landmarks else heads[0] + [0.0, 50.0, 0.0]
    tails = [top]
    n_bones = 10  # root, three per arm, two thighs, the neck
    w = np.zeros((len(v), n_bones))
    w[:, 0] = 1.0
    for k, (side, tag) in enumerate((("left", "L"), ("right", "R"))):
        s, a, e, r = (p(f.format(s=side)) for f in ARM_LANDMARKS)
        joint = s + SHOULDER_JOINT * (a - s)
        hand_tip = r + 0.4 * (r - e)
        base = 1 + 3 * k
        bone_names += [f"upperarm_{tag}", f"forearm_{tag}", f"hand_{tag}"]
        parents += [0, base, base + 1]
        heads += [joint, e, r]
        tails += [e, r, hand_tip]
        arm = parts.mask(f"{side}_arm")
        x = v[arm]
        up = (e - joint) / np.linalg.norm(e - joint)
        fore = (r - e) / np.linalg.norm(r - e)
        on_arm = _ramp((x - joint) @ up, BLEND_CM["shoulder"])  # the shoulder blends into the torso
        lower = _ramp((x - e) @ up, BLEND_CM["elbow"])
        hand = _ramp((x - r) @ fore, BLEND_CM["wrist"])
        wa = np.zeros((len(x), n_bones))
        wa[:, 0] = 1.0 - on_arm
        wa[:, base] = on_arm * (1.0 - lower)
        wa[:, base + 1] = on_arm * lower * (1.0 - hand)
        wa[:, base + 2] = on_arm * lower * hand
        w[arm] = wa
    # the legs and the head hang from bones of their own that never move, so
    # the skin weights name the same body parts as the landmark cut planes
    for part, name, down in (
        (BodyPart.LEFT_LEG, "thigh_L", True),
        (BodyPart.RIGHT_LEG, "thigh_R", True),
        (BodyPart.HEAD, "neck", False),
    ):
        mask = parts.mask(part)
        pts = v[mask] if mask.any() else heads[0][None, :]
        bone_names.append(name)
        parents.append(0)
        heads.append(pts[np.argmax(pts[:, 1])])
        tails.append(pts[np.argmin(pts[:, 1])] if down else pts[np.argmax(pts[:, 1])] + [0.0, 1.0, 0.0])
        w[mask] = 0.0
        w[mask, len(bone_names) - 1] = 1.0
    # two bones per vertex: the largest two weights, renormalised
    order = np.argsort(-w, axis=1)[:, :2]
    top2 = np.take_along_axis(w, order, axis=1)
    top2 /= top2.sum(axis=1, keepdims=True)
    skeleton = Skeleton(
        names=tuple(bone_names), parents=np.array(parents), heads=np.array(heads), tails=np.array(tails)
    )
    return replace(character, skeleton=skeleton, skin=Skin(bone_indices=order, weights=top2))
