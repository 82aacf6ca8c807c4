"""A knit drafted shorter than the span to its hem's landmark is placed stretched down to it; a woven is not."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest

from patternbridge.assemble.place.length import LengthStretch, hem_vertices, worn_lengths
from patternbridge.pattern.fabric import FabricClass

LEGGINGS = Path(__file__).resolve().parents[2] / ".." / "shared" / "aama" / "GLX4802S19_AAMA.DXF"


def _stretch(scale: float) -> LengthStretch:
    return LengthStretch(
        key="leg", landmark="ankle_outside_right", hem_mark="hem", pivot_y=60.0, hem_y=0.0,
        need=scale - 1.0, limit=0.3, scale=scale,
    )  # fmt: skip


def test_worn_lengths_stretch_along_the_axis_below_the_pivot_only():
    uv = np.array([[0.0, 10.0], [0.0, 12.0], [2.0, 10.0], [1.0, 11.0], [0.0, 70.0], [0.0, 72.0]])
    edges = np.array([[0, 1], [0, 2], [0, 3], [4, 5]])
    rest = np.linalg.norm(uv[edges[:, 1]] - uv[edges[:, 0]], axis=1)
    got = worn_lengths(_stretch(1.2), uv, edges, rest)
    # along the axis × 1.2, across it unchanged, at 45° × 1.1 (cos² = ½), above the pivot unchanged
    np.testing.assert_allclose(got / rest, [1.2, 1.0, 1.1, 1.0])
    np.testing.assert_allclose(worn_lengths(_stretch(1.0), uv, edges, rest), rest)
    # a copy not stretched keeps its heights bit for bit (a woven garment places exactly as before)
    y = np.array([0.1, 3.3, 59.7, 61.0]) * np.pi
    np.testing.assert_array_equal(_stretch(1.0).heights(y), y)


def test_the_held_hem_is_the_boundary_next_to_the_hem_mark():
    p2 = np.array([[0.0, 0.0], [10.0, 0.5], [10.0, 30.0], [0.0, 30.0], [5.0, 1.0]])
    np.testing.assert_array_equal(hem_vertices(_stretch(1.1), p2, n_boundary=4), [0, 1])


@pytest.fixture(scope="module")
def leggings(tmp_path_factory):
    from patternbridge.bridge.upright import upright_pattern
    from patternbridge.workflow import load_garment_spec

    if not LEGGINGS.exists():
        pytest.skip("shared patterns not available")
    garment = load_garment_spec(LEGGINGS)[0]
    sidecar = tmp_path_factory.mktemp("legs") / garment.drape_sidecar_name
    sidecar.write_bytes(dict(garment.inferred)[sidecar.name])
    return upright_pattern(garment.pattern, sidecar)  # as the fit drapes it


def _placed(character, pattern):
    """(stretches, placed positions, pmesh) of ``pattern`` on ``character`` as ``prepare`` places it."""
    from patternbridge.assemble.bodyparts import segment_body
    from patternbridge.assemble.collision import BodyCollider
    from patternbridge.assemble.mesh2d import mesh_pattern
    from patternbridge.assemble.place import place_instances
    from patternbridge.assemble.place.length import length_stretches
    from patternbridge.assemble.place.wrap import bounding_cylinders
    from patternbridge.report import Report

    body = np.asarray(character.vertices)
    parts = segment_body(character)
    pm = mesh_pattern(pattern, max_edge_cm=3.0)
    cylinders = bounding_cylinders(body, parts)
    stretches = length_stretches(character, body, pattern, pm, cylinders)
    placed = place_instances(
        character, body, pattern, pm, cylinders, Report(), scene=BodyCollider(body, character.faces), parts=parts
    )
    return stretches, placed, pm


def _hem_heights(pm, placed) -> dict[str, float]:
    from patternbridge.assemble.place.wrap import instance_points2d

    out = {}
    for inst in pm.instances:
        p2 = instance_points2d(pm, inst)[: pm.pieces[inst.piece].n_boundary]
        out[inst.key] = float(placed[inst.key][np.flatnonzero(p2[:, 1] <= p2[:, 1].min() + 1.0), 1].mean())
    return out


@pytest.mark.shared
def test_stretch_knit_leggings_start_at_the_ankle_and_woven_ones_at_their_length(character_e, leggings):
    # GLX4802S19 is drafted 10.5 cm short of its sample body's outside leg (a
    # stretch knit pulled down when worn): at its pattern length the hem sat
    # 11 cm above E's ankle, on the calf
    assert leggings.fabric_class is FabricClass.STRETCH_KNIT
    ankle = {k: character_e.landmarks[f"ankle_outside_{k}"].position[1] for k in ("left", "right")}
    stretches, placed, pm = _placed(character_e, leggings)
    assert len(stretches) == 2
    hems = _hem_heights(pm, placed)
    for key, ls in stretches.items():
        side = ls.landmark.rsplit("_", 1)[1]
        assert ls.landmark.startswith("ankle_outside_")
        assert ls.stretched and 0.03 < ls.need <= ls.limit, ls
        # the placed hem on the ankle's height (the axis is nearly vertical)
        assert abs(hems[key] - ankle[side]) < 1.5, (key, hems[key], ankle[side])
    # two pieces on two legs: one on each ankle
    assert {ls.landmark for ls in stretches.values()} == {"ankle_outside_left", "ankle_outside_right"}

    woven = dataclasses.replace(leggings, fabric_class=FabricClass.WOVEN)
    w_stretches, w_placed, w_pm = _placed(character_e, woven)
    assert not any(ls.stretched for ls in w_stretches.values())
    w_hems = _hem_heights(w_pm, w_placed)
    for key, ls in w_stretches.items():
        # a need, not taken: the woven hangs at its pattern length, well above the ankle (its need is measured
        # from its crotch laid under the body's, length.crotch_drop; the knit is pulled up into the crotch)
        assert 0.0 < ls.need <= stretches[key].need
        assert w_hems[key] - hems[key] > 5.0, (key, w_hems[key], hems[key])


@pytest.mark.shared
def test_a_stretch_knit_short_beyond_the_fabric_s_reach_hangs_at_its_length(character_e, leggings):
    # the same leggings cut off 40 cm above the hem (a bike short): reaching
    # the ankle would take more than the knit's 30 % along the grain
    from patternbridge.assemble.place.length import length_stretch
    from patternbridge.assemble.place.wrap import instance_points2d

    _, _, pm = _placed(character_e, leggings)
    inst = pm.instances[0]
    p2 = instance_points2d(pm, inst)
    marks = pm.pieces[inst.piece].marks
    anchor_y = float(p2[marks[leggings.piece(inst.piece).placement.anchor_mark], 1])
    common = dict(marks=marks, anchor_y=anchor_y, anchor_h=anchor_y, landmark="ankle_outside_right")
    hem_y = float(p2[:, 1].min())
    within = length_stretch(leggings, inst, p2, target_h=hem_y - 5.0, **common)
    beyond = length_stretch(leggings, inst, p2, target_h=hem_y - 40.0, **common)
    assert within.stretched and beyond.need > beyond.limit and not beyond.stretched
    above = length_stretch(leggings, inst, p2, target_h=hem_y + 5.0, **common)  # longer than the span
    assert above.need < 0 and not above.stretched


@pytest.mark.shared
def test_library_trousers_and_shorts_are_not_stretched(character_e):
    from patternbridge.library.catalogue import load_garment

    for name in ("trousers", "shorts"):
        pattern = load_garment(name)
        stretches, _, _ = _placed(character_e, pattern)
        assert pattern.fabric_class is FabricClass.WOVEN
        assert not any(ls.stretched for ls in stretches.values()), name


@pytest.mark.shared
def test_the_hem_rise_of_a_copy_worn_stretched_is_measured_against_its_worn_length(character_e, leggings):
    # placed on its landmark the hem has not risen; against the pattern's
    # length it would read as hanging lower (a rise below 0) and a hem that
    # rode up from the ankle to the calf would be hidden by the stretch
    from patternbridge.assemble.defects import grain_directions, hem_rise_cm

    stretches, placed, pm = _placed(character_e, leggings)
    x = np.concatenate([placed[inst.key] for inst in pm.instances])
    group = np.repeat(np.arange(len(pm.instances)), [len(placed[inst.key]) for inst in pm.instances])
    grain = grain_directions(leggings, pm)
    plain = hem_rise_cm(leggings, pm, x, group, grain)
    worn = hem_rise_cm(leggings, pm, x, group, grain, stretches)
    for key, ls in stretches.items():
        # the leg below the crotch and the rise laid stretched to pass under the crotch (length.crotch_drop)
        gained = (ls.scale - 1.0) * (ls.pivot_y - ls.hem_y) + ls.rise.stretch_cm
        assert plain[key] < -0.5 * gained, (key, plain[key], gained)
        assert abs(worn[key]) < 3.0, (key, worn[key])
        assert worn[key] - plain[key] == pytest.approx(gained, abs=2.0)
    # the same copy drawn 8 cm up the leg rises by about that much
    lifted = x.copy()
    for i, inst in enumerate(pm.instances):
        p2y = pm.pieces[inst.piece].points[:, 1]
        low = p2y < p2y.min() + 30.0
        lifted[(group == i).nonzero()[0][low], 1] += 8.0 * (1.0 - (p2y[low] - p2y.min()) / 30.0)
    up = hem_rise_cm(leggings, pm, lifted, group, grain, stretches)
    for key in stretches:
        assert up[key] - worn[key] == pytest.approx(8.0, abs=1.5), (key, up[key], worn[key])


@pytest.mark.shared
def test_the_leggings_place_the_same_from_memory_and_from_their_files_read_back(character_e, tmp_path):
    # same inputs, same bytes: the fit drapes the pattern it inferred in memory, a user runs it again with the
    # inferred sidecar saved beside the DXF, and a graded pattern is saved to JSON and read back; the placed
    # cloth (its positions, the springs' worn lengths, the stretches) must not depend on which
    import shutil

    from patternbridge.assemble.pipeline import prepare
    from patternbridge.bridge.upright import upright_pattern
    from patternbridge.bridge.worn import worn_pattern
    from patternbridge.io.pattern_json import load_pattern_json, save_pattern_json
    from patternbridge.workflow import load_garment_spec

    if not LEGGINGS.exists():
        pytest.skip("shared patterns not available")
    garment = load_garment_spec(LEGGINGS)[0]
    inferred = tmp_path / "inferred" / garment.drape_sidecar_name
    inferred.parent.mkdir()
    inferred.write_bytes(dict(garment.inferred)[inferred.name])
    beside = tmp_path / "beside"
    beside.mkdir()
    shutil.copy(LEGGINGS, beside / LEGGINGS.name)
    shutil.copy(inferred, beside / inferred.name)
    again = load_garment_spec(beside / LEGGINGS.name)[0]
    assert again.sidecar == beside / inferred.name and not again.inferred  # read back, not inferred
    save_pattern_json(again.pattern, tmp_path / "pattern.json")
    read_back = load_pattern_json(tmp_path / "pattern.json")

    sims = [
        prepare(character_e, worn_pattern(upright_pattern(p, s), s), seed=0)
        for p, s in ((garment.pattern, inferred), (read_back, again.sidecar))
    ]
    a, b = sims
    np.testing.assert_array_equal(a.x_placed, b.x_placed)
    np.testing.assert_array_equal(a.cloth.rest, b.cloth.rest)
    np.testing.assert_array_equal(a.cloth.uv, b.cloth.uv)
    assert a.stretches == b.stretches and all(ls.stretched for ls in a.stretches.values()) and len(a.stretches) == 2


@pytest.mark.shared
def test_the_leggings_crotch_corners_start_under_the_crotch(character_e, leggings):
    # the rise of a knit worn stretched is laid stretched (up to the knit's
    # 30 % along the grain) to take its crotch corners under the body's
    # crotch, the waist kept on its landmark (length.crotch_drop). Laid at its
    # pattern length, the front rise's corner sat 1.8 cm above E's crotch and
    # 8 cm in front of it, the back's behind it, and closing the inseam's top
    # folded the crotch through itself (104 self-crossing triangles on E)
    from patternbridge.assemble.place.wrap import instance_points2d

    crotch = character_e.landmarks["crotch_point"].position
    stretches, placed, pm = _placed(character_e, leggings)
    for inst in pm.instances:
        p2 = instance_points2d(pm, inst)[: pm.pieces[inst.piece].n_boundary]
        # the rise tips: the outline's two extreme vertices across the grain (front and back crotch corners)
        tips = placed[inst.key][[int(np.argmin(p2[:, 0])), int(np.argmax(p2[:, 0]))]]
        assert np.all(tips[:, 1] < crotch[1] - 0.5), (inst.key, tips, crotch)
        assert np.all(np.linalg.norm(tips - crotch, axis=1) < 4.5), (inst.key, tips, crotch)
        # the waist stays on its landmark: the anchor mark placed within 1.5 cm of its height
        pl = leggings.piece(inst.piece).placement
        side = "left" if inst.copy.value == "mirror" else "right"
        anchor = placed[inst.key][pm.pieces[inst.piece].marks[pl.anchor_mark]]
        assert abs(anchor[1] - character_e.landmarks[f"waist_side_{side}"].position[1]) < 1.5
        assert stretches[inst.key].rise.rise_scale > 1.0 and stretches[inst.key].rise.shift_cm == 0.0
