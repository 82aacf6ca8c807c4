"""The shared variants measured as delivered, against their independent reference values, and pose-free girths."""

from __future__ import annotations

import json
from dataclasses import replace

import pytest

from patternbridge.measure import measure
from patternbridge.measure.reference import comparable_values, waist_line_lengths
from patternbridge.mesh.character import Landmark, LandmarkSource
from patternbridge.mesh.load import load_character

pytestmark = pytest.mark.shared

ALL = (
    "stature",
    "bust_girth",
    "waist_girth",
    "hip_girth",
    "arm_length_left",
    "arm_length_right",
    "back_length",
    "shoulder_width",
    "inside_leg_left",
    "outside_leg_left",
)
#: variant -> values held to the bar (stature 1 %, the rest 3 %); the others are
#: known limits of detection alone (docs/measurements.md, "Reference values")
HELD = {
    "A_superhero_bent.obj": ALL,
    "C_heavy_male_tpose_remesh.obj": ALL,
    "I_tall_apple_woman.obj": ALL,
    "B_slim_female_tpose.glb": tuple(k for k in ALL if k not in ("back_length", "outside_leg_left")),
    "D_cartoon_child_rigged.glb": tuple(k for k in ALL if k not in ("back_length", "outside_leg_left")),
    "F_tall_thin_elder_mm_back.obj": tuple(k for k in ALL if k not in ("back_length", "outside_leg_left")),
}
#: variants without a landmark file: their waist lengths are held to the tailor's natural waist line
DETECTED_WAIST = ("B_slim_female_tpose.glb", "D_cartoon_child_rigged.glb", "F_tall_thin_elder_mm_back.obj")


@pytest.fixture(scope="module")
def variants(shared_dir):
    return shared_dir / "characters" / "variants"


def _reference(variants, mesh: str) -> dict[str, float]:
    stem = mesh.rsplit(".", 1)[0]
    ref = json.loads((variants / f"{stem}.reference.json").read_text())
    out = {"stature": ref["stature"]["value_cm"]}
    for group in ("girths", "lengths"):
        out.update({k: v["value_cm"] for k, v in ref[group].items()})
    return out


@pytest.mark.parametrize("mesh", sorted(HELD))
def test_variant_against_reference(variants, mesh):
    character, _ = load_character(variants / mesh)
    result = measure(character, partial=True)
    ours = comparable_values(character, result)
    ref = _reference(variants, mesh)
    off = {k: 100.0 * (ours[k] - ref[k]) / ref[k] for k in HELD[mesh]}
    bad = {k: round(v, 1) for k, v in off.items() if abs(v) > (1.0 if k == "stature" else 3.0)}
    assert not bad, f"{mesh}: % off the reference: {bad}"


@pytest.mark.parametrize("mesh", DETECTED_WAIST)
def test_detected_waist_lengths_follow_the_natural_waist_line(variants, mesh):
    """Back length and outside leg run to the natural (narrowest, horizontal) waist, as a tailor takes them.

    The reference files end them on fixed template vertices 3-5 cm below that
    line on B and F (back length 11-12 % longer): the target here is the same
    on-skin geodesic from the answer key's landmarks to the waist line at the
    reference's own natural-waist height.
    """
    character, _ = load_character(variants / mesh)
    result = measure(character, partial=True)
    assert result.landmarks["waist_back"].source != LandmarkSource.FILE
    ours = comparable_values(character, result)
    ref = json.loads((variants / f"{mesh.rsplit('.', 1)[0]}.reference.json").read_text())
    key = {
        k: Landmark(name=k, position=character.vertices[v["vertex"]], vertex=v["vertex"])
        for k, v in ref["landmark_to_nearest_vertex"].items()
    }
    rise = ref["supplementary"]["narrowest_torso_hull"]["height_cm"] - ref["girths"]["waist_girth"]["height_cm"]
    tailor = waist_line_lengths(character.vertices, character.faces, key, float(key["waist_front"].position[1] + rise))
    assert set(tailor) == {"back_length", "outside_leg_left"}
    off = {k: round(100.0 * (ours[k] - v) / v, 1) for k, v in tailor.items()}
    assert all(abs(v) <= 3.0 for v in off.values()), off
    # the fixed vertex the reference ends on lies well below the line on B and F
    if mesh.startswith(("B_", "F_")):
        assert ref["lengths"]["back_length"]["value_cm"] > 1.08 * tailor["back_length"]


@pytest.mark.parametrize("name", ["C_heavy_male", "E_average_male"])
def test_detected_waist_lengths_on_the_shared_characters(characters_dir, name):
    """C's template waist vertices sit on its belly, 5-7 cm above its natural waist (back length +15 % against
    them from detection), E's back one a row below its narrowest level (+3.6 %): against the tailor's waist
    line at the reference code's own waist level, detection alone is within 3 %."""
    ch = load_character(characters_dir / f"{name}.obj")[0]
    level = json.loads((characters_dir / f"{name}.json").read_text())["landmark_rules_rerun_here"]["levels_cm"]
    tailor = waist_line_lengths(ch.vertices, ch.faces, ch.landmarks, float(level["waist_level_y"]))
    ours = comparable_values(ch, measure(replace(ch, landmarks={}, skeleton=None, skin=None), partial=True))
    off = {k: round(100.0 * (ours[k] - v) / v, 1) for k, v in tailor.items()}
    assert set(off) == {"back_length", "outside_leg_left"}
    assert all(abs(v) <= 3.0 for v in off.values()), off


@pytest.mark.parametrize("name", ["A_superhero", "F_tall_thin_elder"])
def test_arm_and_shoulder_lengths_from_detection_alone(characters_dir, name):
    """Detection alone (no landmarks, no rig) against the sidecar landmarks, bar 3 %.

    A's shoulder points sat on the lower corner of its deltoid (arm length -5.3 %,
    shoulder width +8.4 %), F's wrist points 1.9 cm short of the hand (arm -3.5 %).
    """
    ch = load_character(characters_dir / f"{name}.obj")[0]
    ref = comparable_values(ch, measure(ch, partial=True))
    ours = comparable_values(ch, measure(replace(ch, landmarks={}, skeleton=None, skin=None), partial=True))
    off = {
        k: round(100.0 * (ours[k] - ref[k]) / ref[k], 1)
        for k in ("arm_length_left", "arm_length_right", "shoulder_width")
    }
    assert all(abs(v) <= 3.0 for v in off.values()), off


@pytest.mark.parametrize("name", ["A_superhero", "C_heavy_male", "E_average_male"])
def test_torso_girths_from_detection_alone(characters_dir, name):
    """Detection alone against the sidecar landmarks, bar 3 %: the under-bust fold is read on the front
    profile through the bust points, and the men's bust points sat 3-4 cm out from their nipples (A's
    under-bust 104.0 cm against 125.3, -17 %: its torso widens 4 cm per cm of height under the pectorals)."""
    ch = load_character(characters_dir / f"{name}.obj")[0]
    ref = measure(ch, partial=True).values_cm()
    ours = measure(replace(ch, landmarks={}, skeleton=None, skin=None), partial=True).values_cm()
    off = {
        k: round(100.0 * (ours[k] - ref[k]) / ref[k], 1)
        for k in ("chest_girth", "underbust_girth", "waist_girth", "high_hip_girth", "hip_girth")
    }
    assert all(abs(v) <= 3.0 for v in off.values()), off


#: girths that hold across the pose (the elbow's snug tape of the straightened
#: elbow: C's A-pose and T-pose elbows were 3.8 % apart cut square to the
#: surface-straightened arm); the neck-base tape stops at the side neck points
#: (the whole section of its plane reached down the raised trapezius of the
#: rigless T-posed C: +4.1 %, docs/measurements.md)
POSE_FREE = (
    "chest_girth",
    "underbust_girth",
    "waist_girth",
    "high_hip_girth",
    "hip_girth",
    "neck_girth",
    "neck_base_girth",
    "head_girth",
    "upper_arm_girth_left",
    "upper_arm_girth_right",
    "elbow_girth_left",
    "elbow_girth_right",
    "wrist_girth_left",
    "wrist_girth_right",
    "thigh_girth_left",
    "knee_girth_left",
    "calf_girth_left",
    "ankle_girth_left",
)


@pytest.mark.parametrize(
    "a_pose, t_pose",
    [
        ("B_slim_female.obj", "variants/B_slim_female_tpose.glb"),  # rigged: re-posed arms down
        ("C_heavy_male.obj", "variants/C_heavy_male_tpose_remesh.obj"),  # no rig, remeshed
    ],
)
def test_a_pose_and_t_pose_girths_agree(characters_dir, a_pose, t_pose):
    a = measure(load_character(characters_dir / a_pose)[0]).values_cm()
    t = measure(load_character(characters_dir / t_pose)[0]).values_cm()
    off = {k: round(100.0 * (t[k] - a[k]) / a[k], 1) for k in POSE_FREE}
    assert all(abs(v) <= 3.0 for v in off.values()), off


@pytest.mark.parametrize(
    "bent, other",
    [
        ("B_slim_female.obj", "variants/B_slim_female_tpose.glb"),  # 35° A-pose elbow / straight T-pose elbow
        ("A_superhero.obj", "variants/A_superhero_bent.obj"),  # 45° / 75° elbows
    ],
)
def test_elbow_girth_is_taken_with_the_elbow_straight(characters_dir, bent, other):
    """A bent elbow is unbent from the surface before its girth: the flexion no longer counts.

    Across the bisector of the bent elbow the girths differed by 4.7 % (B, 22.5
    against 21.4 cm) and 18 % (A, 36.2 against 42.6 cm at 75°).
    """
    a = measure(load_character(characters_dir / bent)[0]).measurements
    b = measure(load_character(characters_dir / other)[0]).measurements
    for side in ("left", "right"):
        ga, gb = a[f"elbow_girth_{side}"], b[f"elbow_girth_{side}"]
        assert ga.details["straightened_deg"] > 25.0
        assert abs(gb.value_cm - ga.value_cm) <= 0.03 * ga.value_cm, (ga.value_cm, gb.value_cm)


def test_wrist_girth_does_not_depend_on_where_the_wrist_point_lands(characters_dir):
    """The snug tape at the narrowest wrist: the file's, the rig's and the detected wrist points agree.

    Through the wrist point itself (the section grows 3 cm per cm into the hand)
    B measured 15.3 cm from its file's point, 14.4 from its rig's 1.4 cm away
    (the T-posed glTF: -5.5 %), D 15.4 against 13.4 from detection.
    """
    measured = {}
    for name in ("B_slim_female.obj", "D_cartoon_child.obj", "variants/B_slim_female_tpose.glb"):
        ch = load_character(characters_dir / name)[0]
        measured[name] = with_file = measure(ch).values_cm()
        alone = measure(replace(ch, landmarks={}, skeleton=None, skin=None)).values_cm()
        for side in ("left", "right"):
            k = f"wrist_girth_{side}"
            assert abs(alone[k] - with_file[k]) <= 0.02 * with_file[k], (name, with_file[k], alone[k])
    a, t = measured["B_slim_female.obj"], measured["variants/B_slim_female_tpose.glb"]
    assert abs(t["wrist_girth_left"] - a["wrist_girth_left"]) <= 0.03 * a["wrist_girth_left"]
