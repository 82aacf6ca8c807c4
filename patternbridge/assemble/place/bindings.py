"""Bindings laid along the edges they bind: a strip sewn on an opening starts as the cloth's continuation beyond it.

A neck or armhole binding is a straight strip sewn by one long edge all
along an opening (folded over it, :mod:`patternbridge.bridge.worn`). The
wrap lays it on its anchor's proxy like any band, as a horizontal ring at the
height of its landmark (an armhole binding round the torso at the armpit),
while the opening it binds runs up and over the shoulder: a racer back's
armhole climbs the strap to the nape. The seam graph, linear, then bends
the ring onto the opening by its seams alone and lays it there turned over
along the steep parts, which the drape keeps (``simple.DXF``'s armhole
bindings worn inside out up the racer straps and knotted where they close at
the top of the straps).

So after the seam graph has closed the pieces, each binding is laid again
from the edge it is sewn to: each of its sewn vertices on its partner's, and
every other vertex at its pattern offset from the sewn edge, across the edge
along the partner's surface, away from the partner's cloth (a local frame
per sewn vertex: the edge's tangent and the surface's direction across it,
blended over the :data:`NEAREST` nearest sewn vertices in the pattern). A
binding cut the right side up (:func:`~.handedness.sewn_turned`) then lies
outside out with its sewn edge closed, as it is worn; the seam graph is
solved once more to settle it against the body and the other cloth.
"""

from __future__ import annotations

import numpy as np

from ...pattern.model import BINDING_ROLES, Pattern
from ..export_attributes import vertex_normals
from ..mesh2d import PatternMesh
from .wrap import instance_points2d

__all__ = ["NEAREST", "binding_keys", "lay_bindings"]

#: sewn vertices whose frames are blended for each vertex of a binding
NEAREST = 3


def binding_keys(pattern: Pattern, pmesh: PatternMesh) -> set[str]:
    """Instance keys of the bindings sewn to pieces that are not bindings (bands sewn only to one another, as
    ``clo-pattern.dxf``'s, bind no edge)."""
    binding = {inst.key for inst in pmesh.instances if pattern.piece(inst.piece).role in BINDING_ROLES}
    return {
        i.key
        for sp in pmesh.seams
        for i, other in ((sp.a, sp.b), (sp.b, sp.a))
        if i.key in binding and other.key not in binding
    }


def lay_bindings(pmesh: PatternMesh, placed: dict[str, np.ndarray], keys: set[str]) -> dict[str, np.ndarray]:
    """``placed`` with every binding of ``keys`` laid along the edge it is sewn to (see the module).

    Parameters
    ----------
    pmesh : the pattern mesh (seams, instances)
    placed : instance key -> (n, 3) positions, cm (its partners' edges where they are to be bound)
    keys : the bindings (:func:`binding_keys`)

    Returns
    -------
    instance key -> (n, 3) positions, cm (a new dict; the bindings' arrays are new)
    """
    out = dict(placed)
    by_key = {inst.key: inst for inst in pmesh.instances}
    for key in sorted(keys):
        own, target, across = _edge_frames(pmesh, placed, key, keys)
        if len(own) < 2:
            continue
        out[key] = _laid(instance_points2d(pmesh, by_key[key]), own, target, across)
    return out


def _edge_frames(
    pmesh: PatternMesh, placed: dict[str, np.ndarray], key: str, bindings: set[str]
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The binding's sewn vertices (ordered along its boundary), their partners' mean positions (k, 3) and the
    unit directions (k, 3) across the partners' edge along their surface, away from their cloth."""
    sums: dict[int, list] = {}
    for sp in pmesh.seams:
        sides = ((sp.a, sp.a_vertices, sp.b, sp.b_vertices), (sp.b, sp.b_vertices, sp.a, sp.a_vertices))
        for me, mine, other, theirs in sides:
            if me.key != key or other.key == key or other.key in bindings:
                continue
            x = placed[other.key]
            away = _away_from_cloth(x, pmesh.pieces[other.piece].faces, np.asarray(theirs))
            for v, p, d in zip(np.asarray(mine).tolist(), x[theirs], away, strict=True):
                sums.setdefault(v, []).append((p, d))
    own = np.array(sorted(sums), dtype=np.int64)
    if len(own) == 0:
        return own, np.zeros((0, 3)), np.zeros((0, 3))
    # along the boundary (its first vertices, in order), starting after the widest gap: the edge may run past 0
    n_boundary = pmesh.pieces[next(i.piece for i in pmesh.instances if i.key == key)].n_boundary
    gaps = np.diff(np.r_[own, own[0] + n_boundary])
    own = np.roll(own, -(int(np.argmax(gaps)) + 1))
    target = np.array([np.mean([p for p, _ in sums[v]], axis=0) for v in own.tolist()])
    away = np.array([np.sum([d for _, d in sums[v]], axis=0) for v in own.tolist()])
    return own, target, away


def _away_from_cloth(x: np.ndarray, faces: np.ndarray, edge: np.ndarray) -> np.ndarray:
    """(k, 3) unit vectors at the boundary vertices ``edge`` of a placed piece: in its surface (the mean normal of
    the faces round each), across its edge, pointing off its cloth."""
    centroid = x[faces].mean(axis=1)
    inward = np.zeros_like(x)
    for c in range(3):
        np.add.at(inward, faces[:, c], centroid - x[faces[:, c]])
    n = vertex_normals(x, faces)[edge]
    off = -inward[edge]
    off -= np.sum(off * n, axis=1, keepdims=True) * n
    return off / np.maximum(np.linalg.norm(off, axis=1, keepdims=True), 1e-12)


def _laid(p2: np.ndarray, own: np.ndarray, target: np.ndarray, away: np.ndarray) -> np.ndarray:
    """(n, 3) positions of a binding with pattern coordinates ``p2`` whose vertices ``own`` go on ``target``.

    Each sewn vertex carries a frame: the edge's tangent in the pattern and on
    the body (its neighbours along the sewn edge), the pattern's direction
    across the edge into the strip, and ``away`` on the body. Every vertex
    lies at its pattern offset from each of its :data:`NEAREST` nearest sewn
    vertices mapped through their frames, blended by inverse squared distance.
    """
    u = p2[own]
    nxt = np.r_[1 : len(own), len(own) - 1]
    prv = np.r_[0, 0 : len(own) - 1]
    t2 = u[nxt] - u[prv]
    t2 /= np.maximum(np.linalg.norm(t2, axis=1, keepdims=True), 1e-12)
    t3 = target[nxt] - target[prv]
    t3 /= np.maximum(np.linalg.norm(t3, axis=1, keepdims=True), 1e-12)
    d3 = away - np.sum(away * t3, axis=1, keepdims=True) * t3
    d3 /= np.maximum(np.linalg.norm(d3, axis=1, keepdims=True), 1e-12)
    d2 = np.stack([-t2[:, 1], t2[:, 0]], axis=1)
    inside = p2.mean(axis=0) - u
    d2 *= np.where(np.sum(d2 * inside, axis=1) < 0.0, -1.0, 1.0)[:, None]
    dist = np.linalg.norm(p2[:, None, :] - u[None, :, :], axis=2)
    k = min(NEAREST, len(own))
    near = np.argsort(dist, axis=1)[:, :k]
    w = 1.0 / (np.take_along_axis(dist, near, axis=1) ** 2 + 1e-6)
    w /= w.sum(axis=1, keepdims=True)
    rel = p2[:, None, :] - u[near]
    along = np.sum(rel * t2[near], axis=2)
    off = np.sum(rel * d2[near], axis=2)
    pos = target[near] + along[..., None] * t3[near] + off[..., None] * d3[near]
    out = np.sum(w[..., None] * pos, axis=1)
    out[own] = target
    return out
