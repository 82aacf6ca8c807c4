"""Boundary stretches of every piece, measured on the sew line in every graded size.

A piece's sew line is cut at its turn points, its notches and at corners
sharper than ``CORNER_DEG`` (files that mark no turn points); the pieces
between two cuts are *stretches*. A candidate seam side is a *run* of one or
more consecutive stretches that turns no corner sharper than ``RUN_CORNER_DEG``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..library.seams import graded_sew_lines, sew_line
from ..pattern.geometry import interior_angles
from ..pattern.model import Pattern, Piece, VertexKind

__all__ = ["Run", "corner_vertices", "piece_runs", "runs", "turning"]

CORNER_DEG = 30.0
RUN_CORNER_DEG = 35.0
MAX_RUN = 6


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class Run:
    """Consecutive stretches ``start`` → ``end`` of one piece (outline order).

    graded_cm : (n_sizes,) sew-line length in every graded size
    notch_fracs : arc-length fractions of the notches strictly inside
    break_fracs : the same for every break inside (notches and turn points)
    bend_rad : total signed turning along the run (positive: convex, CCW outline)
    chord_cm : straight distance between the two ends (sample size)
    parts : indices of the elementary stretches it covers (piece-local)
    """

    piece: str
    start: int
    end: int
    length_cm: float
    graded_cm: np.ndarray
    notch_fracs: tuple[float, ...]
    bend_rad: float
    chord_cm: float
    parts: tuple[int, ...]
    break_fracs: tuple[float, ...] = ()

    def __post_init__(self) -> None:
        graded = np.array(self.graded_cm, dtype=np.float64).reshape(-1)
        graded.flags.writeable = False
        object.__setattr__(self, "graded_cm", graded)

    @property
    def straightness(self) -> float:
        return self.chord_cm / max(self.length_cm, 1e-9)

    @property
    def key(self) -> tuple[str, int, int]:
        return (self.piece, self.start, self.end)


def _indices(n: int, s: int, e: int) -> np.ndarray:
    return np.arange(s, e + 1) if e > s else np.r_[s:n, 0 : e + 1]


def turning(points: np.ndarray) -> np.ndarray:
    """Signed turning angle at every vertex of a closed CCW line, (n,) radians (left turn > 0)."""
    return np.pi - interior_angles(points)


def breaks(piece: Piece) -> np.ndarray:
    """Sorted vertex indices where the piece's boundary is cut into stretches."""
    pts, _ = sew_line(piece)
    n = len(pts)
    brk = np.zeros(n, dtype=bool)
    if piece.kinds is not None:
        brk |= np.array([k == VertexKind.TURN for k in piece.kinds])
    for notch in piece.notches:
        brk[notch.vertex] = True
    brk |= np.abs(turning(pts)) > np.radians(CORNER_DEG)
    return np.nonzero(brk)[0]


def corner_vertices(pattern: Pattern) -> set[tuple[str, int]]:
    """(piece, vertex) of every corner sharper than ``RUN_CORNER_DEG``: no run, and no merged seam, turns one."""
    out = set()
    for piece in pattern.pieces:
        turn = turning(sew_line(piece)[0])
        out |= {(piece.name, int(v)) for v in np.nonzero(np.abs(turn) > np.radians(RUN_CORNER_DEG))[0]}
    return out


def piece_runs(piece: Piece, graded: np.ndarray, *, max_run: int = MAX_RUN) -> list[Run]:
    """Runs of 1..``max_run`` consecutive stretches of one piece.

    graded : (n_sizes, n, 2) the piece's sew line in every size
    """
    pts = graded[0] if len(graded) == 1 else sew_line(piece)[0]
    n = len(pts)
    brk = breaks(piece)
    m = len(brk)
    if m < 2:
        return []
    turn = turning(pts)
    sharp = np.abs(turn) > np.radians(RUN_CORNER_DEG)
    notch_vertices = {nt.vertex for nt in piece.notches}
    brk_set = {int(b) for b in brk}
    seg_len = np.linalg.norm(np.roll(graded, -1, axis=1) - graded, axis=-1)  # (S, n)
    out = []
    for i in range(m):
        for run in range(1, min(max_run, m - 1) + 1):
            inner = [brk[(i + k) % m] for k in range(1, run)]
            if inner and sharp[inner].any():
                break
            s, e = int(brk[i]), int(brk[(i + run) % m])
            idx = _indices(n, s, e)
            graded_len = seg_len[:, idx[:-1]].sum(axis=1)
            cum = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(pts[idx], axis=0), axis=1))])
            length = float(cum[-1])
            if length < 1e-6:
                continue
            fracs = tuple(float(cum[k] / length) for k in range(1, len(idx) - 1) if int(idx[k]) in notch_vertices)
            out.append(
                Run(
                    piece=piece.name,
                    start=s,
                    end=e,
                    length_cm=length,
                    graded_cm=graded_len,
                    notch_fracs=fracs,
                    bend_rad=float(turn[idx[1:-1]].sum()),
                    chord_cm=float(np.hypot(*(pts[e] - pts[s]))),
                    parts=tuple((i + k) % m for k in range(run)),
                    break_fracs=tuple(float(cum[k] / length) for k in range(1, len(idx) - 1) if int(idx[k]) in brk_set),
                )
            )
    return out


def runs(pattern: Pattern, lines: dict[str, np.ndarray] | None = None) -> dict[str, list[Run]]:
    """Runs of every piece: name -> list of :class:`Run` (a strip's long edges whole, however many marks)."""
    from .orient import is_strip

    lines = graded_sew_lines(pattern) if lines is None else lines
    return {
        p.name: piece_runs(p, lines[p.name], max_run=len(breaks(p)) if is_strip(p) else MAX_RUN) for p in pattern.pieces
    }
