"""The grader's three objectives and its constraint, vectorised over the population.

All functions take the outline points of every individual at once,
``points : (n_pop, n_points, 2)`` cm (from :meth:`PatternGrid.outlines`), and
an :class:`ObjectiveData` compiled once per pattern and character by
:func:`objective_data`. Nothing loops over individuals.

Objectives (all minimised)
--------------------------
1. **Measurement error**, cm: mean over the pattern's measurement links of
   ``|target - achieved|`` with ``target = body measurement + ease`` (for a
   proportional link, the sample distance scaled by body / sample body) and
   ``achieved = Σ factor · length(leg)`` (thesis eq. 4.5; a link may run over
   several pieces sewn together); an ``at_least`` link counts only when it
   falls short (:func:`link_error`). A leg taken across the grain also
   counts how far its end marks have slid up or down against each other
   (:func:`level_slip`): a girth is taken at its level, and without this a
   chest line could tilt, or a side waist slide down the seam, to reach
   the target.
2. **Seam error**, cm: mean over seams of
   ``|L_b - L_a - ease|`` (whole-seam length mismatch)
   ``+ Σ_k |l_b,k - l_a,k - ease/(K-1)| / (K-1)`` (eq. 4.7: the two sides are
   sampled at the same K arc-length fractions of the original seam, so
   corresponding stitch intervals must stay equal)
   ``+ Σ_k |Δθ_a,k - Δθ_b,k| / (K-2)`` (eq. 4.6: the change of the turning
   angle at corresponding stitch points must agree, 1 rad counted as 1 cm)
   ``+ mean |notch misalignment|`` (corresponding notches, paired in sewing
   order, keep their original offset along the seam).
   The sum over both parts divided by the number of points follows eq. 4.8.
3. **Shape error**, rad: mean ``|Δ inner angle|`` at the critical points
   (turn points, marks, notches, extremes), averaged per piece and then over
   the pieces — Kendall's shape: invariant to moving, rotating and uniformly
   scaling a piece. :func:`shape_error_all` (every outline vertex) is
   reported beside it.

Constraint: ``G = 0.05 - fold_margin <= 0``; every grid cell stays a convex
quad with at least 5 % of its original corner cross products (with the cubic
grid map, also the Jacobian determinant sampled inside every cell,
:meth:`~.grid.PatternGrid.fold_margin`), so no piece folds and a simple
outline stays simple.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..pattern.geometry import boundary_indices
from ..pattern.model import Pattern
from .grid import PatternGrid, pattern_darts

__all__ = [
    "Evaluation",
    "ObjectiveData",
    "across_legs",
    "angle_change",
    "balanced_links",
    "chord_lengths",
    "curve_kink",
    "dart_lengths",
    "evaluate",
    "level_slip",
    "link_error",
    "link_lengths",
    "link_shares",
    "measurement_error",
    "objective_data",
    "piece_axes_turn",
    "piece_pose",
    "residuals",
    "seam_error",
    "shape_error",
    "shape_error_all",
]

FOLD_MARGIN = 0.05
"""Smallest allowed cell corner cross product relative to the original."""


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class ObjectiveData:
    """Index arrays and targets of one grading problem (all int64 / float64).

    Points are global outline indices (see :class:`PatternGrid`); ``edge e``
    runs from point ``e`` to point ``nxt[e]`` of the same piece.
    """

    nxt: np.ndarray  # (N,) next vertex in the same piece
    prv: np.ndarray  # (N,) previous vertex
    # measurements
    link_ids: tuple[str, ...]
    link_measurements: tuple[str, ...]
    target_cm: np.ndarray  # (L,)
    at_least: np.ndarray  # (L,) bool: no error when the distance exceeds the target
    link_edges: np.ndarray  # (N, L) factor per boundary edge
    chord_a: np.ndarray  # (C,)
    chord_b: np.ndarray  # (C,)
    chord_across: np.ndarray  # (C, 2) unit vector square to the grain for an "across" leg, else 0
    chord_level0: np.ndarray  # (C,) original rise of each chord along the grain, cm
    link_chords: np.ndarray  # (C, L)
    # seams
    seam_ids: tuple[str, ...]
    seam_labels: tuple[tuple[str, str], ...]
    seam_ease_cm: np.ndarray  # (S,)
    seam_a_edges: np.ndarray  # (N, S) 0/1
    seam_b_edges: np.ndarray  # (N, S)
    sample_i0: np.ndarray  # (Q,) sample = (1-w) P[i0] + w P[i1]
    sample_i1: np.ndarray
    sample_w: np.ndarray
    interval_a: np.ndarray  # (I, 2) consecutive sample indices on side a
    interval_b: np.ndarray  # (I, 2) the corresponding interval on side b
    interval_seam: np.ndarray  # (I,)
    turn_a: np.ndarray  # (T, 3) prev/cur/next sample indices on side a
    turn_b: np.ndarray  # (T, 3) the corresponding triple on side b (pairing order)
    turn_seam: np.ndarray  # (T,)
    turn_sign_b: np.ndarray  # (T,) +1 or -1 (b traversed against its outline)
    turn0: np.ndarray  # (T,) original Δ-reference: θ_a0 - sign·θ_b0
    notch_a: np.ndarray  # (N, M) arc length from seam start (side a) per notch pair
    notch_b: np.ndarray  # (N, M) same on side b, own order
    notch_b_len: np.ndarray  # (N, M) full length of side b when b is reversed, else 0
    notch_b_sign: np.ndarray  # (M,) -1 if b reversed
    notch_offset0: np.ndarray  # (M,)
    notch_seam: np.ndarray  # (M,)
    # shape
    critical: np.ndarray  # (K,) global indices
    darts: np.ndarray  # (D, 3) first rim, point, last rim of every dart (global indices)
    angle0: np.ndarray  # (N,) original inner angles
    piece_of_point: np.ndarray  # (N,) piece index of every point
    points0: np.ndarray  # (N, 2) original outline points
    centre0: np.ndarray  # (P, 2) original piece centroids (vertex mean)
    extent_cm: np.ndarray  # (P,) piece extents
    span_edges: np.ndarray  # (N, B) 0/1: outline edges of each span between consecutive critical points
    span_piece: np.ndarray  # (B,) piece of each span
    span_len0: np.ndarray  # (B,) original span lengths
    span_a: np.ndarray  # (B,) first critical point of each span (global index)
    span_b: np.ndarray  # (B,) last critical point of each span
    # normalisers
    n_seams: int


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class Evaluation:
    """Every figure of a population, arrays with a leading ``n_pop`` axis."""

    achieved_cm: np.ndarray  # (n_pop, L)
    measurement_error: np.ndarray  # (n_pop,)
    seam_mismatch_cm: np.ndarray  # (n_pop, S) L_b - L_a - ease
    seam_edge_cm: np.ndarray  # (n_pop, S)
    seam_angle: np.ndarray  # (n_pop, S)
    notch_cm: np.ndarray  # (n_pop, M) misalignment per notch pair
    seam_error: np.ndarray  # (n_pop,)
    shape_error: np.ndarray  # (n_pop,)
    shape_error_all: np.ndarray  # (n_pop,) mean |Δ angle| over all vertices

    @property
    def F(self) -> np.ndarray:
        """(n_pop, 3) objectives."""
        return np.stack([self.measurement_error, self.seam_error, self.shape_error], axis=1)


def _neighbours(grid: PatternGrid) -> tuple[np.ndarray, np.ndarray]:
    n = grid.n_points
    nxt = np.arange(1, n + 1)
    prv = np.arange(-1, n - 1)
    for a, b in zip(grid.point_offsets[:-1], grid.point_offsets[1:], strict=False):
        nxt[b - 1] = a
        prv[a] = b - 1
    return nxt.astype(np.int64), prv.astype(np.int64)


def _range_points(grid: PatternGrid, piece: str, start: str, end: str, where: str) -> np.ndarray:
    """Global point indices from mark ``start`` to mark ``end`` in outline order."""
    try:
        k = grid.piece_index(piece)
    except KeyError:
        raise InputError(f"{where}: unknown piece {piece!r} (pieces: {[g.name for g in grid.pieces]}); "
                         "fix the pattern's bridge data") from None
    p = grid.pattern.pieces[k]
    for m in (start, end):
        if m not in p.marks:
            raise InputError(f"{where}: piece {piece!r} has no mark {m!r} (marks: {sorted(p.marks)}); "
                             "fix the pattern's bridge data")
    idx = boundary_indices(p.n_vertices, p.marks[start], p.marks[end])
    return grid.point_offsets[k] + idx


def _angles(points: np.ndarray, prv: np.ndarray, nxt: np.ndarray) -> np.ndarray:
    """Inner angle (CCW outlines) at every point, (..., N) radians in (0, 2π)."""
    a = points[..., prv, :] - points
    b = points[..., nxt, :] - points
    cross = b[..., 0] * a[..., 1] - b[..., 1] * a[..., 0]
    dot = np.sum(a * b, axis=-1)
    ang = np.arctan2(cross, dot)
    return np.where(ang < 0, ang + 2 * np.pi, ang)


def _turning(s: np.ndarray, triples: np.ndarray) -> np.ndarray:
    """Signed turning angle at the middle sample of each triple, (..., T)."""
    p, c, n = s[..., triples[:, 0], :], s[..., triples[:, 1], :], s[..., triples[:, 2], :]
    d1 = c - p
    d2 = n - c
    cross = d1[..., 0] * d2[..., 1] - d1[..., 1] * d2[..., 0]
    dot = np.sum(d1 * d2, axis=-1)
    return np.arctan2(cross, dot)


def _arc_samples(points0: np.ndarray, idx: np.ndarray, fractions: np.ndarray):
    """Samples at arc-length ``fractions`` of the polyline ``points0[idx]``.

    Returns ``(i0, i1, w)`` so that sample = (1-w)·P[i0] + w·P[i1].
    """
    poly = points0[idx]
    seg = np.linalg.norm(np.diff(poly, axis=0), axis=1)
    cum = np.concatenate([[0.0], np.cumsum(seg)])
    total = cum[-1]
    s = fractions * total
    k = np.clip(np.searchsorted(cum, s, side="right") - 1, 0, len(seg) - 1)
    w = np.where(seg[k] > 0, (s - cum[k]) / np.where(seg[k] > 0, seg[k], 1.0), 0.0)
    return idx[k], idx[k + 1], np.clip(w, 0.0, 1.0)


def objective_data(
    grid: PatternGrid,
    measurements: Mapping[str, float],
    *,
    n_samples: int = 17,
    source: str = "pattern",
) -> ObjectiveData:
    """Compile the targets and index arrays of grading ``grid.pattern`` to ``measurements``.

    Parameters
    ----------
    grid : the pattern's control grids (:func:`build_grid`)
    measurements : body measurement id -> value in cm
    n_samples : stitch points sampled along each seam (thesis: point pairs)
    source : name used in error messages (file or garment name)

    Raises
    ------
    InputError
        The pattern has no measurement links (with how to add them), or the
        character lacks measurements the links need (listed by name), or the
        bridge data names unknown pieces or marks.
    """
    pattern: Pattern = grid.pattern
    _check_links(pattern, measurements, source)
    nxt, prv = _neighbours(grid)
    points0 = grid.outlines(grid.x0[None, :])[0]
    links = _link_arrays(grid, measurements, points0, nxt, source)
    seams = _seam_arrays(grid, points0, n_samples, source)
    notches = _notch_arrays(grid, source)
    spans = _span_arrays(grid, points0, nxt)
    data = ObjectiveData(
        nxt=nxt, prv=prv,
        span_edges=spans.edges, span_piece=spans.piece, span_len0=spans.len0, span_a=spans.a, span_b=spans.b,
        link_ids=tuple(lk.id for lk in pattern.measurements),
        link_measurements=tuple(lk.measurement for lk in pattern.measurements),
        target_cm=links.target_cm, link_edges=links.link_edges,
        at_least=np.array([lk.at_least for lk in pattern.measurements], dtype=bool),
        chord_a=links.chord_a, chord_b=links.chord_b,
        chord_across=links.chord_across, chord_level0=links.chord_level0,
        link_chords=links.link_chords,
        seam_ids=tuple(s.id for s in pattern.seams), seam_labels=seams.labels,
        seam_ease_cm=np.array([s.ease_cm for s in pattern.seams], dtype=np.float64),
        seam_a_edges=seams.a_edges, seam_b_edges=seams.b_edges,
        sample_i0=seams.sample_i0, sample_i1=seams.sample_i1, sample_w=seams.sample_w,
        interval_a=seams.interval_a, interval_b=seams.interval_b, interval_seam=seams.interval_seam,
        turn_a=seams.turn_a, turn_b=seams.turn_b, turn_seam=seams.turn_seam, turn_sign_b=seams.turn_sign_b,
        turn0=np.zeros(len(seams.turn_seam)),
        notch_a=notches.a, notch_b=notches.b, notch_b_len=notches.b_len,
        notch_b_sign=notches.b_sign, notch_offset0=notches.offset0, notch_seam=notches.seam,
        critical=np.concatenate([grid.point_offsets[k] + g.critical
                                 for k, g in enumerate(grid.pieces)]).astype(np.int64),
        darts=_dart_array(grid), angle0=_angles(points0, prv, nxt), n_seams=len(pattern.seams),
        piece_of_point=np.repeat(np.arange(len(grid.pieces)), np.diff(grid.point_offsets)).astype(np.int64),
        points0=points0,
        centre0=np.stack([points0[a:b].mean(axis=0)
                          for a, b in zip(grid.point_offsets[:-1], grid.point_offsets[1:], strict=True)]),
        extent_cm=np.array([g.extent_cm for g in grid.pieces]),
    )
    _set_design_references(data)
    return data


def _check_links(pattern: Pattern, measurements: Mapping[str, float], source: str) -> None:
    """Raise :class:`InputError` when the pattern has no links or the character lacks a measurement they need."""
    if not pattern.measurements:
        raise InputError(
            f"{source}: the pattern has no landmark-to-measurement mapping (no measurement links); "
            "add them with `patternbridge seams infer PATTERN` or write them into the pattern's "
            "bridge-data sidecar (see docs/library.md), then run fit again"
        )
    missing = sorted({lk.measurement for lk in pattern.measurements} - set(measurements))
    if missing:
        raise InputError(
            f"{source}: the character lacks measurements the garment needs ({', '.join(missing)}); "
            "measure them (patternbridge measure --all) or give them in the measurements JSON"
        )


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class _LinkArrays:
    """The measurement links as arrays (the fields of :class:`ObjectiveData` of the same names)."""

    link_edges: np.ndarray  # (N, L)
    chord_a: np.ndarray  # (C,)
    chord_b: np.ndarray  # (C,)
    chord_across: np.ndarray  # (C, 2)
    chord_level0: np.ndarray  # (C,)
    link_chords: np.ndarray  # (C, L)
    target_cm: np.ndarray  # (L,)


def _link_arrays(grid: PatternGrid, measurements: Mapping[str, float], points0: np.ndarray, nxt: np.ndarray,
                 source: str) -> _LinkArrays:
    """Every link's legs: edge factors for legs along the outline, chords for the straight and across ones."""
    pattern = grid.pattern
    L = len(pattern.measurements)
    link_edges = np.zeros((grid.n_points, L))
    chords: list[tuple[int, int, int, float]] = []
    chord_dirs: list[np.ndarray] = []  # across the grain, or 0 for a plain chord
    for j, link in enumerate(pattern.measurements):
        if not link.legs:
            raise InputError(f"{source}: measurement link {link.id!r} has no legs; give it at least one")
        for leg in link.legs:
            idx = _range_points(grid, leg.piece, leg.start, leg.end, f"{source}: link {link.id!r}")
            if leg.along in ("chord", "across"):
                chords.append((int(idx[0]), int(idx[-1]), j, leg.factor))
                across = pattern.pieces[grid.piece_index(leg.piece)].across_grain
                chord_dirs.append(across if leg.along == "across" else np.zeros(2))
            else:
                np.add.at(link_edges, (idx[:-1], j), leg.factor)
    chord_a = np.array([c[0] for c in chords], dtype=np.int64)
    chord_b = np.array([c[1] for c in chords], dtype=np.int64)
    chord_across = np.array(chord_dirs, dtype=np.float64).reshape(len(chords), 2)
    link_chords = np.zeros((len(chords), L))
    for r, c in enumerate(chords):
        link_chords[r, c[2]] += c[3]
    return _LinkArrays(
        link_edges=link_edges, chord_a=chord_a, chord_b=chord_b, chord_across=chord_across,
        chord_level0=_rise(points0[None], chord_a, chord_b, chord_across)[0], link_chords=link_chords,
        target_cm=_link_targets(pattern, measurements, points0, nxt, link_edges, chord_a, chord_b, chord_across,
                                link_chords, source))


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class _SeamArrays:
    """The seams' edges, stitch samples, intervals and turning triples (:class:`ObjectiveData`'s fields)."""

    labels: tuple[tuple[str, str], ...]
    a_edges: np.ndarray  # (N, S)
    b_edges: np.ndarray  # (N, S)
    sample_i0: np.ndarray  # (Q,)
    sample_i1: np.ndarray  # (Q,)
    sample_w: np.ndarray  # (Q,)
    interval_a: np.ndarray  # (I, 2)
    interval_b: np.ndarray  # (I, 2)
    interval_seam: np.ndarray  # (I,)
    turn_a: np.ndarray  # (T, 3)
    turn_b: np.ndarray  # (T, 3)
    turn_seam: np.ndarray  # (T,)
    turn_sign_b: np.ndarray  # (T,)


def _seam_arrays(grid: PatternGrid, points0: np.ndarray, n_samples: int, source: str) -> _SeamArrays:
    """Both sides of every seam sampled at ``n_samples`` arc-length fractions, paired in sewing order."""
    pattern = grid.pattern
    n, S = grid.n_points, len(pattern.seams)
    a_edges = np.zeros((n, S))
    b_edges = np.zeros((n, S))
    i0s, i1s, ws = [], [], []
    int_a, int_b, int_s = [], [], []
    tr_a, tr_b, tr_s, tr_sign = [], [], [], []
    labels = []
    fractions = np.linspace(0.0, 1.0, n_samples)
    q = 0
    for s_i, seam in enumerate(pattern.seams):
        where = f"{source}: seam {seam.id!r}"
        ia = _range_points(grid, seam.a.piece, seam.a.start, seam.a.end, where)
        ib = _range_points(grid, seam.b.piece, seam.b.start, seam.b.end, where)
        labels.append((f"{seam.a.piece}:{seam.a.start}-{seam.a.end}",
                       f"{seam.b.piece}:{seam.b.start}-{seam.b.end}"))
        np.add.at(a_edges, (ia[:-1], s_i), 1.0)
        np.add.at(b_edges, (ib[:-1], s_i), 1.0)
        a0, a1, aw = _arc_samples(points0, ia, fractions)
        ib_pair = ib[::-1] if seam.reverse else ib
        b0, b1, bw = _arc_samples(points0, ib_pair, fractions)
        base_a = q
        base_b = q + n_samples
        i0s += [a0, b0]
        i1s += [a1, b1]
        ws += [aw, bw]
        q += 2 * n_samples
        ks = np.arange(n_samples - 1)
        int_a.append(np.stack([base_a + ks, base_a + ks + 1], axis=1))
        int_b.append(np.stack([base_b + ks, base_b + ks + 1], axis=1))
        int_s.append(np.full(n_samples - 1, s_i))
        kt = np.arange(1, n_samples - 1)
        tr_a.append(np.stack([base_a + kt - 1, base_a + kt, base_a + kt + 1], axis=1))
        tr_b.append(np.stack([base_b + kt - 1, base_b + kt, base_b + kt + 1], axis=1))
        tr_s.append(np.full(n_samples - 2, s_i))
        # b's turning measured in pairing order is the negative of its own-order turning
        tr_sign.append(np.full(n_samples - 2, -1.0 if seam.reverse else 1.0))
    return _SeamArrays(
        labels=tuple(labels), a_edges=a_edges, b_edges=b_edges,
        sample_i0=(np.concatenate(i0s) if i0s else np.zeros(0, np.int64)).astype(np.int64),
        sample_i1=(np.concatenate(i1s) if i1s else np.zeros(0, np.int64)).astype(np.int64),
        sample_w=np.concatenate(ws) if ws else np.zeros(0),
        interval_a=(np.concatenate(int_a) if int_a else np.zeros((0, 2), np.int64)).astype(np.int64),
        interval_b=(np.concatenate(int_b) if int_b else np.zeros((0, 2), np.int64)).astype(np.int64),
        interval_seam=(np.concatenate(int_s) if int_s else np.zeros(0, np.int64)).astype(np.int64),
        turn_a=(np.concatenate(tr_a) if tr_a else np.zeros((0, 3), np.int64)).astype(np.int64),
        turn_b=(np.concatenate(tr_b) if tr_b else np.zeros((0, 3), np.int64)).astype(np.int64),
        turn_seam=(np.concatenate(tr_s) if tr_s else np.zeros(0, np.int64)).astype(np.int64),
        turn_sign_b=np.concatenate(tr_sign) if tr_sign else np.zeros(0))


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class _NotchArrays:
    """The notch pairs of the seams (:class:`ObjectiveData`'s ``notch_*`` fields)."""

    a: np.ndarray  # (N, M)
    b: np.ndarray  # (N, M)
    b_len: np.ndarray  # (N, M)
    b_sign: np.ndarray  # (M,)
    offset0: np.ndarray  # (M,) zeros until the design's offsets are set
    seam: np.ndarray  # (M,)


def _notch_arrays(grid: PatternGrid, source: str) -> _NotchArrays:
    """Notches strictly inside each side of a seam, paired in sewing order when both sides have as many."""
    pattern = grid.pattern
    n = grid.n_points
    n_a_cols, n_b_cols, nb_len_cols, n_sign, n_off, n_seam = [], [], [], [], [], []
    notch_sets = {}
    for piece in pattern.pieces:
        notch_sets[piece.name] = {int(nt.vertex) for nt in piece.notches}
    for s_i, seam in enumerate(pattern.seams):
        where = f"{source}: seam {seam.id!r}"
        ia = _range_points(grid, seam.a.piece, seam.a.start, seam.a.end, where)
        ib = _range_points(grid, seam.b.piece, seam.b.start, seam.b.end, where)
        pa = grid.pattern.piece(seam.a.piece)
        pb = grid.pattern.piece(seam.b.piece)
        off_a = grid.point_offsets[grid.piece_index(pa.name)]
        off_b = grid.point_offsets[grid.piece_index(pb.name)]
        na = [i for i in ia[1:-1] if (i - off_a) in notch_sets[pa.name]]
        nb = [i for i in ib[1:-1] if (i - off_b) in notch_sets[pb.name]]
        if seam.reverse:
            nb = nb[::-1]
        if na and len(na) == len(nb):
            for va, vb in zip(na, nb, strict=False):
                col_a = np.zeros(n)
                pos_a = int(np.flatnonzero(ia == va)[0])
                col_a[ia[:pos_a]] = 1.0
                col_b = np.zeros(n)
                pos_b = int(np.flatnonzero(ib == vb)[0])
                col_b[ib[:pos_b]] = 1.0
                col_bl = np.zeros(n)
                if seam.reverse:
                    col_bl[ib[:-1]] = 1.0
                n_a_cols.append(col_a)
                n_b_cols.append(col_b)
                nb_len_cols.append(col_bl)
                n_sign.append(-1.0 if seam.reverse else 1.0)
                n_seam.append(s_i)
                n_off.append(0.0)
    M = len(n_seam)
    return _NotchArrays(
        a=np.stack(n_a_cols, axis=1) if M else np.zeros((n, 0)),
        b=np.stack(n_b_cols, axis=1) if M else np.zeros((n, 0)),
        b_len=np.stack(nb_len_cols, axis=1) if M else np.zeros((n, 0)),
        b_sign=np.array(n_sign, dtype=np.float64), offset0=np.array(n_off, dtype=np.float64),
        seam=np.array(n_seam, dtype=np.int64))


def _dart_array(grid: PatternGrid) -> np.ndarray:
    """(D, 3) int64: first rim, point, last rim of every dart, global indices."""
    dart_idx = [grid.point_offsets[grid.piece_index(name)] + np.array(t)
                for name, triples in pattern_darts(grid.pattern).items() for t in triples]
    return np.array(dart_idx, dtype=np.int64).reshape(-1, 3)


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class _SpanArrays:
    """The spans between consecutive critical points (:class:`ObjectiveData`'s ``span_*`` fields)."""

    edges: np.ndarray  # (N, B)
    piece: np.ndarray  # (B,)
    len0: np.ndarray  # (B,)
    a: np.ndarray  # (B,)
    b: np.ndarray  # (B,)


def _span_arrays(grid: PatternGrid, points0: np.ndarray, nxt: np.ndarray) -> _SpanArrays:
    """Every span between consecutive critical points of a piece: its outline edges, ends and length."""
    n = grid.n_points
    spans, span_piece, span_a, span_b = [], [], [], []
    for k, g in enumerate(grid.pieces):
        crit_k = np.asarray(g.critical)
        n_k = len(g.outline_weights)
        for a, b in zip(crit_k, np.roll(crit_k, -1), strict=False):
            col = np.zeros(n)
            col[grid.point_offsets[k] + boundary_indices(n_k, int(a), int(b))[:-1]] = 1.0
            spans.append(col)
            span_piece.append(k)
            span_a.append(grid.point_offsets[k] + int(a))
            span_b.append(grid.point_offsets[k] + int(b))
    span_edges = np.stack(spans, axis=1)
    edge_len0 = np.linalg.norm(points0[nxt] - points0, axis=1)
    return _SpanArrays(edges=span_edges, piece=np.array(span_piece, dtype=np.int64), len0=edge_len0 @ span_edges,
                       a=np.array(span_a, dtype=np.int64), b=np.array(span_b, dtype=np.int64))


def _set_design_references(data: ObjectiveData) -> None:
    """Set the original design's turning-angle relation and notch offsets on the freshly built ``data``."""
    p0 = data.points0[None, :, :]
    samples = _samples(data, p0)
    ta = _turning(samples, data.turn_a)[0]
    tb = _turning(samples, data.turn_b)[0] * data.turn_sign_b
    edge0 = _edge_lengths(data, p0)
    pos_a, pos_b = _notch_positions(data, edge0)
    object.__setattr__(data, "turn0", ta - tb)
    object.__setattr__(data, "notch_offset0", (pos_b - pos_a)[0])


def _link_targets(pattern, measurements, points0, nxt, link_edges, chord_a, chord_b, chord_across, link_chords,
                  source) -> np.ndarray:
    """(L,) target of every link, cm: body + ease, or for a proportional link ``L₀ · body / (L₀ − ease)``.

    ``L₀`` is the link's distance in the sample size and ``L₀ − ease`` the
    sample body's measurement (the library writes the ease the sample
    realises), so a proportional link keeps the design's ratio of the
    distance to the body measurement it follows.
    """
    links = pattern.measurements
    body = np.array([float(measurements[lk.measurement]) for lk in links])
    ease = np.array([lk.ease_cm for lk in links], dtype=np.float64)
    target = body + ease
    prop = np.array([lk.proportional for lk in links], dtype=bool)
    if not prop.any():
        return target
    v = points0[chord_b] - points0[chord_a]
    across = np.any(chord_across != 0.0, axis=1)
    chord0 = np.where(across, np.abs(np.sum(v * chord_across, axis=1)), np.linalg.norm(v, axis=1))
    length0 = np.linalg.norm(points0[nxt] - points0, axis=1) @ link_edges + chord0 @ link_chords
    sample_body = length0 - ease
    bad = prop & (sample_body <= 0.0)
    if bad.any():
        names = [lk.id for lk, b in zip(links, bad, strict=True) if b]
        raise InputError(f"{source}: proportional links {names} have an ease not below their sample distance "
                         f"(sample body measurement <= 0); fix their ease_cm in the bridge data")
    return np.where(prop, length0 * body / np.where(prop, sample_body, 1.0), target)


def _edge_lengths(data: ObjectiveData, points: np.ndarray) -> np.ndarray:
    return np.linalg.norm(points[:, data.nxt, :] - points, axis=-1)


def _samples(data: ObjectiveData, points: np.ndarray) -> np.ndarray:
    w = data.sample_w[None, :, None]
    return (1 - w) * points[:, data.sample_i0, :] + w * points[:, data.sample_i1, :]


def _notch_positions(data: ObjectiveData, edges: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    pos_a = edges @ data.notch_a
    pos_b = edges @ data.notch_b
    lb = edges @ data.notch_b_len
    pos_b = np.where(data.notch_b_sign < 0, lb - pos_b, pos_b)
    return pos_a, pos_b


def measurement_error(data: ObjectiveData, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Achieved pattern distances and the mean absolute error.

    Parameters
    ----------
    points : (n_pop, N, 2) float64, cm

    Returns
    -------
    achieved : (n_pop, L) float64, cm
    error : (n_pop,) float64, cm — mean over links of ``|link_error|`` plus
        ``factor · |level_slip|`` of their legs taken across the grain
    """
    edges = _edge_lengths(data, points)
    achieved = link_lengths(data, points, edges)
    slip = 0.0
    if len(data.chord_a):
        slip = np.abs(level_slip(data, points)) @ np.abs(data.link_chords)
    return achieved, np.mean(np.abs(link_error(data, achieved)) + slip, axis=1)


def link_lengths(data: ObjectiveData, points: np.ndarray, edges: np.ndarray) -> np.ndarray:
    """Achieved distance of every measurement link, ``(n_pop, L)`` cm.

    ``edges`` are the outline edge lengths ``(n_pop, N)`` of ``points``
    (computed once by the caller when it needs them for other terms too).
    """
    achieved = edges @ data.link_edges
    if len(data.chord_a):
        achieved = achieved + chord_lengths(data, points) @ data.link_chords
    return achieved


def across_legs(data: ObjectiveData) -> np.ndarray:
    """(C,) bool: the chord legs taken across the grain."""
    return np.any(data.chord_across != 0.0, axis=1)


def _rise(points: np.ndarray, a: np.ndarray, b: np.ndarray, across: np.ndarray) -> np.ndarray:
    """(n_pop, C) rise of each chord ``a → b`` along the grain (``across`` turned a quarter back), cm."""
    grain = np.stack([-across[:, 1], across[:, 0]], axis=1)
    return np.einsum("pcj,cj->pc", points[:, b, :] - points[:, a, :], grain)


def level_slip(data: ObjectiveData, points: np.ndarray) -> np.ndarray:
    """How far each chord's end has moved along the grain against its start, ``(n_pop, C)`` cm.

    0 for plain chords: only legs taken across the grain keep their level.
    """
    rise = _rise(points, data.chord_a, data.chord_b, data.chord_across)
    return np.where(across_legs(data), rise - data.chord_level0, 0.0)


def chord_lengths(data: ObjectiveData, points: np.ndarray) -> np.ndarray:
    """Length of every chord leg, ``(n_pop, C)`` cm: straight, or its span across the grain."""
    v = points[:, data.chord_b, :] - points[:, data.chord_a, :]
    across = np.abs(np.einsum("pcj,cj->pc", v, data.chord_across))
    return np.where(across_legs(data), across, np.linalg.norm(v, axis=-1))


def link_error(data: ObjectiveData, achieved: np.ndarray) -> np.ndarray:
    """Signed ``achieved - target`` per link, 0 where an ``at_least`` link is exceeded.

    ``achieved`` is ``(..., L)`` cm; the result has its shape.
    """
    e = np.asarray(achieved, dtype=np.float64) - data.target_cm
    return np.where(data.at_least & (e > 0.0), 0.0, e)


def dart_lengths(data: ObjectiveData, points: np.ndarray) -> np.ndarray:
    """Length of every dart, the mean of its two legs (rim to point), ``(n_pop, D)`` cm."""
    if not len(data.darts):
        return np.zeros((points.shape[0], 0))
    a, x, b = data.darts.T
    la = np.linalg.norm(points[:, x, :] - points[:, a, :], axis=-1)
    lb = np.linalg.norm(points[:, b, :] - points[:, x, :], axis=-1)
    return 0.5 * (la + lb)


def balanced_links(data: ObjectiveData) -> np.ndarray:
    """(L,) bool: links over two or more pieces whose legs all add (a girth over a front and a back).

    A link with a negative leg (a band's length taken as its edge minus the
    opening it runs along) is a difference, not a sum: its parts are no
    shares of it.
    """
    _, shared = link_shares(data, data.points0[None])
    positive = ~np.any(data.link_edges < 0, axis=0)
    if len(data.chord_a):
        positive &= ~np.any(data.link_chords < 0, axis=0)
    return shared & positive


def link_shares(data: ObjectiveData, points: np.ndarray,
                edges: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Each piece's share of every measurement link.

    A girth measured over a front and a back, or an arm length over a sleeve
    and a cuff, fixes the total; how it is split between the pieces is the
    design's. The share of piece ``p`` in link ``l`` is the part of the
    achieved value the legs on ``p`` contribute, divided by the whole.

    Parameters
    ----------
    points : (n_pop, N, 2) float64, cm
    edges : (n_pop, N) outline edge lengths of ``points`` when the caller
        has them, else computed

    Returns
    -------
    shares : (n_pop, P, L) float64 — zero where a link has no leg on a piece
    shared : (L,) bool — links with legs on two or more pieces (the ones
        whose split the fit leaves free)
    """
    n_pop = points.shape[0]
    P, L = len(data.centre0), len(data.target_cm)
    edges = _edge_lengths(data, points) if edges is None else edges
    part = np.zeros((n_pop, P, L))
    on_piece = np.zeros((P, L), dtype=bool)
    for p in range(P):
        mask = data.piece_of_point == p
        part[:, p] = edges[:, mask] @ data.link_edges[mask]
        on_piece[p] |= np.any(data.link_edges[mask] != 0, axis=0)
    if len(data.chord_a):
        chord = chord_lengths(data, points)
        cp = data.piece_of_point[data.chord_a]
        for p in range(P):
            mask = cp == p
            part[:, p] += chord[:, mask] @ data.link_chords[mask]
            on_piece[p] |= np.any(data.link_chords[mask] != 0, axis=0)
    total = part.sum(axis=1, keepdims=True)
    shares = part / np.where(np.abs(total) > 1e-12, total, 1.0)
    return shares, on_piece.sum(axis=0) >= 2


def _seam_terms(data: ObjectiveData, points: np.ndarray, edges: np.ndarray):
    S = data.n_seams
    mismatch = edges @ data.seam_b_edges - edges @ data.seam_a_edges - data.seam_ease_cm
    samples = _samples(data, points)
    la = np.linalg.norm(samples[:, data.interval_a[:, 1]] - samples[:, data.interval_a[:, 0]], axis=-1)
    lb = np.linalg.norm(samples[:, data.interval_b[:, 1]] - samples[:, data.interval_b[:, 0]], axis=-1)
    counts_i = np.maximum(np.bincount(data.interval_seam, minlength=S), 1)
    ease_i = data.seam_ease_cm[data.interval_seam] / counts_i[data.interval_seam]
    edge_dev = lb - la - ease_i
    ta = _turning(samples, data.turn_a)
    tb = _turning(samples, data.turn_b) * data.turn_sign_b
    ang_dev = (ta - tb) - data.turn0
    ang_dev = (ang_dev + np.pi) % (2 * np.pi) - np.pi
    pos_a, pos_b = _notch_positions(data, edges)
    notch = (pos_b - pos_a) - data.notch_offset0
    return mismatch, edge_dev, ang_dev, notch, counts_i


def _per_seam(values: np.ndarray, seam: np.ndarray, S: int) -> np.ndarray:
    """Sum (n_pop, K) values into (n_pop, S) by seam index."""
    out = np.zeros((values.shape[0], S))
    if values.shape[1]:
        np.add.at(out.T, seam, values.T)
    return out


def seam_error(data: ObjectiveData, points: np.ndarray) -> dict[str, np.ndarray]:
    """Seam figures of every individual (see the module docstring).

    Returns
    -------
    dict with ``mismatch_cm (n_pop, S)``, ``edge_cm (n_pop, S)``,
    ``angle (n_pop, S)``, ``notch_cm (n_pop, M)`` and ``error (n_pop,)``.
    """
    S = data.n_seams
    n_pop = len(points)
    if S == 0:
        z = np.zeros((n_pop, 0))
        return {"mismatch_cm": z, "edge_cm": z, "angle": z, "notch_cm": z, "error": np.zeros(n_pop)}
    edges = _edge_lengths(data, points)
    mismatch, edge_dev, ang_dev, notch, counts_i = _seam_terms(data, points, edges)
    edge_cm = _per_seam(np.abs(edge_dev), data.interval_seam, S) / counts_i
    counts_t = np.maximum(np.bincount(data.turn_seam, minlength=S), 1)
    angle = _per_seam(np.abs(ang_dev), data.turn_seam, S) / counts_t
    counts_n = np.bincount(data.notch_seam, minlength=S)
    notch_s = _per_seam(np.abs(notch), data.notch_seam, S) / np.maximum(counts_n, 1)
    per_seam = np.abs(mismatch) + edge_cm + angle + notch_s
    return {"mismatch_cm": mismatch, "edge_cm": edge_cm, "angle": angle, "notch_cm": notch,
            "error": per_seam.mean(axis=1)}


def angle_change(data: ObjectiveData, points: np.ndarray) -> np.ndarray:
    """Signed inner-angle change at every outline vertex, ``(n_pop, N)`` rad in [-π, π)."""
    d = _angles(points, data.prv, data.nxt) - data.angle0
    return (d + np.pi) % (2 * np.pi) - np.pi


def shape_error(data: ObjectiveData, points: np.ndarray) -> np.ndarray:
    """(n_pop,) mean ``|Δ inner angle|`` at the critical points, averaged per piece (rad).

    Each piece's critical points are averaged first and the pieces weigh the
    same, so a piece with many marks (a shirt front) does not outweigh a
    small one (a cuff), and the figure does not depend on how finely the
    curves between critical points are sampled.
    """
    d = np.abs(angle_change(data, points))[:, data.critical]
    P = len(data.centre0)
    piece = data.piece_of_point[data.critical]
    counts = np.bincount(piece, minlength=P).astype(np.float64)
    sums = np.zeros((len(points), P))
    np.add.at(sums.T, piece, d.T)
    has = counts > 0
    return (sums[:, has] / counts[has]).mean(axis=1)


def shape_error_all(data: ObjectiveData, points: np.ndarray) -> np.ndarray:
    """(n_pop,) mean ``|Δ inner angle|`` over every outline vertex (rad; a secondary figure)."""
    return np.abs(angle_change(data, points)).mean(axis=1)


def curve_kink(data: ObjectiveData, points: np.ndarray) -> np.ndarray:
    """(n_pop,) largest ``|Δ inner angle|`` at an outline vertex that is no critical point, rad.

    Those vertices sample the design's curves and straight runs, so a large
    change at one of them is a point the graded pattern added: the kink a
    tailor sees at once (a secondary figure; the all-vertex mean of
    :func:`shape_error_all` spreads it over the whole outline).
    """
    d = np.abs(angle_change(data, points))
    plain = np.ones(d.shape[1], dtype=bool)
    plain[data.critical] = False
    return d[:, plain].max(axis=1, initial=0.0)


def evaluate(data: ObjectiveData, points: np.ndarray) -> Evaluation:
    """All objectives of a population, ``points (n_pop, N, 2)``."""
    points = np.asarray(points, dtype=np.float64)
    achieved, m_err = measurement_error(data, points)
    seams = seam_error(data, points)
    return Evaluation(
        achieved_cm=achieved, measurement_error=m_err,
        seam_mismatch_cm=seams["mismatch_cm"], seam_edge_cm=seams["edge_cm"],
        seam_angle=seams["angle"], notch_cm=seams["notch_cm"], seam_error=seams["error"],
        shape_error=shape_error(data, points),
        shape_error_all=shape_error_all(data, points),
    )


def piece_pose(data: ObjectiveData, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Rotation (rad) and centroid shift (cm) of every piece against the original.

    The rotation is the least-squares (Procrustes) angle between the
    centred original and current outline vertices.

    Returns
    -------
    rotation : (n_pop, P) ; shift : (n_pop, P, 2)
    """
    P = len(data.centre0)
    counts = np.bincount(data.piece_of_point, minlength=P).astype(np.float64)
    sums = np.zeros((points.shape[0], P, 2))
    np.add.at(sums.transpose(1, 0, 2), data.piece_of_point, points.transpose(1, 0, 2))
    centre = sums / counts[None, :, None]
    q = points - centre[:, data.piece_of_point, :]
    q0 = data.points0 - data.centre0[data.piece_of_point]
    cross = q0[None, :, 0] * q[..., 1] - q0[None, :, 1] * q[..., 0]
    dot = q0[None, :, 0] * q[..., 0] + q0[None, :, 1] * q[..., 1]
    cs = np.zeros((points.shape[0], P))
    ds = np.zeros((points.shape[0], P))
    np.add.at(cs.T, data.piece_of_point, cross.T)
    np.add.at(ds.T, data.piece_of_point, dot.T)
    return np.arctan2(cs, ds), centre - data.centre0[None]


def piece_axes_turn(data: ObjectiveData, points: np.ndarray) -> np.ndarray:
    """Turn of every piece's drawing axes under its best-fit linear map, ``(n_pop, P, 2)`` rad.

    The least-squares 2×2 map ``M`` taking the centred original vertices of a
    piece to its centred current ones; ``[..., 0]`` is the turn of the x axis
    (``atan2(M10, M00)``), ``[..., 1]`` that of the y axis
    (``atan2(-M01, M11)``). Per-axis scaling, what grading does along and
    across the grain, turns neither; a rotation turns both alike; a shear (a
    band slanted into a parallelogram, its ends running down its length)
    turns one. Linear in the points for a fixed piece, vectorised over the
    population.
    """
    points = np.asarray(points, dtype=np.float64)
    P = len(data.centre0)
    counts = np.bincount(data.piece_of_point, minlength=P).astype(np.float64)
    sums = np.zeros((points.shape[0], P, 2))
    np.add.at(sums.transpose(1, 0, 2), data.piece_of_point, points.transpose(1, 0, 2))
    q = points - (sums / counts[None, :, None])[:, data.piece_of_point, :]
    q0 = data.points0 - data.centre0[data.piece_of_point]
    # M = (Σ q q0ᵀ)(Σ q0 q0ᵀ)⁻¹ per piece
    qq0 = np.zeros((points.shape[0], P, 2, 2))
    outer = q[..., :, None] * q0[None, :, None, :]  # (n_pop, N, 2, 2)
    np.add.at(qq0.transpose(1, 0, 2, 3), data.piece_of_point, outer.transpose(1, 0, 2, 3))
    g = np.zeros((P, 2, 2))
    np.add.at(g, data.piece_of_point, q0[:, :, None] * q0[:, None, :])
    m = qq0 @ np.linalg.inv(g + 1e-12 * np.eye(2))[None]
    return np.stack([np.arctan2(m[..., 1, 0], m[..., 0, 0]), np.arctan2(-m[..., 0, 1], m[..., 1, 1])], axis=-1)


def _slack(r: np.ndarray, slack: float) -> np.ndarray:
    """Residual with a dead zone: 0 within ``±slack``, linear beyond it."""
    if slack <= 0:
        return r
    return np.sign(r) * np.maximum(np.abs(r) - slack, 0.0)


def residuals(
    data: ObjectiveData,
    points: np.ndarray,
    *,
    w_measure: float = 1.0,
    w_seam: float = 8.0,
    w_interval: float = 1.0,
    w_notch: float = 4.0,
    w_turn: float = 0.3,
    w_critical: float = 10.0,
    w_angle: float = 4.0,
    w_rotation: float = 3.0,
    w_shift: float = 0.05,
    w_proportion: float = 0.5,
    w_direction: float = 4.0,
    measure_slack_cm: float = 0.0,
    seam_slack_cm: float = 0.0,
) -> np.ndarray:
    """Weighted residual vector of every individual, ``(n_pop, n_res)``.

    ``measure_slack_cm`` and ``seam_slack_cm`` are dead zones: errors within
    them cost nothing, so the shape terms may use the tolerance the fit
    allows. The least-squares form of the three objectives used by the repair step
    (:func:`patternbridge.grade.repair.repair`): measurement residuals (cm), seam
    length mismatches and notch offsets (cm, weighted up so they close to well
    under 1 mm), stitch-interval differences (cm), turning-angle disagreement
    along seams (rad), and inner-angle changes at critical points and at all
    vertices (rad, scaled by the piece count so the shape term does not grow
    with resolution), the change of proportions between the spans joining
    consecutive critical points (weak), the change of direction of those
    spans relative to the piece (keeps straight edges such as the centre
    front where they were), each piece's rotation (a graded piece keeps its
    orientation to the grain) and, weakly, its centroid shift.
    """
    points = np.asarray(points, dtype=np.float64)
    achieved, _ = measurement_error(data, points)
    parts = [w_measure * _slack(link_error(data, achieved), measure_slack_cm)]
    level = across_legs(data)
    if level.any():
        parts.append(w_measure * level_slip(data, points)[:, level])
    if data.n_seams and (w_seam or w_interval or w_notch or w_turn):  # all zero: no seam columns
        edges = _edge_lengths(data, points)
        mismatch, edge_dev, ang_dev, notch, _ = _seam_terms(data, points, edges)
        mismatch = _slack(mismatch, seam_slack_cm)
        notch = _slack(notch, seam_slack_cm)
        parts += [w_seam * mismatch, w_interval * edge_dev, w_notch * notch, w_turn * ang_dev]
    d = _angles(points, data.prv, data.nxt) - data.angle0
    d = (d + np.pi) % (2 * np.pi) - np.pi
    n_all = d.shape[1]
    parts.append(w_critical * d[:, data.critical] / np.sqrt(max(len(data.critical), 1) / 10.0))
    parts.append(w_angle * d / np.sqrt(n_all / 10.0))
    # proportions: each span between critical points keeps its share of the
    # piece's growth (log length ratio minus the piece's mean log ratio)
    edges = np.linalg.norm(points[:, data.nxt, :] - points, axis=-1)
    ratio = np.log(np.maximum(edges @ data.span_edges, 1e-9) / np.maximum(data.span_len0, 1e-9))
    P = len(data.centre0)
    counts = np.maximum(np.bincount(data.span_piece, minlength=P), 1)
    mean = np.zeros((len(points), P))
    np.add.at(mean.T, data.span_piece, ratio.T)
    mean /= counts
    parts.append(w_proportion * (ratio - mean[:, data.span_piece]) / np.sqrt(max(ratio.shape[1], 1) / 10.0))
    rotation, shift = piece_pose(data, points)
    # direction of each span's chord, relative to the piece's rotation: keeps
    # straight lines (centre front, hems, grain-parallel edges) where they were
    c0 = data.points0[data.span_b] - data.points0[data.span_a]
    c = points[:, data.span_b, :] - points[:, data.span_a, :]
    turn = np.arctan2(c0[None, :, 0] * c[..., 1] - c0[None, :, 1] * c[..., 0],
                      c0[None, :, 0] * c[..., 0] + c0[None, :, 1] * c[..., 1])
    turn = (turn - rotation[:, data.span_piece] + np.pi) % (2 * np.pi) - np.pi
    parts.append(w_direction * turn / np.sqrt(max(turn.shape[1], 1) / 10.0))
    parts.append(w_rotation * rotation)
    parts.append(w_shift * (shift / data.extent_cm[None, :, None]).reshape(len(points), -1))
    return np.concatenate(parts, axis=1)

