"""Dressing a character end to end: placement, sewing, draping, files."""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest

from patternbridge.assemble import assemble, dress
from patternbridge.assemble.collision import BodyCollider
from patternbridge.assemble.export_gltf import read_glb
from patternbridge.assemble.mesh2d import mesh_pattern
from patternbridge.assemble.skin_check import signed_distance
from patternbridge.errors import InputError


@pytest.mark.shared
def test_garment_without_placement_hints_is_a_clear_input_error(character_e, tshirt_factory):
    with pytest.raises(InputError, match="no placement hint"):
        assemble(character_e, tshirt_factory(placement=False))


@pytest.mark.shared
def test_garment_without_seams_is_an_input_error(character_e, tshirt):
    with pytest.raises(InputError, match="no seams"):
        assemble(character_e, dataclasses.replace(tshirt, seams=()))


@pytest.fixture(scope="module")
def dressed(character_e, tshirt, tmp_path_factory):
    out = tmp_path_factory.mktemp("fit")
    report = dress(character_e, tshirt, out, max_edge_cm=3.0)
    return out, report


@pytest.mark.shared
@pytest.mark.slow
def test_dress_writes_every_file_and_a_json_report(dressed):
    out, report = dressed
    for name in (
        "garment.glb",
        "garment.obj",
        "garment.mtl",
        "garment.usda",
        "fit_front.png",
        "fit_back.png",
        "fit_side.png",
    ):
        assert (out / name).stat().st_size > 0
    json.dumps(report)
    assert report["verdict"] in ("ok", "flawed", "failed")
    assert (report["verdict"] == "ok") == (report["verdict_reasons"] == [])
    for key in ("penetrating_vertices", "max_seam_gap_mm", "stretch", "seconds"):
        assert key in report
    assert set(report["stretch"]["percentiles"]) >= {"p5", "p50", "p95"}
    # the seams welding closed by more than 5 mm, widest first, agree with the widest gap
    opened = report["seams_open_before_weld"]
    assert [r["max_mm"] for r in opened] == sorted((r["max_mm"] for r in opened), reverse=True)
    assert all(r["max_mm"] > 5.0 for r in opened)
    if report["max_seam_gap_before_weld_mm"] > 5.05:
        assert opened[0]["seam"] == report["worst_seam_before_weld"]
        assert opened[0]["max_mm"] == pytest.approx(report["max_seam_gap_before_weld_mm"], abs=0.06)
    else:
        assert opened == []


@pytest.mark.shared
@pytest.mark.slow
def test_no_vertex_inside_the_body_and_seams_closed(dressed, character_e):
    out, report = dressed
    assert report["penetrating_vertices"] == 0
    assert report["crossing_triangles"] == 0
    assert report["max_seam_gap_mm"] <= 1.0
    doc, binary = read_glb((out / "garment.glb").read_bytes())
    pos = []
    for prim in doc["meshes"][0]["primitives"]:
        acc = doc["accessors"][prim["attributes"]["POSITION"]]
        view = doc["bufferViews"][acc["bufferView"]]
        pos.append(np.frombuffer(binary, np.float32, acc["count"] * 3, view["byteOffset"]).reshape(-1, 3))
    pos = np.concatenate(pos).astype(np.float64) * 100.0
    sd = signed_distance(character_e.vertices, character_e.faces, pos)  # not the solver's collider
    assert sd.min() > -0.05  # float32 rounding of the file
    # the garment covers the torso: between the waist and the chest
    assert pos[:, 1].min() < 100.0 and pos[:, 1].max() > 140.0


@pytest.mark.shared
@pytest.mark.slow
def test_uvs_are_pattern_coordinates_and_weights_sum_to_one(character_e, tshirt):
    pattern = tshirt
    g = assemble(character_e, pattern, max_edge_cm=4.0, steps=40)
    pm = mesh_pattern(pattern, max_edge_cm=4.0)
    for i, key in enumerate(g.instance_names):
        piece = key.split("~")[0]
        np.testing.assert_allclose(g.uv[g.instance == i], pm.pieces[piece].points)
    np.testing.assert_allclose(g.weights.sum(axis=1), 1.0)
    assert g.joints.max() < len(character_e.skeleton.names)
    # welded: sewn vertices share one position exactly
    for w in np.unique(g.weld):
        members = g.vertices[g.weld == w]
        assert np.ptp(members, axis=0).max() == 0.0


@pytest.mark.shared
@pytest.mark.slow
def test_same_seed_same_garment(character_e, tshirt):
    a = assemble(character_e, tshirt, seed=3, max_edge_cm=5.0, steps=20)
    b = assemble(character_e, tshirt, seed=3, max_edge_cm=5.0, steps=20)
    np.testing.assert_array_equal(a.vertices, b.vertices)


@pytest.fixture(scope="module")
def placed_library(character_e):
    """The library shirt and trousers placed on E (wrapped, then the seam graph closed; no draping)."""
    from patternbridge.assemble.bodyparts import segment_body
    from patternbridge.assemble.place import place_garment
    from patternbridge.library import load_garment
    from patternbridge.report import Report

    body = np.asarray(character_e.vertices)
    parts = segment_body(character_e)
    scene = BodyCollider(body, character_e.faces)
    out = {}
    for name in ("shirt", "trousers"):
        pattern = load_garment(name)
        pm = mesh_pattern(pattern, max_edge_cm=3.0)
        out[name] = place_garment(character_e, body, pattern, pm, parts, Report(), scene=scene)
    out["waist_y"] = float(body[character_e.landmarks["waist_back"].vertex][1])
    return out


def _seam_gaps(pm, placed, prefix):
    for sp in pm.seams:
        if sp.seam.startswith(prefix):
            yield (
                sp.seam,
                np.linalg.norm(
                    placed[sp.a.key][sp.a_vertices] - placed[sp.b.key][sp.b_vertices],
                    axis=1,
                ),
            )


@pytest.mark.shared
def test_cuff_is_placed_on_the_sleeve_hem_it_is_sewn_to(placed_library):
    pm, placed = placed_library["shirt"]
    found = 0
    for seam, gap in _seam_gaps(pm, placed, "cuff_"):
        if "closure" in seam:
            continue
        found += 1
        # the cuff's anchor (its corner on the wrist point) alone left it
        # about 20 cm from the hem; on the hem the pairs start close
        assert np.median(gap) < 5.0, (seam, np.median(gap))
    assert found == 2


@pytest.mark.shared
def test_yoke_lies_over_the_shoulders_between_the_back_and_the_fronts(placed_library, character_e):
    pm, placed = placed_library["shirt"]
    gaps = dict(_seam_gaps(pm, placed, "shoulder_"))
    gaps.update(_seam_gaps(pm, placed, "yoke"))
    assert set(gaps) == {"shoulder_right", "shoulder_left", "yoke"}
    for seam, gap in gaps.items():
        # standing up behind the neck on the torso cylinder the yoke's shoulder
        # edges start 30-35 cm from the fronts'; the seam graph brings them
        # within 1.5 cm (measured 1.44 cm at the worst pair)
        assert gap.max() < 2.0, (seam, gap.max())
    yoke = placed["yoke"]
    scene = BodyCollider(np.asarray(character_e.vertices), character_e.faces)
    assert not scene.inside(yoke).any()
    # it goes from the back up to the top of the shoulders (the line through
    # the neck-shoulder points), not standing behind the neck
    body = np.asarray(character_e.vertices)
    top = body[character_e.landmarks["neck_shoulder_point_right"].vertex]
    back = body[character_e.landmarks["back_neck_point"].vertex]
    assert yoke[:, 2].max() > top[2] - 1.0
    assert yoke[:, 2].min() < back[2] - 3.0
    assert yoke[:, 1].max() < top[1] + 3.0


@pytest.mark.shared
def test_collar_stands_on_the_neckline_it_is_sewn_to(placed_library, character_e):
    pm, placed = placed_library["shirt"]
    gaps = dict(_seam_gaps(pm, placed, "collar_"))
    assert set(gaps) == {"collar_back", "collar_front_right", "collar_front_left", "collar_closure"}
    for seam, gap in gaps.items():
        # on the head's cylinder the collar's ends start at the sides of the
        # head: 25 cm from the fronts' neck edges and 23 cm from each other;
        # the seam graph brings every pair within 2.1 cm (1.4 cm before the
        # layers were separated: cloth next to the seam that went through
        # the fronts is held on the collar's layer, over them)
        assert gap.max() < 2.5, (seam, gap.max())
    collar = placed["collar"]
    scene = BodyCollider(np.asarray(character_e.vertices), character_e.faces)
    assert not scene.inside(collar).any()
    # it stands up from the neckline: the top edge (pattern y above the neck
    # edge) lies higher than the sewn edge at the centre back
    piece = pm.pieces["collar"]
    assert collar[piece.marks["top_cb"], 1] > collar[piece.marks["cb"], 1] + 3.0


@pytest.mark.shared
def test_collar_starts_round_the_neck_not_the_head(placed_library, character_e):
    # wrapped once round on its own length about the neck's cross-section at
    # the back neck point, the collar's side neck marks start 2.7 cm from the
    # body's side neck points and its edges near their pattern lengths; on the
    # head's cylinder (centred on the head's box, its radius) they started
    # 6.2 cm behind the neck and the seam graph stretched edges to 2.3 x (p95),
    # and the drape kept the neckline off the nape: the collar 17 % too long
    # round (the demo's girth at 153 cm)
    pm, placed = placed_library["shirt"]
    piece = pm.pieces["collar"]
    collar = placed["collar"]
    body = np.asarray(character_e.vertices)
    nsp = np.array([body[character_e.landmarks[f"neck_shoulder_point_{s}"].vertex] for s in ("left", "right")])
    for mark in ("snp_left", "snp_right"):
        d = np.linalg.norm(nsp - collar[piece.marks[mark]], axis=1).min()
        assert d < 4.0, (mark, d)
    faces = piece.faces
    e = np.unique(np.sort(np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]]), axis=1), axis=0)
    placed_len = np.linalg.norm(collar[e[:, 0]] - collar[e[:, 1]], axis=1)
    ratio = placed_len / np.linalg.norm(piece.points[e[:, 0]] - piece.points[e[:, 1]], axis=1)
    assert np.percentile(ratio, 95) < 1.6, np.percentile(ratio, 95)


@pytest.mark.shared
def test_sleeves_start_as_tubes_round_the_arm(placed_library):
    pm, placed = placed_library["shirt"]
    # the underarm seam's two edges start side by side all along the sleeve
    # (on one radius for the whole sleeve they were up to 25 cm apart at the wrist)
    gaps = dict(_seam_gaps(pm, placed, "sleeve_"))
    assert set(gaps) == {"sleeve_right", "sleeve_left"}
    for seam, gap in gaps.items():
        assert gap.max() < 4.0, (seam, gap.max())


@pytest.mark.shared
def test_trouser_legs_front_and_back_go_once_round_together(placed_library):
    pm, placed = placed_library["trousers"]
    gaps = dict(_seam_gaps(pm, placed, "side_"))
    gaps.update(_seam_gaps(pm, placed, "inside_leg_"))
    assert len(gaps) == 4
    for seam, gap in gaps.items():
        # the side seam sits on the anchor's angle row by row, the inside
        # leg seam on the far side: both start nearly closed
        assert np.median(gap) < 1.0, (seam, np.median(gap))
        assert np.percentile(gap, 90) < 3.0, (seam, np.percentile(gap, 90))


@pytest.mark.shared
def test_trouser_seat_goes_round_the_hips_and_the_band_round_the_waist(placed_library):
    pm, placed = placed_library["trousers"]
    gaps = dict(_seam_gaps(pm, placed, "front_rise"))
    gaps.update(_seam_gaps(pm, placed, "back_rise"))
    gaps.update(_seam_gaps(pm, placed, "waistband_closure"))
    # on the leg cylinders the centre seams started a hand's width apart
    # (median 4-5 cm on E, up to 13 cm on C) and the waistband's ends 25-40 cm apart
    assert np.median(gaps["front_rise"]) < 2.5, np.median(gaps["front_rise"])
    assert np.median(gaps["back_rise"]) < 2.5, np.median(gaps["back_rise"])
    assert gaps["waistband_closure"].max() < 1.0, gaps["waistband_closure"].max()
    band = placed["waistband"]
    waist = np.asarray(placed_library["waist_y"])
    assert abs(np.median(band[:, 1]) - waist) < 6.0


@pytest.mark.shared
def test_pins_free_the_cloth_near_open_seams(character_e):
    from patternbridge.assemble.drape import seam_gaps
    from patternbridge.assemble.pipeline import ANCHOR_FREE_CM, anchor_weights, prepare
    from patternbridge.library import load_garment

    sim = prepare(character_e, load_garment("trousers"), max_edge_cm=4.0)
    # the placement closes the sample trousers' seams on E within 1 cm: the smallest piece (the waistband)
    # lifted 3 cm opens the seams to it
    smallest = np.argmin(np.bincount(sim.cloth.group))
    sim.cloth.x[sim.cloth.group == smallest] += np.array([0.0, 3.0, 0.0])
    w = anchor_weights(sim)
    gaps = seam_gaps(sim.cloth.x, sim.cloth.seams)
    open_v = np.unique(sim.cloth.seams[gaps > 1.0].ravel())
    assert len(open_v) > 0
    assert np.all(w[open_v] == 0.0)
    assert w.max() > 0.0
    # far from any open seam (in the pattern) the cloth is pinned
    far = np.ones(len(w), dtype=bool)
    for v in open_v:
        same = sim.cloth.group == sim.cloth.group[v]
        far &= ~same | (np.linalg.norm(sim.cloth.uv - sim.cloth.uv[v], axis=1) > ANCHOR_FREE_CM[1])
    assert far.any() and np.all(w[far] == w.max())


def test_only_a_shirt_yoke_lies_over_the_shoulders():
    # the yoke is sewn to the fronts and to the back; counted round the
    # torso it widened E's cylinder from 18 to 26 cm
    from patternbridge.assemble.mesh2d import mesh_pattern
    from patternbridge.assemble.place.wrap import _over_shoulders
    from patternbridge.library import load_garment

    shirt = load_garment("shirt")
    pmesh = mesh_pattern(shirt, max_edge_cm=4.0)
    assert {inst.key for inst in pmesh.instances if _over_shoulders(shirt, pmesh, inst)} == {"yoke"}
    # a dress's back bodice halves are sewn to the larger front bodice and
    # skirt back too, but down their sides: they go round the body (laid
    # over the shoulders, the centre back started 21 cm open and ended 30 cm)
    for name in ("trousers", "dress", "tshirt"):
        garment = load_garment(name)
        pmesh = mesh_pattern(garment, max_edge_cm=4.0)
        assert not any(_over_shoulders(garment, pmesh, inst) for inst in pmesh.instances), name


def test_widths_of_a_trapezoid():
    from patternbridge.assemble.place.wrap import _widths

    trapezoid = np.array([[-10.0, 0.0], [10.0, 0.0], [5.0, 10.0], [-5.0, 10.0]])
    np.testing.assert_allclose(_widths(trapezoid, np.array([0.5, 5.0, 9.5, 12.0])), [19.5, 15.0, 10.5, 0.0])


@pytest.fixture(scope="module")
def sewn_shirt(character_e):
    """The library shirt on E, sewn and draped on a coarse mesh (the T-pose, the arms lowered), not welded."""
    from patternbridge.assemble.pipeline import prepare, seam_gap_table, simulate
    from patternbridge.library import load_garment

    sim = prepare(character_e, load_garment("shirt"), max_edge_cm=3.5, steps=120)
    placed = {r.seam: r.max_mm for r in seam_gap_table(sim)}
    simulate(sim)
    return sim, placed, {r.seam: r.max_mm for r in seam_gap_table(sim)}


@pytest.mark.shared
def test_the_simulation_sews_every_shirt_seam(sewn_shirt):
    sim, placed, sewn = sewn_shirt
    assert set(sewn) == set(placed) and len(sewn) == 22
    # placed from the seam graph the widest seam starts 2-6 cm open (wrapped
    # on the cylinders alone the armholes started 15-17 cm from the sleeve
    # caps): sewing, not welding, closes the rest
    assert 10.0 < max(placed.values()) < 80.0, placed
    # the torso's cylinder carries the fronts and the back side by side, the
    # yoke lying over the shoulders: counted as a fourth piece round the body
    # it widened the cylinder and the side seams started 26 cm open
    assert max(placed["side_left"], placed["side_right"]) < 120.0, placed
    worst = max(sewn, key=sewn.get)
    gaps = np.array(list(sewn.values()))
    # measured with Coulomb friction and the cuffs sewn over the first two
    # keyframes on the way down: median 2.7 mm, 18 of 22 seams within 5 mm,
    # the widest a shoulder at 7.1 mm (over three keyframes: 2.5 mm, 19 of 22;
    # friction as damping of the sliding and the cuffs sewn with the arms up:
    # median 2.9 mm, 17 of 22; with seam springs as weak as the stretch
    # springs: median 3.5 mm, 16 of 22). With the torso's cylinder carrying
    # the pieces side by side and the cuffs held at their gaps while the arms
    # are up: median 2.8 mm, 18 of 22, the widest a cuff at 17.4 mm (on this
    # coarse mesh the widest seam moves between 8 and 20 mm with how firmly
    # the cuffs are held, 0-20 % of a seam's weight)
    assert sewn[worst] < 22.0, (worst, sewn[worst])
    assert np.median(gaps) < 3.0, np.median(gaps)
    assert np.mean(gaps < 5.0) >= 0.8, sorted(sewn.items(), key=lambda kv: -kv[1])
    # and the cloth ends outside the skin
    assert not sim.collider.inside(sim.cloth.x).any()


@pytest.mark.shared
def test_a_character_without_landmarks_gets_the_anchors_its_pieces_hang_from(characters_dir):
    from patternbridge.assemble.pipeline import with_anchor_landmarks
    from patternbridge.library import load_garment
    from patternbridge.mesh.load import load_character

    bare, _ = load_character(characters_dir / "variants" / "D_cartoon_child_rigged.glb")  # no sidecar
    reference, _ = load_character(characters_dir / "D_cartoon_child.obj")  # the same body with its sidecar
    trousers = load_garment("trousers")
    assert not bare.landmarks
    dressed, added = with_anchor_landmarks(bare, trousers)
    anchors = {p.placement.anchor for p in trousers.pieces}
    assert anchors <= set(added)
    for name in anchors:  # found from the rig and the geometry, near where the sidecar puts them
        off = np.linalg.norm(dressed.landmarks[name].position - reference.landmarks[name].position)
        assert off < 3.0, (name, off)
    # a character that has them is left as it is
    assert with_anchor_landmarks(reference, trousers) == (reference, [])
