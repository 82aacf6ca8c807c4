"""The six shared characters: completeness, symmetry, shape ordering, pose invariance, bad input."""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest

from patternbridge.cli.main import main
from patternbridge.errors import LandmarkError
from patternbridge.measure import (
    MEASUREMENT_IDS,
    load_measurements,
    measure,
    measurements_to_dict,
    write_measurements,
)
from patternbridge.mesh.character import Landmark
from patternbridge.mesh.landmarks import (
    LANDMARK_NAMES,
    detect_landmarks,
    landmark_errors,
)
from patternbridge.mesh.load import load_character

pytestmark = pytest.mark.shared

NAMES = (
    "A_superhero",
    "B_slim_female",
    "C_heavy_male",
    "D_cartoon_child",
    "E_average_male",
    "F_tall_thin_elder",
)


@pytest.fixture(scope="module")
def characters(characters_dir):
    return {n[0]: load_character(characters_dir / f"{n}.obj")[0] for n in NAMES}


@pytest.fixture(scope="module")
def results(characters):
    return {k: measure(c) for k, c in characters.items()}


def test_every_id_measured(results, characters_dir):
    index = json.loads((characters_dir / "index.json").read_text())["characters"]
    for key, res in results.items():
        values = res.values_cm()
        assert list(values) == list(MEASUREMENT_IDS), key
        assert all(np.isfinite(x) and x > 0 for x in values.values()), key
        name = next(n for n in NAMES if n[0] == key)
        assert values["stature"] == pytest.approx(index[name]["stature_cm"], abs=0.06)
        assert all(lm.source == "file" for lm in res.landmarks.values())


def test_left_right_agree(results):
    for key, res in results.items():
        v = res.values_cm()
        for mid in v:
            if mid.endswith("_left"):
                right = v[mid.replace("_left", "_right")]
                assert v[mid] == pytest.approx(right, rel=0.01), (key, mid)


def test_values_follow_the_shapes(results):
    v = {k: r.values_cm() for k, r in results.items()}
    assert v["A"]["chest_girth"] > 1.3 * v["E"]["chest_girth"]
    assert v["D"]["arm_length_left"] < 0.75 * v["E"]["arm_length_left"]
    assert v["C"]["waist_girth"] > 1.25 * v["E"]["waist_girth"]  # the belly
    assert v["A"]["upper_arm_girth_left"] > 1.3 * v["E"]["upper_arm_girth_left"]
    assert v["A"]["waist_girth"] < v["E"]["waist_girth"]  # V shape
    assert v["B"]["hip_girth"] > v["B"]["chest_girth"] > v["B"]["waist_girth"]
    assert (
        v["D"]["head_girth"] > 0.95 * v["E"]["head_girth"]
    )  # enlarged head on a child
    for r in v.values():  # plausible order of magnitude everywhere
        assert (
            r["wrist_girth_left"]
            < r["elbow_girth_left"] + 3
            < r["upper_arm_girth_left"] + 6
        )
        assert r["ankle_girth_left"] < r["calf_girth_left"] < r["thigh_girth_left"]
        assert r["inside_leg_left"] < r["outside_leg_left"] < r["stature"]
        assert r["arm_length_left"] < r["neck_to_wrist_left"]
    # the side length runs from the armpit down to the waist: never shorter
    # than the straight line, and the child's is a third shorter than E's
    assert v["D"]["side_length"] < 0.75 * v["E"]["side_length"] < v["A"]["side_length"]
    for key, res in results.items():
        side = res["side_length"]
        assert side.details["straight_cm"] <= side.value_cm <= 1.1 * side.details["straight_cm"], key


def test_neck_girth_is_the_collar_girth(results):
    """EN 13402-1 neck girth: collar-sized, under the neck-base girth, symmetric."""
    v = {k: r.values_cm() for k, r in results.items()}
    assert 38.0 <= v["E"]["neck_girth"] <= 42.5  # an average man's collar
    assert v["A"]["neck_girth"] > 1.1 * v["E"]["neck_girth"]  # the superhero's neck
    assert v["D"]["neck_girth"] < 0.85 * v["E"]["neck_girth"]  # the child's
    for key, res in results.items():
        neck, base = res["neck_girth"], res["neck_base_girth"]
        assert neck.value_cm < base.value_cm - 3.0, key  # no trapezius slope
        assert 25.0 < neck.value_cm < 55.0, key
        # the plane holds the nape and stays in the mid-sagittal plane
        np.testing.assert_allclose(
            neck.details["plane_origin"], res.landmarks["back_neck_point"].position
        )
        assert abs(neck.details["plane_normal"][0]) < 1e-6, key
        assert abs(neck.polyline[:, 0].max() + neck.polyline[:, 0].min()) < 0.01, key
        # in front it passes above the jugular notch, below the chin
        assert 1.0 < neck.details["front_above_front_neck_cm"] < 8.0, key


def test_leg_tapes_stay_on_the_leg(characters, results):
    """Inside and outside leg follow the leg like a held tape, not a chord through the air."""
    from scipy.spatial import cKDTree
    from trimesh.remesh import subdivide_to_size

    for key, res in results.items():
        c = characters[key]
        # surface samples <= 1 cm apart (below the waist, where the leg tapes run):
        # a point on the skin is within ~0.6 cm of one
        waist_y = res.landmarks["waist_side_right"].position[1]
        low = c.faces[c.vertices[c.faces][:, :, 1].min(axis=1) < waist_y + 2.0]
        dense, _ = subdivide_to_size(c.vertices, low, max_edge=1.0)
        tree = cKDTree(dense)
        # the outside leg is taut from the waist over the hip; from there on the skin
        hip_y = res.landmarks["hip_side_right"].position[1]
        for mid, top in (("inside_leg_left", np.inf), ("outside_leg_right", hip_y)):
            poly = res.measurements[mid].polyline
            # every 1 cm along the polyline (a straightened span keeps only its ends)
            seg = np.linalg.norm(np.diff(poly, axis=0), axis=1)
            s = np.concatenate([[0.0], np.cumsum(seg)])
            t = np.linspace(0.0, s[-1], int(s[-1]) + 2)
            pts = np.column_stack([np.interp(t, s, poly[:, i]) for i in range(3)])
            dist, _ = tree.query(pts[pts[:, 1] <= top + 1e-9])
            assert dist.max() < 1.0, (key, mid, float(dist.max()))


def test_json_round_trip(results, tmp_path):
    res = results["E"]
    path = write_measurements(tmp_path / "m.json", res)
    back = load_measurements(path)
    assert back.values_cm() == pytest.approx(res.values_cm(), abs=1e-3)
    d = measurements_to_dict(back)
    assert d["units"] == "cm" and set(d["landmarks"]) == set(LANDMARK_NAMES)
    m = d["measurements"]["waist_girth"]
    assert m["kind"] == "girth" and len(m["polyline"]) > 10 and m["landmarks"]
    assert d["measurements"]["arm_length_left"]["kind"] == "length"
    assert {"units", "up", "component", "source"} <= set(d["assumed"])
    # a closed hull: first point repeated, girth = polyline length
    poly = np.array(m["polyline"])
    np.testing.assert_allclose(poly[0], poly[-1])
    assert np.linalg.norm(np.diff(poly, axis=0), axis=1).sum() == pytest.approx(
        m["value_cm"], abs=0.01
    )
    (tmp_path / "plain.json").write_text(json.dumps({"waist_girth": 80.5}))
    assert load_measurements(tmp_path / "plain.json").values_cm() == {
        "waist_girth": 80.5
    }


def test_bad_measurement_files(tmp_path):
    from patternbridge.errors import InputError

    with pytest.raises(InputError, match="no such measurements file"):
        load_measurements(tmp_path / "none.json")
    (tmp_path / "bad.json").write_text("[1, 2")
    with pytest.raises(InputError, match="not valid JSON"):
        load_measurements(tmp_path / "bad.json")
    (tmp_path / "other.json").write_text(
        json.dumps({"measurements": {"x": {"kind": "girth"}}})
    )
    with pytest.raises(InputError, match="malformed"):
        load_measurements(tmp_path / "other.json")
    (tmp_path / "inch.json").write_text(json.dumps({"units": "in", "measurements": {}}))
    with pytest.raises(InputError, match="not 'cm'"):
        load_measurements(tmp_path / "inch.json")


def _posed(c, rotations):
    from patternbridge.mesh.skinning import pose_vertices

    v = pose_vertices(c, rotations)
    marks = {
        k: Landmark(name=k, position=v[lm.vertex], vertex=lm.vertex, source=lm.source)
        for k, lm in c.landmarks.items()
    }
    return dataclasses.replace(c, vertices=v, landmarks=marks)


def test_pose_invariance(characters, results):
    """A-pose, T-pose, T-pose with the elbows bent 45 degrees more (linear blend skinning)."""
    from patternbridge.mesh.skinning import a_to_t_pose_rotations, bend_elbow_rotations

    c = characters["E"]
    t = a_to_t_pose_rotations(c.skeleton)
    bent = {
        **t,
        **bend_elbow_rotations(c.skeleton, "left"),
        **bend_elbow_rotations(c.skeleton, "right"),
    }
    poses = [results["E"], measure(_posed(c, t)), measure(_posed(c, bent))]
    for side in ("left", "right"):
        arm = np.array([r[f"arm_length_{side}"].value_cm for r in poses])
        straight = np.array(
            [r[f"arm_length_{side}"].details["straight_cm"] for r in poses]
        )
        assert np.ptp(arm) / arm.min() <= 0.05
        assert (
            np.ptp(straight) / straight.max() >= 0.15
        )  # the shoulder-wrist chord changes a lot
    for mid in (
        "waist_girth",
        "hip_girth",
        "high_hip_girth",
        "thigh_girth_left",
        "calf_girth_left",
        "head_girth",
    ):
        vals = np.array([r[mid].value_cm for r in poses])
        assert np.ptp(vals) / vals.min() <= 0.01, mid
    neck = np.array([r["neck_girth"].value_cm for r in poses])
    assert np.ptp(neck) <= 1.0  # the neck barely moves (the neck base does: 2 cm)


def test_detected_landmarks_near_reference(characters):
    errors = {}
    for key, c in characters.items():
        found = detect_landmarks(c.vertices, c.faces)
        assert set(found) == set(LANDMARK_NAMES), key
        assert all(lm.source == "detected" for lm in found.values())
        errors[key] = landmark_errors(found, c.landmarks)
    all_err = np.array([e for per in errors.values() for e in per.values()])
    assert np.median(all_err) < 3.0
    for per in errors.values():
        assert per["top_of_head"] < 0.5 and per["crotch_point"] < 3.0
        assert per["wrist_point_left"] < 5.0 and per["ankle_outside_left"] < 5.0


def test_measure_with_detected_landmarks_only(characters):
    c = dataclasses.replace(characters["E"], landmarks={}, skeleton=None, skin=None)
    res = measure(c)
    assert set(res.values_cm()) == set(MEASUREMENT_IDS)
    assert {lm.source for lm in res.landmarks.values()} == {"detected"}
    ref = measure(characters["E"]).values_cm()
    got = res.values_cm()
    for mid in (
        "stature",
        "waist_girth",
        "hip_girth",
        "chest_girth",
        "thigh_girth_left",
    ):
        assert got[mid] == pytest.approx(ref[mid], rel=0.05), mid


def test_skeleton_landmarks(characters):
    from patternbridge.mesh.landmarks import skeleton_landmarks

    c = characters["B"]
    found = skeleton_landmarks(c)
    assert {
        "elbow_point_left",
        "wrist_point_left",
        "knee_point_left",
        "crotch_point",
    } <= set(found)
    assert all(lm.source == "skeleton" for lm in found.values())
    err = landmark_errors(found, c.landmarks)
    assert max(err.values()) < 8.0 and np.median(list(err.values())) < 4.0


def test_missing_landmarks(characters):
    c = dataclasses.replace(characters["E"], landmarks={}, skeleton=None, skin=None)
    with pytest.raises(LandmarkError, match="are missing") as info:
        measure(c, detect=False)
    assert "\n" not in str(info.value) and "--partial" in str(info.value)
    keep = {
        k: v
        for k, v in characters["E"].landmarks.items()
        if not k.startswith("elbow_point")
    }
    res = measure(
        dataclasses.replace(characters["E"], landmarks=keep, skeleton=None, skin=None),
        detect=False,
        partial=True,
    )
    assert "arm_length_left" in res.missing and "elbow_girth_right" in res.missing
    assert "waist_girth" in res.values_cm() and "arm_length_left" not in res.values_cm()


def test_cli(characters_dir, tmp_path, capsys):
    out = tmp_path / "E.json"
    png = tmp_path / "E.png"
    code = main(
        [
            "measure",
            str(characters_dir / "E_average_male.obj"),
            "-o",
            str(out),
            "--png",
            str(png),
        ]
    )
    assert code == 0
    data = json.loads(out.read_text())
    assert data["measurements"]["stature"]["value_cm"] == pytest.approx(
        177.79, abs=0.05
    )
    from PIL import Image

    assert Image.open(png).size[0] > Image.open(png).size[1]
    # bad input: one line, exit 2, nothing written
    bad = tmp_path / "lm.json"
    bad.write_text(json.dumps({"landmarks": {"nose": {"vertex": 1}}}))
    capsys.readouterr()
    code = main(
        [
            "measure",
            str(characters_dir / "E_average_male.obj"),
            "--landmarks",
            str(bad),
            "-o",
            str(tmp_path / "x.json"),
        ]
    )
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and "unknown landmark 'nose'" in err[0]
    assert not (tmp_path / "x.json").exists()
    code = main(
        ["measure", str(tmp_path / "missing.obj"), "-o", str(tmp_path / "x.json")]
    )
    assert code == 2
    # a picture name that is not .png: refused before anything is measured or written
    capsys.readouterr()
    code = main(
        [
            "measure",
            str(characters_dir / "E_average_male.obj"),
            "-o",
            str(tmp_path / "x.json"),
            "--png",
            str(tmp_path / "x.jpg"),
        ]
    )
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and "x.jpg" in err[0]
    assert not (tmp_path / "x.json").exists() and not (tmp_path / "x.jpg").exists()


def test_detection_in_t_pose(characters):
    """Arms raised by skinning: the detected points still land near the moved reference vertices."""
    from patternbridge.mesh.skinning import a_to_t_pose_rotations

    c = _posed(characters["E"], a_to_t_pose_rotations(characters["E"].skeleton))
    found = detect_landmarks(c.vertices, c.faces)
    err = landmark_errors(found, c.landmarks)
    assert len(err) == len(LANDMARK_NAMES)
    assert np.median(list(err.values())) < 3.0 and max(err.values()) < 12.0
    assert err["armpit_point_left"] < 4.0 and err["wrist_point_left"] < 5.0
