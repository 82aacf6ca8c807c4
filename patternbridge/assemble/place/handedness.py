"""Which way round a piece cut in pairs is worn on a limb: the one whose seams face their partners.

A sleeve (or a one-piece leg, a cuff) cut twice gives a left and a right
copy, one the mirror image of the other. The bridge data say which body part
the drawn copy goes on; the seams say which half of its cap is sewn to the
front of the bodice. When the two disagree (a file drafts its sleeve as the
left one, its sidecar puts the drawn copy on the right arm) the drawn copy,
wrapped on its arm, turns its front cap to the back: every armhole seam
starts across the arm, and sewing it twists the sleeve half round the arm and
drags the bodice up with it (the sleeves stood out as wings and the body
crumpled).

Of a pair, which copy is drawn as printed and which mirrored does not change
the garment, only which of the two goes on which side. So each such piece is
wrapped both ways and worn the way its seams across the limb's root start
closer together (:func:`choose_mirrored`; a cuff follows its sleeve); a piece worn mirrored has its mesh
mirrored in x (:func:`mirrored_mesh`), so the primary copy is the mirror of
the drawing and the mirror copy the drawing itself. No piece name, role or
body-part string is tested: the choice is a function of the seam graph and
the wrap.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from ...pattern.model import Copy
from ..mesh2d import PatternMesh, PieceMesh

__all__ = ["choose_mirrored", "mirrored_mesh", "paired_limb_pieces", "sewn_turned", "with_mirrored"]

#: a piece is worn mirrored only when that brings its seams' squared gaps this much below the drawing's
GAIN = 0.8


def mirrored_mesh(mesh: PieceMesh) -> PieceMesh:
    """``mesh`` mirrored in x: points (x, y) -> (-x, y); faces re-wound counter-clockwise (the boundary runs
    clockwise; vertex ids, marks and seams are unchanged)."""
    return dataclasses.replace(mesh, points=mesh.points * np.array([-1.0, 1.0]), faces=mesh.faces[:, ::-1].copy())


def with_mirrored(pmesh: PatternMesh, pieces: frozenset[str]) -> PatternMesh:
    """``pmesh`` with the meshes of ``pieces`` mirrored (:func:`mirrored_mesh`)."""
    if not pieces:
        return pmesh
    meshes = {name: mirrored_mesh(m) if name in pieces else m for name, m in pmesh.pieces.items()}
    return dataclasses.replace(pmesh, pieces=meshes)


def paired_limb_pieces(pmesh: PatternMesh, on_limb: dict[str, bool]) -> frozenset[str]:
    """Pieces cut in a pair (a primary and a mirror copy) whose copies go on a limb (``on_limb``: instance key ->
    whether its body part is a limb) and that are sewn to another piece."""
    copies: dict[str, set] = {}
    for inst in pmesh.instances:
        copies.setdefault(inst.piece, set()).add(inst.copy)
    sewn = {sp.a.piece for sp in pmesh.seams if sp.a.piece != sp.b.piece} | {
        sp.b.piece for sp in pmesh.seams if sp.a.piece != sp.b.piece
    }
    return frozenset(
        inst.piece
        for inst in pmesh.instances
        if inst.copy is Copy.PRIMARY
        and copies[inst.piece] == {Copy.PRIMARY, Copy.MIRROR}
        and on_limb[inst.key]
        and inst.piece in sewn
    )


def _gaps(pmesh: PatternMesh, piece: str, positions: dict[str, np.ndarray], part: dict[str, object]) -> float:
    """Sum of squared distances (cm²) between the sewn vertex pairs of ``piece``'s seams to copies on another
    body part (``part``: instance key -> body part)."""
    total = 0.0
    for sp in pmesh.seams:
        if (sp.a.piece == piece) == (sp.b.piece == piece) or part[sp.a.key] == part[sp.b.key]:
            continue
        d = positions[sp.a.key][sp.a_vertices] - positions[sp.b.key][sp.b_vertices]
        total += float(np.sum(d * d))
    return total


def choose_mirrored(
    pmesh: PatternMesh,
    candidates: frozenset[str],
    drawn: dict[str, np.ndarray],
    mirrored: dict[str, np.ndarray],
    part: dict[str, object],
) -> frozenset[str]:
    """The ``candidates`` to wear mirrored: those whose seams across the limb's root start closer that way.

    Parameters
    ----------
    pmesh : the meshed pattern as drawn
    candidates : pieces that may be worn mirrored (:func:`paired_limb_pieces`)
    drawn : instance key -> (n, 3) cm, every copy wrapped as drawn
    mirrored : instance key -> (n, 3) cm, the copies of the candidates wrapped mirrored
    part : instance key -> its body part

    Only the seams to copies on another body part (a sleeve's armholes on the
    torso) say which way round a piece goes: a candidate sewn across is worn
    mirrored when their summed squared gaps fall below :data:`GAIN` × those as
    drawn. A candidate sewn only to pieces on its own limb (a cuff, to its
    sleeve) has no such evidence (a band is nearly symmetric, and wrapped at
    the wrist its gaps to the sleeve are mostly the distance between them): it
    follows the piece it is sewn to, so that the two still run the same way
    round the limb.
    """
    keys = {inst.key: inst.piece for inst in pmesh.instances}
    across = {
        p for sp in pmesh.seams if part[sp.a.key] != part[sp.b.key] for p in (sp.a.piece, sp.b.piece) if p in candidates
    }
    chosen: set[str] = set()
    for piece in sorted(across):
        mine = [k for k, p in keys.items() if p == piece]
        flipped = dict(drawn) | {k: mirrored[k] for k in mine}
        if _gaps(pmesh, piece, flipped, part) < GAIN * _gaps(pmesh, piece, drawn, part):
            chosen.add(piece)
    followers = set(candidates) - across
    grown = True
    while grown:
        grown = False
        for sp in pmesh.seams:
            for me, other in ((sp.a.piece, sp.b.piece), (sp.b.piece, sp.a.piece)):
                if me in followers and other in chosen and me not in chosen:
                    chosen.add(me)
                    grown = True
    return frozenset(chosen)


def _directions(pmesh: PatternMesh, inst, ids: np.ndarray) -> np.ndarray:
    """(k-1,) +1 / -1 / 0: whether each step ids[i] -> ids[i+1] runs along the instance's wound faces, against, or
    is no edge of them (a mirror copy is wound the other way round, as the cloth stacks it)."""
    f = pmesh.pieces[inst.piece].faces
    f = f[:, ::-1] if inst.copy is Copy.MIRROR else f
    e = np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]])
    n = int(f.max()) + 1
    fwd = np.zeros(n * n, dtype=bool)
    fwd[e[:, 0] * n + e[:, 1]] = True
    a, b = np.asarray(ids[:-1], dtype=np.int64), np.asarray(ids[1:], dtype=np.int64)
    return fwd[a * n + b].astype(np.int64) - fwd[b * n + a].astype(np.int64)


def sewn_turned(pmesh: PatternMesh) -> frozenset[str]:
    """Pieces to cut the other side up: every seam of theirs to other pieces sews them on turned over.

    Two pieces sewn edge to edge with both outsides out run their sewn edges
    opposite ways round their wound faces (as two triangles of one surface
    share an edge). A seam whose two sides run the same way can only be
    closed with one side turned over: a binding sewn so all round is worn
    inside out, or twists half round between its seams. The drawing of a
    strip does not say which of its faces is the fabric's right side, so such
    a piece is cut the other side up: its mirror image (:func:`mirrored_mesh`),
    which runs each of its seams the other way. Pieces are taken from the
    least sewn (a binding before the bodice it binds); a piece with a seam
    that sews it on as drawn stays as drawn.
    """
    seams: list[tuple[str, str, bool]] = []
    for sp in pmesh.seams:
        if sp.a.piece == sp.b.piece:
            continue
        da = _directions(pmesh, sp.a, sp.a_vertices)
        db = _directions(pmesh, sp.b, sp.b_vertices)
        both = (da != 0) & (db != 0)
        same = int(np.count_nonzero(both & (da == db)))
        seams.append((sp.a.piece, sp.b.piece, same > int(np.count_nonzero(both)) - same))
    steps: dict[str, int] = {}
    for sp in pmesh.seams:
        if sp.a.piece != sp.b.piece:
            for piece in (sp.a.piece, sp.b.piece):
                steps[piece] = steps.get(piece, 0) + len(sp.a_vertices) - 1
    flipped: set[str] = set()
    for piece in sorted(steps, key=lambda p: (steps[p], p)):
        mine = [((a in flipped) != (b in flipped)) != turned for a, b, turned in seams if piece in (a, b)]
        if mine and all(mine):
            flipped.add(piece)
    return frozenset(flipped)
