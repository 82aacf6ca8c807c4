"""The untangling on a real garment: the crossings the placement leaves in shorts are undone while sewing."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from brute_force import crossing_triangles

from patternbridge.assemble.cloth import weld_groups
from patternbridge.assemble.phases import Sew, run_phases
from patternbridge.assemble.pipeline import prepare
from patternbridge.library import load_garment

pytestmark = [pytest.mark.shared, pytest.mark.slow]


def _welded(x: np.ndarray, faces: np.ndarray, seams: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Positions and faces with every group of sewn vertices made one vertex at its mean."""
    weld = weld_groups(len(x), seams)
    ids, inv = np.unique(weld, return_inverse=True)
    wx = np.zeros((len(ids), 3))
    np.add.at(wx, inv, x)
    wx /= np.bincount(inv)[:, None]
    return wx, inv[faces]


def _crotch_through(sim, reach_cm: float = 8.0, depth_cm: float = 2.5) -> None:
    """Every leg piece's cloth near its crotch corner pushed across the body's midplane (in place).

    The placement lays the four crotch corners under the crotch, each leg's
    cloth on its side (``place.wrap``); this gives the sewing the crossings
    an older placement left there: the pieces of both legs pressed through
    each other under the crotch.
    """
    x, group = sim.cloth.x, sim.cloth.group
    offsets = np.searchsorted(group, np.arange(len(sim.names)))
    for i, inst in enumerate(sim.pmesh.instances):
        mark = sim.pmesh.pieces[inst.piece].marks.get("crotch_point")
        if mark is None:
            continue
        mine = np.flatnonzero(group == i)
        corner = x[offsets[i] + mark]
        near = np.clip(1.0 - np.linalg.norm(x[mine] - corner, axis=1) / reach_cm, 0.0, 1.0)
        x[mine, 0] -= np.sign(np.median(x[mine, 0]) - corner[0]) * depth_cm * near


@pytest.fixture(scope="module")
def sewn_shorts(characters_dir):
    """The library shorts placed on B, their crotch pushed through itself, sewn as planned and with the untangling
    turned off."""
    from patternbridge.mesh.load import load_character

    character, _ = load_character(characters_dir / "B_slim_female.obj")
    out = {}
    for untangle in (True, False):
        sim = prepare(character, load_garment("shorts"), seed=0, max_edge_cm=3.0)
        _crotch_through(sim)
        placed = crossing_triangles(*_welded(sim.cloth.x, sim.cloth.faces, sim.cloth.seams))
        sew = next(p for p in sim.phases if isinstance(p, Sew))
        assert sew.untangle  # planned: a garment sewn in the rest pose untangles
        run_phases(sim, (dataclasses.replace(sew, untangle=untangle),))
        gaps = np.linalg.norm(sim.cloth.x[sim.cloth.seams[:, 0]] - sim.cloth.x[sim.cloth.seams[:, 1]], axis=1)
        out[untangle] = placed, crossing_triangles(*_welded(sim.cloth.x, sim.cloth.faces, sim.cloth.seams)), gaps
    return out


def test_the_sewing_undoes_the_crossings_of_the_placement(sewn_shorts):
    placed, sewn, gaps = sewn_shorts[True]
    assert placed > 0  # the pieces of both legs pressed through each other under the crotch
    assert sewn <= placed // 5, (placed, sewn)
    assert gaps.max() < 0.2  # cm: the seams are closed, the untangling did not pull them open
    # without the untangling the sewing keeps them (the check can fail)
    _, kept, _ = sewn_shorts[False]
    assert kept > 2 * max(sewn, 1), (kept, sewn)
