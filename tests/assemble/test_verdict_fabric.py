"""The verdict knows the fabric: knits stretch, a knit too small still fails, a hem ridden up is flagged."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from test_verdict import _measured, _radius_for, _seam_welded, _tube

from patternbridge.assemble.defects import girth_strain, grain_directions, hem_rise_cm
from patternbridge.assemble.mesh2d import mesh_pattern
from patternbridge.assemble.verdict import Check, Verdict, VerdictLimits, edge_limits, judge, limits_for
from patternbridge.pattern.fabric import FABRIC_STRETCH, FabricClass


def _tube_strain(strain: float) -> float:
    """The tightest girth strain measured on a 60 cm tube wrapped round a cylinder ``strain`` x its girth."""
    girth = 60.0
    x, uv, faces = _tube(girth, 30.0, lambda v: np.full_like(v, _radius_for(girth, strain)))
    return float(girth_strain(x, uv, faces, _seam_welded(uv))[1].max())


def _girth_verdict(strain: float, fabric: FabricClass) -> Verdict:
    verdict, _ = judge(_measured(girth_strain=_tube_strain(strain), girth_pieces=("leg",)), limits_for(fabric))
    return verdict


def test_a_woven_keeps_the_documented_limits():
    assert limits_for(FabricClass.WOVEN) == VerdictLimits()
    assert (VerdictLimits().girth_flawed, VerdictLimits().girth_failed) == (1.03, 1.08)


def test_the_girth_limits_are_the_wovens_shifted_by_the_fabrics_worn_stretch():
    for fabric, stretch in FABRIC_STRETCH.items():
        lim = limits_for(fabric)
        assert lim.fabric is fabric
        assert lim.girth_flawed == pytest.approx(1.03 + stretch.across_worn)
        assert lim.girth_failed == pytest.approx(1.08 + stretch.across_worn)
        # every class stretches further across the grain than along it, and is worn short of its limit
        assert stretch.across_worn < stretch.across_limit and stretch.along_worn <= stretch.across_worn


def test_leggings_at_their_drafted_negative_ease_pass_as_a_stretch_knit_and_fail_as_a_woven():
    # the real leggings are drafted 15.6 % under the calf of their sample body
    assert _girth_verdict(1.156, FabricClass.STRETCH_KNIT) is Verdict.OK
    assert _girth_verdict(1.156, FabricClass.WOVEN) is Verdict.FAILED


def test_a_knit_two_sizes_too_small_still_fails():
    # a size step is 4-5 % of a girth: two sizes under the leggings' design
    assert _girth_verdict(1.156 * 1.09, FabricClass.STRETCH_KNIT) is Verdict.FAILED
    # one size under it shows (flawed), as a woven a size too small does
    assert _girth_verdict(1.156 * 1.045, FabricClass.STRETCH_KNIT) is Verdict.FLAWED
    # a jersey top drafted 3.8 % under the chest (the real tank), two sizes smaller
    assert _girth_verdict(1.038, FabricClass.KNIT) is Verdict.OK
    assert _girth_verdict(1.038 * 1.09, FabricClass.KNIT) is Verdict.FAILED


def test_the_report_names_the_fabric_and_its_limits():
    _, reasons = judge(_measured(girth_strain=1.3, girth_pieces=("leg",)), limits_for("stretch_knit"))
    assert reasons[0].check is Check.GIRTH and reasons[0].verdict is Verdict.FAILED
    assert reasons[0].limit == pytest.approx(23.0)
    assert "stretch knit" in reasons[0].message
    d = limits_for("knit").to_dict()
    assert d["class"] == "knit" and d["girth_failed"] == pytest.approx(1.13)
    assert d["stretch"] == FABRIC_STRETCH[FabricClass.KNIT].to_dict()


def test_edge_limits_follow_the_grain_for_a_stretch_knit_and_keep_the_woven_bias_floor():
    lim = VerdictLimits()
    grain = np.array([[0.0, 1.0]])  # one instance, grain along +y
    d = np.array([[0.0, 2.0], [3.0, 0.0], [1.0, 1.0]])  # along, across, on the bias
    group = np.zeros(3, dtype=np.int64)
    s = FABRIC_STRETCH[FabricClass.STRETCH_KNIT]
    flawed, torn = edge_limits(lim, (FabricClass.STRETCH_KNIT,), group, grain, d)
    np.testing.assert_allclose(
        torn, [max(1.33, 1 + s.along_limit), 1 + s.across_limit, 1 + (s.along_limit + s.across_limit) / 2]
    )
    np.testing.assert_allclose(flawed, [1.10, 1 + s.across_worn, max(1.10, 1 + (s.along_worn + s.across_worn) / 2)])
    # a woven edge is judged as before, whatever its direction
    flawed, torn = edge_limits(lim, (FabricClass.WOVEN,), group, grain, d)
    np.testing.assert_array_equal(flawed, 1.10)
    np.testing.assert_array_equal(torn, 1.33)
    # an edge stretched 40 % across the grain of a stretch knit is within its limit; along it, torn
    _, torn = edge_limits(lim, (FabricClass.STRETCH_KNIT,), group[:2], grain, d[:2])
    assert (1.4 > torn).tolist() == [True, False]


def _flat(pattern, pmesh, squeeze: float = 1.0, turn: bool = False):
    """Every instance laid flat in the x-y plane as cut (y up), its height squeezed by ``squeeze`` about its top."""
    xs, group = [], []
    for i, inst in enumerate(pmesh.instances):
        pts = pmesh.pieces[inst.piece].points
        top = pts[:, 1].max()
        x = np.column_stack([pts[:, 0], top - squeeze * (top - pts[:, 1]), np.full(len(pts), 10.0 * i)])
        if turn:  # held out sideways, as a sleeve in an A pose
            x = x[:, [1, 0, 2]]
        xs.append(x)
        group.append(np.full(len(pts), i))
    return np.concatenate(xs), np.concatenate(group)


def test_a_hem_ridden_up_is_measured_and_fails_the_level_check(tshirt):
    pmesh = mesh_pattern(tshirt, max_edge_cm=3.0)
    grain = grain_directions(tshirt, pmesh)
    x, group = _flat(tshirt, pmesh)
    hanging = hem_rise_cm(tshirt, pmesh, x, group, grain)
    # as cut, nothing rides up; the front and back hang from their neck marks
    assert {"front", "back"} <= set(hanging)
    assert max(abs(v) for v in hanging.values()) < 1e-9
    # squeezed to 70 % of its height the front's hem comes up by 30 % of its drop below the neck mark
    x, group = _flat(tshirt, pmesh, squeeze=0.7)
    rise = hem_rise_cm(tshirt, pmesh, x, group, grain)
    front = pmesh.pieces["front"]
    drop = front.points[front.marks["neck_centre"], 1] - front.points[: front.n_boundary, 1].min()
    assert rise["front"] == pytest.approx(0.3 * drop, rel=0.05)
    verdict, reasons = judge(_measured(hem_rise_cm=rise))
    assert verdict is Verdict.FAILED and reasons[0].check is Check.LEVEL and reasons[0].where[0] in rise
    # a piece held out sideways does not hang from its anchor: not measured
    x, group = _flat(tshirt, pmesh, turn=True)
    assert hem_rise_cm(tshirt, pmesh, x, group, grain) == {}


def test_a_pieces_fabric_class_is_one_of_the_classes(tshirt):
    rib = dataclasses.replace(tshirt.pieces[0], fabric_class="stretch_knit")
    assert rib.fabric_class is FabricClass.STRETCH_KNIT
    with pytest.raises(ValueError):
        dataclasses.replace(tshirt.pieces[0], fabric_class="felt")
