"""Pictures of library garments: pieces, seams colour-coded pairwise, every size nested.

Each seam gets one colour, drawn on both of its ranges (on the sample size's
sew line) and labelled with its id, so a pattern maker can see at a glance
what sews to what. The cut line is solid black, the sew line dashed, the
other sizes thin grey sew lines; notches are ticks into the piece, grain lines
arrows, body landmarks dots.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from ..atomic import atomic_path
from ..pattern.geometry import boundary_indices
from ..pattern.model import Copy, Pattern

__all__ = ["plot_library_garment"]


def _layout(boxes: list[tuple[float, float]], gap: float) -> list[tuple[float, float]]:
    """Shelf-pack (w, h) boxes; returns lower-left offsets."""
    total_w = sum(w for w, _ in boxes) + gap * len(boxes)
    row_limit = max(
        max(w for w, _ in boxes), total_w / max(1.0, np.sqrt(len(boxes) / 1.6))
    )
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

    from ..library.seams import graded_sew_lines, sew_line

    lines = graded_sew_lines(pattern)
    gap = 6.0
    boxes, lows = [], []
    for piece in pattern.pieces:
        allpts = np.concatenate([piece.outline, lines[piece.name].reshape(-1, 2)])
        lo, hi = allpts.min(axis=0), allpts.max(axis=0)
        boxes.append((hi[0] - lo[0], hi[1] - lo[1] + 4.0))
        lows.append(lo)
    offsets = _layout(boxes, gap)
    shift = {
        p.name: np.array(offsets[i]) - lows[i] for i, p in enumerate(pattern.pieces)
    }

    cmap = plt.get_cmap("tab20")
    colours = {s.id: cmap(i % 20) for i, s in enumerate(pattern.seams)}
    span_w = max(o[0] + b[0] for o, b in zip(offsets, boxes, strict=True))
    span_h = -min(o[1] for o in offsets)
    fig_w = 16.0
    fig_h = max(6.0, fig_w * span_h / max(span_w, 1.0) + 1.5)
    fig, ax = plt.subplots(figsize=(fig_w, fig_h))
    for piece in pattern.pieces:
        d = shift[piece.name]
        cut = piece.outline + d
        sew, _ = sew_line(piece)
        sew = sew + d
        for graded in lines[piece.name]:
            g = np.vstack([graded, graded[:1]]) + d
            ax.plot(g[:, 0], g[:, 1], color="0.72", lw=0.5, zorder=1)
        c = np.vstack([cut, cut[:1]])
        ax.plot(c[:, 0], c[:, 1], color="black", lw=1.1, zorder=3)
        s = np.vstack([sew, sew[:1]])
        ax.plot(s[:, 0], s[:, 1], color="0.35", lw=0.6, ls="--", zorder=2)
        for notch in piece.notches:
            p0 = cut[notch.vertex]
            v = np.array([np.cos(notch.angle), np.sin(notch.angle)]) * max(
                notch.depth_cm, 0.6
            )
            ax.plot(
                [p0[0], p0[0] + v[0]],
                [p0[1], p0[1] + v[1]],
                color="black",
                lw=1.4,
                zorder=4,
            )
        if piece.grain_line is not None:
            gl = piece.grain_line.points + d
            ax.annotate(
                "",
                xy=gl[1],
                xytext=gl[0],
                arrowprops=dict(arrowstyle="<|-|>", color="0.25", lw=0.8),
                zorder=3,
            )
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
    for s in pattern.seams:
        col = colours[s.id]
        for k, e in enumerate((s.a, s.b)):
            if e.copy is Copy.MIRROR:
                continue  # the mirror copy is not drawn; its seam shows on the primary
            piece = pattern.piece(e.piece)
            sew, _ = sew_line(piece)
            idx = boundary_indices(
                piece.n_vertices, piece.marks[e.start], piece.marks[e.end]
            )
            pts = sew[idx] + shift[piece.name]
            ax.plot(
                pts[:, 0],
                pts[:, 1],
                color=col,
                lw=3.2,
                alpha=0.85,
                solid_capstyle="butt",
                zorder=2.5,
            )
            if np.linalg.norm(np.diff(pts, axis=0), axis=1).sum() < 4.0:
                continue  # too short to label legibly; the colour still pairs it
            mid = pts[len(pts) // 2]
            ax.annotate(
                s.id + (f" +{s.ease_cm:g}" if s.ease_cm and k == 1 else ""),
                mid,
                fontsize=5.5,
                color=col,
                xytext=(2, 2),
                textcoords="offset points",
                zorder=6,
                bbox=dict(boxstyle="round,pad=0.1", fc="white", ec="none", alpha=0.7),
            )
    ax.set_aspect("equal")
    ax.axis("off")
    sizes = ", ".join(pattern.rules.sizes or (pattern.sample_size,))
    ax.set_title(
        title
        or f"{pattern.style}: {pattern.description}\nsizes {sizes} (sample {pattern.sample_size}); "
        "cut line solid, sew line dashed, seams colour-paired, grey = graded sizes, "
        "red = body landmarks",
        fontsize=9,
    )
    fig.tight_layout()
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=dpi)
    plt.close(fig)
    return Path(path)
