"""How a design shares the reduction between two girth levels among its darts and seams.

A skirt's front is wider at the hip than at the waist; the difference is
taken partly by the darts' intake and partly by the slope of the side seams
(and of a centre seam, when it slopes). How the design splits it is as much
the design as the girths themselves: graded so that the side seam takes the
whole of a deeper reduction, the hip curve is pulled straight while the darts
keep their intake. Proportional scaling keeps the split (every part scales
with the width), so the final step holds it as a design term
(:func:`suppression_terms`, in :class:`~.step_terms.StepTerms`).

For every piece and every two neighbouring girth levels it carries (waist
and hip, chest and waist: girth links, by the measurement catalogue's kind,
with legs on the piece) where a dart takes part, the **reduction** ``R`` is the
wider level's length on the piece minus the narrower's, and its **parts**
are

* the intake of every dart whose two rims end legs of the narrower level
  (the distance between its rims);
* the slope of every seam between the levels: at each end of the wider
  level's legs, how far the nearest end of the narrower level's legs (along
  the outline) lies inwards across the grain, when one side of a seam runs
  through both (a neck and a chest are joined by no seam: no slope).

The term is ``(part − s₀ · R) / R₀`` for every part, ``s₀ = part₀ / R₀`` its
share in the sample: the share's error, scaled by how much there is to
share. A piece that carries a level only through a seam (a dress's skirt,
sewn to the bodice's waist) takes the level's legs over that seam.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np

from ..measure.definitions import GIRTH_IDS
from .grid import PatternGrid
from .objectives import ObjectiveData, _range_points, chord_lengths

__all__ = ["Suppression", "suppression", "suppression_parts", "suppression_terms"]

MIN_REDUCTION_FRAC = 0.03
"""A pair of levels whose sample reduction is below this fraction of the wider level's length on the piece (or
under 1 cm) is not held: there is nothing the design shares."""


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class Suppression:
    """The reductions and their parts, as index arrays over the reference line.

    pair_piece : (G,) piece of every pair of levels ; pair_links : (G, 2)
    narrower and wider link ; reduce_edges : (N, G) +1 on the wider
    level's boundary edges, −1 on the narrower's ; reduce_chords : (C, G)
    the same for chord legs ; r0 : (G,) sample reductions, cm ;
    dart_rims : (Dg, 2) rim indices of every dart part ; dart_pair : (Dg,) ;
    slope_ends : (Sg, 2) wide end, narrow end ; slope_dir : (Sg, 2) the
    inward direction across the grain at the wide end ; slope_pair : (Sg,) ;
    share0 : (Dg + Sg,) sample shares, darts first
    """

    pair_piece: np.ndarray
    pair_links: np.ndarray
    reduce_edges: np.ndarray
    reduce_chords: np.ndarray
    r0: np.ndarray
    dart_rims: np.ndarray
    dart_pair: np.ndarray
    slope_ends: np.ndarray
    slope_dir: np.ndarray
    slope_pair: np.ndarray
    share0: np.ndarray

    @property
    def n_parts(self) -> int:
        return len(self.share0)


def _level_legs(
    grid: PatternGrid, data: ObjectiveData
) -> tuple[dict[tuple[int, int], list[tuple[np.ndarray, bool]]], list[set[int]]]:
    """(piece, girth link) -> its legs on the piece as (global point range, chord?), seams carried one hop.

    Also every seam side's points (global indices), for the slopes.
    """
    pattern = grid.pattern
    legs: dict[tuple[int, int], list[tuple[np.ndarray, bool]]] = {}
    girth = set(GIRTH_IDS)
    for j, link in enumerate(pattern.measurements):
        if link.measurement not in girth:
            continue
        for leg in link.legs:
            idx = _range_points(grid, leg.piece, leg.start, leg.end, f"link {link.id!r}")
            legs.setdefault((grid.piece_index(leg.piece), j), []).append((idx, leg.along in ("chord", "across")))
    carried: dict[tuple[int, int], list[tuple[np.ndarray, bool]]] = {}
    sides: list[set[int]] = []
    for seam in pattern.seams:
        ia = _range_points(grid, seam.a.piece, seam.a.start, seam.a.end, f"seam {seam.id!r}")
        ib = _range_points(grid, seam.b.piece, seam.b.start, seam.b.end, f"seam {seam.id!r}")
        sides += [set(ia.tolist()), set(ib.tolist())]
        for src, dst in ((ia, ib), (ib, ia)):
            ks, kd = int(data.piece_of_point[src[0]]), int(data.piece_of_point[dst[0]])
            if ks == kd or len(src) < 2:
                continue
            for (k, j), ls in legs.items():
                if k != ks or (kd, j) in legs:
                    continue
                inside = any(not chord and set(src[:-1].tolist()) <= set(r[:-1].tolist()) for r, chord in ls)
                if inside:
                    carried.setdefault((kd, j), []).append((dst, False))
    return {**legs, **carried}, sides


def _arc(points: np.ndarray, nxt: np.ndarray, a: int, b: int, lo: int, hi: int) -> float:
    """Shorter outline distance between global points ``a`` and ``b`` of the piece ``[lo, hi)``."""
    seg = np.linalg.norm(points[nxt[lo:hi]] - points[lo:hi], axis=1)
    s = np.concatenate([[0.0], np.cumsum(seg)])
    d = abs(s[a - lo] - s[b - lo])
    return float(min(d, s[-1] - d))


def suppression(grid: PatternGrid, data: ObjectiveData) -> Suppression:
    """The design's split of every reduction between neighbouring girth levels of a piece (see the module)."""
    pattern = grid.pattern
    legs, sides = _level_legs(grid, data)
    p0 = data.points0
    n, C = len(p0), len(data.chord_a)
    chord0 = chord_lengths(data, p0[None])[0] if C else np.zeros(0)
    cols_e, cols_c, pieces, links, r0s = [], [], [], [], []
    darts, dart_pair, ends, dirs, slope_pair = [], [], [], [], []
    for k in range(len(grid.pieces)):
        lo, hi = int(grid.point_offsets[k]), int(grid.point_offsets[k + 1])
        across = pattern.pieces[k].across_grain
        grain = np.array([-across[1], across[0]])
        levels = sorted(
            (float(np.mean([p0[r[[0, -1]]] @ grain for r, _ in ls])), j) for (kk, j), ls in legs.items() if kk == k
        )
        for (_, j1), (_, j2) in itertools.pairwise(levels):
            e, c, length = {}, {}, {}
            for j in (j1, j2):
                e[j], c[j] = np.zeros(n), np.zeros(C)
                for r, chord in legs[(k, j)]:
                    if chord:
                        hit = np.flatnonzero((data.chord_a == r[0]) & (data.chord_b == r[-1]))
                        c[j][hit[:1]] = 1.0
                    else:
                        e[j][r[:-1]] = 1.0
                length[j] = float(np.linalg.norm(p0[data.nxt] - p0, axis=1) @ e[j] + chord0 @ c[j])
            narrow, wide = (j1, j2) if length[j1] < length[j2] else (j2, j1)
            r0 = length[wide] - length[narrow]
            if r0 < max(1.0, MIN_REDUCTION_FRAC * length[wide]):
                continue
            g = len(pieces)
            narrow_ends = np.unique(np.concatenate([r[[0, -1]] for r, _ in legs[(k, narrow)]]))
            wide_ends = np.unique(np.concatenate([r[[0, -1]] for r, _ in legs[(k, wide)]]))
            mine = [(a, b) for a, _x, b in data.darts if a in narrow_ends and b in narrow_ends]
            if not mine:
                continue  # no dart takes part: the seams share it alone, which the shares of the girths hold
            darts += mine
            dart_pair += [g] * len(mine)
            centre = float(np.mean(p0[wide_ends] @ across))
            for h in np.setdiff1d(wide_ends, narrow_ends):
                w = min(narrow_ends, key=lambda v, h=h: _arc(p0, data.nxt, int(h), int(v), lo, hi))
                if not any(int(h) in side and int(w) in side for side in sides):
                    continue  # no seam runs between them: not a seam's slope
                inward = across * np.sign(centre - float(p0[h] @ across))
                ends.append((h, w))
                dirs.append(inward)
                slope_pair.append(g)
            pieces.append(k)
            links.append((narrow, wide))
            cols_e.append(e[wide] - e[narrow])
            cols_c.append(c[wide] - c[narrow])
            r0s.append(r0)
    return _assemble(n, C, pieces, links, cols_e, cols_c, r0s, darts, dart_pair, ends, dirs, slope_pair, p0)


def _assemble(n, C, pieces, links, cols_e, cols_c, r0s, darts, dart_pair, ends, dirs, slope_pair, p0) -> Suppression:
    G = len(pieces)
    r0 = np.array(r0s, dtype=np.float64)
    dart_rims = np.array(darts, dtype=np.int64).reshape(-1, 2)
    slope_ends = np.array(ends, dtype=np.int64).reshape(-1, 2)
    slope_dir = np.array(dirs, dtype=np.float64).reshape(-1, 2)
    dart_pair_a = np.array(dart_pair, dtype=np.int64)
    slope_pair_a = np.array(slope_pair, dtype=np.int64)
    intake0 = np.linalg.norm(p0[dart_rims[:, 1]] - p0[dart_rims[:, 0]], axis=1)
    slope0 = np.sum((p0[slope_ends[:, 1]] - p0[slope_ends[:, 0]]) * slope_dir, axis=1)
    share0 = np.concatenate([intake0 / r0[dart_pair_a], slope0 / r0[slope_pair_a]]) if G else np.zeros(0)
    return Suppression(
        pair_piece=np.array(pieces, dtype=np.int64),
        pair_links=np.array(links, dtype=np.int64).reshape(-1, 2),
        reduce_edges=np.stack(cols_e, axis=1) if G else np.zeros((n, 0)),
        reduce_chords=np.stack(cols_c, axis=1) if G else np.zeros((C, 0)),
        r0=r0,
        dart_rims=dart_rims,
        dart_pair=dart_pair_a,
        slope_ends=slope_ends,
        slope_dir=slope_dir,
        slope_pair=slope_pair_a,
        share0=share0,
    )


def suppression_parts(
    sup: Suppression, data: ObjectiveData, points: np.ndarray, edges: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Reductions ``(n_pop, G)`` and parts ``(n_pop, Dg + Sg)`` (darts first) of ``points (n_pop, N, 2)``, cm."""
    r = edges @ sup.reduce_edges
    if len(data.chord_a):
        r = r + chord_lengths(data, points) @ sup.reduce_chords
    intake = np.linalg.norm(points[:, sup.dart_rims[:, 1]] - points[:, sup.dart_rims[:, 0]], axis=-1)
    slope = np.einsum("pij,ij->pi", points[:, sup.slope_ends[:, 1]] - points[:, sup.slope_ends[:, 0]], sup.slope_dir)
    return r, np.concatenate([intake, slope], axis=1)


def suppression_terms(sup: Suppression, data: ObjectiveData, points: np.ndarray, edges: np.ndarray) -> np.ndarray:
    """``(part − s₀ · R) / R₀`` of every part, ``(n_pop, Dg + Sg)``: the error of each part's share."""
    r, parts = suppression_parts(sup, data, points, edges)
    pair = np.concatenate([sup.dart_pair, sup.slope_pair])
    return (parts - sup.share0 * r[:, pair]) / sup.r0[pair]
