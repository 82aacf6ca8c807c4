"""Sleeves of real tailors' files placed on the arms the way round they are worn (place/handedness.py).

``MEN CLASSIC TEE.DXF`` drafts its sleeve as the left one while the inferred
sidecar puts the drawn copy on the right arm; wrapped as drawn, each sleeve
turned its front cap to the back of the arm, the armhole seams started across
the arm, and the drape twisted the sleeves into wings and crumpled the body.
The CLO shirt's flat sleeve caps were sewn to the back armholes upside down
(the cap top to the underarm) until the sidecar ran such a seam up the body.
Checked right after placement, in the dressing pose, from the pictures'
geometry alone: the cap half sewn to the front lies in front of the half sewn
to the back, the cap top sits by the shoulder point, and every armhole seam
starts closed.
"""

from __future__ import annotations

import numpy as np
import pytest

from patternbridge.assemble.pipeline import prepare, with_anchor_landmarks
from patternbridge.pattern.model import BodyPart, Copy, Side

ARMS = {BodyPart.LEFT_ARM, BodyPart.RIGHT_ARM}


def _placed(aama_dir, character_e, name, tmp_path_factory):
    from patternbridge.bridge.fit_input import pattern_for_fit
    from patternbridge.bridge.upright import upright_pattern

    fit = pattern_for_fit(aama_dir / name, tmp_path_factory.mktemp("worn"))
    pattern = upright_pattern(fit.pattern, fit.sidecar)
    dressed, _ = with_anchor_landmarks(character_e, pattern)
    return prepare(dressed, pattern, seed=0, max_edge_cm=3.0)


@pytest.fixture(scope="module", params=["MEN CLASSIC TEE.DXF", "clo-pattern.dxf"])
def placed(request, aama_dir, character_e, tmp_path_factory):
    return _placed(aama_dir, character_e, request.param, tmp_path_factory)


def _offsets(sim) -> dict[str, int]:
    sizes = [len(sim.pmesh.pieces[inst.piece].points) for inst in sim.pmesh.instances]
    return dict(zip(sim.names, np.concatenate([[0], np.cumsum(sizes)[:-1]]).tolist(), strict=True))


def _armhole_seams(sim):
    """(seam, sleeve instance, its sewn vertices, torso instance, theirs, the torso piece's side)."""
    for sp in sim.pmesh.seams:
        sides = ((sp.a, sp.a_vertices, sp.b, sp.b_vertices), (sp.b, sp.b_vertices, sp.a, sp.a_vertices))
        for me, va, other, vb in sides:
            part = sim.pattern.piece(me.piece).placement.body_part
            other_pl = sim.pattern.piece(other.piece).placement
            if part in ARMS and other_pl.body_part is BodyPart.TORSO:
                yield sp.seam, me, va, other, vb, other_pl.side


def test_each_sleeve_turns_its_front_cap_to_the_front(placed):
    """Front is +z: the cap sewn to a front lies in front of the cap sewn to a back, by more than 3 cm."""
    off, x = _offsets(placed), placed.cloth.x
    z: dict[str, dict[Side, list[float]]] = {}
    for _, me, va, _, _, side in _armhole_seams(placed):
        z.setdefault(me.key, {}).setdefault(side, []).extend(x[va + off[me.key], 2].tolist())
    assert len(z) == 2
    for key, sides in z.items():
        front, back = np.mean(sides[Side.FRONT]), np.mean(sides[Side.BACK])
        assert front > back + 3.0, f"{key}: front cap z {front:.1f} cm, back cap z {back:.1f} cm"


def test_sleeve_cap_tops_sit_at_the_shoulder_points(placed):
    off, x = _offsets(placed), placed.cloth.x
    for inst in placed.pmesh.instances:
        pl = placed.pattern.piece(inst.piece).placement
        if pl.body_part not in ARMS:
            continue
        top = x[placed.pmesh.pieces[inst.piece].marks[pl.anchor_mark] + off[inst.key]]
        name = pl.anchor
        if inst.copy is Copy.MIRROR:
            name = name.replace("right", "left") if "right" in name else name.replace("left", "right")
        mark = placed.character.landmarks[name]
        shoulder = placed.body[mark.vertex] if mark.vertex is not None else np.asarray(mark.position)
        assert np.linalg.norm(top - shoulder) < 6.0, f"{inst.key}: cap top {np.linalg.norm(top - shoulder):.1f} cm"


def test_armhole_seams_start_closed(placed):
    """The widest pair of every armhole seam starts within 3 cm.

    Wrapped as drawn the tee's started 8.8 cm open; the CLO caps sewn upside down 14.0 cm.
    """
    off, x = _offsets(placed), placed.cloth.x
    for seam, me, va, other, vb, _ in _armhole_seams(placed):
        gap = np.linalg.norm(x[va + off[me.key]] - x[vb + off[other.key]], axis=1).max()
        assert gap < 3.0, f"{seam}: {gap:.1f} cm"


def test_the_swap_is_reported_only_where_the_drawing_is_the_other_side(aama_dir, character_e, tmp_path_factory):
    """The T-shirt drafted with a right sleeve is placed as drawn (its armhole seams start within 3 cm too)."""
    sim = _placed(aama_dir, character_e, "GMH1004F15-2.DXF", tmp_path_factory)
    assert not [f for f in sim.findings if f.code == "worn-mirrored"]
    off, x = _offsets(sim), sim.cloth.x
    for seam, me, va, other, vb, _ in _armhole_seams(sim):
        gap = np.linalg.norm(x[va + off[me.key]] - x[vb + off[other.key]], axis=1).max()
        assert gap < 3.0, f"{seam}: {gap:.1f} cm"


def test_a_cuff_follows_its_sleeve_whatever_its_own_gaps():
    """The library shirt's cuff, sewn only to its sleeve on the same arm, takes the sleeve's way round.

    Positions are made up: mirrored, every cuff vertex lies on the sleeve vertex it is sewn to (its own gaps
    say "mirror"), while the sleeve's armhole gaps decide; the cuff is mirrored exactly when the sleeve is.
    """
    from patternbridge.assemble.mesh2d import mesh_pattern
    from patternbridge.assemble.place.handedness import choose_mirrored, paired_limb_pieces
    from patternbridge.assemble.place.wrap import LIMBS, instance_part
    from patternbridge.library import load_garment

    pattern = load_garment("shirt")
    pm = mesh_pattern(pattern, max_edge_cm=4.0)
    part = {inst.key: instance_part(pattern, inst) for inst in pm.instances}
    candidates = paired_limb_pieces(pm, {k: p in LIMBS for k, p in part.items()})
    assert {"sleeve", "cuff"} <= candidates
    rng = np.random.default_rng(0)
    drawn = {inst.key: rng.normal(scale=20.0, size=(len(pm.pieces[inst.piece].points), 3)) for inst in pm.instances}
    for sleeve_mirrored_fits in (False, True):
        mirrored = {k: v + 50.0 for k, v in drawn.items()}  # mirrored, every seam across the arm's root opens
        for sp in pm.seams:
            for me, va, other, vb in (
                (sp.a, sp.a_vertices, sp.b, sp.b_vertices),
                (sp.b, sp.b_vertices, sp.a, sp.a_vertices),
            ):
                if me.piece == "cuff" and other.piece == "sleeve":
                    mirrored[me.key][va] = drawn[other.key][vb]
                if sleeve_mirrored_fits and me.piece == "sleeve" and part[other.key] is not part[me.key]:
                    mirrored[me.key][va] = drawn[other.key][vb]
        chosen = choose_mirrored(pm, candidates, drawn, mirrored, part)
        assert ("cuff" in chosen) == ("sleeve" in chosen) == sleeve_mirrored_fits
