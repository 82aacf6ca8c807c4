"""The pattern as worn, for the drape only: bands applied flat cut to their opening, spare copies left out.

A binding cut longer than the opening it binds (``simple.DXF``'s bindings,
13 cm longer than their neckline and armholes in every size) is sewn from one
end in the workroom, and where the sewing comes back to its start the excess
is cut off and the two ends lapped. The sidecar records the two cut lines
(``trim``: a mark on the sewn edge where the sewn range starts or ends, and
the mark straight across the strip from it, :class:`.model.Trim`); before
draping, :func:`worn_pattern` removes the strip beyond them and sews the two
cut ends to each other, on every copy the seams sew. The graded DXF sent back
keeps the designer's whole strip.

A band hung below a limb piece's anchor (a short sleeve's cuff,
``Placement.drop_cm``, :func:`.band_anchor.band_below`) takes its drop from
the graded partner (:func:`hung_bands`): the sidecar's drop is the sample
size's, and a sleeve graded shorter brings its cuff up with its hem.

A band the file cuts more often than the garment sews it (``GLX0926S16``'s
neck binding, cut as a pair for one neckline) is draped in the copies sewn
(``worn_copies``); the DXF keeps the file's quantity.
"""

from __future__ import annotations

import dataclasses
import os

import numpy as np

from ..io.json_file import read_json
from ..library.seams import range_indices, sew_line
from ..pattern.model import Copy, EdgeRange, Pattern, Piece, Quantity, Seam

__all__ = ["hung_bands", "trim_piece", "worn_pattern"]


def _between(n: int, a: int, b: int) -> list[int]:
    """Vertices strictly between ``a`` and ``b`` in outline order (0 <= a, b < n)."""
    return [int(v) for v in np.mod(np.arange(a + 1, a + 1 + (b - a - 1) % n), n)]


def trim_piece(piece: Piece, start: int, start_across: int, end: int, end_across: int) -> tuple[Piece, np.ndarray]:
    """``piece`` without the vertices between ``end`` and ``end_across`` and between ``start_across`` and
    ``start`` (outline order), and the new index of every old vertex (-1: removed).

    Marks and notches on removed vertices are dropped; the paired sew line
    (``sew_lines[0]`` with one point per outline vertex) is cut alike.

    Examples
    --------
    >>> strip = Piece(name="b", outline=[[0, 0], [2, 0], [12, 0], [12, 1], [2, 1], [0, 1]], marks={"s": 1})
    >>> trimmed, index = trim_piece(strip, 1, 4, 2, 3)
    >>> trimmed.outline.tolist(), index.tolist()
    ([[2.0, 0.0], [12.0, 0.0], [12.0, 1.0], [2.0, 1.0]], [-1, 0, 1, 2, 3, -1])
    """
    n = len(piece.outline)
    gone = set(_between(n, end, end_across)) | set(_between(n, start_across, start))
    keep = np.array([v for v in range(n) if v not in gone], dtype=np.int64)
    index = np.full(n, -1, dtype=np.int64)
    index[keep] = np.arange(len(keep))
    sew = list(piece.sew_lines)
    if sew and sew[0].closed and len(sew[0].points) == n:
        line = sew[0]
        sew[0] = dataclasses.replace(
            line,
            points=np.asarray(line.points)[keep],
            kinds=None if line.kinds is None else tuple(line.kinds[v] for v in keep),
            rules=None if line.rules is None else tuple(line.rules[v] for v in keep),
        )
    trimmed = dataclasses.replace(
        piece,
        outline=np.asarray(piece.outline)[keep],
        kinds=None if piece.kinds is None else tuple(piece.kinds[v] for v in keep),
        rules=None if piece.rules is None else tuple(piece.rules[v] for v in keep),
        sew_lines=tuple(sew),
        marks={name: int(index[v]) for name, v in piece.marks.items() if index[v] >= 0},
        notches=tuple(
            dataclasses.replace(m, vertex=int(index[m.vertex])) for m in piece.notches if index[m.vertex] >= 0
        ),
    )
    return trimmed, index


def fold_piece(piece: Piece, sewn: np.ndarray, share: float) -> Piece:
    """``piece`` with every vertex off its sewn edge moved toward it, to ``share`` of its distance (outline and
    paired sew line alike): a binding folded over the edge it binds, worn at its finished width.

    ``sewn`` : the vertex indices of the sewn edge, in outline order (consecutive vertices form its segments).

    Examples
    --------
    >>> strip = Piece(name="b", outline=[[0, 0], [10, 0], [10, 4], [0, 4]])
    >>> fold_piece(strip, np.array([0, 1]), 0.5).outline.tolist()
    [[0.0, 0.0], [10.0, 0.0], [10.0, 2.0], [0.0, 2.0]]
    """
    sewn = np.asarray(sewn, dtype=np.int64)

    def fold(points: np.ndarray) -> np.ndarray:
        pts = np.asarray(points, dtype=np.float64)
        a, b = pts[sewn[:-1]], pts[sewn[1:]]
        d = b - a
        rel = pts[:, None, :] - a[None, :, :]
        t = np.clip(np.einsum("nkj,kj->nk", rel, d) / np.maximum(np.einsum("kj,kj->k", d, d), 1e-12), 0.0, 1.0)
        foot = a[None, :, :] + t[:, :, None] * d[None, :, :]
        dist = np.linalg.norm(pts[:, None, :] - foot, axis=2)
        near = foot[np.arange(len(pts)), np.argmin(dist, axis=1)]
        out = near + share * (pts - near)
        out[sewn] = pts[sewn]
        return out

    n = len(piece.outline)
    sew = list(piece.sew_lines)
    if sew and sew[0].closed and len(sew[0].points) == n:
        sew[0] = dataclasses.replace(sew[0], points=fold(sew[0].points))
    return dataclasses.replace(piece, outline=fold(piece.outline), sew_lines=tuple(sew))


def _folded(pattern: Pattern, shares: dict[str, float]) -> Pattern:
    """``pattern`` with each piece of ``shares`` folded over the edge its seams to other pieces sew."""
    pieces = []
    for p in pattern.pieces:
        ranges = [
            range_indices(p, r.start, r.end)
            for s in pattern.seams
            for r, other in ((s.a, s.b), (s.b, s.a))
            if r.piece == p.name and other.piece != p.name and r.copy is Copy.PRIMARY
        ]
        if p.name not in shares or not ranges:
            pieces.append(p)
            continue
        n = len(p.outline)
        on = np.zeros(n, dtype=bool)
        for idx in ranges:
            on[idx] = True
        start = int(np.flatnonzero(on & ~np.roll(on, 1))[0]) if not on.all() else 0
        order = np.mod(np.arange(start, start + n), n)
        sewn = order[on[order]]
        pieces.append(fold_piece(p, sewn, shares[p.name]))
    return dataclasses.replace(pattern, pieces=tuple(pieces))


def _worn_copies(pattern: Pattern, worn: dict[str, list[str]]) -> Pattern:
    """``pattern`` cutting each piece of ``worn`` only in the copies listed, without seams on the others."""
    pieces = tuple(
        dataclasses.replace(
            p, quantity=Quantity(right=int(Copy.PRIMARY in worn[p.name]), left=int(Copy.MIRROR in worn[p.name]))
        )
        if p.name in worn
        else p
        for p in pattern.pieces
    )
    seams = tuple(s for s in pattern.seams if all(r.piece not in worn or r.copy in worn[r.piece] for r in (s.a, s.b)))
    return dataclasses.replace(pattern, pieces=pieces, seams=seams)


def _hem_drop(pattern: Pattern, band: Piece) -> float | None:
    """How far the middle of the edge ``band``'s drawn copy is sewn to lies below the anchor mark of the piece
    it hangs from (the seam partner placed on the same anchor, upright pattern); None when there is none."""
    for s in pattern.seams:
        for mine, other in ((s.a, s.b), (s.b, s.a)):
            if mine.piece != band.name or other.piece == band.name or mine.copy is not Copy.PRIMARY:
                continue
            partner = pattern.piece(other.piece)
            pl = partner.placement
            if pl is None or pl.anchor != band.placement.anchor or pl.drop_cm or pl.anchor_mark not in partner.marks:
                continue
            pts = np.asarray(sew_line(partner)[0], dtype=np.float64)
            idx = range_indices(partner, other.start, other.end)
            run = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(pts[idx], axis=0), axis=1))])
            mid = idx[int(np.argmin(np.abs(run - 0.5 * run[-1])))]
            return max(float(pts[partner.marks[pl.anchor_mark], 1] - pts[mid, 1]), 0.0)
    return None


def hung_bands(pattern: Pattern) -> Pattern:
    """``pattern`` (stood upright) with the drop of every band hung below its partner's anchor measured on the
    pattern's own (graded) partner."""
    pieces = []
    for p in pattern.pieces:
        drop = _hem_drop(pattern, p) if p.placement is not None and p.placement.drop_cm > 0.0 else None
        pieces.append(
            p if drop is None else dataclasses.replace(p, placement=dataclasses.replace(p.placement, drop_cm=drop))
        )
    return dataclasses.replace(pattern, pieces=tuple(pieces))


def worn_pattern(pattern: Pattern, sidecar: str | os.PathLike) -> Pattern:
    """``pattern`` as the garment is worn: bands hung below a limb piece at its graded hem (:func:`hung_bands`),
    bands cut in the copies the sidecar's ``worn_copies`` lists only, and every band it records a ``trim`` for
    cut to its opening and closed there.

    The closure is sewn on each copy of the band that the pattern's seams sew;
    measurement links naming a removed mark are dropped (the drape does not
    grade).
    """
    pattern = hung_bands(pattern)
    data = read_json(sidecar, hint="give a sidecar written by 'patternbridge bridge infer'", what="sidecar file")
    entries = data.get("pieces", [])
    worn = {e["name"]: [Copy(c) for c in e["worn_copies"]] for e in entries if e.get("worn_copies")}
    pattern = _worn_copies(pattern, worn) if worn else pattern
    trims = {e["name"]: e["trim"] for e in entries if e.get("trim")}
    shares = {e["name"]: float(e["worn_width_share"]) for e in entries if e.get("worn_width_share")}
    pattern = _trimmed(pattern, trims) if trims else pattern
    return _folded(pattern, shares) if shares else pattern


def _trimmed(pattern: Pattern, trims: dict) -> Pattern:
    """``pattern`` with every band of ``trims`` cut at its two cut lines and closed there."""
    pieces, seams, dropped = [], list(pattern.seams), set()
    for piece in pattern.pieces:
        t = trims.get(piece.name)
        names = None if t is None else [t[k] for k in ("start", "start_across", "end", "end_across")]
        if names is None or any(m not in piece.marks for m in names):
            pieces.append(piece)
            continue
        trimmed, _ = trim_piece(piece, *(int(piece.marks[m]) for m in names))
        pieces.append(trimmed)
        dropped |= {(piece.name, m) for m in piece.marks if m not in trimmed.marks}
        copies = {r.copy for s in pattern.seams for r in (s.a, s.b) if r.piece == piece.name} or {Copy.PRIMARY}
        start, start_across, end, end_across = names
        for copy in sorted(copies):
            seams.append(
                Seam(
                    id=f"{piece.name}_trimmed_{copy}",
                    a=EdgeRange(piece=piece.name, start=end, end=end_across, copy=copy),
                    b=EdgeRange(piece=piece.name, start=start_across, end=start, copy=copy),
                    reverse=True,
                )
            )
    seams = [s for s in seams if not {(r.piece, m) for r in (s.a, s.b) for m in (r.start, r.end)} & dropped]
    links = tuple(
        m for m in pattern.measurements if not {(g.piece, k) for g in m.legs for k in (g.start, g.end)} & dropped
    )
    return dataclasses.replace(pattern, pieces=tuple(pieces), seams=tuple(seams), measurements=links)
