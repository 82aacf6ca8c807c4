"""Bindings wrapped the way up their seams meet the opening they bind (place/wrap.py, ``_bindings_way_up``).

``simple.DXF``'s bindings are drawn with the edge they sew on top: wrapped as
drawn, the neck binding ran round the neck against its neckline and its seams
started 20-36 cm across the neck, and the drape caught it round the neck.
Checked right after wrapping, on E_average_male, from the geometry alone: each
binding runs round the body the same way as the edge it is sewn to, and its
seams start within 18 cm (as drawn, graded to E: 20 and 30 cm, running against the neckline).
"""

from __future__ import annotations

import numpy as np
import pytest

from patternbridge.assemble.bodyparts import segment_body
from patternbridge.assemble.collision import BodyCollider
from patternbridge.assemble.mesh2d import mesh_pattern
from patternbridge.assemble.pipeline import with_anchor_landmarks
from patternbridge.assemble.place import wrap_worn_side
from patternbridge.pattern.model import Role
from patternbridge.report import Report

pytestmark = pytest.mark.shared


@pytest.fixture(scope="module")
def wrapped(aama_dir, character_e, tmp_path_factory):
    from patternbridge.bridge.fit_input import pattern_for_fit
    from patternbridge.bridge.upright import upright_pattern
    from patternbridge.bridge.worn import worn_pattern

    fit = pattern_for_fit(aama_dir / "simple.DXF", tmp_path_factory.mktemp("bound"))
    pattern = worn_pattern(upright_pattern(fit.pattern, fit.sidecar), fit.sidecar)
    character, _ = with_anchor_landmarks(character_e, pattern)
    body = np.array(character.vertices, dtype=np.float64)  # a tank is dressed in the rest pose
    parts = segment_body(character, vertices=body)
    pmesh = mesh_pattern(pattern, max_edge_cm=3.0)
    pmesh, out = wrap_worn_side(
        character, body, pattern, pmesh, parts, Report(), scene=BodyCollider(body, character.faces)
    )
    return pattern, pmesh, out, body


def _travel(points: np.ndarray, centre: np.ndarray) -> float:
    """Signed angle (rad) swept round the vertical through ``centre`` from the first point to the last."""
    angle = np.unwrap(np.arctan2(points[:, 0] - centre[0], points[:, 2] - centre[2]))
    return float(angle[-1] - angle[0])


def test_the_neck_binding_runs_round_the_neck_the_way_its_neckline_does(wrapped):
    pattern, pmesh, out, body = wrapped
    seen = 0
    for sp in pmesh.seams:
        sides = ((sp.a, sp.a_vertices, sp.b, sp.b_vertices), (sp.b, sp.b_vertices, sp.a, sp.a_vertices))
        for me, va, other, vb in sides:
            if pattern.piece(me.piece).role is not Role.NECK_BINDING or other.piece == me.piece:
                continue
            band, partner = out[me.key][va], out[other.key][vb]
            # round the neck: the centre of the body's cross-section at the neckline's height
            near = body[np.abs(body[:, 1] - partner[:, 1].mean()) < 1.0]
            centre = 0.5 * (near.min(axis=0) + near.max(axis=0))
            t_band, t_partner = _travel(band, centre), _travel(partner, centre)
            assert t_band * t_partner > 0, (other.key, t_band, t_partner)  # as drawn: against it
            gap = np.linalg.norm(band - partner, axis=1).mean()
            assert gap < 18.0, (other.key, gap)  # turned: 14.2 and 16.5 cm in the sample size
            seen += 1
    assert seen == 2  # the front's and the back's neckline
