"""Cloth worn turned over: a strip round a cylinder, untwisted, with a half twist, and pleated."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh
from measured import clean_measured

from patternbridge.assemble.turned import free_edge_faces, outward_cos, patches, turned_cloth
from patternbridge.assemble.verdict import Check, Measured, Verdict, VerdictLimits, judge

R_CM = 10.0  # the body: a cylinder of this radius
WIDTH_CM = 4.0  # the strap's width


def _body() -> tuple[np.ndarray, np.ndarray]:
    cyl = trimesh.creation.cylinder(radius=R_CM, height=80.0, sections=96)
    cyl.apply_transform(trimesh.transformations.rotation_matrix(np.pi / 2, [1, 0, 0]))  # its axis along y
    return np.asarray(cyl.vertices, dtype=np.float64), np.asarray(cyl.faces, dtype=np.int64)


def _grid_faces(nu: int, nv: int) -> np.ndarray:
    """Two triangles per cell of an nu x nv grid of points (u major), wound u then v (normal u x v)."""
    i, j = np.meshgrid(np.arange(nu - 1), np.arange(nv - 1), indexing="ij")
    a = (i * nv + j).ravel()
    b, c, d = a + nv, a + nv + 1, a + 1
    return np.concatenate([np.stack([a, b, c], 1), np.stack([a, c, d], 1)])


def _strap(twist: float, nu: int = 121, nv: int = 5) -> tuple[np.ndarray, np.ndarray]:
    """A strap 3/4 of the way round the body, its width along the axis, turned by ``twist`` about its length.

    The turn happens between a third and two thirds of the way (smoothly), about the strap's
    centre line, which runs far enough off the skin (0.6 cm + half the width) for the strap
    to turn without cutting the body. Faces are wound with the normal away from the body where untwisted.
    """
    theta = np.linspace(0.0, 1.5 * np.pi, nu)
    s = np.clip((theta / (1.5 * np.pi) - 1 / 3) * 3, 0.0, 1.0)
    phi = twist * s * s * (3 - 2 * s)
    rc = R_CM + 0.6 + WIDTH_CM / 2
    radial = np.stack([np.cos(theta), np.zeros(nu), np.sin(theta)], 1)
    up = np.array([0.0, 1.0, 0.0])
    d = np.cos(phi)[:, None] * up + np.sin(phi)[:, None] * radial
    v = np.linspace(-WIDTH_CM / 2, WIDTH_CM / 2, nv)
    x = (rc * radial)[:, None, :] + v[None, :, None] * d[:, None, :]
    faces = _grid_faces(nu, nv)[:, ::-1]  # tangent x up points into the body: wind the other way round
    return x.reshape(-1, 3), faces


def _pleat(depth_cm: float = 6.0, height_cm: float = 20.0) -> tuple[np.ndarray, np.ndarray]:
    """A band round the body with a pleat: forward 0.6 cm off the skin, back ``depth_cm`` 0.5 cm out, forward again.

    The middle layer of the pleat is turned over, between the layers under and over it.
    """
    arc = []  # (angle, radius) along the band's cross-section
    back = depth_cm / (R_CM + 1.1)
    t1 = np.linspace(0.0, 0.5 * np.pi, 40)
    arc += [(t, R_CM + 0.6) for t in t1]
    arc += [(t, R_CM + 1.1) for t in np.linspace(0.5 * np.pi, 0.5 * np.pi - back, 12)]
    arc += [(t, R_CM + 1.6) for t in np.linspace(0.5 * np.pi - back, np.pi, 40)]
    theta, r = np.array(arc).T
    ring = np.stack([r * np.cos(theta), np.zeros(len(r)), r * np.sin(theta)], 1)
    y = np.linspace(-height_cm / 2, height_cm / 2, 9)
    x = ring[:, None, :] + y[None, :, None] * np.array([0.0, 1.0, 0.0])
    return x.reshape(-1, 3), _grid_faces(len(ring), len(y))[:, ::-1]


def _turned(x: np.ndarray, faces: np.ndarray):
    bv, bf = _body()
    return turned_cloth(x, faces, np.arange(len(x)), bv, bf)


def test_an_untwisted_strap_faces_out_everywhere():
    x, faces = _strap(0.0)
    t = _turned(x, faces)
    assert t.cos.min() > 0.99  # its normal is the direction away from the cylinder's axis
    assert len(t.area_cm2) == 0
    verdict, reasons = judge(_measured(t))
    assert verdict is Verdict.OK and reasons == ()


def test_a_strap_with_a_half_twist_is_turned_over_beyond_it_and_the_verdict_names_it():
    x, faces = _strap(np.pi)
    t = _turned(x, faces)
    assert len(t.area_cm2) == 1  # one patch: from where the turn passes 120 degrees to the strap's end
    # analytic: the strap's width times the arc of its centre line from the turn's 120 degrees to the end
    rc = R_CM + 0.6 + WIDTH_CM / 2
    s = 0.6527  # smoothstep(s) = 2/3 (the turn at 120 degrees)
    theta0 = (1 / 3 + s / 3) * 1.5 * np.pi
    expected = WIDTH_CM * rc * (1.5 * np.pi - theta0)
    assert t.area_cm2[0] == pytest.approx(expected, rel=0.08)
    verdict, reasons = judge(_measured(t))
    assert verdict is Verdict.FAILED
    assert [r.check for r in reasons] == [Check.TURNED]
    assert reasons[0].where == ("strap",)
    assert "turned over" in reasons[0].message


def test_a_full_twist_turns_only_its_middle():
    x, faces = _strap(2 * np.pi)
    t = _turned(x, faces)
    area = t.area_cm2.max()
    rc = R_CM + 0.6 + WIDTH_CM / 2
    # turned between 120 and 240 degrees of the turn, well under the half twist's tail but a strap wide
    assert WIDTH_CM * rc * 0.2 < area < WIDTH_CM * rc * 1.0
    assert judge(_measured(t))[0] is not Verdict.OK


def test_a_pleat_is_a_fold_not_cloth_worn_turned_over():
    x, faces = _pleat()
    t = _turned(x, faces)
    turned = t.cos < -0.5
    area = 6.0 * 20.0
    assert turned.sum() > 0.8 * 2 * 11 * 8  # the pleat's middle layer is turned over (and reaches the edges)...
    assert t.covered[turned].all()  # ... under the layer folded back over it
    assert len(t.area_cm2) == 0
    assert area > VerdictLimits().turned_failed_cm2  # counted, the pleat would fail the drape


def _band(flip) -> tuple[np.ndarray, np.ndarray]:
    """A band 20 cm high half round the body, 0.6 cm off it; the cells where ``flip(u, v)`` wound inside out."""
    nu, nv = 41, 21
    theta = np.linspace(0.0, np.pi, nu)
    y = np.linspace(-10.0, 10.0, nv)
    r = R_CM + 0.6
    x = np.stack(np.broadcast_arrays(r * np.cos(theta)[:, None], y[None, :], r * np.sin(theta)[:, None]), -1)
    faces = _grid_faces(nu, nv)[:, ::-1]
    cell_u, cell_v = np.tile(np.arange(nu - 1).repeat(nv - 1), 2), np.tile(np.tile(np.arange(nv - 1), nu - 1), 2)
    inside_out = flip(cell_u, cell_v)
    faces[inside_out] = faces[inside_out, ::-1]
    return x.reshape(-1, 3), faces


def test_cloth_turned_inside_a_piece_is_a_crease_but_turned_to_its_edge_is_worn_inside_out():
    # the same 8 x 6 cells turned, once in the middle of the band, once reaching its top edge
    middle = _turned(*_band(lambda u, v: (u >= 16) & (u < 24) & (v >= 7) & (v < 13)))
    top = _turned(*_band(lambda u, v: (u >= 16) & (u < 24) & (v >= 14)))
    assert (middle.cos < -0.99).sum() == (top.cos < -0.99).sum() == 2 * 8 * 6
    assert len(middle.area_cm2) == 0
    cell = (R_CM + 0.6) * np.pi / 40 * 1.0
    assert top.area_cm2.tolist() == pytest.approx([8 * 6 * cell], rel=0.01)
    # the pictures mark the patch beyond the limit, and nothing of a patch under it
    assert top.faces(5.0).sum() == 2 * 8 * 6 and not top.faces(8 * 6 * cell * 1.01).any()
    assert not middle.faces(0.0).any()


def test_free_edges_are_those_of_one_triangle_on_the_welded_cloth():
    faces = np.array([[0, 1, 2], [3, 4, 5]])
    assert free_edge_faces(faces, np.arange(6)).tolist() == [True, True]
    # welded along (1, 2) ~ (3, 4): each triangle keeps two free edges
    assert free_edge_faces(faces, np.array([0, 1, 2, 2, 1, 5])).tolist() == [True, True]
    # a closed tetrahedron has none
    tet = np.array([[0, 1, 2], [0, 3, 1], [1, 3, 2], [2, 3, 0]])
    assert not free_edge_faces(tet, np.arange(4)).any()


def test_patches_join_faces_across_a_seam_but_not_at_a_corner():
    # two triangles sharing an edge only through welded vertices, and a third touching at one corner
    faces = np.array([[0, 1, 2], [3, 4, 5], [6, 7, 8]])
    weld = np.array([0, 1, 2, 1, 2, 9, 2, 10, 11])
    out = patches(faces, weld, np.array([True, True, True]))
    assert out.tolist() == [0, 0, 1]
    assert patches(faces, weld, np.array([False, True, False])).tolist() == [-1, 0, -1]


def test_outward_cos_is_the_normal_against_the_direction_off_the_skin():
    x = np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [0.0, 1.0, 1.0]])
    f = np.array([[0, 1, 2]])
    below = np.array([[1 / 3, 1 / 3, 0.0]])
    assert outward_cos(x, f, below)[0] == pytest.approx(1.0)
    assert outward_cos(x, f[:, ::-1], below)[0] == pytest.approx(-1.0)
    beside = np.array([[1 / 3, 5.0, 1.0]])  # the skin beside the face: its normal runs along the skin
    assert outward_cos(x, f, beside)[0] == pytest.approx(0.0, abs=1e-12)


def _measured(t) -> Measured:
    return clean_measured(turned_cm2={"strap": float(t.area_cm2.max())} if len(t.area_cm2) else {})
