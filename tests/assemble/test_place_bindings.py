"""Bindings laid along the edges they bind (place/bindings.py).

Analytic: a strip sewn to the edge of a flat sheet is laid as the sheet's continuation beyond that edge, at its
pattern offsets. On the shared data: ``simple.DXF`` (a racer-back tank with neck and armhole bindings) placed on
E_average_male in the dressing pose: every binding lies outside out beyond the edge it is sewn to,
and no triangle of the placed garment passes through another (wrapped as a ring round the torso and bent onto the
armhole by the seam graph, the armhole bindings lay turned over up the racer straps, 35 and 39 % of their triangles
facing the skin, with 2 crossing triangles; the drape kept them so, 18-23 cm² worn inside out at the nape).
"""

from __future__ import annotations

import numpy as np
import pytest
from brute_force import crossing_triangles

from patternbridge.assemble.cloth import weld_groups
from patternbridge.assemble.place.bindings import _laid
from patternbridge.assemble.turned import outward_cos
from patternbridge.pattern.model import Role


def test_a_strip_sewn_to_a_sheets_edge_is_laid_as_its_continuation():
    # the sheet lies in the plane z = 1 below y = 0, its edge along x; on the body the edge runs along x too
    edge = np.linspace(0.0, 10.0, 6)
    target = np.stack([edge, np.zeros(6), np.ones(6)], axis=1)
    away = np.tile([0.0, 1.0, 0.0], (6, 1))  # off the sheet's cloth: +y
    # the strip in its pattern: 2 cm wide, sewn by its lower edge, drawn turned 90° (its edge along pattern y)
    s, t = np.meshgrid(edge, [0.0, 1.0, 2.0], indexing="ij")
    p2 = np.stack([-t.ravel() + 5.0, s.ravel() - 3.0], axis=1)
    own = np.flatnonzero(t.ravel() == 0.0)
    x = _laid(p2, own, target, away)
    expected = np.stack([s.ravel(), t.ravel(), np.ones(s.size)], axis=1)
    assert np.abs(x - expected).max() < 1e-9


def test_a_curved_edge_is_followed_by_the_strip_at_its_offsets():
    # the edge a quarter circle of radius 10 in the plane z = 0, the sheet inside it: the strip lies outside
    phi = np.linspace(0.0, np.pi / 2, 9)
    target = np.stack([10 * np.cos(phi), 10 * np.sin(phi), np.zeros(9)], axis=1)
    away = np.stack([np.cos(phi), np.sin(phi), np.zeros(9)], axis=1)
    arc = 10 * phi
    p2 = np.concatenate([np.stack([arc, np.zeros(9)], axis=1), np.stack([arc, np.full(9, 1.5)], axis=1)])
    x = _laid(p2, np.arange(9), target, away)
    radius = np.linalg.norm(x[9:, :2], axis=1)
    # 1.5 cm beyond the edge all along, within 1 mm: the neighbours' frames are tangents 2 cm along the arc
    assert np.abs(radius - 11.5).max() < 0.1
    assert np.abs(x[:, 2]).max() < 1e-9


@pytest.fixture(scope="module")
def tank_on_e(aama_dir, character_e, tmp_path_factory):
    from patternbridge.assemble.pipeline import prepare
    from patternbridge.bridge.fit_input import pattern_for_fit
    from patternbridge.bridge.upright import upright_pattern
    from patternbridge.bridge.worn import worn_pattern

    fit = pattern_for_fit(aama_dir / "simple.DXF", tmp_path_factory.mktemp("bound"))
    pattern = worn_pattern(upright_pattern(fit.pattern, fit.sidecar), fit.sidecar)
    return prepare(character_e, pattern)


def _closest_skin(sim, points: np.ndarray) -> np.ndarray:
    import open3d as o3d

    from patternbridge.assemble.collision import triangle_scene

    scene = triangle_scene(np.asarray(sim.body, dtype=np.float64), np.asarray(sim.character.faces))
    return scene.compute_closest_points(o3d.core.Tensor(points.astype(np.float32)))["points"].numpy()


@pytest.mark.shared
def test_the_tanks_bindings_are_placed_outside_out_on_their_edges(tank_on_e):
    sim = tank_on_e
    x, faces, group = sim.x_placed, sim.cloth.faces, sim.cloth.group
    face_group = group[faces[:, 0]]
    cos = outward_cos(x, faces, _closest_skin(sim, x[faces].mean(axis=1)).astype(np.float64))
    roles = [sim.pattern.piece(inst.piece).role for inst in sim.pmesh.instances]
    bindings = [g for g, role in enumerate(roles) if role in (Role.NECK_BINDING, Role.ARMHOLE_BINDING)]
    assert len(bindings) == 3  # the neck binding, both armhole bindings
    for g in bindings:
        facing_skin = float(np.mean(cos[face_group == g] < 0.0))
        assert facing_skin < 0.1, (sim.names[g], facing_skin)  # wrapped and bent by the seam graph: 0.35, 0.39


@pytest.mark.shared
def test_the_placed_tank_does_not_pass_through_itself(tank_on_e):
    sim = tank_on_e
    assert crossing_triangles(sim.x_placed, sim.cloth.faces, weld_groups(len(sim.x_placed), sim.cloth.seams)) == 0
