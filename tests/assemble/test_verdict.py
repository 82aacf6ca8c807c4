"""The drape verdict: limits, reasons, the independent skin check and the pattern-level seam check."""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest
import trimesh
from measured import clean_measured

from patternbridge.assemble.defects import girth_strain, seam_excess_cm
from patternbridge.assemble.mesh2d import mesh_pattern
from patternbridge.assemble.skin_check import skin_check
from patternbridge.assemble.verdict import Check, Measured, Verdict, VerdictLimits, judge, worst


def _measured(**kw) -> Measured:
    sewn = dict(seam_gaps_mm={"side": 0.5}, seam_excess_cm={"side": 0.0}, levels_cm={"front": 0.5})
    return clean_measured(**{**sewn, **kw})


def test_a_clean_drape_is_ok_with_no_reason():
    verdict, reasons = judge(_measured())
    assert verdict is Verdict.OK
    assert reasons == ()


@pytest.mark.parametrize(
    ("change", "check", "expected"),
    [
        ({"seam_gaps_mm": {"side": 3.0, "cuff": 1.0}}, Check.SEAM_GAP, Verdict.FLAWED),
        ({"seam_gaps_mm": {"side": 22.0}}, Check.SEAM_GAP, Verdict.FAILED),
        ({"seam_excess_cm": {"side": 10.0}}, Check.SEAM_LENGTH, Verdict.FAILED),
        ({"self_crossing": {"front": 4}}, Check.SELF_CROSSING, Verdict.FLAWED),
        ({"self_crossing": {"front": 400, "back": 251}}, Check.SELF_CROSSING, Verdict.FAILED),
        ({"skin_depth_mm": 3.0, "skin_share": 0.001, "skin_pieces": ("front",)}, Check.SKIN, Verdict.FLAWED),
        ({"skin_depth_mm": 3.0, "skin_share": 0.05, "skin_pieces": ("front",)}, Check.SKIN, Verdict.FAILED),
        ({"stretch_share": 0.04, "stretch_pieces": ("sleeve",)}, Check.STRETCH, Verdict.FLAWED),
        ({"stretch_share": 0.2, "torn_share": 0.05}, Check.STRETCH, Verdict.FAILED),
        ({"levels_cm": {"waistband": 12.0}}, Check.LEVEL, Verdict.FAILED),
        ({"girth_strain": 1.04, "girth_pieces": ("back",)}, Check.GIRTH, Verdict.FLAWED),
        ({"girth_strain": 1.09, "girth_pieces": ("back",)}, Check.GIRTH, Verdict.FAILED),
        ({"turned_cm2": {"strap": 8.0, "front": 2.0}}, Check.TURNED, Verdict.FLAWED),
        ({"turned_cm2": {"binding": 35.0}}, Check.TURNED, Verdict.FAILED),
    ],
)
def test_each_check_beyond_its_limit_gives_its_reason(change, check, expected):
    verdict, reasons = judge(_measured(**change))
    assert verdict is expected
    assert [r.check for r in reasons] == [check]
    assert reasons[0].verdict is expected
    assert reasons[0].value > reasons[0].limit
    json.dumps([r.to_dict() for r in reasons])


def test_the_verdict_is_the_worst_reason_and_reasons_come_worst_first():
    verdict, reasons = judge(_measured(seam_gaps_mm={"side": 3.0}, self_crossing={"front": 300}))
    assert verdict is Verdict.FAILED
    assert [r.verdict for r in reasons] == [Verdict.FAILED, Verdict.FLAWED]
    assert reasons[1].where == ("side",)
    assert worst([]) is Verdict.OK


def test_limits_are_the_documented_ones_and_can_be_changed():
    strict = VerdictLimits(seam_gap_flawed_mm=0.1)
    assert judge(_measured(), strict)[0] is Verdict.FLAWED
    assert VerdictLimits().seam_gap_flawed_mm == 2.0
    assert str(Verdict.FAILED) == "failed"


def _tube(girth_cm: float, height_cm: float, radius_at, n: int = 24, rows: int = 9):
    """A tube of cloth cut from a ``girth_cm`` x ``height_cm`` rectangle, wrapped round a y-axis cylinder.

    ``radius_at(v)`` is the radius at pattern height ``v`` (cm). The seam is
    left unwelded (the last column repeats the first), as in a draped garment.
    """
    u, v = np.meshgrid(np.linspace(0.0, girth_cm, n + 1), np.linspace(0.0, height_cm, rows))
    uv = np.column_stack([u.ravel(), v.ravel()])
    angle = 2 * np.pi * uv[:, 0] / girth_cm
    r = radius_at(uv[:, 1])
    x = np.column_stack([r * np.cos(angle), uv[:, 1], r * np.sin(angle)])
    k = np.arange(rows - 1)[:, None] * (n + 1) + np.arange(n)[None, :]
    k = k.ravel()
    faces = np.concatenate([np.column_stack([k, k + 1, k + n + 2]), np.column_stack([k, k + n + 2, k + n + 1])])
    return x, uv, faces


def _seam_welded(uv: np.ndarray) -> np.ndarray:
    """Weld ids of the tube: the last column sewn to the first."""
    girth = uv[:, 0].max()
    column = np.where(np.isclose(uv[:, 0], girth), 0.0, uv[:, 0])
    return np.unique(np.column_stack([column, uv[:, 1]]), axis=0, return_inverse=True)[1].ravel()


def _radius_for(girth_cm: float, strain, n: int = 24):
    """The radius whose n-gon has a perimeter ``strain`` x ``girth_cm``."""
    return strain * girth_cm / (2 * n * np.sin(np.pi / n))


def test_girth_strain_of_a_tube_round_a_cylinder_is_its_stretch_all_the_way_round():
    girth = 90.0
    for strain in (1.0, 1.05, 0.97):
        x, uv, faces = _tube(girth, 40.0, lambda v, s=strain: np.full_like(v, _radius_for(girth, s)))
        heights, measured, face_cut = girth_strain(x, uv, faces, _seam_welded(uv))
        # cuts every cm from a cm above the hem; the top edge (at 40 cm) is cut along the cloth's edge: an open curve
        assert heights[0] == pytest.approx(1.0) and heights[-1] == pytest.approx(39.0)
        assert measured == pytest.approx(strain, abs=1e-9)
        # each cut goes once round the tube, through the 2 x 24 triangles of a row (at a row's height, the row
        # below: its vertices count as above the plane)
        assert set(face_cut.sum(axis=1)) == {48}


def test_girth_strain_ignores_stretch_along_the_tube_and_finds_the_tight_level():
    girth = 90.0
    # stretched 20 % down its length: no girth is stretched
    x, uv, faces = _tube(girth, 40.0, lambda v: np.full_like(v, _radius_for(girth, 1.0)))
    x[:, 1] *= 1.2
    assert girth_strain(x, uv, faces, _seam_welded(uv))[1] == pytest.approx(1.0, abs=1e-9)
    # a tube tight at the top: 1.0 at the hem rising to 1.08 at 40 cm, linear in height between the rows
    x, uv, faces = _tube(girth, 40.0, lambda v: _radius_for(girth, 1.0 + 0.002 * v))
    heights, measured, _ = girth_strain(x, uv, faces, _seam_welded(uv))
    # the n-gon's perimeter is linear in the radius, so the cut at height h measures 1 + 0.002 h exactly
    assert measured == pytest.approx(1.0 + 0.002 * heights, abs=1e-9)
    assert heights[np.argmax(measured)] == pytest.approx(39.0)


def test_girth_strain_is_measured_on_the_skin_under_the_solver_s_margin():
    # a leg's knit, 28 cm round, worn on a 33.3 cm calf (19 % strain); the solver keeps it 0.6 cm off the skin
    girth, strain, offset = 28.0, 33.3 / 28.0, 0.6
    n = 96  # fine enough that the n-gon's parallel curve is within 0.05 % of 2π x the offset longer
    skin = _radius_for(girth, strain, n)
    x, uv, faces = _tube(girth, 20.0, lambda v: np.full_like(v, skin + offset), n=n)
    drape = girth_strain(x, uv, faces, _seam_welded(uv))[1]
    # the drape's own length reads the margin as stretch: 2π x 0.6 cm more round a 33.3 cm calf, 11 % more
    assert drape == pytest.approx(strain + 2 * np.pi * offset / girth, rel=1e-3)
    assert drape.max() - strain > 0.13
    on_skin = girth_strain(x, uv, faces, _seam_welded(uv), skin_offset_cm=offset)[1]
    assert on_skin == pytest.approx(strain, rel=1e-3)
    # two legs: each closed curve is moved in by the margin (twice 2π x 0.6 off the sum of their lengths)
    x2 = np.concatenate([x - [10.0, 0.0, 0.0], x + [10.0, 0.0, 0.0]])
    f2, uv2 = np.concatenate([faces, faces + len(x)]), np.concatenate([uv, uv])
    weld2 = np.concatenate([_seam_welded(uv), _seam_welded(uv) + len(x)])
    _, both, face_cut = girth_strain(x2, uv2, f2, weld2, skin_offset_cm=offset)
    assert both == pytest.approx(strain, rel=1e-3)
    assert set(face_cut.sum(axis=1)) == {4 * n}
    # a loop of cloth under 4π x the margin round closes round nothing a garment dresses: not a girth
    sx, suv, sf = _tube(3.0, 20.0, lambda v: np.full_like(v, _radius_for(3.0, 1.0, n)), n=n)
    assert len(girth_strain(sx, suv, sf, _seam_welded(suv), skin_offset_cm=offset)[0]) == 0
    assert len(girth_strain(sx, suv, sf, _seam_welded(suv))[0]) > 0


def test_girth_strain_leaves_out_curves_that_do_not_close():
    girth = 90.0
    x, uv, faces = _tube(girth, 40.0, lambda v: np.full_like(v, _radius_for(girth, 1.0)))
    # unsewn, the tube is a sheet: no cut closes round, and no girth is measured
    heights, measured, face_cut = girth_strain(x, uv, faces, np.arange(len(x)))
    assert len(heights) == len(measured) == len(face_cut) == 0
    # a slit up the tube from the hem to 20 cm (the seam sewn only above it) opens the cuts below
    sewn_above = np.where(np.isclose(uv[:, 0], girth) & (uv[:, 1] < 20.0), len(x), 0) + _seam_welded(uv)
    heights, _, _ = girth_strain(x, uv, faces, sewn_above)
    # (the cut at 20 cm still crosses the last unsewn edge, from 15 to 20 cm)
    assert heights.min() == pytest.approx(21.0)
    assert np.all(np.diff(heights) == pytest.approx(1.0))


def test_skin_check_finds_a_triangle_through_a_sphere_by_its_middle():
    sphere = trimesh.creation.icosphere(subdivisions=4, radius=10.0)
    # a cloth-sized triangle whose corners are all outside but whose middle dips into the sphere's cap
    through = np.array([[-4.0, 9.5, -2.0], [4.0, 9.5, -2.0], [0.0, 9.5, 4.0]])
    assert np.all(np.linalg.norm(through, axis=1) > 10.0)
    # and one well clear of it
    clear = through + np.array([0.0, 2.0, 0.0])
    v = np.concatenate([through, clear])
    f = np.array([[0, 1, 2], [3, 4, 5]])
    check = skin_check(sphere.vertices, sphere.faces, v, f)
    assert check.inside(0.1).tolist() == [True, False]
    # the deepest point of the plane y = 9.5 inside the sphere lies 0.5 cm under the skin (polygonal sphere:
    # a little less); the samples reach most of it
    assert 0.25 < check.depth_cm[0] <= 0.5
    assert check.depth_cm[1] == 0.0


def test_a_seam_ten_cm_too_long_is_found_in_the_pattern(tshirt):
    before = seam_excess_cm(tshirt, mesh_pattern(tshirt, max_edge_cm=3.0))
    assert before["side_r"] < 0.1  # the side seams match in the fixture
    longer = _lengthen_side_seam(tshirt, 10.0)
    excess = seam_excess_cm(longer, mesh_pattern(longer, max_edge_cm=3.0))
    # the side seam runs straight down from the underarm: moving its hem end 10 cm lengthens it by 10 cm
    assert excess["side_r"] == pytest.approx(10.0, abs=0.3)
    assert {k: v for k, v in excess.items() if k != "side_r"} == pytest.approx(
        {k: v for k, v in before.items() if k != "side_r"}, abs=1e-6
    )


def _lengthen_side_seam(pattern, cm: float):
    """``pattern`` with the front's right side seam ``cm`` longer: its hem corner moved down."""
    front = pattern.piece("front")
    outline = np.array(front.outline)
    hem = front.marks["hem_r"]
    outline[hem, 1] -= cm
    return dataclasses.replace(
        pattern,
        pieces=tuple(dataclasses.replace(p, outline=outline) if p.name == "front" else p for p in pattern.pieces),
    )


@pytest.mark.shared
def test_the_pictures_draw_the_flagged_faces_red(character_e):
    from patternbridge.assemble.garment import Garment
    from patternbridge.assemble.pictures import render_fit

    # a small patch of cloth 5 cm in front of the chest, two triangles
    v = np.array([[-10.0, 120.0, 0.0], [10.0, 120.0, 0.0], [10.0, 140.0, 0.0], [-10.0, 140.0, 0.0]])
    v[:, 2] = np.asarray(character_e.vertices)[:, 2].max() + 5.0
    f = np.array([[0, 1, 2], [0, 2, 3]])
    n = len(v)

    def red_pixels(flagged):
        g = Garment(
            vertices=v,
            faces=f,
            uv=v[:, :2],
            instance=np.zeros(n, np.int64),
            instance_names=("patch",),
            weld=np.arange(n),
            joints=np.zeros((n, 0), np.int64),
            weights=np.zeros((n, 0)),
            skeleton=None,
            flagged=np.array(flagged),
        )
        img = render_fit(g, character_e, "front", size=(200, 300)).astype(int)
        return int(np.count_nonzero((img[..., 0] > 150) & (img[..., 1] < 80) & (img[..., 2] < 80)))

    assert red_pixels([False, False]) == 0
    assert red_pixels([True, False]) > 50
