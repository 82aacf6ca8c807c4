"""Segment a character into body parts: torso, head, arms and legs.

A rigged character is split by its skin weights: every bone belongs to the
part of the first limb root above it in the hierarchy (upper arm, upper leg,
neck), the others to the torso, and each vertex goes to the part that holds
most of its weight. Without a rig, cut planes at the landmarks do the same
job: below the crotch is a leg, beyond the armpit an arm, above the neck
points the head.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np

from ..errors import LandmarkError
from ..mesh.character import Character
from ..pattern.model import BodyPart

__all__ = [
    "HAND_SHARE",
    "PARTS",
    "BodyParts",
    "crotch_height",
    "first_ancestor",
    "hand_masks",
    "limb_axis",
    "segment_body",
]

log = logging.getLogger(__name__)

#: the parts in label order (the neck is part of the head)
PARTS: tuple[BodyPart, ...] = (
    BodyPart.TORSO,
    BodyPart.HEAD,
    BodyPart.LEFT_ARM,
    BodyPart.RIGHT_ARM,
    BodyPart.LEFT_LEG,
    BodyPart.RIGHT_LEG,
)
_INDEX = {part: i for i, part in enumerate(PARTS)}


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class BodyParts:
    """Per-vertex body-part labels.

    labels : (V,) int64 index into :data:`PARTS`
    source : ``"skin"`` (from the skin weights) or ``"landmarks"`` (cut planes)
    """

    labels: np.ndarray
    source: str

    def mask(self, part: BodyPart | str) -> np.ndarray:
        """(V,) bool: the vertices of ``part`` (the enum or its value; the neck counts as the head)."""
        part = BodyPart(part)
        return self.labels == _INDEX[BodyPart.HEAD if part is BodyPart.NECK else part]


def _bone_parts(character: Character) -> np.ndarray:
    from ..mesh.skinning import find_bone

    skel = character.skeleton
    roots: dict[int, int] = {}
    for role, side, part in (
        ("upperarm", "left", BodyPart.LEFT_ARM),
        ("upperarm", "right", BodyPart.RIGHT_ARM),
        ("upperleg", "left", BodyPart.LEFT_LEG),
        ("upperleg", "right", BodyPart.RIGHT_LEG),
        ("neck", None, BodyPart.HEAD),
    ):
        try:
            roots[find_bone(skel, role, side)] = _INDEX[part]
        except Exception:  # a rig without that bone: the part falls back to the torso
            continue
    first = first_ancestor(skel.parents, set(roots))
    return np.array([roots.get(int(r), _INDEX[BodyPart.TORSO]) for r in first], dtype=np.int64)


def first_ancestor(parents: np.ndarray, roots: set[int]) -> np.ndarray:
    """(B,) int64: for every bone the first of ``roots`` met walking up from it (itself included), else -1."""
    out = np.full(len(parents), -1, dtype=np.int64)
    for b in range(len(parents)):
        k = b
        while k >= 0 and k not in roots:
            k = int(parents[k])
        out[b] = k
    return out


def limb_axis(points: np.ndarray, toward: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Centre (3,) and unit principal axis (3,) of a limb's ``points`` (n, 3), the axis pointing to ``toward``."""
    c = points.mean(axis=0)
    axis = np.linalg.svd(points - c, full_matrices=False)[2][0]
    axis = axis / np.linalg.norm(axis)
    return c, (axis if axis @ (toward - c) >= 0 else -axis)


def _from_skin(character: Character) -> np.ndarray:
    bone_part = _bone_parts(character)
    idx = character.skin.bone_indices
    w = np.where(idx >= 0, character.skin.weights, 0.0)
    part = bone_part[np.maximum(idx, 0)]
    acc = np.zeros((len(idx), len(PARTS)))
    np.add.at(acc, (np.repeat(np.arange(len(idx)), idx.shape[1]), part.ravel()), w.ravel())
    return np.argmax(acc, axis=1).astype(np.int64)


def _from_landmarks(character: Character, vertices: np.ndarray) -> np.ndarray:
    lm = {name: mark.at(vertices, character.faces) for name, mark in character.landmarks.items()}
    need = (
        "crotch_point",
        "armpit_point_left",
        "armpit_point_right",
        "front_neck_point",
        "back_neck_point",
    )
    missing = [n for n in need if n not in lm]
    if missing:
        raise LandmarkError(
            f"{character.name}: cannot segment the body without a rig ({', '.join(missing)} missing); "
            "give these landmarks with --landmarks FILE or load a rigged character"
        )
    x, y = vertices[:, 0], vertices[:, 1]
    labels = np.full(len(vertices), _INDEX[BodyPart.TORSO], dtype=np.int64)
    crotch_y = lm["crotch_point"][1]
    legs = y < crotch_y
    labels[legs & (x >= 0)] = _INDEX[BodyPart.LEFT_LEG]
    labels[legs & (x < 0)] = _INDEX[BodyPart.RIGHT_LEG]
    ax_l, ax_r = lm["armpit_point_left"], lm["armpit_point_right"]
    arms_l = (x > ax_l[0]) & ~legs
    arms_r = (x < ax_r[0]) & ~legs
    labels[arms_l] = _INDEX[BodyPart.LEFT_ARM]
    labels[arms_r] = _INDEX[BodyPart.RIGHT_ARM]
    neck_y = 0.5 * (lm["front_neck_point"][1] + lm["back_neck_point"][1])
    head = (y > neck_y) & ~arms_l & ~arms_r
    labels[head] = _INDEX[BodyPart.HEAD]
    return labels


def segment_body(character: Character, *, vertices: np.ndarray | None = None) -> BodyParts:
    """Label every body vertex with its part.

    Parameters
    ----------
    character : the character (rigged or with landmarks)
    vertices : (V, 3) float64, cm, optional posed positions for the landmark
        cut planes; the skin-weight split does not depend on the pose.

    Returns
    -------
    :class:`BodyParts`

    Raises
    ------
    LandmarkError
        The character has no rig and lacks the crotch, armpit or neck landmarks.
    """
    v = character.vertices if vertices is None else np.asarray(vertices, dtype=np.float64)
    if character.skeleton is not None and character.skin is not None:
        labels = _from_skin(character)
        if np.all(np.bincount(labels, minlength=len(PARTS))[2:] > 0):
            return BodyParts(labels=labels, source="skin")
        log.warning(
            "%s: skin weights do not name four limbs; cutting at the landmarks",
            character.name,
        )
    return BodyParts(labels=_from_landmarks(character, v), source="landmarks")


def crotch_height(character: Character, vertices: np.ndarray, parts: BodyParts) -> float | None:
    """Height (y, cm) of the crotch in ``vertices`` (V, 3), or None.

    The ``crotch_point`` landmark's surface point, else the top of the legs;
    None when the landmark has no vertex and no vertex is labelled a leg.
    """
    lm = character.landmarks.get("crotch_point")
    if lm is not None and (lm.vertex is not None or lm.face is not None):
        return float(lm.at(vertices, character.faces)[1])
    legs = parts.mask(BodyPart.LEFT_LEG) | parts.mask(BodyPart.RIGHT_LEG)
    return float(vertices[legs, 1].max()) if legs.any() else None


HAND_SHARE = 0.22  # share of an arm's length taken by the hand, when there is no wrist bone to go by


def hand_masks(character: Character, vertices: np.ndarray, parts: BodyParts) -> list[np.ndarray]:
    """(V,) bool masks of the hands (the vertices beyond each wrist), one per arm the body has.

    A rigged character's hand is what the wrist bone and the bones below
    it hold most of; otherwise the distal :data:`HAND_SHARE` of the arm
    along its principal axis, pointing away from the torso.
    """
    from ..mesh.skinning import find_bone

    v = np.asarray(vertices, dtype=np.float64)
    out = []
    skel, skin = character.skeleton, character.skin
    torso_c = v[parts.mask(BodyPart.TORSO)].mean(axis=0) if parts.mask(BodyPart.TORSO).any() else v.mean(axis=0)
    for side, part in (("left", BodyPart.LEFT_ARM), ("right", BodyPart.RIGHT_ARM)):
        arm = parts.mask(part)
        if not arm.any():
            continue
        mask = None
        if skel is not None and skin is not None:
            try:
                wrist = find_bone(skel, "wrist", side)
            except Exception:  # no wrist bone: cut by the arm's length below
                wrist = None
            if wrist is not None:
                below = first_ancestor(skel.parents, {wrist}) == wrist
                idx = skin.bone_indices
                w = np.where((idx >= 0) & below[np.maximum(idx, 0)], skin.weights, 0.0).sum(axis=1)
                mask = arm & (w > 0.5)
        if mask is None or not mask.any():
            c, axis = limb_axis(v[arm], torso_c)
            h = (v - c) @ axis
            mask = arm & (h < h[arm].min() + HAND_SHARE * np.ptp(h[arm]))
        out.append(mask)
    return out
