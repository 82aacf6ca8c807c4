"""Inferred marks and placement (``bridge.landmarks``) on the real files of ../shared/aama."""

from __future__ import annotations

import numpy as np
import pytest

from patternbridge.bridge import infer_bridge
from patternbridge.bridge.alternatives import copies_cut
from patternbridge.bridge.landmarks import piece_landmarks
from patternbridge.bridge.sidecar import inference_sidecar
from patternbridge.io.dxf_aama import read_dxf
from patternbridge.library.seams import sew_line
from patternbridge.pattern.model import Role

pytestmark = pytest.mark.shared


def test_one_piece_leg_side_waist_lies_half_way_round_the_waist(aama_dir):
    """Leggings: each leg's side waist is in the middle third of the leg's width, not at the top of a rise."""
    pattern, _ = read_dxf(aama_dir / "GLX4802S19_AAMA.DXF")
    inference = infer_bridge(pattern)
    found = piece_landmarks(pattern, inference)
    legs = [p for p in pattern.pieces if inference.roles[p.name].role is Role.LEG]
    assert len(legs) == 3
    for piece in legs:
        up = inference.orientations[piece.name].apply(sew_line(piece)[0])
        x = up[:, 0]
        at = up[found[piece.name].marks["side_waist"]]
        share = (at[0] - x.min()) / np.ptp(x)
        assert 1 / 3 < share < 2 / 3, (piece.name, share)
        # on the waist: above the crotch point and within the top 15 % of the leg
        assert at[1] > up[:, 1].max() - 0.15 * np.ptp(up[:, 1])


def test_clo_shirt_sleeves_go_on_the_arm_of_the_bodice_they_are_sewn_to(aama_dir):
    """The CLO shirt draws left and right pieces separately: one sleeve on each arm, sewn as drawn."""
    pattern, _ = read_dxf(aama_dir / "clo-pattern.dxf")
    inference = infer_bridge(pattern)
    found = piece_landmarks(pattern, inference)
    sleeves = [p.name for p in pattern.pieces if inference.roles[p.name].role is Role.SLEEVE]
    arms = sorted(found[s].placement["body_part"] for s in sleeves)
    assert arms == ["left_arm", "right_arm"]
    for s in sleeves:
        arm_side = found[s].placement["body_part"].split("_")[0]
        assert found[s].placement["anchor"] == f"shoulder_point_{arm_side}"
        partners = {j.a.piece if j.b.piece == s else j.b.piece for j in inference.joins if s in (j.a.piece, j.b.piece)}
        bodices = [b for b in partners - {s} if inference.roles[b].role in (Role.FRONT, Role.BACK)]
        assert bodices
        for b in bodices:  # the bodice halves it is sewn into are drafted for the same side
            assert f"shoulder_point_{arm_side}" in found[b].landmarks


@pytest.mark.parametrize("stem", ["clo-pattern.dxf", "simple.DXF", "MEN CLASSIC TEE.DXF", "GMX1016S18_AAMA.DXF"])
def test_seams_name_only_copies_that_are_cut(aama_dir, stem):
    """No seam of an inferred sidecar sews a mirror copy of a piece cut once without a fold."""
    pattern, _ = read_dxf(aama_dir / stem)
    inference = infer_bridge(pattern)
    sidecar = inference_sidecar(pattern, inference)
    single = {
        p.name
        for p in pattern.pieces
        if copies_cut(p) <= 1 and inference.orientations[p.name].fold is None and p.mirror_line is None
    }
    for seam in sidecar["seams"]:
        for side in (seam["a"], seam["b"]):
            assert not (side["piece"] in single and side["copy"] == "mirror"), seam["id"]
