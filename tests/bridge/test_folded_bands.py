"""A band folded along its length is worn as its drawn half; a half piece on a fold is joined to its mirror."""

from __future__ import annotations

import pytest

from patternbridge.bridge import infer_bridge
from patternbridge.bridge.sidecar import folded_double, inference_sidecar
from patternbridge.io.dxf_aama import read_dxf

POLO = "GMX1016S18_AAMA.DXF"


@pytest.mark.shared
def test_the_polo_cuffs_fold_joins_no_mirror_half_and_each_sleeve_gets_a_cuff(aama_dir):
    # the rib cuff is drawn 2.2 x 28.5 cm with its fold along its length: cut unfolded, folded double. Joined to
    # its mirror copy, the two sleeves' cuffs were one ring and the seam graph drew both sleeves into the chest
    pattern, _ = read_dxf(aama_dir / POLO)
    inference = infer_bridge(pattern)
    folded = {j.a.piece: folded_double(pattern, inference, j) for j in inference.joins if j.kind == "fold"}
    assert folded == {"GMX1016S18FR": False, "GMX1016S18BK": False, "GMX1016S18CU": True}
    seams = inference_sidecar(pattern, inference)["seams"]
    folds = {s["a"]["piece"] for s in seams if s["kind"] == "fold"}
    assert folds == {"GMX1016S18FR", "GMX1016S18BK"}  # the halves on the fold still make whole pieces
    cuff = "GMX1016S18CU"
    to_sleeves = {
        (s["a"]["copy"], s["b"]["copy"]) for s in seams if {s["a"]["piece"], s["b"]["piece"]} == {cuff, "GMX1016S18SS"}
    }
    assert len(to_sleeves) == 2  # the drawn cuff on one sleeve, its mirror copy on the other
    joined = [s for s in seams if s["a"]["piece"] == s["b"]["piece"] == cuff and s["a"]["copy"] != s["b"]["copy"]]
    assert not joined
