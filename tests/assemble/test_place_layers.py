"""Placement of real garments on shared characters: the layers the seam-graph solve separates."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from patternbridge.assemble.bodyparts import segment_body
from patternbridge.assemble.cloth import weld_groups
from patternbridge.assemble.collision import BodyCollider
from patternbridge.assemble.mesh2d import mesh_pattern
from patternbridge.assemble.place import SeamGraphSettings, bounding_cylinders, close_seams, place_instances
from patternbridge.assemble.selfcross import self_crossing
from patternbridge.assemble.skin_check import skin_check
from patternbridge.library import load_garment
from patternbridge.mesh.load import load_character
from patternbridge.report import Report


@pytest.fixture(scope="module")
def dress_on_a(characters_dir):
    """The library dress (sample size) wrapped on A's body-part proxies, with its mesh and the body's collider."""
    character, _ = load_character(characters_dir / "A_superhero.obj")
    pattern = load_garment("dress")
    body = np.asarray(character.vertices, dtype=np.float64)
    parts = segment_body(character)
    scene = BodyCollider(body, character.faces)
    pmesh = mesh_pattern(pattern, max_edge_cm=2.5)
    wrapped = place_instances(
        character, body, pattern, pmesh, bounding_cylinders(body, parts), Report(), scene=scene, parts=parts
    )
    return character, pmesh, wrapped, scene


def _stacked(pmesh, placed):
    """(positions, faces, sewn pairs) of all copies stacked in instance order."""
    keys = [inst.key for inst in pmesh.instances]
    offsets = np.concatenate([[0], np.cumsum([len(placed[k]) for k in keys])])
    faces = np.concatenate([pmesh.pieces[i.piece].faces + offsets[n] for n, i in enumerate(pmesh.instances)])
    index = {k: n for n, k in enumerate(keys)}
    pairs = np.concatenate(
        [
            np.stack([sp.a_vertices + offsets[index[sp.a.key]], sp.b_vertices + offsets[index[sp.b.key]]], axis=1)
            for sp in pmesh.seams
        ]
    )
    return np.concatenate([placed[k] for k in keys]), faces, pairs


def _through_cloth(x, faces, pairs) -> int:
    """Triangles through other cloth of the garment (the sides of a seam count as one vertex)."""
    return int(np.count_nonzero(self_crossing(x, faces, np.zeros(len(faces), np.int64), weld_groups(len(x), pairs))))


@pytest.mark.shared
def test_the_dress_on_a_starts_in_layers_not_through_itself(dress_on_a):
    character, pmesh, wrapped, scene = dress_on_a
    linear = _stacked(
        pmesh,
        close_seams(pmesh, wrapped, scene, dataclasses.replace(SeamGraphSettings(), layer_rounds=0, flatten_rounds=0)),
    )
    x, faces, pairs = _stacked(pmesh, close_seams(pmesh, wrapped, scene))
    # measured in A's rest pose: the linear seam solve alone leaves 57
    # triangles through other cloth (the bodice through the skirt at the
    # waist, the armholes); separated into layers, 5
    before, after = _through_cloth(*linear), _through_cloth(x, faces, pairs)
    assert before > 0
    assert after <= before // 5, (before, after)
    # no triangle through the skin (independent signed distance, deeper than 1 mm): 20 before the clean-up
    body = np.asarray(character.vertices, dtype=np.float64)
    assert np.count_nonzero(skin_check(body, character.faces, linear[0], faces).inside(0.1)) > 0
    assert np.count_nonzero(skin_check(body, character.faces, x, faces).inside(0.1)) == 0
    assert not scene.inside(x).any()
