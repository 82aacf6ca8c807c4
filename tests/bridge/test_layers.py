"""Pieces left out of the drape (``bridge.layers``) and bands hung below a limb piece's anchor
(``bridge.band_anchor.band_below``), on the real polo ``GMX1016S18``."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from patternbridge.assemble.place.wrap import anchor_position
from patternbridge.bridge import infer_bridge
from patternbridge.bridge.fit_input import pattern_for_fit
from patternbridge.bridge.layers import draped_only, left_out
from patternbridge.bridge.sidecar import inference_sidecar
from patternbridge.bridge.upright import upright_pattern
from patternbridge.bridge.worn import hung_bands, worn_pattern
from patternbridge.io.dxf_aama import read_dxf
from patternbridge.library import garment_names, load_garment
from patternbridge.mesh.character import Character, Landmark
from patternbridge.pattern.model import EdgeRange, Pattern, Piece, Placement, Seam

POLO = "GMX1016S18_AAMA.DXF"
_SQUARE = [[0.0, 0.0], [10.0, 0.0], [10.0, 10.0], [0.0, 10.0]]


@pytest.mark.shared
def test_polo_drape_leaves_out_the_interlinings_and_the_unsewn_plackets(aama_dir, tmp_path):
    """The polo's fused interlinings IX, IY and the plackets YP, YL (no seam inferred) are not draped; the
    garment's shell (halves, sleeve, cuff, collar) is, and the graded pattern keeps every piece."""
    loaded = pattern_for_fit(aama_dir / POLO, tmp_path)
    gone = {x.piece[len("GMX1016S18") :]: x.why for x in left_out(loaded.pattern)}
    assert gone == {"IX": "interlining", "IY": "interlining", "YP": "unsewn", "YL": "unsewn"}
    draped, _ = draped_only(loaded.pattern)
    assert {p.name[len("GMX1016S18") :] for p in draped.pieces} == {"FR", "BK", "SS", "CU", "CO"}
    assert all(s.a.piece in {p.name for p in draped.pieces} for s in draped.seams)
    assert len(loaded.pattern.pieces) == 9


def test_library_garments_drape_every_piece():
    """Every library piece is sewn into its garment: nothing is left out."""
    for name in garment_names():
        assert left_out(load_garment(name)) == (), name


def test_a_piece_sewn_only_to_an_unsewn_piece_is_left_out():
    """Two pieces sewn to each other but to no body piece hang free: both are left out; the front stays."""
    pieces = (
        Piece(name="front", outline=_SQUARE, role="front", marks={"a": 0, "b": 1}),
        Piece(name="pocket", outline=_SQUARE, role="pocket", marks={"a": 0, "b": 1}),
        Piece(name="flap", outline=_SQUARE, role="other", marks={"a": 0, "b": 1}),
    )
    seam = Seam(id="s", a=EdgeRange(piece="pocket", start="a", end="b"), b=EdgeRange(piece="flap", start="a", end="b"))
    out = left_out(Pattern(style="t", pieces=pieces, seams=(seam,)))
    assert [(x.piece, x.why) for x in out] == [("pocket", "unsewn"), ("flap", "unsewn")]


@pytest.mark.shared
def test_polo_short_sleeve_cuff_hangs_at_the_sleeve_hem_not_the_wrist(aama_dir):
    """The rib cuff sewn to the short sleeve's hem hangs from the sleeve's anchor (shoulder point) by the
    sleeve's own cap-to-hem height (upright, sample size), not at the wrist."""
    pattern, _ = read_dxf(aama_dir / POLO)
    inference = infer_bridge(pattern)
    data = inference_sidecar(pattern, inference)
    pieces = {p["name"]: p for p in data["pieces"]}
    cuff, sleeve = pieces["GMX1016S18CU"], pieces["GMX1016S18SS"]
    pl = cuff["placement"]
    assert (pl["body_part"], pl["anchor"]) == ("right_arm", "shoulder_point_right"), pl
    up = inference.orientations["GMX1016S18SS"].apply(np.asarray(pattern.piece("GMX1016S18SS").outline))
    height = float(np.ptp(up[:, 1]))  # cap top to hem of the sleeve as drawn
    assert sleeve["placement"]["anchor_mark"] == "cap_top"
    assert 15.0 < pl["drop_cm"] < 30.0
    assert abs(pl["drop_cm"] - height) < 3.0, (pl["drop_cm"], height)


def test_anchor_position_walks_the_drop_down_the_limb_landmarks():
    """A drop walks shoulder -> elbow -> wrist (analytic points), past the wrist along the last step."""
    points = {"shoulder_point_right": [0, 0, 0], "elbow_point_right": [0, -30, 0], "wrist_point_right": [20, -30, 0]}
    body = Character(
        vertices=[[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]],
        faces=[[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
        name="sticks",
        landmarks={k: Landmark(name=k, position=v) for k, v in points.items()},
    )

    def at(drop):
        pl = Placement(
            body_part="right_arm", side="around", anchor="shoulder_point_right", anchor_mark="m", drop_cm=drop
        )
        return anchor_position(body, body.vertices, pl, False)

    np.testing.assert_allclose(at(0.0), [0, 0, 0])
    np.testing.assert_allclose(at(12.0), [0, -12, 0])
    np.testing.assert_allclose(at(40.0), [10, -30, 0])
    np.testing.assert_allclose(at(55.0), [25, -30, 0])


@pytest.mark.shared
def test_the_cuff_drop_follows_the_graded_sleeve(aama_dir, tmp_path):
    """Drape time: a sleeve shortened to 80 % of its height brings the cuff's drop to 80 % (the drop is measured
    on the graded partner, not the sample size's sidecar value)."""
    loaded = pattern_for_fit(aama_dir / POLO, tmp_path)
    upright = upright_pattern(loaded.pattern, loaded.sidecar)
    drop = worn_pattern(upright, loaded.sidecar).piece("GMX1016S18CU").placement.drop_cm
    squash = np.array([1.0, 0.8])
    shorter = dataclasses.replace(
        upright,
        pieces=tuple(
            dataclasses.replace(
                p,
                outline=np.asarray(p.outline) * squash,
                sew_lines=tuple(dataclasses.replace(s, points=np.asarray(s.points) * squash) for s in p.sew_lines),
            )
            if p.name == "GMX1016S18SS"
            else p
            for p in upright.pieces
        ),
    )
    assert hung_bands(shorter).piece("GMX1016S18CU").placement.drop_cm == pytest.approx(0.8 * drop, rel=1e-6)


def test_fit_says_which_pieces_it_did_not_drape_in_one_line():
    from patternbridge.cli.fit import drape_warnings

    lines = drape_warnings({"left_out": [{"piece": "IX", "why": "interlining"}, {"piece": "YP", "why": "unsewn"}]})
    said = [line for line in lines if "not draped" in line]
    assert len(said) == 1 and "IX (interlining" in said[0] and "YP (sewn to no piece" in said[0]
    assert not [line for line in drape_warnings({}) if "not draped" in line]
