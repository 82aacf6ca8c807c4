"""Leg girth links below the thigh: knee, calf and ankle across a leg piece at the levels the body is measured at.

Checked on the real leggings ``GLX4802S19`` (a one-piece leg, sample size 36
of the European women's sizes): each link's two vertices lie at the level
(its share of the sample body's inside leg below the crotch point), the link
measures what the outline measures there (interpolated independently of the
vertices), its ease is what a stretch legging carries, and a cropped leg
whose hem is above a level has no link there.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from patternbridge.bridge import infer_bridge
from patternbridge.bridge.landmarks import piece_landmarks
from patternbridge.bridge.sidecar import inference_sidecar
from patternbridge.bridge.size_chart import LEG_LEVELS, REFERENCE_BODY_CM, choose_chart
from patternbridge.io.dxf_aama import read_dxf
from patternbridge.library.seams import link_lengths, sew_line
from patternbridge.library.sidecar import apply_sidecar
from patternbridge.pattern.json_check import check_sidecar_dict

LEGGINGS = "GLX4802S19_AAMA.DXF"
GIRTHS = ("knee_girth", "calf_girth", "ankle_girth")


def _width_at(up: np.ndarray, level: float) -> float:
    """The outline's extent across the grain at height ``level``, from its crossings of that height."""
    a, b = up, np.roll(up, -1, axis=0)
    hit = (a[:, 1] - level) * (b[:, 1] - level) <= 0
    hit &= a[:, 1] != b[:, 1]
    t = (level - a[hit, 1]) / (b[hit, 1] - a[hit, 1])
    x = a[hit, 0] + t * (b[hit, 0] - a[hit, 0])
    return float(np.ptp(x))


def test_every_size_system_has_the_leg_girths_a_link_reads():
    """Knee, calf and ankle in every system's body; the calf, which no chart states, within 2 cm of the knee."""
    charts = (
        choose_chart(tuple(str(s) for s in range(26, 54, 2)), "36"),
        choose_chart(tuple(str(s) for s in range(42, 72, 2)), "50"),
        choose_chart(("M",), "M"),
    )
    for chart in charts:
        body = chart.body_cm
        assert set(LEG_LEVELS) <= set(body), chart.system
        assert abs(body["calf_girth_right"] - body["knee_girth_right"]) <= 2.0
        assert body["thigh_girth_right"] > body["knee_girth_right"] > body["ankle_girth_right"]
    # levels run down the leg in the order the body has them
    assert list(LEG_LEVELS.values()) == sorted(LEG_LEVELS.values())
    assert REFERENCE_BODY_CM["calf_girth_right"] == pytest.approx(REFERENCE_BODY_CM["knee_girth_right"])


@pytest.mark.shared
def test_leggings_have_knee_calf_and_ankle_links_at_the_body_levels(aama_dir, tmp_path):
    pattern, _ = read_dxf(aama_dir / LEGGINGS)
    inference = infer_bridge(pattern)
    (leg,) = inference.chosen
    body = choose_chart(pattern.sizes, pattern.sample_size).body_cm
    sidecar = tmp_path / "leggings.seams.json"
    sidecar.write_text(json.dumps(inference_sidecar(pattern, inference)))
    applied = apply_sidecar(pattern, sidecar)
    links = {m.id: m for m in applied.measurements}
    k = list(applied.sizes).index(applied.sample_size)
    lengths = {key: float(v[k]) for key, v in link_lengths(applied).items()}
    assert set(GIRTHS) <= set(links)  # before: nothing below the thigh

    up = inference.orientations[leg].apply(sew_line(pattern.piece(leg))[0])
    crotch_y = up[piece_landmarks(pattern, inference)[leg].marks["crotch_point"], 1]
    hem_y = up[:, 1].min()
    for link_id in GIRTHS:
        link = links[link_id]
        (g,) = link.legs
        assert g.piece == leg and g.along == "across"
        # drafted under the body, the girth follows it in proportion: the stretch it is worn at is the design
        assert link.proportional == (link.ease_cm < 0.0), link_id
        i, j = applied.piece(leg).mark(g.start), applied.piece(leg).mark(g.end)
        level = max(crotch_y - LEG_LEVELS[link.measurement] * body["inside_leg_right"], hem_y)
        # the two vertices on either side of the leg, each within 4 cm of the level (the outline's vertex spacing)
        assert abs(up[i, 1] - level) <= 4.0 and abs(up[j, 1] - level) <= 4.0, link_id
        assert up[i, 0] * up[j, 0] < 0
        # what the link measures is the leg's width there, read off the outline between its vertices
        assert lengths[link_id] == pytest.approx(_width_at(up, 0.5 * (up[i, 1] + up[j, 1]) + 1e-6), abs=0.6)
        assert link.ease_cm == pytest.approx(lengths[link_id] - body[link.measurement], abs=0.01)
    # a stretch legging: at or a little under the body, never looser than it, the calf the tightest
    share = {n: links[n].ease_cm / body[links[n].measurement] for n in GIRTHS}
    assert -0.15 <= share["knee_girth"] <= 0.0
    assert -0.20 <= share["calf_girth"] <= 0.0
    assert -0.10 <= share["ankle_girth"] <= 0.05
    # the ankle of a leg that reaches the ankle is its hem
    g = links["ankle_girth"].legs[0]
    assert up[applied.piece(leg).mark(g.start), 1] == pytest.approx(hem_y)


@pytest.mark.shared
def test_a_short_leg_has_no_link_below_its_hem(aama_dir):
    """The leggings' short option ``GLX4802SLS`` (13 cm inseam) stops above the knee: a thigh link only."""
    from patternbridge.bridge.links import measurement_links

    pattern, _ = read_dxf(aama_dir / LEGGINGS)
    links = {m.id for m in measurement_links(pattern, infer_bridge(pattern, pieces=["GLX4802SLS"]))}
    assert "thigh_girth" in links
    assert not links & set(GIRTHS)


@pytest.mark.shared
def test_a_sidecar_without_the_leg_links_still_loads(aama_dir, tmp_path):
    """A leggings sidecar written before the leg links (waist, thigh, leg length only) validates and applies."""
    pattern, _ = read_dxf(aama_dir / LEGGINGS)
    data = inference_sidecar(pattern, infer_bridge(pattern))
    levels = ("knee_level", "calf_level")
    data["measurements"] = [m for m in data["measurements"] if m["id"] not in (*GIRTHS, *levels)]
    check_sidecar_dict(data)
    path = tmp_path / "old.seams.json"
    path.write_text(json.dumps(data))
    applied = apply_sidecar(pattern, path)
    assert {m.id for m in applied.measurements} == {"waist_girth", "thigh_girth", "leg_length"}


@pytest.mark.shared
@pytest.mark.slow
def test_leggings_graded_to_a_child_meet_its_calf_and_knee(aama_dir, shared_dir, tmp_path):
    """GLX4802S19 on D_cartoon_child: the graded calf and knee are the child's, under it by the pattern's share.

    The leggings are drafted 9 % (knee) and 16 % (calf) under the sample
    body: graded to the child they are that share under its girths, worn at
    the stretch the pattern is drafted for (with the ease added in cm the calf
    would be 20 % under the child's, 25 % stretched).

    Measured independently off the graded outline (its width at the link's
    vertices); before the leg links the calf was graded with the width alone.
    """
    from patternbridge.workflow import FitOptions, fit

    result = fit(
        shared_dir / "characters" / "D_cartoon_child.obj",
        aama_dir / LEGGINGS,
        seed=0,
        options=FitOptions(pop_size=8, n_gen=2, drape=False),
        out_dir=tmp_path / "out",
    )
    body = {m["id"]: m["body_cm"] for m in result.report["measurements"]}
    graded = result.grading.pattern
    orientation = infer_bridge(result.grading.original).orientations
    original = result.grading.original
    sample_body = choose_chart(original.sizes, original.sample_size).body_cm
    links = [m for m in graded.measurements if m.id in ("knee_girth", "calf_girth")]
    assert len(links) == 2
    for link in links:
        (g,) = link.legs
        piece = graded.piece(g.piece)
        up = orientation[g.piece].apply(sew_line(piece)[0])
        i, j = piece.mark(g.start), piece.mark(g.end)
        width = abs(up[j, 0] - up[i, 0])
        sample = sample_body[link.measurement]
        assert width == pytest.approx(body[link.id] * (sample + link.ease_cm) / sample, abs=0.5), link.id
        assert abs(width - (body[link.id] + link.ease_cm)) > 0.6  # not the cm ease: 1.2 cm (calf), 0.8 (knee)


@pytest.mark.shared
@pytest.mark.slow
def test_leggings_graded_to_a_calf_larger_than_the_knee_keep_the_calf_at_its_level(aama_dir, shared_dir, tmp_path):
    """GLX4802S19 on E_average_male (calf 39.5 cm, knee 37.6): the calf line stays at its share of the leg.

    With the widths alone the grading slid the calf link's vertices up the
    taper to 1.6 cm under the knee's (39.6 cm above the hem, where the sample
    has them 28.7 cm up): read off the graded outline, each level's height
    above the hem over the graded inseam (crotch point to hem) is the
    sample's within 3 % of the inseam.
    """
    from patternbridge.workflow import FitOptions, fit

    result = fit(
        shared_dir / "characters" / "E_average_male.obj",
        aama_dir / LEGGINGS,
        seed=0,
        options=FitOptions(pop_size=8, n_gen=2, drape=False),
        out_dir=tmp_path / "out",
    )
    original, graded = result.grading.original, result.grading.pattern
    inference = infer_bridge(original)
    (leg,) = inference.chosen
    crotch = piece_landmarks(original, inference)[leg].marks["crotch_point"]
    links = {m.id: m for m in graded.measurements}
    assert {"knee_level", "calf_level"} <= set(links)
    share = {}
    for name, pattern in (("sample", original), ("graded", graded)):
        up = inference.orientations[leg].apply(sew_line(pattern.piece(leg))[0])
        hem, inseam = up[:, 1].min(), up[crotch, 1] - up[:, 1].min()
        piece = pattern.piece(leg)
        share[name] = {
            k: (np.mean([up[piece.mark(links[k].legs[0].start), 1], up[piece.mark(links[k].legs[0].end), 1]]) - hem)
            / inseam
            for k in ("knee_girth", "calf_girth")
        }
    assert share["graded"] == pytest.approx(share["sample"], abs=0.03)
    assert share["graded"]["knee_girth"] - share["graded"]["calf_girth"] > 0.1  # the calf well under the knee


def test_a_loose_trouser_leg_is_not_held_to_the_body_below_the_thigh():
    """The library trousers read from their DXF: knee 1.26 times the knee, hem 1.86 times the ankle: style widths.

    Held to a child's knee and ankle with an adult's ease they narrowed below
    the knee and their pieces turned 3.9-4.3° (limit 2°); the width grading
    keeps them in proportion to the rest of the leg.
    """
    from patternbridge.bridge.links import LEG_AT_BODY, measurement_links
    from patternbridge.library.catalogue import LIBRARY_DIR

    pattern, _ = read_dxf(LIBRARY_DIR / "trousers" / "trousers_aama.dxf")
    inference = infer_bridge(pattern)
    body = choose_chart(pattern.sizes, pattern.sample_size).body_cm
    # the front's and back's widths at the knee notch and at the hem, read off the outlines
    knee = hem = 0.0
    for name in ("front", "back"):
        up = inference.orientations[name].apply(sew_line(pattern.piece(name))[0])
        crotch_y = up[piece_landmarks(pattern, inference)[name].marks["crotch_point"], 1]
        knee += _width_at(up, crotch_y - LEG_LEVELS["knee_girth_right"] * body["inside_leg_right"])
        hem += _width_at(up, up[:, 1].min() + 0.5)
    assert knee > LEG_AT_BODY * body["knee_girth_right"] and hem > LEG_AT_BODY * body["ankle_girth_right"]
    links = {m.id for m in measurement_links(pattern, inference)}
    assert "thigh_girth" in links and not links & set(GIRTHS)
