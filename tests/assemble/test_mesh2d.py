"""Seam-matched meshing of pattern pieces."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from shapely.geometry import Point, Polygon

from patternbridge.assemble.mesh2d import mesh_pattern
from patternbridge.errors import InputError
from patternbridge.pattern.model import EdgeRange, Seam


def test_seam_sides_have_equal_counts_and_matching_ends(tshirt):
    pm = mesh_pattern(tshirt, max_edge_cm=2.0)
    by_id = {s.id: s for s in tshirt.seams}
    for sp in pm.seams:
        assert len(sp.a_vertices) == len(sp.b_vertices) >= 2
        seam = by_id[sp.seam]
        pa, pb = pm.pieces[sp.a.piece], pm.pieces[sp.b.piece]
        # ends of the ranges are the marks (b read backwards for a reversed seam)
        assert sp.a_vertices[0] == pa.marks[seam.a.start]
        assert sp.a_vertices[-1] == pa.marks[seam.a.end]
        b_first, b_last = (seam.b.end, seam.b.start) if seam.reverse else (seam.b.start, seam.b.end)
        assert sp.b_vertices[0] == pb.marks[b_first]
        assert sp.b_vertices[-1] == pb.marks[b_last]


def test_matched_vertices_sit_at_equal_arc_fractions(tshirt):
    pm = mesh_pattern(tshirt, max_edge_cm=2.0)
    for sp in pm.seams:
        fa = []
        for piece, ids in ((sp.a.piece, sp.a_vertices), (sp.b.piece, sp.b_vertices)):
            pts = pm.pieces[piece].points[ids]
            s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(pts, axis=0), axis=1))])
            fa.append(s / s[-1])
        np.testing.assert_allclose(fa[0], fa[1], atol=0.08)


def test_boundary_follows_outline_and_edges_are_short(tshirt):
    pm = mesh_pattern(tshirt, max_edge_cm=2.0)
    for piece in tshirt.pieces:
        m = pm.pieces[piece.name]
        poly = Polygon(piece.outline)
        boundary = m.points[: m.n_boundary]
        assert all(poly.exterior.distance(Point(p)) < 1e-6 for p in boundary)
        # interior points inside, triangles cover the piece area, all CCW
        u, w = (
            m.points[m.faces[:, 1]] - m.points[m.faces[:, 0]],
            m.points[m.faces[:, 2]] - m.points[m.faces[:, 0]],
        )
        area = 0.5 * (u[:, 0] * w[:, 1] - u[:, 1] * w[:, 0])
        assert np.all(area > 0)
        assert area.sum() == pytest.approx(poly.area, rel=0.02)
        e = np.linalg.norm(m.points[m.faces] - m.points[np.roll(m.faces, 1, axis=1)], axis=2)
        assert np.percentile(e, 95) < 2.0 * 1.6


def test_marks_are_boundary_vertices(tshirt):
    pm = mesh_pattern(tshirt, max_edge_cm=3.0)
    for piece in tshirt.pieces:
        m = pm.pieces[piece.name]
        for name, v in piece.marks.items():
            np.testing.assert_allclose(m.points[m.marks[name]], piece.outline[v], atol=1e-9)


def test_mirror_instances_are_created_for_pairs(tshirt):
    pm = mesh_pattern(tshirt, max_edge_cm=3.0)
    assert [i.key for i in pm.instances] == ["front", "back", "sleeve", "sleeve~mirror"]


def test_unknown_seam_mark_is_an_input_error(tshirt):
    bad = Seam(
        id="bad",
        a=EdgeRange(piece="front", start="hem_l", end="nowhere"),
        b=EdgeRange(piece="back", start="hem_l", end="hem_r"),
    )
    with pytest.raises(InputError, match="nowhere"):
        mesh_pattern(dataclasses.replace(tshirt, seams=(*tshirt.seams, bad)))


def test_unknown_seam_piece_is_an_input_error(tshirt):
    bad = Seam(
        id="bad",
        a=EdgeRange(piece="pocket", start="a", end="b"),
        b=EdgeRange(piece="back", start="hem_l", end="hem_r"),
    )
    with pytest.raises(InputError, match="pocket"):
        mesh_pattern(dataclasses.replace(tshirt, seams=(*tshirt.seams, bad)))


def test_only_the_cuffs_wait_for_the_arms_to_come_down():
    from patternbridge.assemble.pipeline import limb_end_seams
    from patternbridge.library.catalogue import load_garment

    shirt = load_garment("shirt")
    pm = mesh_pattern(shirt, max_edge_cm=3.0)
    late = limb_end_seams(shirt, pm)
    assert sorted(sp.seam for sp, lt in zip(pm.seams, late, strict=True) if lt) == ["cuff_left", "cuff_right"]
    trousers = load_garment("trousers")
    assert not limb_end_seams(trousers, mesh_pattern(trousers, max_edge_cm=3.0)).any()


@pytest.mark.parametrize("name", ["tshirt", "shirt"])
def test_cuts_carried_round_a_loop_of_seams_leave_no_sliver(name):
    # the sleeve cap is eased into the armhole, so a cut carried round the loop of seams at the underarm
    # (armhole front, underarm seam, armhole back, side seam) comes back a few hundredths of a mm from where
    # it started; meshed as they were, those cuts made boundary vertices 0.003 cm apart and a fan of
    # triangles from 0.003 to 2 cm round each underarm corner, which crumpled through itself
    from patternbridge.assemble.mesh2d import _on_sew_line
    from patternbridge.library.catalogue import load_garment

    garment = load_garment(name)
    pm = mesh_pattern(garment, max_edge_cm=2.5)
    for piece in garment.pieces:
        m = pm.pieces[piece.name]
        b = m.points[: m.n_boundary]
        assert np.linalg.norm(np.roll(b, -1, axis=0) - b, axis=1).min() >= 0.1 * 2.5
        e = np.linalg.norm(m.points[m.faces] - m.points[np.roll(m.faces, 1, axis=1)], axis=2)
        assert e.min() > 0.05 * 2.5
        sew_line = _on_sew_line(piece).outline
        for mark, v in piece.marks.items():  # the marks keep their vertices
            np.testing.assert_allclose(m.points[m.marks[mark]], sew_line[v], atol=1e-9)
    for sp in pm.seams:
        assert len(sp.a_vertices) == len(sp.b_vertices) >= 2
