"""A piece every seam of which sews it on turned over is cut the other side up (its mirror image)."""

from __future__ import annotations

import numpy as np

from patternbridge.assemble.mesh2d import Instance, PatternMesh, PieceMesh, SeamPairs
from patternbridge.assemble.place.handedness import mirrored_mesh, sewn_turned, with_mirrored
from patternbridge.pattern.model import Copy


def _square(name: str, x0: float) -> PieceMesh:
    """A 10 cm square from x0, its corners counter-clockwise (0 bottom left), two triangles wound counter-clockwise."""
    pts = np.array([[x0, 0.0], [x0 + 10, 0.0], [x0 + 10, 10.0], [x0, 10.0]])
    return PieceMesh(name=name, points=pts, faces=np.array([[0, 1, 2], [0, 2, 3]]), n_boundary=4)


def _sewn(strip_vertices: list[int]) -> PatternMesh:
    """A body square between a side square (sewn flat, as drawn) and a strip sewn to its right edge (1 -> 2, up)
    in the order ``strip_vertices``."""
    body, side, strip = (Instance(piece=n, copy=Copy.PRIMARY) for n in ("body", "side", "strip"))
    seams = (
        SeamPairs(seam="side", a=side, b=body, a_vertices=np.array([1, 2]), b_vertices=np.array([0, 3])),
        SeamPairs(seam="strip", a=body, b=strip, a_vertices=np.array([1, 2]), b_vertices=np.array(strip_vertices)),
    )
    pieces = {"side": _square("side", -10.0), "body": _square("body", 0.0), "strip": _square("strip", 10.0)}
    return PatternMesh(pieces=pieces, instances=(side, body, strip), seams=seams, max_edge_cm=2.5)


def test_pieces_sewn_beside_each_other_as_drawn_are_not_turned():
    # each left edge runs 0 -> 3 (up) like the right edge it is sewn to: one flat surface, every outside up
    assert sewn_turned(_sewn([0, 3])) == frozenset()


def test_a_strip_sewn_the_other_way_round_is_cut_the_other_side_up():
    # sewn 3 -> 0 against the body's 1 -> 2: the strip must be turned over to close the seam; the body, sewn to
    # the side as drawn, stays
    pm = _sewn([3, 0])
    assert sewn_turned(pm) == frozenset({"strip"})
    assert sewn_turned(with_mirrored(pm, frozenset({"strip"}))) == frozenset()
    # the mirror image is the same cloth, its faces wound counter-clockwise again
    m = mirrored_mesh(pm.pieces["strip"])
    u, w = m.points[m.faces[:, 1]] - m.points[m.faces[:, 0]], m.points[m.faces[:, 2]] - m.points[m.faces[:, 0]]
    assert (u[:, 0] * w[:, 1] - u[:, 1] * w[:, 0] > 0).all()


def test_a_mirror_copy_is_wound_the_other_way_round():
    # the strip's mirror copy sewn 0 -> 3 to the body: the cloth stacks it wound the other way, so it is turned
    pm = _sewn([0, 3])
    mirror = Instance(piece="strip", copy=Copy.MIRROR)
    seam = SeamPairs(seam="strip", a=pm.seams[1].a, b=mirror, a_vertices=np.array([1, 2]), b_vertices=np.array([0, 3]))
    pm = PatternMesh(pieces=pm.pieces, instances=(*pm.instances, mirror), seams=(pm.seams[0], seam), max_edge_cm=2.5)
    assert sewn_turned(pm) == frozenset({"strip"})
