"""Every library garment: complete bridge data, seams that sew, links that fit, files that round-trip."""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from patternbridge.library import garment_dir, garment_names
from patternbridge.library.catalogue import GARMENTS
from patternbridge.library.seams import (
    check_seams,
    graded_sew_lines,
    link_lengths,
    sew_line,
)
from patternbridge.library.sizes import MEN, WOMEN
from patternbridge.pattern.geometry import is_simple, signed_area
from patternbridge.pattern.model import BodyPart, Polyline
from patternbridge.testing import assert_patterns_equal

MEASUREMENT_IDS = {
    "chest_girth",
    "bust_girth",
    "waist_girth",
    "hip_girth",
    "neck_girth",
    "upper_arm_girth_right",
    "wrist_girth_right",
    "thigh_girth_right",
    "knee_girth_right",
    "ankle_girth_right",
    "back_length",
    "front_length",
    "shoulder_width",
    "shoulder_length_right",
    "arm_length_right",
    "crotch_length",
    "outside_leg_right",
    "inside_leg_right",
    "waist_to_hip",
    "side_length",
    "back_width",
    "stature",
}


def test_library_has_the_six_garments():
    assert set(garment_names()) == set(GARMENTS)
    with pytest.raises(KeyError):
        garment_dir("cape")


def test_garment_files_are_committed(garment):
    d = garment_dir(garment.style)
    for suffix in (".json", "_aama.dxf", "_astm.dxf", ".rul", ".seams.json"):
        assert (d / f"{garment.style}{suffix}").is_file(), suffix
    assert (d / "draft.py").is_file()
    assert (
        Path(__file__).resolve().parents[2]
        / "docs"
        / "library"
        / f"{garment.style}.png"
    ).is_file()


def test_at_least_five_sizes_with_one_rule_per_vertex(garment):
    assert len(garment.sizes) >= 5
    assert garment.sample_size in garment.sizes
    for piece in garment.pieces:
        assert all(r is not None and r in garment.rules.deltas for r in piece.rules)
        pts, rules = sew_line(piece)
        assert pts is not piece.outline and len(pts) == piece.n_vertices
        # the sample row of every rule is zero
        k = garment.rules.sizes.index(garment.sample_size)
        assert all(np.all(garment.rules.deltas[r][k] == 0) for r in rules)


def test_outlines_are_ccw_simple_and_contain_the_sew_line(garment):
    lines = graded_sew_lines(garment)
    for piece in garment.pieces:
        assert signed_area(piece.outline) > 0 and is_simple(piece.outline)
        for graded in lines[piece.name]:
            assert signed_area(graded) > 0 and is_simple(graded), piece.name
        assert float(signed_area(piece.outline)) > float(
            signed_area(sew_line(piece)[0])
        )


def test_every_piece_has_placement_and_grain(garment, shared_dir):
    names = set(json.loads((shared_dir / "characters" / "landmarks.json").read_text()))
    for piece in garment.pieces:
        pl = piece.placement
        assert pl is not None, piece.name
        assert pl.anchor in names and pl.anchor_mark in piece.marks
        assert set(piece.landmarks) <= names
        assert piece.grain_line is not None
        if piece.quantity.left:
            # paired pieces are drafted for the right side of the body
            assert pl.body_part in (
                BodyPart.TORSO,
                BodyPart.RIGHT_ARM,
                BodyPart.RIGHT_LEG,
            )
            assert all(not k.endswith("_left") for k in piece.landmarks)


def test_every_garment_names_its_measurements(garment):
    assert garment.has_bridge_data
    ids = {m.measurement for m in garment.measurements}
    assert ids <= MEASUREMENT_IDS
    assert "waist_girth" in ids or "chest_girth" in ids or "bust_girth" in ids
    for m in garment.measurements:
        for g in m.legs:
            piece = garment.piece(g.piece)
            assert g.start in piece.marks and g.end in piece.marks


def test_links_realise_body_plus_ease_in_the_sample_size(garment):
    chart = WOMEN if garment.style in ("skirt", "dress") else MEN
    body = chart.dims
    achieved = link_lengths(garment)
    k = list(garment.sizes).index(garment.sample_size)
    for m in garment.measurements:
        target = body[m.measurement] + m.ease_cm
        if m.proportional:  # the sample distance scaled by body / sample body
            sample = body[m.measurement][chart.sizes.index(chart.sample_size)]
            target = achieved[m.id][k] * body[m.measurement] / sample
        assert achieved[m.id][k] == pytest.approx(
            target[chart.sizes.index(chart.sample_size)], abs=0.06
        ), m.id
        # and the graded sizes follow the chart within a few centimetres
        assert np.max(np.abs(achieved[m.id] - target)) < 3.0, m.id


def test_seams_pass_in_every_size(garment):
    results = check_seams(garment)
    assert len(results) == len(garment.seams) * len(garment.sizes)
    failed = [(r.seam, r.size, r.problems) for r in results if not r.ok]
    assert not failed


def test_a_broken_seam_is_caught(garment):
    seam = garment.seams[0]
    piece = garment.piece(seam.a.piece)
    pts = np.array(piece.sew_lines[0].points) * 1.02  # the piece sewn 2 % too large
    broken_line = Polyline(
        points=pts,
        kinds=piece.sew_lines[0].kinds,
        rules=piece.sew_lines[0].rules,
        closed=True,
    )
    broken = replace(
        garment,
        pieces=tuple(
            replace(p, sew_lines=(broken_line,)) if p.name == piece.name else p
            for p in garment.pieces
        ),
    )
    bad = {r.seam for r in check_seams(broken) if not r.ok}
    assert seam.id in bad


def test_a_missing_notch_is_caught(garment):
    seam = next(
        (
            s
            for s in garment.seams
            if any(
                n.vertex in _inside(garment, s.a)
                for n in garment.piece(s.a.piece).notches
            )
        ),
        None,
    )
    if seam is None:
        pytest.skip("no seam with notches")
    piece = garment.piece(seam.a.piece)
    inside = _inside(garment, seam.a)
    notches = tuple(n for n in piece.notches if n.vertex not in inside)
    broken = replace(
        garment,
        pieces=tuple(
            replace(p, notches=notches) if p.name == piece.name else p
            for p in garment.pieces
        ),
    )
    assert any(r.seam == seam.id and not r.ok for r in check_seams(broken))


def _inside(pattern, e):
    from patternbridge.library.seams import range_indices

    idx = range_indices(pattern.piece(e.piece), e.start, e.end)
    return set(int(i) for i in idx[1:-1])


def test_committed_json_is_what_draft_py_builds(garment, draft_module):
    built = draft_module(garment.style)["build"]()
    assert_patterns_equal(built, garment, atol_cm=1e-9)


@pytest.mark.parametrize("flavor", ["aama", "astm"])
def test_dxf_rul_sidecar_round_trip(garment, flavor, tmp_path):
    from patternbridge.io.dxf_aama import read_dxf, write_dxf
    from patternbridge.library.sidecar import apply_sidecar, write_sidecar

    dxf, rul = tmp_path / f"g_{flavor}.dxf", tmp_path / "g.rul"
    write_dxf(garment, dxf, flavor=flavor, rul_path=rul)
    sidecar = write_sidecar(garment, tmp_path / "g.seams.json")
    back, _report = read_dxf(dxf, rul=rul)
    back = apply_sidecar(back, sidecar)
    assert_patterns_equal(
        garment,
        back,
        atol_cm=1e-3,
        atol_rad=1e-3,
        ignore={"provenance", "source_angle_deg"},
    )
    assert not [r for r in check_seams(back) if not r.ok]


def test_committed_dxf_reads_back_to_the_json(garment):
    from patternbridge.io.dxf_aama import read_dxf
    from patternbridge.library.sidecar import apply_sidecar

    d = garment_dir(garment.style)
    back, _ = read_dxf(d / f"{garment.style}_aama.dxf", rul=d / f"{garment.style}.rul")
    back = apply_sidecar(back, d / f"{garment.style}.seams.json")
    assert_patterns_equal(
        garment,
        back,
        atol_cm=1e-3,
        atol_rad=1e-3,
        ignore={"provenance", "source_angle_deg"},
    )


def test_sew_line_grading_agrees_with_the_pattern_grader(garment):
    from patternbridge.pattern.grading import grade

    lines = graded_sew_lines(garment)
    for k, size in enumerate(garment.sizes):
        sized = grade(garment, size)
        for piece in sized.pieces:
            np.testing.assert_allclose(piece.sew_lines[0].points, lines[piece.name][k], atol=1e-9)


def test_a_girth_across_the_grain_is_the_span_square_to_the_grain_line():
    """The shirt front's hem leg is its x span (grain along y), and stays so with the piece turned 30°."""
    from patternbridge.library import load_garment
    from patternbridge.library.seams import leg_lengths
    from patternbridge.pattern.model import Leg, Line

    shirt = load_garment("shirt")
    front = shirt.piece("front")
    leg = Leg(piece="front", start="side_hem", end="cf_hem", along="across")
    chord = replace(leg, along="chord")
    k = list(shirt.sizes).index(shirt.sample_size)
    line = graded_sew_lines(shirt)["front"][k]
    span = abs(line[front.mark("cf_hem"), 0] - line[front.mark("side_hem"), 0])
    assert leg_lengths(shirt, (leg,))[k] == pytest.approx(span)
    assert leg_lengths(shirt, (chord,))[k] > span + 0.5  # the shirt tail: the centre front hem drops 6 cm
    t = np.radians(30.0)
    rot = np.array([[np.cos(t), -np.sin(t)], [np.sin(t), np.cos(t)]])
    turned = replace(front, grain_line=Line(points=front.grain_line.points @ rot.T))
    assert turned.across_grain == pytest.approx(front.across_grain @ rot.T)
    lines = {"front": line[None] @ rot.T}
    assert leg_lengths(replace(shirt, pieces=(turned,)), (leg,), lines)[0] == pytest.approx(span)
