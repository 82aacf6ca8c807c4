"""Bands placed where the opening they are sewn to lies (``bridge.band_anchor``), on the real tanks."""

from __future__ import annotations

import json

import numpy as np
import pytest

from patternbridge.bridge import infer_bridge
from patternbridge.bridge.landmarks import piece_landmarks
from patternbridge.bridge.sidecar import inference_sidecar
from patternbridge.io.dxf_aama import read_dxf
from patternbridge.pattern.model import Role

pytestmark = pytest.mark.shared

TANKS = ("simple.DXF", "GLX0926S16.DXF", "GLX0924S16_NEW.DXF")


def _swap(landmark):
    side = landmark.rsplit("_", 1)
    return {"right": f"{side[0]}_left", "left": f"{side[0]}_right"}.get(side[-1], landmark)


def _sidecar(aama_dir, stem):
    pattern, _ = read_dxf(aama_dir / stem)
    return pattern, inference_sidecar(pattern, infer_bridge(pattern))


@pytest.mark.parametrize("stem", TANKS)
def test_bindings_are_anchored_on_a_landmark_of_the_opening_they_bind(aama_dir, stem):
    """An armhole binding goes on the torso at the armpit, a neck binding on the neck at a neck landmark; the
    band's anchor vertex is an end of one of its seams whose other end is the bodice's mark on that landmark."""
    _, data = _sidecar(aama_dir, stem)
    pieces = {p["name"]: p for p in data["pieces"]}
    bindings = [p for p in pieces.values() if p["role"] in ("armhole_binding", "neck_binding")]
    assert bindings
    for band in bindings:
        pl = band["placement"]
        if band["role"] == "armhole_binding":
            assert (pl["body_part"], pl["anchor"]) == ("torso", "armpit_point_right"), pl
        else:
            assert pl["body_part"] == "neck" and "neck" in pl["anchor"], pl
        vertex = band["marks"][pl["anchor_mark"]]["vertex"]
        met = set()
        for s in data["seams"]:
            if s["b"]["piece"] != band["name"] or s["b"]["copy"] != "primary":
                continue
            other = pieces[s["a"]["piece"]]
            ends = [band["marks"][s["b"][k]]["vertex"] for k in ("start", "end")]
            partner = [np.array(other["marks"][s["a"][k]]["xy"]) for k in ("start", "end")]
            if s["reverse"]:
                partner = partner[::-1]
            mirrored = s["a"]["copy"] == "mirror"
            for v, p in zip(ends, partner, strict=True):
                if v == vertex:  # the bodice's landmarks within 3 cm of the seam end the anchor vertex meets
                    met |= {
                        _swap(lm) if mirrored else lm
                        for lm, mark in other["landmarks"].items()
                        if np.linalg.norm(np.array(other["marks"][mark]["xy"]) - p) <= 3.0
                    }
        assert pl["anchor"] in met, (band["name"], pl, met)


def test_armhole_binding_is_placed_at_the_underarm_not_on_the_arm(aama_dir, characters_dir, tmp_path):
    """simple.DXF on E: both copies of the armhole binding start on the torso by the armpit (they were wrapped
    round the upper arm at the shoulder point and pulled the bodice up onto the arm)."""
    from patternbridge.assemble.bodyparts import segment_body
    from patternbridge.assemble.collision import BodyCollider
    from patternbridge.assemble.mesh2d import mesh_pattern
    from patternbridge.assemble.place import place_instances
    from patternbridge.assemble.place.wrap import bounding_cylinders
    from patternbridge.bridge.upright import upright_pattern
    from patternbridge.library.sidecar import apply_sidecar
    from patternbridge.mesh.load import load_character
    from patternbridge.report import Report

    pattern, data = _sidecar(aama_dir, "simple.DXF")
    sidecar = tmp_path / "simple.seams.json"
    sidecar.write_text(json.dumps(data))
    pattern = upright_pattern(apply_sidecar(pattern, sidecar), sidecar)
    character, _ = load_character(characters_dir / "E_average_male.obj")
    body = np.asarray(character.vertices)
    parts = segment_body(character)
    pm = mesh_pattern(pattern, max_edge_cm=3.0)
    placed = place_instances(
        character,
        body,
        pattern,
        pm,
        bounding_cylinders(body, parts),
        Report(),
        scene=BodyCollider(body, character.faces),
        parts=parts,
    )
    band = next(p["name"] for p in data["pieces"] if p["role"] == "armhole_binding")
    copies = [inst for inst in pm.instances if inst.piece == band]
    assert len(copies) == 2
    for inst in copies:
        side = "left" if inst.copy.value == "mirror" else "right"
        armpit = body[character.landmarks[f"armpit_point_{side}"].vertex]
        shoulder = body[character.landmarks[f"shoulder_point_{side}"].vertex]
        pts = placed[inst.key]
        # the band lies round the armhole: level with the armpit (round the upper arm at the shoulder point it
        # started 13 cm higher, level with the shoulder point)
        assert abs(np.median(pts[:, 1]) - armpit[1]) < 6.0, (inst.key, np.median(pts[:, 1]), armpit[1])
        assert np.median(pts[:, 1]) < shoulder[1] - 8.0, (inst.key, np.median(pts[:, 1]), shoulder[1])


def test_cuff_keeps_its_role_place_when_its_partner_has_no_landmark_on_the_seam(aama_dir):
    """The polo's rib cuff is sewn to a sleeve hem, which carries no body landmark: it stays on the wrist."""
    pattern, _ = read_dxf(aama_dir / "GMX1016S18_AAMA.DXF")
    inference = infer_bridge(pattern)
    found = piece_landmarks(pattern, inference)
    cuffs = [n for n in inference.chosen if inference.roles[n].role is Role.CUFF]
    assert cuffs
    for name in cuffs:
        assert found[name].placement["anchor"].startswith("wrist_point"), found[name].placement


@pytest.mark.parametrize("stem", ["GLX0924S16_NEW.DXF", "GLX0926S16.DXF", "simple.DXF"])
def test_no_seam_adds_a_copy_that_is_sewn_to_nothing_else(aama_dir, stem):
    """A band's mirror copy sewn to no other piece (a second neck binding, even one the file cuts) is not closed
    on itself: the garment wears the band in the copies it sews (``worn_copies``)."""
    _, data = _sidecar(aama_dir, stem)
    copies = {(e["piece"], e["copy"]) for s in data["seams"] for e in (s["a"], s["b"])}
    joined = {
        (e["piece"], e["copy"]) for s in data["seams"] if s["a"]["piece"] != s["b"]["piece"] for e in (s["a"], s["b"])
    }
    assert not copies - joined
