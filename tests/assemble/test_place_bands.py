"""Bands on the tube edges they close (a shirt's cuffs on its sleeve hems), placed outside them, not through them."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from brute_force import crossing_triangles

from patternbridge.assemble.cloth import weld_groups
from patternbridge.assemble.pipeline import prepare
from patternbridge.assemble.place import bounding_cylinders, wrap_worn_side
from patternbridge.assemble.skin_check import signed_distance
from patternbridge.io.pattern_json import load_pattern_json
from patternbridge.mesh.load import load_character
from patternbridge.pattern.model import BodyPart
from patternbridge.report import Report

DATA = Path(__file__).parent / "data"


@pytest.fixture(scope="module")
def shirt_on_a(characters_dir):
    """The library shirt graded to A_superhero (``fit_pattern``, 40 x 40, seed 0) prepared on A in the dressing
    pose, and its wrap: its sleeves are 9 cm longer than A's arm in the pose, their hems over the hands."""
    character, _ = load_character(characters_dir / "A_superhero.obj")
    pattern = load_pattern_json(DATA / "shirt_A_superhero_graded.json")
    sim = prepare(character, pattern)
    _, wrapped = wrap_worn_side(character, sim.body, pattern, sim.pmesh, sim.parts, Report(), scene=sim.collider)
    return sim, wrapped


def _arm_frame(sim, part: BodyPart):
    cyl = bounding_cylinders(sim.body, sim.parts)[part]
    return cyl.center, cyl.axis, cyl.e0, cyl.e1


def _polar(x, centre, axis, e0, e1):
    d = x - centre
    return np.arctan2(d @ e1, d @ e0), d @ axis, np.hypot(d @ e0, d @ e1)


@pytest.mark.shared
@pytest.mark.parametrize("copy", ["primary", "mirror"])
def test_a_cuff_is_wrapped_on_its_sleeve_hem_outside_it(shirt_on_a, copy):
    sim, wrapped = shirt_on_a
    suffix = "" if copy == "primary" else "~mirror"
    cuff, sleeve = f"cuff{suffix}", f"sleeve{suffix}"
    (sp,) = [s for s in sim.pmesh.seams if {s.a.key, s.b.key} == {cuff, sleeve}]
    vc, vs = (sp.a_vertices, sp.b_vertices) if sp.a.key == cuff else (sp.b_vertices, sp.a_vertices)
    part = BodyPart.RIGHT_ARM if copy == "primary" else BodyPart.LEFT_ARM
    frame = _arm_frame(sim, part)
    th_c, h_c, r_c = _polar(wrapped[cuff][vc], *frame)
    th_s, h_s, r_s = _polar(wrapped[sleeve][vs], *frame)
    # every sewn pair faces its partner round the arm (as drawn on its wrist landmark the cuff's closure
    # started half a turn from the underarm seam it is sewn on), at the hem's height along the arm
    turn = np.abs(np.angle(np.exp(1j * (th_c - th_s))))
    assert np.degrees(turn).max() < 30.0, np.degrees(turn).round()
    assert np.abs(h_c - h_s).max() < 1.5
    # its seam side lies outside the hem, and the cuff beyond the hem, not inside the sleeve
    assert np.mean(r_c) > np.mean(r_s) + 0.3, (np.mean(r_c), np.mean(r_s))
    _, h_cuff, _ = _polar(wrapped[cuff], *frame)
    _, h_sleeve, _ = _polar(wrapped[sleeve], *frame)
    assert h_cuff.max() < np.mean(h_s) + 1.0 < h_sleeve.max()


@pytest.mark.shared
def test_the_placed_sleeves_and_cuffs_do_not_pass_through_each_other(shirt_on_a):
    sim, _ = shirt_on_a
    cloth = sim.cloth
    label = weld_groups(len(cloth.x), cloth.seams)
    for suffix in ("", "~mirror"):
        ids = [sim.names.index(f"sleeve{suffix}"), sim.names.index(f"cuff{suffix}")]
        keep = np.isin(cloth.group[cloth.faces[:, 0]], ids)
        # the sides of each seam at their mean, one vertex
        x = cloth.x.copy()
        for k in range(3):
            x[:, k] = (np.bincount(label, x[:, k]) / np.bincount(label))[label]
        assert crossing_triangles(x, cloth.faces[keep], label) == 0


@pytest.mark.shared
def test_the_collar_is_wrapped_down_the_neckline_and_placed_outside_the_neck(shirt_on_a, characters_dir):
    sim, wrapped = shirt_on_a
    character, _ = load_character(characters_dir / "A_superhero.obj")
    faces = np.asarray(character.faces)
    bn, fn = (character.landmarks[k].at(sim.body, faces) for k in ("back_neck_point", "front_neck_point"))
    marks = sim.pmesh.pieces["collar"].marks
    collar = wrapped["collar"]
    front = 0.5 * (collar[marks["end_left"]] + collar[marks["end_right"]])
    # the collar's neck edge follows the neckline down to the front (wrapped level at the back neck point its
    # front stood 1.2 cm higher than its back, on the throat under the chin), its back on the back neck point
    assert collar[marks["cb"], 1] - front[1] > 0.9 * (bn[1] - fn[1]), (collar[marks["cb"], 1], front[1], bn, fn)
    assert abs(collar[marks["cb"], 1] - bn[1]) < 1.0
    # placed (the seam graph's contact clears the top leant over the nape), the collar is outside the neck by the
    # independent signed distance
    placed = sim.cloth.x[sim.cloth.group == sim.names.index("collar")]
    assert signed_distance(sim.body, faces, placed).min() > 0.5
