"""The cloth solver's seams: gathered lengths, and closing a seam by simulation."""

from __future__ import annotations

import numpy as np

from patternbridge.assemble.drape import build_cloth, drape, gathered_lengths, seam_gaps


def _strip(width: float, n: int, y0: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """A strip of 2n triangles, ``width`` cm long and 2 cm high, bottom edge on y = y0; points, faces."""
    xs = np.linspace(0.0, width, n + 1)
    pts = np.concatenate([np.stack([xs, np.full(n + 1, y0)], 1), np.stack([xs, np.full(n + 1, y0 + 2.0)], 1)])
    faces = []
    for i in range(n):
        a, b, c, d = i, i + 1, n + 1 + i + 1, n + 1 + i
        faces += [(a, b, c), (a, c, d)]
    return pts, np.array(faces, dtype=np.int64)


def test_gathered_seam_takes_the_shorter_sides_lengths():
    # a 12 cm edge sewn to a 9 cm edge, 3 segments each: the longer side's
    # segments are sewn flat at 3 cm, the rest of the cloth keeps its lengths
    long_pts, long_f = _strip(12.0, 3)
    short_pts, short_f = _strip(9.0, 3, y0=-2.0)
    top = np.arange(4) + 4  # the short strip's top edge, y = 0
    bottom = np.arange(4)  # the long strip's bottom edge
    cloth = build_cloth(
        [np.c_[long_pts, np.zeros(8)], np.c_[short_pts, np.zeros(8)]],
        [long_pts, short_pts],
        [long_f, short_f],
        [(0, 1, bottom, top)],
    )
    sewn = np.isin(cloth.edges, np.r_[bottom, top + 8]).all(axis=1) & (
        np.abs(cloth.uv[cloth.edges[:, 0], 1] - cloth.uv[cloth.edges[:, 1], 1]) < 1e-9
    )
    sewn &= np.isclose(cloth.uv[cloth.edges[:, 0], 1], 0.0)
    assert sewn.sum() == 6
    np.testing.assert_allclose(cloth.target[sewn], 3.0)
    np.testing.assert_allclose(cloth.rest[sewn & (cloth.edges[:, 0] < 8)], 4.0)  # the pattern's lengths are kept
    np.testing.assert_array_equal(cloth.target[~sewn], cloth.rest[~sewn])


def test_gathered_lengths_leave_equal_seams_and_unknown_edges_alone():
    edges = np.array([[0, 1], [1, 2], [3, 4], [4, 5]])
    rest = np.array([2.0, 2.0, 2.0, 2.0])
    out = gathered_lengths(edges, rest, [(np.array([0, 1, 2]), np.array([3, 4, 5]))])
    np.testing.assert_array_equal(out, rest)
    # vertices sewn in an order that is not along an edge of the mesh: nothing to gather
    out = gathered_lengths(edges, np.array([2.0, 2.0, 1.0, 1.0]), [(np.array([0, 2]), np.array([3, 5]))])
    np.testing.assert_array_equal(out, [2.0, 2.0, 1.0, 1.0])


def test_simulation_closes_a_gathered_seam(no_body):
    # two strips 6 cm apart, one 12 cm and one 9 cm long: sewn by the
    # solver alone (no welding) the pairs meet within a tenth of a millimetre
    long_pts, long_f = _strip(12.0, 6)
    short_pts, short_f = _strip(9.0, 6, y0=-2.0)
    x_long = np.c_[long_pts, np.zeros(14)]
    x_short = np.c_[short_pts + [1.5, -6.0], np.zeros(14)]
    cloth = build_cloth(
        [x_long, x_short], [long_pts, short_pts], [long_f, short_f], [(0, 1, np.arange(7), np.arange(7) + 7)]
    )
    assert seam_gaps(cloth.x, cloth.seams).max() > 5.0
    drape(cloth, no_body, steps=60, sew_steps=40, gravity_scale=0.0)
    # (with both sides at their pattern lengths the seam springs fight the
    # stretch springs and the pairs stay three times farther apart)
    assert seam_gaps(cloth.x, cloth.seams).max() < 0.01


def _two_strips(gap_cm: float):
    """Two 9 cm strips, the second ``gap_cm`` below the first, sewn edge to edge (pairs 0-6 with 7-13)."""
    pts, f = _strip(9.0, 6)
    x_a = np.c_[pts, np.zeros(14)]
    x_b = np.c_[pts + [0.0, -gap_cm], np.zeros(14)]
    return build_cloth([x_a, x_b], [pts, pts], [f, f], [(0, 1, np.arange(7), np.arange(7) + 7)])


def test_a_loose_seam_waits_and_then_closes_from_where_it_is(no_body):
    # two strips sewn along one edge, the second one 6 cm off: left loose,
    # the seam pulls nothing while the other cloth is sewn; released with a
    # ramp it closes from the gap it had then, without welding
    cloth = _two_strips(8.0)
    start = seam_gaps(cloth.x, cloth.seams)
    loose = np.ones(len(cloth.seams), dtype=bool)
    solver = drape(cloth, no_body, steps=40, sew_steps=30, gravity_scale=0.0, loose=loose)
    np.testing.assert_allclose(seam_gaps(cloth.x, cloth.seams), start, atol=1e-6)
    solver.restart_seams()
    half = drape(
        cloth,
        no_body,
        steps=20,
        sew_steps=0,
        gravity_scale=0.0,
        solver=solver,
        sew_ramp=(0.0, 0.5),
    )
    gap_half = seam_gaps(cloth.x, cloth.seams)
    assert np.all((gap_half > 0.3 * start) & (gap_half < 0.7 * start))  # half way: the ramp, not a jump
    drape(cloth, no_body, steps=30, sew_steps=0, gravity_scale=0.0, solver=half, sew_ramp=(0.5, 1.0))
    assert seam_gaps(cloth.x, cloth.seams).max() < 0.01


def test_a_loose_seam_keeps_its_two_sides_together_without_closing(no_body):
    # a cuff left unsewn on a raised arm: when its sleeve slides, it follows
    # at the same gap (with no spring at all it stayed behind and turned
    # round the wrist)
    from patternbridge.assemble.drape import DrapeSettings

    def slide(share):
        cloth = _two_strips(3.0)
        start, before = seam_gaps(cloth.x, cloth.seams), cloth.x.copy()
        cloth.v[:14] = [60.0, 0.0, 0.0]  # the sleeve side slides along x
        drape(
            cloth,
            no_body,
            steps=40,
            sew_steps=30,
            gravity_scale=0.0,
            loose=np.ones(len(cloth.seams), dtype=bool),
            settings=DrapeSettings(loose_share=share),
        )
        moved = (cloth.x - before)[:, 0]
        return moved[:14].mean(), moved[14:].mean(), seam_gaps(cloth.x, cloth.seams), start

    a, b, gaps, start = slide(0.1)
    assert a > 5.0 and abs(b - a) < 0.2 * a  # the other side came along
    assert np.all(np.abs(gaps - start) < 0.3)  # at its gap: not sewn
    a, b, gaps, _ = slide(0.0)
    assert a > 5.0 and abs(b) < 1e-6  # no spring: left behind


def test_the_heavier_side_of_a_seam_stays_and_the_lighter_comes_to_it(no_body):
    # two strips 6 cm apart sewn along one edge, without gravity: with equal
    # masses they meet half way; with the second one 30 times as heavy the
    # first one does nearly all of the moving; the next call is back to the
    # plain masses
    def sew(inertia):
        cloth = _two_strips(8.0)
        before = cloth.x.copy()
        solver = drape(cloth, no_body, steps=40, sew_steps=30, gravity_scale=0.0, inertia=inertia)
        assert seam_gaps(cloth.x, cloth.seams).max() < 0.05
        moved = np.linalg.norm(cloth.x - before, axis=1)
        return moved[:14].mean(), moved[14:].mean(), solver

    a, b, _ = sew(None)
    assert abs(a - b) < 0.1 * (a + b)
    a, b, solver = sew(np.r_[np.ones(14), np.full(14, 30.0)])
    assert b < 0.1 * a
    np.testing.assert_allclose(solver.m_h2[14:], 30.0 * solver.m_h2[:14])
    solver.weigh(None)
    np.testing.assert_allclose(solver.m_h2, solver.mass_h2)


def _patch_on_slope(slope_deg: float, friction: float) -> float:
    """How far (cm) a small cloth patch resting on a plane sloped ``slope_deg`` slides down it in 1 s of gravity."""
    import trimesh

    from patternbridge.assemble.collision import BodyCollider
    from patternbridge.assemble.drape import DrapeSettings

    tilt = trimesh.transformations.rotation_matrix(np.radians(slope_deg), [0.0, 0.0, 1.0])
    block = trimesh.creation.box(extents=[200.0, 20.0, 200.0])
    block.apply_transform(tilt)
    normal = tilt[:3, :3] @ [0.0, 1.0, 0.0]
    pts, f = _strip(3.0, 3)
    flat = np.c_[pts[:, 0], np.zeros(len(pts)), pts[:, 1]] - [1.5, 0.0, 1.0]
    x = flat @ tilt[:3, :3].T + (10.0 + 0.6) * normal  # on the top face, at the skin offset
    cloth = build_cloth([x], [pts], [f], [])
    settings = DrapeSettings(friction=friction)
    drape(cloth, BodyCollider(block.vertices, block.faces), steps=60, sew_steps=0, settings=settings)
    down = tilt[:3, :3] @ [-1.0, 0.0, 0.0]  # the slope's downhill direction
    return float(np.mean((cloth.x - x) @ down))


def test_cloth_on_a_slope_sticks_below_the_friction_angle_and_slides_above():
    # Coulomb friction: it holds on a slope gentler than atan(0.6) = 31 degrees and not on a steeper one;
    # without friction it slides on the gentle one too
    assert abs(_patch_on_slope(15.0, 0.6)) < 0.5
    assert _patch_on_slope(50.0, 0.6) > 20.0
    assert _patch_on_slope(15.0, 0.0) > 20.0
