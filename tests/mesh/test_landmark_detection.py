"""Landmarks found on the shared variants without their landmark files, against the reference answer keys.

The reference files list the landmark vertices each variant was measured from
(``landmark_to_nearest_vertex``, ids of the file's own vertices); the code under
test never reads them, the tests do. The loader keeps the vertex order of a
single-component body, so ``character.vertices[id]`` is the reference point.
"""

from __future__ import annotations

import json
import shutil
from dataclasses import replace

import numpy as np
import pytest

from patternbridge.errors import LandmarkError
from patternbridge.measure import measure
from patternbridge.mesh.character import Character, Landmark, LandmarkSource
from patternbridge.mesh.landmark_checks import check_landmarks
from patternbridge.mesh.landmarks import LANDMARK_NAMES, detect_landmarks, resolve_landmarks
from patternbridge.mesh.load import load_character

pytestmark = pytest.mark.shared

#: cm; the waist points follow each body's narrowest level, the answer key a
#: fixed vertex chosen on E (3-7 cm apart on the women and C, see docs/measurements.md)
TOLERANCE_CM = {
    "top_of_head": 1.0,
    "front_neck_point": 3.0,
    "back_neck_point": 1.0,
    "neck_shoulder_point": 3.0,
    "shoulder_point": 1.0,
    "armpit_point": 5.0,
    "axilla_front": 4.0,
    "axilla_back": 4.5,
    "bust_point": 2.5,
    "waist_front": 3.5,
    "waist_back": 6.0,
    "waist_side": 2.5,
    "buttock_point": 4.0,
    "hip_side": 6.0,
    "crotch_point": 3.0,
    "elbow_point": 3.0,
    "wrist_point": 4.0,
    "knee_point": 4.5,
    "ankle_inside": 2.5,
    "ankle_outside": 4.0,
    "heel_point": 2.5,
}
#: a T-posed body without a rig: no corner at the level shoulder, no bend at the
#: straight elbow, the chest level under raised arms (known limits, docs/measurements.md)
T_POSE_NO_RIG_CM = {
    **TOLERANCE_CM,
    "front_neck_point": 7.0,
    "shoulder_point": 2.0,
    "bust_point": 7.0,
    "elbow_point": 2.0,  # a straight elbow: half-way (9 cm off while a bulge counted as a bend)
    "waist_front": 4.5,  # C's answer-key waist is a fixed vertex on its belly
    "waist_back": 7.0,
    "waist_side": 7.5,
}


def _tolerance(name: str, table: dict[str, float]) -> float:
    return table[name.removesuffix("_left").removesuffix("_right")]


@pytest.fixture(scope="module")
def variants(shared_dir):
    return shared_dir / "characters" / "variants"


def _answer_key(variants, name):
    ref = json.loads((variants / f"{name}.reference.json").read_text())
    return {k: v["vertex"] for k, v in ref["landmark_to_nearest_vertex"].items()}


def _measured(path):
    character, report = load_character(path)
    return character, report, measure(character, partial=True)


@pytest.mark.parametrize(
    "name, mesh",
    [
        ("B_slim_female_tpose", "B_slim_female_tpose.glb"),  # skinned glTF, T-pose, no landmarks
        ("D_cartoon_child_rigged", "D_cartoon_child_rigged.glb"),  # skinned glTF, A-pose
        ("F_tall_thin_elder_mm_back", "F_tall_thin_elder_mm_back.obj"),  # mm, facing -Z, nothing else
    ],
)
def test_landmarks_without_a_landmark_file(variants, name, mesh):
    character, _, result = _measured(variants / mesh)
    key = _answer_key(variants, name)
    assert set(result.landmarks) >= set(LANDMARK_NAMES)
    far = {
        n: round(float(np.linalg.norm(result.landmarks[n].position - character.vertices[key[n]])), 1)
        for n in LANDMARK_NAMES
    }
    bad = {n: d for n, d in far.items() if d > _tolerance(n, TOLERANCE_CM)}
    assert not bad, f"{name}: landmarks beyond their tolerance (cm): {bad}"


def test_t_pose_obj_without_sidecar_gives_right_landmarks(variants, tmp_path):
    """The issue's case: shoulder points landed on the hands (66 cm out) with no warning."""
    path = tmp_path / "C_heavy_male_tpose_remesh.obj"
    shutil.copy(variants / path.name, path)  # the OBJ alone: units, up axis, facing, landmarks all found
    character, _, result = _measured(path)
    assert character.assumed["units"].startswith("m") and character.assumed["up"].startswith("+Z")
    assert not result.missing
    key = _answer_key(variants, "C_heavy_male_tpose_remesh")
    far = {
        n: round(float(np.linalg.norm(result.landmarks[n].position - character.vertices[key[n]])), 1)
        for n in LANDMARK_NAMES
    }
    bad = {n: d for n, d in far.items() if d > _tolerance(n, T_POSE_NO_RIG_CM)}
    assert not bad, f"landmarks beyond their tolerance (cm): {bad}"
    # the level-arm shoulder rule is coarse, and says so
    assert result.landmarks["shoulder_point_left"].is_low_confidence


def test_skinned_gltf_woman_named_failures(variants):
    """B T-pose glTF without landmarks: nape 2.4 cm low, shoulder points 1.9 cm in, bust points
    3.7 cm in, crotch 1 cm off the midline (inside legs 69.0 / 64.0 cm), back length 28.5 cm."""
    character, report, result = _measured(variants / "B_slim_female_tpose.glb")
    key = _answer_key(variants, "B_slim_female_tpose")
    lm, v = result.landmarks, character.vertices
    assert np.linalg.norm(lm["back_neck_point"].position - v[key["back_neck_point"]]) < 0.5
    # found with the arms re-posed down, carried back to the given pose in its face
    bnp = lm["back_neck_point"]
    assert bnp.face is not None
    np.testing.assert_allclose(bnp.position, np.asarray(bnp.bary) @ v[character.faces[bnp.face]], atol=1e-9)
    # the rig's skin in front of the neck joint sat 1.2 cm above the notch the geometry finds on the key
    assert lm["front_neck_point"].source is LandmarkSource.DETECTED
    assert np.linalg.norm(lm["front_neck_point"].position - v[key["front_neck_point"]]) < 0.5
    for s in ("left", "right"):
        assert np.linalg.norm(lm[f"shoulder_point_{s}"].position - v[key[f"shoulder_point_{s}"]]) < 0.5
        assert np.linalg.norm(lm[f"bust_point_{s}"].position - v[key[f"bust_point_{s}"]]) < 1.0
    assert np.linalg.norm(lm["crotch_point"].position - v[key["crotch_point"]]) < 0.5
    m = result.measurements
    left, right = m["inside_leg_left"].value_cm, m["inside_leg_right"].value_cm
    assert abs(left - right) < 0.01 * left
    assert m["back_length"].value_cm > 36.0  # 28.5 before; the rest is the reference's low waist vertex
    assert not any(code.startswith("units") for code in report.codes())


SIDES = ("left", "right")
SHARED = ("A_superhero", "B_slim_female", "C_heavy_male", "D_cartoon_child", "E_average_male", "F_tall_thin_elder")
BUSTS = ("bust_point_left", "bust_point_right")


def test_detection_alone_on_the_shared_characters(characters_dir):
    """Rule points against the sidecar table, from the geometry alone (landmarks and rig dropped).

    The elbow sat 1.5-2.5 cm down the forearm (4.5 cm on A), the crotch up to
    2.9 cm in front of the inseams' meeting point, A's shoulder points on the
    lower corner of its deltoid (2.5 cm off; arm length -5.3 %, shoulder width
    +8.4 %), the wrist points 0.7-2.0 cm short of the hand (F's arm -3.5 %), the
    jugular notch 2.3-3.9 cm off on A, C, E and F.
    A's elbow stays the weakest point (4.2 cm: its bulging upper arm bends the
    sections' centre line 3 cm below the elbow joint).
    """
    far: dict[str, dict[str, float]] = {}
    for name in SHARED:
        c, _ = load_character(characters_dir / f"{name}.obj")
        found = resolve_landmarks(replace(c, landmarks={}, skeleton=None, skin=None))
        far[name] = {
            n: float(np.linalg.norm(found[n].position - c.landmarks[n].position))
            for n in (
                "crotch_point",
                "front_neck_point",
                *(f"{p}_{s}" for p in ("elbow_point", "shoulder_point", "wrist_point") for s in SIDES),
            )
        }
    assert all(d["crotch_point"] < 0.5 for d in far.values()), far
    elbows = [d[f"elbow_point_{s}"] for d in far.values() for s in SIDES]
    assert np.median(elbows) < 1.5 and max(elbows) < 4.5, far
    assert max(d[f"shoulder_point_{s}"] for d in far.values() for s in SIDES) < 0.5, far
    wrists = [d[f"wrist_point_{s}"] for d in far.values() for s in SIDES]
    assert np.median(wrists) < 0.5 and max(wrists) < 1.2, far
    notches = [d["front_neck_point"] for d in far.values()]
    assert np.median(notches) < 1.8 and max(notches) < 3.0, far


def test_bust_points_from_detection_alone(characters_dir):
    """Most prominent 17.5° out from straight ahead: square to the chord from the front midline to the side's
    lateral extreme they sat 3-4 cm out from the nipples on the men (A 4.0, C 4.4, E 3.2 cm)."""
    far = []
    for name in SHARED:
        c, _ = load_character(characters_dir / f"{name}.obj")
        found = detect_landmarks(c.vertices, c.faces)
        far += [float(np.linalg.norm(found[n].position - c.landmarks[n].position)) for n in BUSTS]
    assert np.median(far) < 1.0 and max(far) < 1.5, np.round(far, 1)


def test_back_neck_points_between_the_vertex_rows(characters_dir):
    """The cervicale at its level on the back midline, a surface point between the vertex rows.

    A's back midline has vertex rows at 158.9, 160.6 (the key) and 162.2 cm; the nearest back-midline
    vertex to 1 % of S above the neck base took the 162.2 row (1.7 cm off, back length +3.5 %). On every
    one of the six the point lies on the midline inside a face, within 0.6 cm of the key, and its nearest
    vertex is the key's. The back length from A's point (tape) is within 1.5 % of the key's."""
    from patternbridge.measure.lengths import measure_lengths
    from patternbridge.mesh.landmark_checks import mirror_plane_x

    for name in SHARED:
        c, _ = load_character(characters_dir / f"{name}.obj")
        bnp = detect_landmarks(c.vertices, c.faces)["back_neck_point"]
        key = c.landmarks["back_neck_point"]
        assert bnp.face is not None, name  # between vertices, not snapped to one
        np.testing.assert_allclose(bnp.at(c.vertices, c.faces), bnp.position, atol=1e-9)
        assert np.min(np.linalg.norm(c.vertices - bnp.position, axis=1)) > 0.05, name
        assert abs(bnp.position[0] - mirror_plane_x(c.vertices, c.faces)) < 0.01, name
        assert np.linalg.norm(bnp.position - key.position) < 0.6, name
        assert bnp.vertex == key.vertex, name
        if name == "A_superhero":
            ours = measure_lengths(c.vertices, c.faces, {**c.landmarks, "back_neck_point": bnp}, ids=["back_length"])
            theirs = measure_lengths(c.vertices, c.faces, c.landmarks, ids=["back_length"])
            back = ours["back_length"]
            np.testing.assert_allclose(back.polyline[0], bnp.position, atol=1e-4)  # the path starts at the point
            assert back.value_cm == pytest.approx(theirs["back_length"].value_cm, rel=0.015)


def test_side_neck_points_from_detection_alone(characters_dir):
    """The neck/shoulder corner of the frontal section's contour: read off the highest skin of a slab around
    the plane (which climbs the trapezius behind it) the points sat 1.3-5.2 cm out along the shoulder and
    down (median 2.8 cm; shoulder lengths -7 to -25 %); in the plane half-way between the back and front neck
    points (in front of the cervical spine) A's lay 3.2 cm off, down its massive trapezius."""
    far = []
    for name in SHARED:
        c, _ = load_character(characters_dir / f"{name}.obj")
        found = detect_landmarks(c.vertices, c.faces)
        pts = [f"neck_shoulder_point_{s}" for s in SIDES]
        far += [float(np.linalg.norm(found[n].position - c.landmarks[n].position)) for n in pts]
        left, right = (found[n].position for n in pts)
        assert np.linalg.norm(left * [-1.0, 1.0, 1.0] - right) < 0.1, name  # found alike on both sides
    assert np.median(far) < 0.5 and max(far) < 2.0, np.round(far, 1)


def test_knee_points_from_detection_alone(characters_dir):
    """The knee cap's corner on the leg's front profile: the front-most leg vertex within 1.1 % of S of 60 % of
    the height from ankle to crotch took the top of that band, on the thigh, 3.0-3.4 cm above the patella on A,
    B and F (knee heights +5 to +7 %)."""
    high = []
    for name in SHARED:
        c, _ = load_character(characters_dir / f"{name}.obj")
        found = detect_landmarks(c.vertices, c.faces)
        for s in SIDES:
            n = f"knee_point_{s}"
            high.append(float(found[n].position[1] - c.landmarks[n].position[1]))
            assert found[n].confidence >= 0.5, (name, n)
    assert max(np.abs(high)) < 1.5 and np.median(np.abs(high)) < 0.5, np.round(high, 1)


def test_jugular_notch_from_detection_alone(characters_dir):
    """The chord of the front midline profile ends where the chin begins: ended at the narrowest neck, under
    the chin of A, E and F, it leaned forward at its top and the notch rose a vertex row (1.1-2.4 cm off on
    all six, median 1.3)."""
    far = []
    for name in SHARED:
        c, _ = load_character(characters_dir / f"{name}.obj")
        found = detect_landmarks(c.vertices, c.faces)
        far.append(float(np.linalg.norm(found["front_neck_point"].position - c.landmarks["front_neck_point"].position)))
    assert np.median(far) < 0.5 and max(far) < 1.5, np.round(far, 1)


def test_buttock_and_hip_points_from_detection_alone(characters_dir):
    """The buttocks' most posterior skin and the hip points level with it: at the widest hip section, where
    the thighs flare 1.5-3.4 cm lower, the buttock points lay 2.6-3.8 cm off on five of the six (median 2.9)
    and the hip points 1.5-5.8 cm (median 1.9; waist-to-hip +9 to +13 % from detection)."""
    buttocks, hips = [], []
    for name in SHARED:
        c, _ = load_character(characters_dir / f"{name}.obj")
        found = detect_landmarks(c.vertices, c.faces)
        for s in SIDES:
            for pts, n in ((buttocks, f"buttock_point_{s}"), (hips, f"hip_side_{s}")):
                pts.append(float(np.linalg.norm(found[n].position - c.landmarks[n].position)))
    assert np.median(buttocks) < 0.5 and max(buttocks) < 2.5, np.round(buttocks, 1)
    assert np.median(hips) < 1.0, np.round(hips, 1)


def test_axilla_folds_from_detection_alone(characters_dir):
    """The folds are the dents between chest (back) and arm in the section 1.1 % of S above the armpit, as the
    reference rule takes them (its re-run on each body is in the sidecar): the front-most / back-most point of
    that section at the armpit's x lay 0.7-5.1 cm off the table's ids (B's front fold 3 cm in and 4 cm forward,
    on the bust; front widths -26 to +7 %) and 1.2-3.2 cm off the rule re-run on A, C and E."""
    frozen, rerun = [], []
    for name in SHARED:
        c, _ = load_character(characters_dir / f"{name}.obj")
        found = detect_landmarks(c.vertices, c.faces)
        again = json.loads((characters_dir / f"{name}.json").read_text())["landmark_rules_rerun_here"]["landmarks"]
        for s in SIDES:
            for n in (f"axilla_front_{s}", f"axilla_back_{s}"):
                frozen.append(float(np.linalg.norm(found[n].position - c.landmarks[n].position)))
                if name[0] in "ACE":  # the rule's own points on these bodies (B, D, F: 1.1-6.6 cm off the table)
                    rerun.append(float(np.linalg.norm(found[n].position - c.vertices[again[n]["vertex"]])))
    assert np.median(frozen) < 1.5 and max(frozen) < 3.5, np.round(frozen, 1)
    assert max(rerun) < 1.2, np.round(rerun, 1)


def test_inner_ankles_from_detection_alone(characters_dir):
    """The inner ankle point lies across from the outer one, level with it (the ray through the ankle): the
    inner-most point of the section sat 1.3-2.3 cm in front of the key's on all six. On B and F the ankle level
    itself lies 1.5 cm low, where the foot still reaches forward, and both ankle points 1.6-1.9 cm in front."""
    far = []
    for name in SHARED:
        c, _ = load_character(characters_dir / f"{name}.obj")
        found = detect_landmarks(c.vertices, c.faces)
        for s in SIDES:
            n = f"ankle_inside_{s}"
            far.append(float(np.linalg.norm(found[n].position - c.landmarks[n].position)))
    assert sum(d < 0.5 for d in far) >= 8 and max(far) < 2.5, np.round(far, 1)


def test_elbows_of_the_heavy_bust_from_detection_alone(variants):
    """The tall apple woman's bust reaches past her armpits; cut open where the arm's faces end, its fragment
    held the arm line's point beside the upper arm and the right elbow came out on her bust, 25 cm off (the
    pair check then averaged it to 9.3 cm). Both elbows from the rule alone, before any check."""
    c, _ = load_character(variants / "I_tall_apple_woman.obj")
    key = _answer_key(variants, "I_tall_apple_woman")
    found = detect_landmarks(c.vertices, c.faces)
    for s in SIDES:
        name = f"elbow_point_{s}"
        assert np.linalg.norm(found[name].position - c.vertices[key[name]]) < 2.0, name
    mirror = found["elbow_point_right"].position * [-1.0, 1.0, 1.0]
    assert np.linalg.norm(found["elbow_point_left"].position - mirror) < 1.0


def test_bent_elbows_from_detection_alone(variants):
    """A bent elbow's olecranon half-way along the arm, level with it along the upper arm: at the largest bend
    of the centre line, which a bulging upper arm pushes below the joint, and anywhere in a sphere an arm wide
    round it, A_superhero_bent's 75° elbows came out 4.1 cm down the forearm."""
    c, _ = load_character(variants / "A_superhero_bent.obj")
    key = _answer_key(variants, "A_superhero_bent")
    found = detect_landmarks(c.vertices, c.faces)
    for s in SIDES:
        name = f"elbow_point_{s}"
        assert np.linalg.norm(found[name].position - c.vertices[key[name]]) < 1.0, name


def test_every_landmark_has_a_confidence_and_evidence(variants):
    _, _, result = _measured(variants / "D_cartoon_child_rigged.glb")
    for name, lm in result.landmarks.items():
        assert 0.0 <= lm.confidence <= 1.0, name
        assert lm.evidence.rule, name
        assert lm.source in (LandmarkSource.SKELETON, LandmarkSource.DETECTED)
    i_tall, _ = load_character(variants / "I_tall_apple_woman.obj")
    file_marks = i_tall.landmarks
    assert all(lm.confidence == 1.0 and "vertex" in lm.evidence.rule for lm in file_marks.values())
    # a landmark file's vertex ids stay those vertices (the file format's ids)
    assert all(
        lm.face is None and np.array_equal(lm.position, i_tall.vertices[lm.vertex]) for lm in file_marks.values()
    )


@pytest.mark.parametrize("name", ["E_average_male", "A_superhero"])
def test_shuffled_vertex_order_measures_the_same(characters_dir, name):
    """No template vertex ids: the rules read the geometry only (A: the shoulder corner, wrist and notch rules)."""
    base, _ = load_character(characters_dir / f"{name}.obj")
    base = replace(base, landmarks={}, skeleton=None, skin=None)
    rng = np.random.default_rng(7)
    perm = rng.permutation(len(base.vertices))
    inverse = np.zeros_like(perm)
    inverse[perm] = np.arange(len(perm))
    shuffled = replace(base, vertices=base.vertices[perm], faces=inverse[base.faces][rng.permutation(len(base.faces))])
    a, b = measure(base), measure(shuffled)
    for mid, m in a.measurements.items():
        assert b.measurements[mid].value_cm == pytest.approx(m.value_cm, rel=0.01, abs=0.2), mid
    for name, lm in a.landmarks.items():
        assert np.linalg.norm(b.landmarks[name].position - lm.position) < 1.0, name


def _with(character: Character, **changes) -> dict[str, Landmark]:
    marks = dict(character.landmarks)
    for name, (position, source) in changes.items():
        marks[name] = Landmark(name=name, position=position, vertex=None, source=source)
    return marks


def test_implausible_landmarks_are_refused_or_corrected(characters_dir):
    e, _ = load_character(characters_dir / "E_average_male.obj")
    v = e.vertices
    elbow = e.landmarks["elbow_point_left"].position
    wrist = e.landmarks["wrist_point_left"].position
    # a file that puts the shoulder point beyond the elbow is an error, one line
    with pytest.raises(LandmarkError, match="shoulder point is beyond the elbow") as exc:
        check_landmarks(e, _with(e, shoulder_point_left=(wrist + 0.5 * (wrist - elbow), "file")))
    assert "\n" not in str(exc.value)
    # a detected one is refused (dropped, so measuring says it is missing)
    out = check_landmarks(e, _with(e, shoulder_point_left=(wrist, "detected")))
    assert "shoulder_point_left" not in out
    # a detected waist above the bust points is refused
    bust = e.landmarks["bust_point_left"].position
    out = check_landmarks(e, _with(e, waist_front=(bust + [0.0, 5.0, 0.0], "detected")))
    assert "waist_front" not in out
    # a detected point 5 cm off its file partner on the symmetric body is mirrored back
    knee = e.landmarks["knee_point_right"].position
    moved = v[np.argmin(np.linalg.norm(v - (knee * [-1, 1, 1] + [0, 5.0, 0]), axis=1))]
    out = check_landmarks(e, _with(e, knee_point_left=(moved, "detected")))
    fixed = out["knee_point_left"]
    assert np.linalg.norm(fixed.position - knee * [-1, 1, 1]) < 0.5
    assert fixed.evidence.checks and "mirrored from knee_point_right" in fixed.evidence.checks[0]
    # a detected midline point 2 cm to the side goes back to the midline
    crotch = e.landmarks["crotch_point"].position
    side = v[np.argmin(np.linalg.norm(v - (crotch + [2.0, 0.3, 0.0]), axis=1))]
    out = check_landmarks(e, _with(e, crotch_point=(side, "detected")))
    assert abs(out["crotch_point"].position[0]) < 0.3
