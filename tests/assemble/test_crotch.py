"""A leg piece's crotch is laid under the body's crotch: the four rise and inseam corners meet between the thighs."""

from __future__ import annotations

import numpy as np
import pytest
from brute_force import crossing_triangles

from patternbridge.assemble.place.length import CrotchDrop
from patternbridge.assemble.place.wrap import CROTCH_TURN_CM, _facing_crotch


def test_the_far_ends_of_the_rows_at_the_crotch_face_it_whatever_the_widths():
    # a front spanning 0.8π and a back 1.2π from the side seam at angle 0: by
    # their widths the inside leg lies at 0.8π, the crotch faces 1.0π
    side, crotch_angle, crotch_h = 0.0, np.pi, 80.0
    share = np.array([0.0, 0.5, 1.0, -0.5, -1.0])
    width_theta = np.array([0.0, 0.4, 0.8, -0.6, -1.2]) * np.pi
    at = _facing_crotch(width_theta, np.full(5, crotch_h + 3.0), share, side, crotch_angle, crotch_h)
    np.testing.assert_allclose(np.mod(at, 2 * np.pi), np.mod([0.0, 0.5, 1.0, -0.5, -1.0], 2) * np.pi, atol=1e-12)
    # both far ends on one angle: the front's and the back's inside leg corners meet
    assert abs(np.mod(at[2] - at[4], 2 * np.pi)) < 1e-12
    # the turn fades below the crotch: half way at half the distance, none beyond it
    half = _facing_crotch(width_theta, np.full(5, crotch_h - CROTCH_TURN_CM / 2), share, side, crotch_angle, crotch_h)
    np.testing.assert_allclose(half, 0.5 * (width_theta + at), atol=1e-12)
    low = _facing_crotch(width_theta, np.full(5, crotch_h - CROTCH_TURN_CM - 1), share, side, crotch_angle, crotch_h)
    np.testing.assert_array_equal(low, width_theta)


def test_a_crotch_drop_stretches_the_rise_evenly_and_lowers_the_rest():
    drop = CrotchDrop(crotch_y=70.0, anchor_y=90.0, stretch_cm=2.0, shift_cm=3.0)
    y = np.array([100.0, 90.0, 80.0, 70.0, 10.0])
    np.testing.assert_allclose(drop.lowered(y), [3.0, 3.0, 4.0, 5.0, 5.0])
    assert drop.rise_scale == pytest.approx(1.1)
    np.testing.assert_array_equal(CrotchDrop().lowered(y), np.zeros(5))


@pytest.mark.shared
@pytest.mark.slow
@pytest.mark.parametrize("garment", ["shorts", "trousers"])
def test_the_crotch_corners_meet_under_the_crotch_and_the_placement_does_not_cross_itself(characters_dir, garment):
    # the library shorts and trousers in their sample size on B_slim_female:
    # by the widths the back's wider crotch put the inside leg's top on the
    # front of the thigh, the four corners 7-8 cm before the body's crotch,
    # and the backs' crotch extensions lay pressed through each other under it
    # (22 and 36 crossing triangles placed)
    from patternbridge.assemble.cloth import weld_groups
    from patternbridge.assemble.pipeline import prepare
    from patternbridge.assemble.place.wrap import landmark_position
    from patternbridge.library import load_garment
    from patternbridge.mesh.load import load_character

    character, _ = load_character(characters_dir / "B_slim_female.obj")
    sim = prepare(character, load_garment(garment), seed=0, max_edge_cm=3.0)
    crotch = landmark_position(character, sim.body, "crotch_point", False)
    offsets = np.searchsorted(sim.cloth.group, np.arange(len(sim.names)))
    corners = np.array(
        [
            sim.cloth.x[offsets[i] + sim.pmesh.pieces[inst.piece].marks["crotch_point"]]
            for i, inst in enumerate(sim.pmesh.instances)
            if "crotch_point" in sim.pmesh.pieces[inst.piece].marks
        ]
    )
    assert len(corners) == 4
    assert np.all(corners[:, 1] < crotch[1]), corners
    assert np.all(np.linalg.norm((corners - crotch)[:, [0, 2]], axis=1) < 4.5), (corners, crotch)
    # an independent count over the garment, the two sides of every seam welded
    weld = weld_groups(len(sim.cloth.x), sim.cloth.seams)
    ids, inv = np.unique(weld, return_inverse=True)
    wx = np.zeros((len(ids), 3))
    np.add.at(wx, inv, sim.cloth.x)
    wx /= np.bincount(inv)[:, None]
    assert crossing_triangles(wx, inv[sim.cloth.faces]) == 0
