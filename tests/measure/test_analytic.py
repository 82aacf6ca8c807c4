"""Analytic mannequins: cylinder, ellipsoid and capsule girths and geodesic lengths."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from patternbridge.measure.girths import BodyFrame, _arm_girths
from patternbridge.measure.section import hull_girth, plane_loops


def _cylinder(radius: float, height: float, sections: int = 512) -> trimesh.Trimesh:
    m = trimesh.creation.cylinder(radius=radius, height=height, sections=sections)
    return m


def _ring(n: int) -> float:
    """Perimeter factor of a regular n-gon inscribed in a unit circle (over 2*pi)."""
    return n * np.sin(np.pi / n) / np.pi


def test_cylinder_girth_is_two_pi_r():
    m = _cylinder(12.0, 80.0)
    sec = plane_loops(
        np.asarray(m.vertices), np.asarray(m.faces), [0, 0, 5.0], [0, 0, 1.0]
    )
    assert len(sec.loops) == 1 and sec.loops[0].closed
    g, ring = hull_girth(sec, sec.loops)
    assert g == pytest.approx(2 * np.pi * 12.0, rel=5e-3)
    assert g == pytest.approx(2 * np.pi * 12.0 * _ring(512), rel=1e-9)
    np.testing.assert_allclose(ring[0], ring[-1])


def test_inclined_plane_gives_an_ellipse():
    r, theta = 10.0, np.radians(30.0)
    m = _cylinder(r, 100.0, sections=720)
    normal = [0.0, np.sin(theta), np.cos(theta)]
    sec = plane_loops(np.asarray(m.vertices), np.asarray(m.faces), [0, 0, 0], normal)
    g, _ = hull_girth(sec, sec.loops)
    a, b = r / np.cos(theta), r
    h = ((a - b) / (a + b)) ** 2
    ramanujan = np.pi * (a + b) * (1 + 3 * h / (10 + np.sqrt(4 - 3 * h)))
    assert g == pytest.approx(ramanujan, rel=5e-3)


def test_ellipsoid_girth():
    m = trimesh.creation.icosphere(subdivisions=6, radius=1.0)
    v = np.asarray(m.vertices) * [15.0, 10.0, 30.0]
    sec = plane_loops(v, np.asarray(m.faces), [0, 0, 0], [0, 0, 1])
    g, _ = hull_girth(sec, sec.loops)
    a, b = 15.0, 10.0
    h = ((a - b) / (a + b)) ** 2
    assert g == pytest.approx(
        np.pi * (a + b) * (1 + 3 * h / (10 + np.sqrt(4 - 3 * h))), rel=5e-3
    )


def test_tape_bridges_hollows():
    """A star-shaped prism: the girth is its convex hull, shorter than its outline."""
    n = 10
    ang = np.arange(2 * n) * np.pi / n
    rad = np.where(np.arange(2 * n) % 2 == 0, 10.0, 5.0)
    poly = np.column_stack([rad * np.cos(ang), rad * np.sin(ang)])
    from shapely.geometry import Polygon

    m = trimesh.creation.extrude_polygon(Polygon(poly), 20.0)
    sec = plane_loops(
        np.asarray(m.vertices), np.asarray(m.faces), [0, 0, 10.0], [0, 0, 1]
    )
    g, _ = hull_girth(sec, sec.loops)
    outline = np.linalg.norm(np.diff(np.vstack([poly, poly[:1]]), axis=0), axis=1).sum()
    hull = 2 * n * 10.0 * np.sin(np.pi / (2 * n)) * 2 / 2  # decagon through the tips
    assert g == pytest.approx(n * 2 * 10.0 * np.sin(np.pi / n), rel=1e-9)
    assert g < outline
    del hull


def test_loops_are_separated_and_selected():
    """Two legs: a horizontal cut gives two loops; the part loop is the one around the axis point."""
    a = _cylinder(6.0, 50.0, 256)
    b = _cylinder(4.0, 50.0, 256)
    v = np.vstack(
        [np.asarray(a.vertices) + [-10, 0, 0], np.asarray(b.vertices) + [10, 0, 0]]
    )
    f = np.vstack([np.asarray(a.faces), np.asarray(b.faces) + len(a.vertices)])
    sec = plane_loops(v, f, [0, 0, 0], [0, 0, 1])
    assert len(sec.loops) == 2
    loops = BodyFrame.part_loops(sec, np.array([10.0, 0, 0]))
    g, _ = hull_girth(sec, loops)
    assert g == pytest.approx(2 * np.pi * 4.0, rel=5e-3)
    g2, _ = hull_girth(sec, sec.loops)  # both: the tape around both legs
    assert g2 == pytest.approx(2 * np.pi * 5.0 + 2 * np.hypot(20.0, 2.0), rel=5e-3)


def test_inclined_capsule_arm_girth_follows_the_axis():
    """An A-pose arm: a capsule 45 degrees below horizontal; girths are taken square to it."""
    r = 5.0
    cap = trimesh.creation.capsule(height=60.0, radius=r, count=[128, 64])
    v = np.asarray(cap.vertices)  # axis along z, centred
    rot = trimesh.transformations.rotation_matrix(
        np.radians(-135.0), [0, 0, 1]
    ) @ trimesh.transformations.rotation_matrix(np.radians(90.0), [0, 1, 0])
    v = v @ rot[:3, :3].T + [40.0, 120.0, 0.0]
    axis = rot[:3, :3] @ [0, 0, 1.0]
    axis = axis if axis[0] > 0 else -axis
    centre = np.array([40.0, 120.0, 0.0])
    up = np.cross(axis, [0, 0, 1.0])
    up = up if up[1] > 0 else -up
    marks = {
        "top_of_head": np.array([0.0, 180.0, 0.0]),
        "shoulder_point_left": centre - 25 * axis + r * up,
        "elbow_point_left": centre + 0 * axis - r * np.array([0, 0, 1.0]),
        "wrist_point_left": centre + 25 * axis - r * np.array([0, 0, 1.0]),
    }
    body = BodyFrame(v, np.asarray(cap.faces), marks)
    out = _arm_girths(body, "left")
    for mid in ("upper_arm_girth_left", "elbow_girth_left", "wrist_girth_left"):
        assert out[mid].value_cm == pytest.approx(2 * np.pi * r, rel=5e-3), mid
        n = out[mid].details["plane_normal"]
        assert abs(abs(n @ axis) - 1) < 1e-3  # square to the limb


geodesic = pytest.importorskip("patternbridge.geodesic")


def test_cylinder_geodesic_lengths():
    """Straight line along a cylinder and a helix-like path: unrolled distances."""
    from patternbridge.measure.lengths import measure_lengths
    from patternbridge.mesh.character import Landmark

    r, n = 10.0, 256
    m = trimesh.creation.cylinder(radius=r, height=60.0, sections=n)
    m = m.subdivide().subdivide()
    v, f = np.asarray(m.vertices), np.asarray(m.faces)
    # open tube: keep the side wall only (no caps) so the shortest path stays on it
    keep = np.abs(np.asarray(m.face_normals)[:, 2]) < 0.5
    f = f[keep]

    def vid(angle, z):
        p = np.array([r * np.cos(angle), r * np.sin(angle), z])
        return int(np.argmin(np.linalg.norm(v - p, axis=1)))

    a, b, c = vid(0.0, -25.0), vid(0.0, 25.0), vid(np.pi / 2, 20.0)
    marks = {
        "back_neck_point": Landmark(name="back_neck_point", position=v[a], vertex=a),
        "waist_back": Landmark(name="waist_back", position=v[b], vertex=b),
        "front_neck_point": Landmark(name="front_neck_point", position=v[a], vertex=a),
        "waist_front": Landmark(name="waist_front", position=v[c], vertex=c),
    }
    out = measure_lengths(v, f, marks, ids=["back_length", "front_length"], tape=False)
    assert out["back_length"].value_cm == pytest.approx(
        np.linalg.norm(v[b] - v[a]), rel=5e-3
    )
    dz = v[c, 2] - v[a, 2]
    arc = r * np.arctan2(v[c, 1], v[c, 0])
    assert out["front_length"].value_cm == pytest.approx(np.hypot(arc, dz), rel=5e-3)


def _neck_mannequin(r: float = 6.0, tilt_deg: float = 20.0):
    """A torso box, a cylinder neck leaning forward by ``tilt_deg`` and a sphere head.

    Returns vertices, faces, the neck axis (unit) and the datum points.
    """
    t = np.radians(tilt_deg)
    axis = np.array([0.0, np.cos(t), np.sin(t)])
    foot = np.array([0.0, 150.0, 0.0])
    neck = trimesh.creation.cylinder(radius=r, height=40.0, sections=360)
    rot = trimesh.geometry.align_vectors([0, 0, 1.0], axis)
    # rings every 2 cm along the neck, as on a body mesh (the search keeps faces by vertex)
    nv, nf = trimesh.remesh.subdivide_to_size(neck.vertices, neck.faces, max_edge=2.0)
    neck = trimesh.Trimesh(nv, nf, process=False)
    nv = np.asarray(neck.vertices) @ rot[:3, :3].T + foot + 10.0 * axis  # into the box
    box = trimesh.creation.box(extents=[40.0, 151.0, 25.0])  # torso down to the floor
    bv = np.asarray(box.vertices) + [0.0, 75.5, 0.0]
    head = trimesh.creation.icosphere(subdivisions=3, radius=10.0)
    hv = np.asarray(head.vertices) + foot + 30.0 * axis
    parts = [(nv, neck.faces), (bv, box.faces), (hv, head.faces)]
    v = np.vstack([p[0] for p in parts])
    offs = np.cumsum([0] + [len(p[0]) for p in parts])
    f = np.vstack([np.asarray(p[1]) + o for p, o in zip(parts, offs[:-1], strict=True)])
    back = np.cross([1.0, 0.0, 0.0], axis)  # unit, pointing backward (-z) and up
    back = -back if back[2] > 0 else back
    side = np.array([1.0, 0.0, 0.0])
    marks = {
        "back_neck_point": foot + 8.0 * axis + r * back,
        "front_neck_point": foot + 3.0 * axis - r * back,
        "neck_shoulder_point_left": foot + 5.0 * axis + r * side,
        "neck_shoulder_point_right": foot + 5.0 * axis - r * side,
        "top_of_head": foot + 40.0 * axis,
    }
    return v, f, axis, marks


@pytest.mark.parametrize("tilt_deg", [0.0, 20.0])
def test_neck_girth_is_the_square_section_of_a_cylinder_neck(tilt_deg):
    """Through the back neck point the snuggest plane is square to the neck: 2 pi r."""
    from patternbridge.measure.girths import _neck_base_girth, _neck_girth

    r = 6.0
    v, f, axis, marks = _neck_mannequin(r, tilt_deg)
    body = BodyFrame(v, f, marks)
    m = _neck_girth(body)
    assert m.value_cm == pytest.approx(2 * np.pi * r * _ring(360), rel=2e-3)
    n = np.asarray(m.details["plane_normal"])
    assert abs(n @ axis) > np.cos(np.radians(1.0))  # the neck axis, to the 1 degree grid
    np.testing.assert_allclose(m.details["plane_origin"], marks["back_neck_point"])
    assert m.polyline[:, 1].min() > 148.0  # the torso box is not in the loop
    # the neck-base plane through the four points is oblique: a longer ellipse
    base = _neck_base_girth(body)
    assert base.value_cm > m.value_cm + 0.5


def test_neck_girth_bad_datum_points():
    from patternbridge.errors import LandmarkError
    from patternbridge.measure.girths import GirthError, _neck_girth

    v, f, axis, marks = _neck_mannequin()
    on_chord = dict(marks, back_neck_point=marks["top_of_head"] - 35.0 * axis)
    on_chord["front_neck_point"] = marks["top_of_head"] - 30.0 * axis
    with pytest.raises(GirthError, match="on the head chord"):
        _neck_girth(BodyFrame(v, f, on_chord))
    far = {k: p + [0.0, 0.0, 500.0] for k, p in marks.items()}
    with pytest.raises(GirthError, match="no neck section"):
        _neck_girth(BodyFrame(v, f, far))
    with pytest.raises(LandmarkError, match="back_neck_point"):
        _neck_girth(
            BodyFrame(v, f, {k: p for k, p in marks.items() if k != "back_neck_point"})
        )
