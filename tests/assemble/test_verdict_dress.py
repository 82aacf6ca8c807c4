"""The drape verdict end to end: deliberately broken garments fail, and say why."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from patternbridge.assemble import assemble
from patternbridge.assemble.skin_check import signed_distance
from patternbridge.assemble.verdict import Check, Verdict, VerdictLimits

pytestmark = [pytest.mark.shared, pytest.mark.slow]

COARSE = {"max_edge_cm": 3.5, "steps": 100}  # a coarse, short drape: the defects below are far beyond the limits


def _shorts(size: str | None = None):
    from patternbridge.library import load_garment
    from patternbridge.pattern.grading import grade

    shorts = load_garment("shorts")
    return grade(shorts, size) if size else shorts


def _lengthen(pattern, piece: str, mark: str, cm: float):
    """``pattern`` with the ``mark`` corner of ``piece`` moved ``cm`` down (the seam ending there longer)."""
    p = pattern.piece(piece)
    i = p.marks[mark]
    outline = np.array(p.outline)
    outline[i, 1] -= cm
    # the sew line (the garment is meshed on it) has one vertex per outline vertex
    sew = []
    for line in p.sew_lines:
        pts = np.array(line.points)
        pts[i, 1] -= cm
        sew.append(dataclasses.replace(line, points=pts))
    moved = dataclasses.replace(p, outline=outline, sew_lines=tuple(sew))
    return dataclasses.replace(pattern, pieces=tuple(moved if q.name == piece else q for q in pattern.pieces))


@pytest.fixture(scope="module")
def sample_shorts(character_e):
    return assemble(character_e, _shorts(), **COARSE)


def test_the_sample_shorts_on_e_are_at_worst_flawed_at_the_crotch(sample_shorts, character_e):
    report = sample_shorts.report
    # measured: seams 1.1 mm open before welding, 0.3 % of the edges beyond 1.10, nothing inside the skin,
    # the waistband 1.6 cm off the waist landmark; the two back halves cross each other in 8 triangles at
    # the crotch (counted over the whole garment, a crossing of two pieces is the garment through itself)
    assert report.verdict in (Verdict.OK, Verdict.FLAWED), [r.message for r in report.reasons]
    assert report.to_dict()["verdict"] == str(report.verdict)
    assert {r.check for r in report.reasons} <= {Check.SELF_CROSSING}
    assert set(report.self_crossing_pieces) <= {"back", "back~mirror"}
    # the verdict's skin check agrees with a signed distance taken here, on the welded garment's vertices
    v, _ = sample_shorts.welded()
    depth_mm = -10.0 * signed_distance(character_e.vertices, character_e.faces, v).min()
    assert report.skin_depth_mm >= depth_mm - 1e-3


def test_a_seam_ten_cm_too_long_fails(character_e):
    broken = _lengthen(_shorts(), "front", "side_hem", 10.0)
    report = assemble(character_e, broken, **COARSE).report
    assert report.verdict is Verdict.FAILED
    seam = [r for r in report.reasons if r.check is Check.SEAM_LENGTH]
    assert seam and seam[0].verdict is Verdict.FAILED
    assert set(seam[0].where) == {"side_right", "side_left"}
    assert seam[0].value == pytest.approx(10.0, abs=1.0)


def test_shorts_a_size_too_small_are_flawed_at_the_waist_by_what_their_waistband_lacks(character_e, sample_shorts):
    small = assemble(character_e, _shorts("76"), **COARSE).report
    # size 76's waistband is 78.0 cm round (the library's waist link), E's waist 81.1 cm (`patternbridge
    # measure`): worn on the skin it is stretched 3.9 % all the way round, a size too small. The drape keeps the
    # cloth 0.6 cm off the skin, 2π x 0.6 = 3.8 cm more round the waist, which read 9.4 % before the girth was
    # measured on the skin
    girth = [r for r in small.reasons if r.check is Check.GIRTH]
    assert girth and girth[0].verdict is Verdict.FLAWED, [r.message for r in small.reasons]
    assert girth[0].where == ("waistband",)  # the tightest girth is the waist
    assert 100 * (small.girth_strain - 1.0) == pytest.approx(100 * (81.1 / 78.0 - 1.0), abs=1.5)
    # the sample size (84, two sizes larger, 86 cm round) is judged better, its girths within the cross grain's give
    assert sample_shorts.report.verdict.rank <= small.verdict.rank
    assert sample_shorts.report.girth_strain < VerdictLimits().girth_flawed < small.girth_strain
    assert small.stretch.beyond_limit_share > sample_shorts.report.stretch.beyond_limit_share


def test_a_waistband_hanging_20_cm_below_the_waist_is_off_its_level(character_e):
    from patternbridge.assemble.defects import anchor_levels_cm
    from patternbridge.assemble.pipeline import prepare

    sim = prepare(character_e, _shorts(), max_edge_cm=3.5)
    body = np.asarray(character_e.vertices)
    placed = anchor_levels_cm(character_e, body, sim.pattern, sim.pmesh, sim.cloth.x, sim.cloth.group)
    # the wrap puts every anchor mark on its landmark's height; closing the
    # seam graph moves them by up to 1.2 cm (the waistband)
    assert max(placed.values()) < 1.5, placed
    band = sim.names.index("waistband")
    x = sim.cloth.x.copy()
    x[sim.cloth.group == band, 1] -= 20.0
    moved = anchor_levels_cm(character_e, body, sim.pattern, sim.pmesh, x, sim.cloth.group)
    assert moved["waistband"] == pytest.approx(20.0, abs=placed["waistband"] + 0.1)
    assert {k: v for k, v in moved.items() if k != "waistband"} == {k: v for k, v in placed.items() if k != "waistband"}
