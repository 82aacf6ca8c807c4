"""Datum points (landmarks): from a file, from the skeleton's joints, or detected from the geometry.

:func:`resolve_landmarks` fills the table of :data:`LANDMARK_NAMES` and
records for every point its source (``"file"``, ``"skeleton"``,
``"detected"``), a confidence and the evidence:

1. the character's own landmarks (sidecar JSON or ``--landmarks FILE``),
   confidence 1;
2. the skeleton, when the character is rigged: each joint is projected to the
   skin along a documented direction (:data:`SKELETON_RULES`), confidence 0.8;
3. detection from the geometry (:mod:`patternbridge.mesh.landmark_detect`, one
   function per body region), anchored on the points of 1 and 2; for the names
   in :data:`GEOMETRY_FIRST` the geometry's point competes with the rig's and
   the more confident one is kept;
4. the plausibility checks of :mod:`patternbridge.mesh.landmark_checks`
   (order along the arm and the torso, the midline, left/right symmetry).

``docs/measurements.md`` gives the errors against the reference tables of the
test characters and their variants.
"""

from __future__ import annotations

import logging
from collections.abc import Mapping

import numpy as np

from ..errors import InputError, LandmarkError
from .character import Character, Landmark, LandmarkEvidence, LandmarkSource
from .landmark_detect import _ray_hit, detect_landmarks

__all__ = [
    "LANDMARK_NAMES",
    "SKELETON_RULES",
    "detect_landmarks",
    "landmark_errors",
    "resolve_landmarks",
    "skeleton_landmarks",
]

log = logging.getLogger(__name__)

#: The landmark vocabulary (as in ``shared/characters/landmarks.json``); left = +X.
LANDMARK_NAMES: tuple[str, ...] = (
    "top_of_head",
    "front_neck_point",
    "back_neck_point",
    "neck_shoulder_point_left",
    "neck_shoulder_point_right",
    "shoulder_point_left",
    "shoulder_point_right",
    "armpit_point_left",
    "armpit_point_right",
    "axilla_front_left",
    "axilla_front_right",
    "axilla_back_left",
    "axilla_back_right",
    "bust_point_left",
    "bust_point_right",
    "waist_front",
    "waist_back",
    "waist_side_left",
    "waist_side_right",
    "buttock_point_left",
    "buttock_point_right",
    "hip_side_left",
    "hip_side_right",
    "crotch_point",
    "elbow_point_left",
    "elbow_point_right",
    "wrist_point_left",
    "wrist_point_right",
    "knee_point_left",
    "knee_point_right",
    "ankle_inside_left",
    "ankle_inside_right",
    "ankle_outside_left",
    "ankle_outside_right",
    "heel_point_left",
    "heel_point_right",
)

_SIGN = {"left": 1.0, "right": -1.0}

#: names the geometry places better than a joint projection when its rule finds
#: its feature. The skin straight above the shoulder joint lies 2-3 cm inside
#: the acromion corner, and the skin behind the neck joint depends on where a
#: rig puts that joint (1.5 cm below the nape on the T-posed B), while the
#: nape is where the neck section widens into the shoulders. Rig and detection
#: both propose these; the more confident one is taken (a found feature: 0.85,
#: the rig: 0.8, a level T-pose arm without a shoulder corner: 0.45). The
#: crotch projected straight down from between the hip joints lies 1.7-2.5 cm
#: off the meeting point of the inseams on the rigged D and B, which the
#: geometry finds where the legs separate. The skin in front of and below the
#: neck joint lies a median 3.2 cm off the jugular notch on the six test
#: bodies; the neck/chest corner of the front midline profile, its chord held
#: below the chin, lies on it or one vertex row away (median 0.0).
GEOMETRY_FIRST = frozenset(
    {"shoulder_point_left", "shoulder_point_right", "back_neck_point", "front_neck_point", "crotch_point"}
)


# --------------------------------------------------------------------------- skeleton
#: landmark -> (bone role, side or None, "head"/"tail", projection direction in the rest frame)
SKELETON_RULES: dict[str, tuple[str, str | None, str, tuple[float, float, float]]] = {
    **{f"shoulder_point_{s}": ("upperarm", s, "head", (0.0, 1.0, 0.0)) for s in ("left", "right")},
    **{f"armpit_point_{s}": ("upperarm", s, "head", (0.0, -1.0, 0.0)) for s in ("left", "right")},
    **{f"elbow_point_{s}": ("lowerarm", s, "head", (0.0, 0.0, -1.0)) for s in ("left", "right")},
    **{f"wrist_point_{s}": ("wrist", s, "head", (0.0, 0.0, -1.0)) for s in ("left", "right")},
    **{f"knee_point_{s}": ("lowerleg", s, "head", (0.0, 0.0, 1.0)) for s in ("left", "right")},
    **{f"ankle_inside_{s}": ("foot", s, "head", (-_SIGN[s], 0.0, 0.0)) for s in ("left", "right")},
    **{f"ankle_outside_{s}": ("foot", s, "head", (_SIGN[s], 0.0, 0.0)) for s in ("left", "right")},
    **{f"heel_point_{s}": ("foot", s, "head", (0.0, -0.5, -1.0)) for s in ("left", "right")},
    "back_neck_point": ("neck", None, "head", (0.0, 0.0, -1.0)),
    "front_neck_point": ("neck", None, "head", (0.0, -0.45, 1.0)),
    "crotch_point": (
        "pelvis",
        None,
        "head",
        (0.0, -1.0, 0.0),
    ),  # from between the hip joints
}


def skeleton_landmarks(character: Character) -> dict[str, Landmark]:
    """Landmarks from the skeleton's joints projected to the skin (:data:`SKELETON_RULES`).

    The elbow point is projected to the outer side of the elbow's bend when the
    arm is bent (the direction from the forearm toward the upper arm), else
    backwards. Joints the skeleton does not have are skipped.
    """
    from .skinning import find_bone

    sk = character.skeleton
    if sk is None:
        return {}
    v = character.vertices
    radius = 0.008 * character.stature_cm
    out: dict[str, Landmark] = {}
    for name, (role, side, end, direction) in SKELETON_RULES.items():
        try:
            b = find_bone(sk, role, side)
        except InputError:
            continue
        joint = sk.heads[b] if end == "head" else sk.tails[b]
        d = np.asarray(direction, dtype=np.float64)
        if name == "crotch_point":  # between the hip joints, not at the pelvis root
            try:
                joint = 0.5 * (
                    sk.heads[find_bone(sk, "upperleg", "left")] + sk.heads[find_bone(sk, "upperleg", "right")]
                )
            except InputError:
                pass
        if name.startswith("elbow_point"):
            try:
                ua = find_bone(sk, "upperarm", side)
                wr = find_bone(sk, "wrist", side)
                u = joint - sk.heads[ua]
                f = sk.heads[wr] - joint
                bend = u / np.linalg.norm(u) - f / np.linalg.norm(f)
                if np.linalg.norm(bend) > 0.2:
                    d = bend
            except InputError:
                pass
        if name.startswith("wrist_point"):
            try:  # the ulna runs from the olecranon to the styloid: the elbow's outer side, square to the forearm
                el = sk.heads[find_bone(sk, "lowerarm", side)]
                u = el - sk.heads[find_bone(sk, "upperarm", side)]
                f = joint - el
                u, f = u / np.linalg.norm(u), f / np.linalg.norm(f)
                bend = u - f
                if np.linalg.norm(bend) > 0.2:
                    d = bend - (bend @ f) * f
            except InputError:
                pass
        hit = _ray_hit(v, joint, d, radius)
        if hit is not None:
            out[name] = Landmark(
                name=name,
                position=v[hit],
                vertex=hit,
                source=LandmarkSource.SKELETON,
                evidence=LandmarkEvidence(
                    rule=f"{sk.names[b]} joint {end} projected to the skin along "
                    f"({d[0]:+.2f}, {d[1]:+.2f}, {d[2]:+.2f})"
                ),
            )
    return out


def resolve_landmarks(character: Character, *, detect: bool = True, check: bool = True) -> dict[str, Landmark]:
    """The character's landmarks, completed from the skeleton and then the geometry, then checked.

    Parameters
    ----------
    character : the body; its own landmarks (file) come first
    detect : detect names still missing from the geometry; the file's and the
        skeleton's points anchor the detection rules
    check : run :func:`~patternbridge.mesh.landmark_checks.check_landmarks`
        (symmetry, order along the arm and the torso); implausible detected
        points are corrected or dropped, implausible file points refused

    Returns
    -------
    name -> Landmark, each with its ``source``, ``confidence`` and ``evidence``.

    Raises
    ------
    LandmarkError
        A landmark given in a file is implausible (``check``).
    """
    from .landmark_checks import check_landmarks

    marks: dict[str, Landmark] = dict(character.landmarks)
    rig: dict[str, Landmark] = {}
    if any(n not in marks for n in LANDMARK_NAMES) and character.skeleton is not None:
        rig = {k: lm for k, lm in skeleton_landmarks(character).items() if k not in marks}
    # the rig's points anchor the detection, except those the geometry places better
    anchors = {**{k: lm for k, lm in rig.items() if k not in GEOMETRY_FIRST}, **marks}
    found: dict[str, Landmark] = {}
    if detect and any(n not in anchors for n in LANDMARK_NAMES):
        try:
            found = detect_landmarks(
                character.vertices,
                character.faces,
                known={k: lm.position for k, lm in anchors.items()},
            )
        except LandmarkError as exc:
            log.warning("%s: landmark detection failed: %s", character.name, exc)
    for name in LANDMARK_NAMES:
        if name in marks:
            continue
        options = [lm for lm in (rig.get(name), found.get(name)) if lm is not None]
        if options:
            marks[name] = max(options, key=lambda lm: lm.confidence)
    for name, lm in found.items():  # names outside the vocabulary the rules give
        marks.setdefault(name, lm)
    if check:
        marks = check_landmarks(character, marks)
    return marks


def landmark_errors(found: Mapping[str, Landmark], reference: Mapping[str, Landmark]) -> dict[str, float]:
    """Distance (cm) from each found landmark to the reference one of the same name."""
    return {
        n: float(np.linalg.norm(found[n].position - reference[n].position))
        for n in LANDMARK_NAMES
        if n in found and n in reference
    }
