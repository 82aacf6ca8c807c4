"""Seam checks and pattern distances on the sew line, in every graded size.

Lengths are measured on a piece's **sew line**: its first closed sew line
(layer 14) when that has one vertex per outline vertex (the library
convention: marks index both lines), else the outline itself (a net pattern).

:func:`check_seams` verifies that every seam's two ranges have equal sew-line
length (or differ by the seam's declared ease) within a tolerance in every
size, and that the notches inside the two ranges line up.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from ..pattern.geometry import arc_lengths, boundary_indices
from ..pattern.grading import piece_displacements
from ..pattern.model import Leg, Pattern, Piece

__all__ = [
    "SeamResult",
    "check_seams",
    "graded_sew_lines",
    "leg_lengths",
    "link_lengths",
    "range_indices",
    "sew_line",
]

SEAM_TOL_CM = 0.1
NOTCH_TOL_CM = 0.15


def _sew_line_index(piece: Piece) -> int | None:
    """Index in ``piece.sew_lines`` of the line seams are measured on (None: the outline)."""
    for i, line in enumerate(piece.sew_lines):
        if line.closed and len(line.points) == piece.n_vertices:
            return i
    return None


def sew_line(piece: Piece) -> tuple[np.ndarray, tuple[str | None, ...]]:
    """``(points (n, 2) cm, rules)`` of the line seams are measured on.

    The first closed sew line with as many vertices as the outline, else the
    outline.
    """
    i = _sew_line_index(piece)
    if i is None:
        return piece.outline, piece.rules
    return piece.sew_lines[i].points, piece.sew_lines[i].rules


def graded_sew_lines(pattern: Pattern) -> dict[str, np.ndarray]:
    """Sew line of every piece in every size: name -> (n_sizes, n, 2) cm.

    Sizes follow ``pattern.rules.sizes`` (one row, the sample, when the
    pattern has no grade rules). Every size is graded as
    :func:`patternbridge.pattern.grading.grade` grades it: rule points move by
    their rule (in the grade reference frame) and the points between rule
    points follow by arc length, so a seam measured here has the length the
    graded piece has.
    """
    table = pattern.rules
    out = {}
    for piece in pattern.pieces:
        pts, _ = sew_line(piece)
        if not table.sizes:
            out[piece.name] = pts[None, :, :].copy()
            continue
        disp = piece_displacements(piece, table)
        i = _sew_line_index(piece)
        out[piece.name] = pts[None, :, :] + (
            disp["outline"] if i is None else disp["sew_lines"][i]
        )
    return out


def range_indices(piece: Piece, start: str, end: str) -> np.ndarray:
    """Vertex indices of the boundary from mark ``start`` to mark ``end`` (outline order)."""
    return boundary_indices(piece.n_vertices, piece.mark(start), piece.mark(end))


def _leg_length(lines: np.ndarray, piece: Piece, g: Leg) -> np.ndarray:
    if g.along != "boundary":
        d = lines[:, piece.mark(g.end)] - lines[:, piece.mark(g.start)]
        return np.abs(d @ piece.across_grain) if g.along == "across" else np.linalg.norm(d, axis=-1)
    idx = range_indices(piece, g.start, g.end)
    seg = np.diff(lines[:, idx], axis=1)
    return np.linalg.norm(seg, axis=-1).sum(axis=-1)


def leg_lengths(
    pattern: Pattern, legs, lines: Mapping[str, np.ndarray] | None = None
) -> np.ndarray:
    """Σ factor·length of ``legs`` in every size, (n_sizes,) cm."""
    lines = graded_sew_lines(pattern) if lines is None else lines
    total = 0.0
    for g in legs:
        total = total + g.factor * _leg_length(
            lines[g.piece], pattern.piece(g.piece), g
        )
    return np.asarray(total, dtype=np.float64)


def link_lengths(pattern: Pattern) -> dict[str, np.ndarray]:
    """Achieved pattern distance of every measurement link: id -> (n_sizes,) cm."""
    lines = graded_sew_lines(pattern)
    return {m.id: leg_lengths(pattern, m.legs, lines) for m in pattern.measurements}


@dataclass(frozen=True, slots=True, kw_only=True)
class SeamResult:
    """Outcome of one seam in one size.

    length_a_cm, length_b_cm : sew-line lengths of the two ranges
    mismatch_cm : ``length_b - length_a - ease_cm`` (0 for a perfect seam)
    notch_error_cm : worst notch misalignment (NaN when the notch counts differ)
    problems : human-readable reasons it failed (empty when ``ok``)
    """

    seam: str
    size: str
    length_a_cm: float
    length_b_cm: float
    ease_cm: float
    mismatch_cm: float
    notch_error_cm: float
    problems: tuple[str, ...] = ()

    @property
    def ok(self) -> bool:
        return not self.problems


def _notch_positions(piece: Piece, idx: np.ndarray, line: np.ndarray) -> np.ndarray:
    """Arc length (cm) of the notches strictly inside the range, in range order."""
    notch_vertices = {n.vertex for n in piece.notches}
    cum = arc_lengths(line[idx])
    return np.array(
        [cum[k] for k in range(1, len(idx) - 1) if int(idx[k]) in notch_vertices]
    )


def check_seams(
    pattern: Pattern,
    *,
    tol_cm: float = SEAM_TOL_CM,
    notch_tol_cm: float = NOTCH_TOL_CM,
) -> list[SeamResult]:
    """Check every seam in every size.

    A seam passes when ``|length_b − length_a − ease_cm| <= tol_cm`` and the
    notches strictly inside its two ranges are equally many and sit at the
    same fraction of the seam (``b`` read backwards when ``reverse``) within
    ``notch_tol_cm``. Fold seams are checked the same way.

    Returns
    -------
    list of :class:`SeamResult`, seam-major, one per size.
    """
    lines = graded_sew_lines(pattern)
    sizes = pattern.rules.sizes or (pattern.sample_size,)
    results = []
    for s in pattern.seams:
        pa, pb = pattern.piece(s.a.piece), pattern.piece(s.b.piece)
        ia, ib = (
            range_indices(pa, s.a.start, s.a.end),
            range_indices(pb, s.b.start, s.b.end),
        )
        for k, size in enumerate(sizes):
            la_pts, lb_pts = lines[pa.name][k], lines[pb.name][k]
            len_a = float(np.linalg.norm(np.diff(la_pts[ia], axis=0), axis=1).sum())
            len_b = float(np.linalg.norm(np.diff(lb_pts[ib], axis=0), axis=1).sum())
            mismatch = len_b - len_a - s.ease_cm
            problems = []
            if abs(mismatch) > tol_cm:
                problems.append(
                    f"length {len_a:.2f} vs {len_b:.2f} cm (ease {s.ease_cm:g}): "
                    f"off by {mismatch * 10:+.1f} mm"
                )
            na = _notch_positions(pa, ia, la_pts)
            nb = _notch_positions(pb, ib, lb_pts)
            if s.reverse:
                nb = (len_b - nb)[::-1]
            if len(na) != len(nb):
                notch_err = float("nan")
                problems.append(
                    f"{len(na)} notch(es) on {s.a.piece} but {len(nb)} on {s.b.piece}"
                )
            elif len(na):
                expected = na * (len_b / max(len_a, 1e-12))
                notch_err = float(np.max(np.abs(nb - expected)))
                if notch_err > notch_tol_cm:
                    problems.append(f"notches off by {notch_err * 10:.1f} mm")
            else:
                notch_err = 0.0
            results.append(
                SeamResult(
                    seam=s.id,
                    size=size,
                    length_a_cm=len_a,
                    length_b_cm=len_b,
                    ease_cm=s.ease_cm,
                    mismatch_cm=mismatch,
                    notch_error_cm=notch_err,
                    problems=tuple(problems),
                )
            )
    return results
