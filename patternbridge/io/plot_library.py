"""Pictures of library garments: pieces, seams colour-coded pairwise, every size nested.

Each seam gets one colour, drawn on both of its ranges (on the sample size's
sew line) and labelled with its id, so a pattern maker can see at a glance
what sews to what. The cut line is solid black, the sew line dashed, the
other sizes thin grey sew lines; notches are ticks into the piece, grain lines
arrows, body landmarks dots.
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..atomic import atomic_path
from ..pattern.geometry import boundary_indices
from ..pattern.model import Copy, Pattern, Piece

__all__ = ["plot_library_garment"]


def _layout(boxes: list[tuple[float, float]], gap: float) -> list[tuple[float, float]]:
    """Shelf-pack (w, h) boxes; returns lower-left offsets."""
    total_w = sum(w for w, _ in boxes) + gap * len(boxes)
    row_limit = max(max(w for w, _ in boxes), total_w / max(1.0, np.sqrt(len(boxes) / 1.6)))
    order = sorted(range(len(boxes)), key=lambda i: -boxes[i][1])
    out = [(0.0, 0.0)] * len(boxes)
    x = y = row_h = 0.0
    for i in order:
        w, h = boxes[i]
        if x > 0 and x + w > row_limit:
            y -= row_h + gap
            x, row_h = 0.0, 0.0
        out[i] = (x, y - h)
        x += w + gap
        row_h = max(row_h, h)
    return out


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class _Sheet:
    """Where each piece goes on the picture.

    shift : piece name -> (2,) float64 cm, added to the piece's coordinates
    width_cm, height_cm : extent of the laid-out pieces
    """

    shift: Mapping[str, np.ndarray]
    width_cm: float
    height_cm: float


def _sheet(pattern: Pattern, lines: Mapping[str, np.ndarray], gap: float) -> _Sheet:
    """Lay the pieces out by the boxes of their outline and graded sew lines, with room for a title."""
    boxes, lows = [], []
    for piece in pattern.pieces:
        allpts = np.concatenate([piece.outline, lines[piece.name].reshape(-1, 2)])
        lo, hi = allpts.min(axis=0), allpts.max(axis=0)
        boxes.append((hi[0] - lo[0], hi[1] - lo[1] + 4.0))
        lows.append(lo)
    offsets = _layout(boxes, gap)
    return _Sheet(
        shift={p.name: np.array(offsets[i]) - lows[i] for i, p in enumerate(pattern.pieces)},
        width_cm=max(o[0] + b[0] for o, b in zip(offsets, boxes, strict=True)),
        height_cm=-min(o[1] for o in offsets),
    )


def _draw_outlines(ax, cut: np.ndarray, sew: np.ndarray, graded: np.ndarray) -> None:
    """Graded sew lines thin grey, the cut line solid black, the sample's sew line dashed."""
    for g in graded:
        g = np.vstack([g, g[:1]])
        ax.plot(g[:, 0], g[:, 1], color="0.72", lw=0.5, zorder=1)
    c = np.vstack([cut, cut[:1]])
    ax.plot(c[:, 0], c[:, 1], color="black", lw=1.1, zorder=3)
    s = np.vstack([sew, sew[:1]])
    ax.plot(s[:, 0], s[:, 1], color="0.35", lw=0.6, ls="--", zorder=2)


def _draw_notch_ticks(ax, piece: Piece, cut: np.ndarray) -> None:
    """Notches as ticks into the piece, at least 0.6 cm long."""
    for notch in piece.notches:
        p0 = cut[notch.vertex]
        v = np.array([np.cos(notch.angle), np.sin(notch.angle)]) * max(notch.depth_cm, 0.6)
        ax.plot([p0[0], p0[0] + v[0]], [p0[1], p0[1] + v[1]], color="black", lw=1.4, zorder=4)


def _draw_grain(ax, piece: Piece, d: np.ndarray) -> None:
    """The grain line as a double-headed arrow."""
    if piece.grain_line is None:
        return
    gl = piece.grain_line.points + d
    ax.annotate(
        "",
        xy=gl[1],
        xytext=gl[0],
        arrowprops=dict(arrowstyle="<|-|>", color="0.25", lw=0.8),
        zorder=3,
    )


def _draw_landmarks(ax, piece: Piece, sew: np.ndarray) -> None:
    """Body landmarks as red dots with their names, on the sew line."""
    for landmark, mark in piece.landmarks.items():
        p0 = sew[piece.marks[mark]]
        ax.plot(*p0, "o", color="crimson", ms=3.5, zorder=5)
        ax.annotate(
            landmark,
            p0,
            xytext=(3, -8),
            textcoords="offset points",
            fontsize=5.5,
            color="crimson",
            zorder=6,
        )


def _draw_name(ax, piece: Piece, sew: np.ndarray) -> None:
    """The piece's name and how many to cut, above it."""
    centre = 0.5 * (sew.min(axis=0) + sew.max(axis=0))
    q = piece.quantity
    cut_text = f"cut {q.right} + {q.left} mirrored" if q.left else f"cut {q.right}"
    ax.text(
        centre[0],
        sew[:, 1].max() + 2.5,
        f"{piece.name}\n{cut_text}",
        ha="center",
        va="bottom",
        fontsize=8,
        weight="bold",
        zorder=6,
    )


def _draw_piece(ax, piece: Piece, d: np.ndarray, graded: np.ndarray) -> None:
    """One piece moved by ``d``: lines, notches, grain, landmarks and name."""
    from ..library.seams import sew_line

    cut = piece.outline + d
    sew, _ = sew_line(piece)
    sew = sew + d
    _draw_outlines(ax, cut, sew, graded + d)
    _draw_notch_ticks(ax, piece, cut)
    _draw_grain(ax, piece, d)
    _draw_landmarks(ax, piece, sew)
    _draw_name(ax, piece, sew)


def _draw_seam(ax, pattern: Pattern, seam, colour, shift: Mapping[str, np.ndarray]) -> None:
    """Both ranges of ``seam`` thick in ``colour`` on the sample's sew line, labelled with its id
    (and its ease on the second range); a mirror copy's range is not drawn."""
    from ..library.seams import sew_line

    for k, e in enumerate((seam.a, seam.b)):
        if e.copy is Copy.MIRROR:
            continue  # the mirror copy is not drawn; its seam shows on the primary
        piece = pattern.piece(e.piece)
        sew, _ = sew_line(piece)
        idx = boundary_indices(piece.n_vertices, piece.marks[e.start], piece.marks[e.end])
        pts = sew[idx] + shift[piece.name]
        ax.plot(pts[:, 0], pts[:, 1], color=colour, lw=3.2, alpha=0.85, solid_capstyle="butt", zorder=2.5)
        if np.linalg.norm(np.diff(pts, axis=0), axis=1).sum() < 4.0:
            continue  # too short to label legibly; the colour still pairs it
        mid = pts[len(pts) // 2]
        ax.annotate(
            seam.id + (f" +{seam.ease_cm:g}" if seam.ease_cm and k == 1 else ""),
            mid,
            fontsize=5.5,
            color=colour,
            xytext=(2, 2),
            textcoords="offset points",
            zorder=6,
            bbox=dict(boxstyle="round,pad=0.1", fc="white", ec="none", alpha=0.7),
        )


def _default_title(pattern: Pattern) -> str:
    sizes = ", ".join(pattern.rules.sizes or (pattern.sample_size,))
    return (
        f"{pattern.style}: {pattern.description}\nsizes {sizes} (sample {pattern.sample_size}); "
        "cut line solid, sew line dashed, seams colour-paired, grey = graded sizes, "
        "red = body landmarks"
    )


def plot_library_garment(
    pattern: Pattern,
    path: str | os.PathLike,
    *,
    dpi: int = 110,
    title: str | None = None,
) -> Path:
    """Draw ``pattern`` (all sizes nested, seams colour-coded) to a PNG, atomically.

    Parameters
    ----------
    pattern : a pattern with bridge data (seams and marks); works without too
    path : output ``.png``
    dpi : resolution

    Returns
    -------
    The path written.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from ..library.seams import graded_sew_lines

    lines = graded_sew_lines(pattern)
    sheet = _sheet(pattern, lines, gap=6.0)
    fig_w = 16.0
    fig_h = max(6.0, fig_w * sheet.height_cm / max(sheet.width_cm, 1.0) + 1.5)
    fig, ax = plt.subplots(figsize=(fig_w, fig_h))
    for piece in pattern.pieces:
        _draw_piece(ax, piece, sheet.shift[piece.name], lines[piece.name])
    cmap = plt.get_cmap("tab20")
    colours = {s.id: cmap(i % 20) for i, s in enumerate(pattern.seams)}
    for seam in pattern.seams:
        _draw_seam(ax, pattern, seam, colours[seam.id], sheet.shift)
    ax.set_aspect("equal")
    ax.axis("off")
    ax.set_title(title or _default_title(pattern), fontsize=9)
    fig.tight_layout()
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=dpi)
    plt.close(fig)
    return Path(path)
