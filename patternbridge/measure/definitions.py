"""The measurement vocabulary: ids, kinds and one-line definitions.

``formats/measurements.md`` is the full contract; this table is what the code
checks against. Ids ending in ``_left``/``_right`` are measured on the
character's own left (+X) and right side.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["DEFINITIONS", "GIRTH_IDS", "LENGTH_IDS", "MEASUREMENT_IDS", "Definition"]


@dataclass(frozen=True, slots=True, kw_only=True)
class Definition:
    """One measurement: ``id``, ``kind`` (``"girth"`` or ``"length"``), ``method``
    (``"hull"``: convex hull of a plane section, ``"geodesic"``: surface path
    with tape correction, ``"vertical"``: height above the floor), the landmarks
    it needs and a one-line definition."""

    id: str
    kind: str
    method: str
    landmarks: tuple[str, ...]
    text: str


def _side(base: str, kind: str, landmarks: tuple[str, ...], text: str) -> list[Definition]:
    kind, method = {
        "girth": ("girth", "hull"),
        "length": ("length", "geodesic"),
        "height": ("length", "vertical"),
    }[kind]
    return [
        Definition(
            id=f"{base}_{s}",
            kind=kind,
            method=method,
            landmarks=tuple(x.format(s=s) for x in landmarks),
            text=text,
        )
        for s in ("left", "right")
    ]


_TORSO = ("armpit_point_left", "armpit_point_right", "crotch_point")

DEFINITIONS: dict[str, Definition] = {
    d.id: d
    for d in [
        Definition(
            id="chest_girth",
            kind="girth",
            method="hull",
            landmarks=_TORSO,
            text="largest horizontal torso girth between mid-way waist-armpit and just under the armpits "
            "(chest / bust)",
        ),
        Definition(
            id="underbust_girth",
            kind="girth",
            method="hull",
            landmarks=(*_TORSO, "bust_point_left", "bust_point_right"),
            text="horizontal torso girth at the under-bust fold below the bust points",
        ),
        Definition(
            id="waist_girth",
            kind="girth",
            method="hull",
            landmarks=_TORSO,
            text="smallest horizontal torso girth in the waist band",
        ),
        Definition(
            id="high_hip_girth",
            kind="girth",
            method="hull",
            landmarks=_TORSO,
            text="horizontal torso girth half-way between the waist and hip levels",
        ),
        Definition(
            id="hip_girth",
            kind="girth",
            method="hull",
            landmarks=_TORSO,
            text="largest horizontal girth between the crotch and the waist (seat, both legs enclosed)",
        ),
        Definition(
            id="neck_girth",
            kind="girth",
            method="hull",
            landmarks=(
                "front_neck_point",
                "back_neck_point",
                "neck_shoulder_point_left",
                "neck_shoulder_point_right",
                "top_of_head",
            ),
            text="neck girth (EN 13402-1): snuggest neck section through the back neck point "
            "(C7), square to the neck; the collar size",
        ),
        Definition(
            id="neck_base_girth",
            kind="girth",
            method="hull",
            landmarks=(
                "front_neck_point",
                "back_neck_point",
                "neck_shoulder_point_left",
                "neck_shoulder_point_right",
            ),
            text="neck-base girth: the tape over the front, back and side neck points, in their plane, "
            "not beyond the side neck points",
        ),
        Definition(
            id="head_girth",
            kind="girth",
            method="hull",
            landmarks=("top_of_head", "front_neck_point"),
            text="largest horizontal head girth above the ears",
        ),
        *_side(
            "upper_arm_girth",
            "girth",
            ("shoulder_point_{s}", "elbow_point_{s}"),
            "largest girth perpendicular to the upper arm, 30-60 % of the way from shoulder point to elbow",
        ),
        *_side(
            "elbow_girth",
            "girth",
            ("shoulder_point_{s}", "elbow_point_{s}", "wrist_point_{s}"),
            "girth through the elbow point square to the arm, the elbow straightened",
        ),
        *_side(
            "wrist_girth",
            "girth",
            ("elbow_point_{s}", "wrist_point_{s}"),
            "smallest girth perpendicular to the forearm from 2.5 % of stature above the wrist point to 0.5 % below",
        ),
        *_side(
            "thigh_girth",
            "girth",
            ("crotch_point", "knee_point_{s}"),
            "largest girth perpendicular to the thigh, 1-5 % of stature below the crotch",
        ),
        *_side(
            "knee_girth",
            "girth",
            ("crotch_point", "knee_point_{s}", "ankle_inside_{s}", "ankle_outside_{s}"),
            "girth through the knee point, perpendicular to the bisector of thigh and shank",
        ),
        *_side(
            "calf_girth",
            "girth",
            ("knee_point_{s}", "ankle_inside_{s}", "ankle_outside_{s}"),
            "largest girth perpendicular to the shank, 15-60 % of the way from knee to ankle",
        ),
        *_side(
            "ankle_girth",
            "girth",
            ("knee_point_{s}", "ankle_inside_{s}", "ankle_outside_{s}"),
            "smallest girth perpendicular to the shank just above the ankle bones",
        ),
        Definition(
            id="stature",
            kind="length",
            method="vertical",
            landmarks=("top_of_head",),
            text="vertical distance from the floor (lowest vertex) to the top of the head; "
            "a height, not a surface path",
        ),
        Definition(
            id="back_length",
            kind="length",
            method="geodesic",
            landmarks=("back_neck_point", "waist_back"),
            text="surface path from the back neck point (nape) down the spine to the back waist",
        ),
        Definition(
            id="front_length",
            kind="length",
            method="geodesic",
            landmarks=("front_neck_point", "waist_front"),
            text="surface path from the front neck point down the centre front to the front waist",
        ),
        Definition(
            id="shoulder_width",
            kind="length",
            method="geodesic",
            landmarks=(
                "shoulder_point_left",
                "back_neck_point",
                "shoulder_point_right",
            ),
            text="surface path shoulder point - back neck point - shoulder point, across the back",
        ),
        Definition(
            id="back_width",
            kind="length",
            method="geodesic",
            landmarks=("axilla_back_left", "axilla_back_right"),
            text="surface path across the back between the back armpit points",
        ),
        Definition(
            id="front_width",
            kind="length",
            method="geodesic",
            landmarks=("axilla_front_left", "axilla_front_right"),
            text="surface path across the chest between the front armpit points",
        ),
        Definition(
            id="waist_to_hip",
            kind="length",
            method="geodesic",
            landmarks=(
                "waist_side_left",
                "hip_side_left",
                "waist_side_right",
                "hip_side_right",
            ),
            text="surface path at the side from the waist point to the hip point (mean of both sides)",
        ),
        Definition(
            id="side_length",
            kind="length",
            method="geodesic",
            landmarks=(
                "armpit_point_left",
                "waist_side_left",
                "armpit_point_right",
                "waist_side_right",
            ),
            text="surface path down the side from the armpit point to the waist point (mean of both sides)",
        ),
        Definition(
            id="crotch_length",
            kind="length",
            method="geodesic",
            landmarks=("waist_front", "crotch_point", "waist_back"),
            text="surface path front waist - crotch point - back waist",
        ),
        *_side(
            "shoulder_length",
            "length",
            ("neck_shoulder_point_{s}", "shoulder_point_{s}"),
            "surface path from the side neck point to the shoulder point",
        ),
        *_side(
            "armhole",
            "length",
            ("axilla_front_{s}", "shoulder_point_{s}", "axilla_back_{s}"),
            "surface path front armpit point - shoulder point - back armpit point",
        ),
        *_side(
            "arm_length",
            "length",
            ("shoulder_point_{s}", "elbow_point_{s}", "wrist_point_{s}"),
            "surface path shoulder point - elbow point - wrist point",
        ),
        *_side(
            "neck_to_wrist",
            "length",
            (
                "back_neck_point",
                "shoulder_point_{s}",
                "elbow_point_{s}",
                "wrist_point_{s}",
            ),
            "surface path back neck point - shoulder point - elbow point - wrist point",
        ),
        *_side(
            "inside_leg",
            "length",
            ("crotch_point", "ankle_inside_{s}"),
            "surface path from the crotch point down the inner leg to the inner ankle "
            "point, held on the skin (no bridging across the leg's concave profile)",
        ),
        *_side(
            "outside_leg",
            "length",
            ("waist_side_{s}", "hip_side_{s}", "ankle_outside_{s}"),
            "surface path from the side waist point over the hip side point (taut) and "
            "down the outer leg on the skin to the outer ankle point",
        ),
        *_side(
            "knee_height",
            "height",
            ("knee_point_{s}",),
            "vertical distance from the floor to the knee point; a height, not a surface path",
        ),
    ]
}

GIRTH_IDS = tuple(k for k, d in DEFINITIONS.items() if d.kind == "girth")
LENGTH_IDS = tuple(k for k, d in DEFINITIONS.items() if d.kind == "length")
MEASUREMENT_IDS = tuple(DEFINITIONS)
