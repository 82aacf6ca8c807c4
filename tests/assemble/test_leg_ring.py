"""Leg pieces whose outline rises above the crotch go round the hips, whatever their cut."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from patternbridge.assemble.place.wrap import _ring_share

LEGGINGS = Path(__file__).resolve().parents[2] / ".." / "shared" / "aama" / "GLX4802S19_AAMA.DXF"


def _trapezoid(x0: float, x1: float) -> np.ndarray:
    """A closed (4, 2) outline from x0 to x1, 30 cm high."""
    return np.array([[x0, 0.0], [x1, 0.0], [x1, 30.0], [x0, 30.0]])


def test_a_piece_with_its_side_line_at_one_end_spans_one_quarter():
    b = _trapezoid(0.0, 20.0)
    p2 = np.array([[0.0, 10.0], [10.0, 10.0], [20.0, 10.0]])
    np.testing.assert_allclose(_ring_share(b, p2, np.zeros(3), both_centres=False), [0.0, 0.5, 1.0])


def test_a_piece_with_its_side_line_inside_spans_two_quarters_to_both_centres():
    # a one-piece leg: 12 cm of front on one hand of the side, 28 cm of back on the other
    b = _trapezoid(-12.0, 28.0)
    p2 = np.array([[-12.0, 10.0], [-6.0, 10.0], [0.0, 10.0], [14.0, 10.0], [28.0, 10.0]])
    np.testing.assert_allclose(_ring_share(b, p2, np.zeros(5), both_centres=True), [-1.0, -0.5, 0.0, 0.5, 1.0])
    # a side line given at one end (an anchor on a rise's top) falls back to the row's middle
    mid = np.array([[-12.0, 10.0], [8.0, 10.0], [28.0, 10.0]])
    np.testing.assert_allclose(_ring_share(b, mid, np.full(3, 28.0), both_centres=True), [-1.0, 0.0, 1.0])


@pytest.mark.shared
def test_a_one_piece_leg_rise_goes_round_the_hips(character_e, tmp_path):
    # real leggings (one-piece legs, each rise sewn to its mirror copy): on the
    # leg's tube the rise went round each leg and the centre seams started
    # 20-40 cm apart
    from patternbridge.assemble.bodyparts import crotch_height, segment_body
    from patternbridge.assemble.collision import BodyCollider
    from patternbridge.assemble.mesh2d import mesh_pattern
    from patternbridge.assemble.place import place_instances
    from patternbridge.assemble.place.wrap import bounding_cylinders
    from patternbridge.pattern.model import BodyPart
    from patternbridge.report import Report
    from patternbridge.workflow import load_garment_spec

    if not LEGGINGS.exists():
        pytest.skip("shared patterns not available")
    from patternbridge.bridge.upright import upright_pattern

    garment = load_garment_spec(LEGGINGS)[0]
    sidecar = tmp_path / garment.drape_sidecar_name
    sidecar.write_bytes(dict(garment.inferred)[sidecar.name])
    pattern = upright_pattern(garment.pattern, sidecar)  # as the fit drapes it
    body = np.asarray(character_e.vertices)
    parts = segment_body(character_e)
    scene = BodyCollider(body, character_e.faces)
    pm = mesh_pattern(pattern, max_edge_cm=3.0)
    placed = place_instances(
        character_e, body, pattern, pm, bounding_cylinders(body, parts), Report(), scene=scene, parts=parts
    )
    crotch_y = crotch_height(character_e, body, parts)
    hips = parts.mask(BodyPart.TORSO) | parts.mask(BodyPart.LEFT_LEG) | parts.mask(BodyPart.RIGHT_LEG)
    torso = body[hips & (np.abs(body[:, 1] - (crotch_y + 10.0)) < 2.0)]
    mid_x = 0.5 * (torso[:, 0].min() + torso[:, 0].max())
    half_hips = 0.5 * np.ptp(torso[:, 0])
    rises = [sp for sp in pm.seams if sp.a.piece == sp.b.piece and sp.a.copy is not sp.b.copy]
    assert len(rises) == 2
    # one rise on the front of the hips, the other on the back (on the leg's
    # tube, the legs of A and E turned half round: the front rise went behind);
    # the shorter rise is the front's
    z_lo, z_hi = torso[:, 2].min(), torso[:, 2].max()
    depth = {}
    for sp in rises:
        a = placed[sp.a.key][sp.a_vertices]
        depth[len(sp.a_vertices)] = np.median((a[a[:, 1] > crotch_y + 8.0, 2] - z_lo) / (z_hi - z_lo))
    short, long_ = min(depth), max(depth)
    assert short != long_
    assert depth[short] > 0.8 and depth[long_] < 0.2, depth
    for sp in rises:
        a, b = placed[sp.a.key][sp.a_vertices], placed[sp.b.key][sp.b_vertices]
        high = (a[:, 1] > crotch_y + 8.0) & (b[:, 1] > crotch_y + 8.0)
        assert high.sum() >= 3, (
            sp.seam,
            a[:, 1].min() - crotch_y,
            a[:, 1].max() - crotch_y,
            np.linalg.norm(a - b, axis=1).round(1),
        )
        gap = np.linalg.norm(a[high] - b[high], axis=1)
        # both halves of each centre seam start near the midline, a few cm apart
        assert np.median(gap) < 5.0, (sp.seam, np.median(gap))
        assert np.all(np.abs(a[high, 0] - mid_x) < 0.35 * half_hips), sp.seam
