"""Pattern pictures: every piece laid out flat, as a pattern maker draws it (SVG/PNG).

:func:`plot_pattern` lays the pieces out without overlap (shelf packing of
their bounding boxes) and draws, per piece, the cut line, the sew line dashed,
the grain line with an arrow head, notches as ticks into the piece, internal
lines, cutouts, drill holes, the mirror line and a label with name, size and
quantity; with ``sizes="all"`` every graded size is overlaid in graded colours.
:func:`plot_overlay` draws two versions of each piece over each other (the
grader's before/after picture).

matplotlib is imported here only (and only when a function runs), through its
object API with the Agg/SVG canvases: no pyplot state, no display needed.
"""

from __future__ import annotations

import logging
import math
import os
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..atomic import atomic_path
from ..errors import InputError
from ..pattern.model import NotchType, Pattern, Piece

__all__ = ["layout_offsets", "plot_overlay", "plot_pattern"]

log = logging.getLogger(__name__)

_FORMATS = {".svg": "svg", ".png": "png", ".pdf": "pdf"}
_SAMPLE_COLOUR = "#1f1f1f"
_FILL = "#f3ead8"  # paper
_GRAIN = "#b03a2e"
_INTERNAL = "#2e6da4"
_NOTCH = "#1f1f1f"
_MIN_TICK_PT = 5.0  # notch ticks are drawn at least this long (points) to stay visible


# ---------------------------------------------------------------------------
# layout
# ---------------------------------------------------------------------------


def _laid_out(boxes: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Offsets of :func:`layout_offsets` and the drawing extent (x0, y0, x1, y1) with a 3 % margin."""
    offsets = layout_offsets(boxes)
    moved = boxes + np.hstack([offsets, offsets])
    margin = 0.03 * float(max(np.ptp(moved[:, [0, 2]]), np.ptp(moved[:, [1, 3]]), 1.0))
    extent = np.concatenate([moved[:, :2].min(axis=0) - margin, moved[:, 2:].max(axis=0) + margin])
    return offsets, extent


def layout_offsets(boxes: np.ndarray, *, gap: float | None = None, aspect: float = 1.5) -> np.ndarray:
    """Shelf-pack axis-aligned boxes; return the translation of each box.

    Parameters
    ----------
    boxes : (k, 4) float64, cm — ``xmin, ymin, xmax, ymax`` per piece
    gap : free space between boxes (cm); default 4 % of the largest box side
    aspect : wanted width / height of the whole layout

    Returns
    -------
    (k, 2) float64 offsets; box ``i`` moved by ``offsets[i]`` overlaps no other.

    Notes
    -----
    Boxes are placed tallest first, left to right on shelves stacked bottom-up
    (like a marker); of the shelf widths that start a new shelf after the
    k-th box, the one whose layout is smallest, with its width/height ratio
    closest to ``aspect``, wins.

    Examples
    --------
    >>> off = layout_offsets(np.array([[0, 0, 10, 10], [0, 0, 10, 10]], float), gap=1)
    >>> off.tolist()
    [[0.0, 0.0], [11.0, 0.0]]
    """
    boxes = np.asarray(boxes, dtype=np.float64).reshape(-1, 4)
    k = len(boxes)
    offsets = np.zeros((k, 2))
    if k == 0:
        return offsets
    w = boxes[:, 2] - boxes[:, 0]
    h = boxes[:, 3] - boxes[:, 1]
    if gap is None:
        gap = 0.04 * float(max(w.max(), h.max(), 1e-9))
    order = np.lexsort((-w, -h))  # tallest first, then widest
    best = None
    # candidate shelf widths: the running widths of the first k boxes in order
    for limit in np.unique(np.maximum(np.cumsum(w[order] + gap) - gap, w.max())):
        cand = _shelves(boxes, w, h, order, float(limit), gap)
        span = np.ptp(np.concatenate([cand, cand + np.column_stack([w, h])]), axis=0)
        ratio = span[0] / max(span[1], 1e-9)
        score = span[0] * span[1] * max(ratio / aspect, aspect / ratio)
        if best is None or score < best[0] - 1e-9:
            best = (score, cand)
    placed = best[1]
    offsets = placed - boxes[:, :2]
    return offsets


def _shelves(boxes, w, h, order, shelf_width: float, gap: float) -> np.ndarray:
    """Lower-left corner of every box, packed on shelves of ``shelf_width``."""
    corners = np.zeros((len(boxes), 2))
    x = y = shelf_h = 0.0
    for i in order:
        if x > 0 and x + w[i] > shelf_width + 1e-9:
            y += shelf_h + gap
            x = shelf_h = 0.0
        corners[i] = (x, y)
        x += w[i] + gap
        shelf_h = max(shelf_h, h[i])
    return corners


def _piece_points(piece: Piece) -> np.ndarray:
    parts = [np.asarray(piece.outline)]
    for line in (piece.grain_line, piece.grade_reference, piece.mirror_line):
        if line is not None:
            parts.append(np.asarray(line.points))
    for poly in (*piece.internal_lines, *piece.cutouts, *piece.sew_lines):
        if len(poly.points):
            parts.append(np.asarray(poly.points))
    return np.concatenate(parts, axis=0)


def _bbox(pieces: Iterable[Piece]) -> np.ndarray:
    pts = np.concatenate([_piece_points(p) for p in pieces], axis=0)
    return np.concatenate([pts.min(axis=0), pts.max(axis=0)])


# ---------------------------------------------------------------------------
# drawing one piece
# ---------------------------------------------------------------------------


@dataclass(frozen=True, slots=True, kw_only=True)
class _Style:
    colour: str
    width: float
    fill: str | None
    details: bool  # grain line, notches, internal lines, labels
    alpha: float = 1.0
    zorder: float = 2.0


def _closed(points: np.ndarray) -> np.ndarray:
    return np.vstack([points, points[:1]])


def _label_point(outline: np.ndarray) -> np.ndarray:
    """A roomy spot inside the outline for the label.

    The pole of inaccessibility is the roomiest point, but on long strips many
    points tie and it may sit near an end; the centroid or the bounding-box
    centre is taken instead when it is nearly as far from the boundary.
    """
    import shapely
    from shapely.ops import polylabel

    poly = shapely.Polygon(outline)
    if not poly.is_valid:
        poly = poly.buffer(0)
    if poly.is_empty:
        return outline.mean(axis=0)
    if poly.geom_type != "Polygon":
        poly = max(poly.geoms, key=lambda g: g.area)
    size = max(np.ptp(outline[:, 0]), np.ptp(outline[:, 1]), 1e-9)
    pole = polylabel(poly, tolerance=size / 200.0)
    lo, hi = outline.min(axis=0), outline.max(axis=0)
    candidates = [poly.centroid, shapely.Point((lo + hi) / 2.0), pole]
    ring = poly.exterior
    room = [ring.distance(c) if poly.contains(c) else -1.0 for c in candidates]
    best = max(room)
    pick = next(c for c, r in zip(candidates, room, strict=True) if r >= 0.8 * best)
    return np.array([pick.x, pick.y])


MAX_LABEL = 60
"""Longest line of text drawn (names, sizes, labels, titles); longer lines are cut with "…"."""


def _short(text: object, limit: int = MAX_LABEL) -> str:
    """``text`` as at most six lines of at most ``limit`` characters.

    Layout time of a text grows with its length (a 2 MB piece name took minutes
    and gigabytes), so whatever comes from a file is cut before it is drawn.

    Examples
    --------
    >>> _short("x" * 100, 5)
    'xxxx…'
    """
    lines = str(text).splitlines() or [""]
    cut = [line if len(line) <= limit else line[: limit - 1] + "…" for line in lines[:6]]
    return "\n".join(cut + (["…"] if len(lines) > 6 else []))


def _quantity_text(piece: Piece) -> str:
    q = piece.quantity
    if q.left and q.right:
        return f"cut {q.total} ({q.right} R + {q.left} L)"
    return f"cut {q.total}"


def _draw_outline(ax, outline: np.ndarray, style: _Style) -> None:
    """The cut line: a closed polygon, filled when the style has a fill."""
    from matplotlib.patches import Polygon

    ax.add_patch(
        Polygon(
            outline,
            closed=True,
            facecolor=style.fill or "none",
            edgecolor=style.colour,
            linewidth=style.width,
            alpha=style.alpha,
            zorder=style.zorder,
            joinstyle="round",
        )
    )


def _draw_sew_lines(ax, piece: Piece, offset: np.ndarray, style: _Style) -> None:
    """The sew lines, dashed and thinner than the cut line."""
    for poly in piece.sew_lines:
        pts = np.asarray(poly.points) + offset
        pts = _closed(pts) if poly.closed else pts
        ax.plot(
            pts[:, 0],
            pts[:, 1],
            color=style.colour,
            linewidth=0.6 * style.width,
            linestyle=(0, (4, 2)),
            alpha=style.alpha,
            zorder=style.zorder + 0.1,
        )


def _draw_internal_lines(ax, piece: Piece, offset: np.ndarray, style: _Style) -> None:
    """Internal lines in blue, each with its label at its first point."""
    for poly in piece.internal_lines:
        pts = np.asarray(poly.points) + offset
        pts = _closed(pts) if poly.closed else pts
        ax.plot(
            pts[:, 0],
            pts[:, 1],
            color=_INTERNAL,
            linewidth=0.7,
            zorder=style.zorder + 0.2,
        )
        if poly.label:
            ax.annotate(
                _short(poly.label),
                pts[0],
                fontsize=6,
                color=_INTERNAL,
                zorder=style.zorder + 0.3,
                xytext=(2, 2),
                textcoords="offset points",
            )


def _draw_cutouts(ax, piece: Piece, offset: np.ndarray, style: _Style) -> None:
    """Cutouts as white holes edged in the piece's colour."""
    for poly in piece.cutouts:
        pts = _closed(np.asarray(poly.points) + offset)
        ax.fill(
            pts[:, 0],
            pts[:, 1],
            facecolor="white",
            edgecolor=style.colour,
            linewidth=style.width * 0.8,
            zorder=style.zorder + 0.2,
        )


def _draw_mirror_line(ax, piece: Piece, offset: np.ndarray, style: _Style) -> None:
    """The mirror (fold) line dash-dotted, with ``FOLD`` written along it."""
    if piece.mirror_line is None:
        return
    pts = np.asarray(piece.mirror_line.points) + offset
    ax.plot(
        pts[:, 0],
        pts[:, 1],
        color=_GRAIN,
        linewidth=0.9,
        linestyle="-.",
        zorder=style.zorder + 0.3,
    )
    mid = pts.mean(axis=0)
    ax.annotate(
        "FOLD",
        mid,
        fontsize=6,
        color=_GRAIN,
        ha="center",
        va="bottom",
        rotation=math.degrees(math.atan2(*(pts[1] - pts[0])[::-1])) % 180 - 0,
        rotation_mode="anchor",
        zorder=style.zorder + 0.4,
    )


def _draw_grain_line(ax, piece: Piece, offset: np.ndarray, style: _Style) -> None:
    """The grain line as an arrow from its first point to its second."""
    from matplotlib.patches import FancyArrowPatch

    if piece.grain_line is None:
        return
    pts = np.asarray(piece.grain_line.points) + offset
    ax.add_patch(
        FancyArrowPatch(
            pts[0],
            pts[1],
            arrowstyle="-|>",
            mutation_scale=9,
            color=_GRAIN,
            linewidth=1.0,
            zorder=style.zorder + 0.5,
            shrinkA=0,
            shrinkB=0,
        )
    )


def _notch_ticks(
    outline: np.ndarray,
    vertex: np.ndarray,
    depth_cm: np.ndarray,
    angle: np.ndarray,
    shortest_cm: float,
) -> tuple[np.ndarray, np.ndarray]:
    """(n, 2) starts and ends of the notch ticks: from the outline vertex along
    the notch angle, at least ``shortest_cm`` long.

    Examples
    --------
    >>> sq = np.array([[0.0, 0.0], [4.0, 0.0], [4.0, 4.0]])
    >>> a, b = _notch_ticks(sq, np.array([1]), np.array([0.2]), np.array([np.pi]), 0.5)
    >>> a.tolist(), b.round(6).tolist()
    ([[4.0, 0.0]], [[3.5, 0.0]])
    """
    starts = outline[vertex]
    lengths = np.array([max(d, shortest_cm) for d in depth_cm])
    ends = starts + lengths[:, None] * np.column_stack([np.cos(angle), np.sin(angle)])
    return starts, ends


def _draw_notches(ax, piece: Piece, outline: np.ndarray, style: _Style, cm_to_pt: float) -> None:
    """Notches as ticks from the boundary into the piece; a T notch gets its cross bar."""
    if not piece.notches:
        return
    starts, ends = _notch_ticks(
        outline,
        np.array([n.vertex for n in piece.notches], dtype=np.int64),
        np.array([n.depth_cm for n in piece.notches], dtype=np.float64),
        np.array([n.angle for n in piece.notches]),
        _MIN_TICK_PT / cm_to_pt,
    )
    for notch, a, b in zip(piece.notches, starts, ends, strict=True):
        lw = 1.1 if notch.type in (NotchType.SLIT, NotchType.V) else 1.6
        ax.plot(
            [a[0], b[0]],
            [a[1], b[1]],
            color=_NOTCH,
            linewidth=lw,
            solid_capstyle="butt",
            zorder=style.zorder + 0.6,
        )
        if notch.type is NotchType.T:
            d = (b - a) / max(float(np.hypot(*(b - a))), 1e-12)
            t = np.array([-d[1], d[0]]) * 0.3
            ax.plot(
                [b[0] - t[0], b[0] + t[0]],
                [b[1] - t[1], b[1] + t[1]],
                color=_NOTCH,
                linewidth=lw,
                zorder=style.zorder + 0.6,
            )


def _draw_drill_holes(ax, piece: Piece, offset: np.ndarray, style: _Style) -> None:
    """Drill holes as a cross with a circle, at least 0.3 cm in radius."""
    for hole in piece.drill_holes:
        c = np.asarray(hole.position) + offset
        r = max(hole.diameter_cm / 2.0, 0.3)
        ax.plot(
            [c[0] - r, c[0] + r],
            [c[1], c[1]],
            color=style.colour,
            linewidth=0.8,
            zorder=style.zorder + 0.6,
        )
        ax.plot(
            [c[0], c[0]],
            [c[1] - r, c[1] + r],
            color=style.colour,
            linewidth=0.8,
            zorder=style.zorder + 0.6,
        )
        ax.add_patch(_circle(c, r * 0.6, style.colour, style.zorder + 0.6))


def _label_fit(outline: np.ndarray, label: str, cm_to_pt: float) -> tuple[bool, float]:
    """Whether the label reads upwards and its font size (pt) to fit the piece.

    Tall narrow pieces (waistbands, plackets) read their label upwards; the
    size fits the longest line along the piece and all lines across it,
    between 4.5 and 11 pt.

    Examples
    --------
    >>> strip = np.array([[0.0, 0.0], [2.0, 0.0], [2.0, 40.0], [0.0, 40.0]])
    >>> _label_fit(strip, "band", 28.35)
    (True, 11.0)
    """
    width_cm = float(np.ptp(outline[:, 0]))
    height_cm = float(np.ptp(outline[:, 1]))
    upright = height_cm > 2.0 * width_cm
    room_cm = height_cm if upright else width_cm
    lines = label.split("\n")
    longest = max(len(s) for s in lines)
    across_cm = width_cm if upright else height_cm
    fit = min(
        room_cm * cm_to_pt / max(longest, 1) / 0.62 * 0.8,
        across_cm * cm_to_pt / (1.3 * len(lines)),
    )
    return upright, float(np.clip(fit, 4.5, 11.0))


def _draw_label(ax, outline: np.ndarray, label: str, style: _Style, cm_to_pt: float) -> None:
    """The piece's label in a white box at a roomy spot inside the outline."""
    label = _short(label)
    at = _label_point(outline)
    upright, size = _label_fit(outline, label, cm_to_pt)
    ax.text(
        at[0],
        at[1],
        label,
        rotation=90 if upright else 0,
        rotation_mode="anchor",
        fontsize=size,
        ha="center",
        va="center",
        color=_SAMPLE_COLOUR,
        zorder=style.zorder + 1.0,
        linespacing=1.25,
        bbox={
            "boxstyle": "round,pad=0.25",
            "facecolor": "white",
            "alpha": 0.75,
            "edgecolor": "none",
        },
    )


def _draw_piece(
    ax,
    piece: Piece,
    offset: np.ndarray,
    style: _Style,
    *,
    cm_to_pt: float,
    label: str | None,
) -> None:
    """Draw ``piece`` moved by ``offset``: its cut and sew lines, then (with
    ``style.details``) its internal lines, cutouts, fold, grain, notches,
    drill holes and label."""
    outline = np.asarray(piece.outline) + offset
    _draw_outline(ax, outline, style)
    _draw_sew_lines(ax, piece, offset, style)
    if not style.details:
        return
    _draw_internal_lines(ax, piece, offset, style)
    _draw_cutouts(ax, piece, offset, style)
    _draw_mirror_line(ax, piece, offset, style)
    _draw_grain_line(ax, piece, offset, style)
    _draw_notches(ax, piece, outline, style, cm_to_pt)
    _draw_drill_holes(ax, piece, offset, style)
    if label:
        _draw_label(ax, outline, label, style, cm_to_pt)


def _circle(centre, radius, colour, zorder):
    from matplotlib.patches import Circle

    return Circle(centre, radius, facecolor="none", edgecolor=colour, linewidth=0.8, zorder=zorder)


# ---------------------------------------------------------------------------
# figure plumbing
# ---------------------------------------------------------------------------


def _format_for(path: Path) -> str:
    fmt = _FORMATS.get(path.suffix.lower())
    if fmt is None:
        raise InputError(f"{path}: unknown picture type {path.suffix!r}; give a .svg or .png file name")
    return fmt


def _figure(extent: np.ndarray, *, legend_rows: int = 0):
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    w_cm = float(extent[2] - extent[0])
    h_cm = float(extent[3] - extent[1])
    width_in = 12.0
    height_in = float(np.clip(width_in * h_cm / max(w_cm, 1e-9), 3.0, 30.0)) + 0.9 + 0.2 * legend_rows
    fig = Figure(figsize=(width_in, height_in), layout="constrained")
    FigureCanvasAgg(fig)
    ax = fig.add_subplot()
    ax.set_aspect("equal", adjustable="box")
    ax.set_xlim(extent[0], extent[2])
    ax.set_ylim(extent[1], extent[3])
    ax.set_xlabel("cm")
    ax.grid(True, color="#e4e4e4", linewidth=0.5, zorder=0)
    ax.set_axisbelow(True)
    for side in ("top", "right"):
        ax.spines[side].set_visible(False)
    cm_to_pt = width_in * 72.0 / max(w_cm, 1e-9) * 0.92
    return fig, ax, cm_to_pt


def _save(fig, path: Path) -> Path:
    import matplotlib

    fmt = _format_for(path)
    # SVG keeps text as text: searchable and editable in a drawing program
    with (
        matplotlib.rc_context({"svg.fonttype": "none", "svg.hashsalt": "patternbridge"}),
        atomic_path(path) as tmp,
    ):
        fig.savefig(tmp, format=fmt, dpi=150, metadata=_metadata(fmt))
    return path


def _metadata(fmt: str) -> dict:
    # reproducible output: no creation date in the file
    if fmt == "svg":
        return {"Date": None}
    if fmt == "pdf":
        return {"CreationDate": None}
    return {}


def _size_colours(n: int) -> list:
    from matplotlib import colormaps

    cmap = colormaps["viridis"]
    if n <= 1:
        return [cmap(0.1)]
    return [cmap(0.05 + 0.85 * i / (n - 1)) for i in range(n)]


def _resolve_sizes(pattern: Pattern, sizes) -> list[str]:
    if sizes is None:
        return [pattern.sample_size]
    size_list = list(pattern.sizes) or [pattern.sample_size]
    if isinstance(sizes, str):
        if sizes.lower() == "all":
            return size_list
        if sizes.lower() == "sample":
            return [pattern.sample_size]
        sizes = [s.strip() for s in sizes.split(",") if s.strip()]
    wanted = [str(s) for s in sizes]
    unknown = [s for s in wanted if s not in size_list]
    if unknown or not wanted:
        raise InputError(
            f"{_short(pattern.style)}: sizes {[_short(s, 20) for s in unknown[:5]]} are not in the size list "
            f"{_short(', '.join(size_list), 200)}; give 'sample', 'all' or sizes of the list"
        )
    return [s for s in size_list if s in set(wanted)]


def _pieces_by_size(pattern: Pattern, sizes: Sequence[str]) -> dict[str, tuple[Piece, ...]]:
    out: dict[str, tuple[Piece, ...]] = {}
    for size in sizes:
        if size == pattern.sample_size:
            out[size] = pattern.pieces
        else:
            from ..pattern.grading import grade

            out[size] = grade(pattern, size).pieces
    return out


def _piece_label(piece: Piece, size: str) -> str:
    return f"{piece.name}\n{size}  {_quantity_text(piece)}" if size else f"{piece.name}\n{_quantity_text(piece)}"


# ---------------------------------------------------------------------------
# public
# ---------------------------------------------------------------------------


_SAMPLE_STYLE = _Style(colour=_SAMPLE_COLOUR, width=1.4, fill=_FILL, details=True, zorder=2.0)


def _size_style(colour, *, outline_only: bool) -> _Style:
    """The sample size in black with its details; another size of an overlay as a coloured outline."""
    if outline_only:
        return _Style(colour=colour, width=0.9, fill=None, details=False, zorder=3.0)
    return _SAMPLE_STYLE


def _size_legend(fig, size_list: Sequence[str], sample: str, colours: dict) -> None:
    """One legend entry per size below the drawing; the sample size is marked."""
    from matplotlib.lines import Line2D

    handles = [
        Line2D(
            [],
            [],
            color=_SAMPLE_COLOUR if s == sample else colours[s],
            linewidth=1.4 if s == sample else 1.0,
            label=_short(f"{s} (sample)" if s == sample else s),
        )
        for s in size_list
    ]
    fig.legend(
        handles=handles,
        loc="outside lower center",
        ncols=min(len(handles), 10),
        frameon=False,
        fontsize=8,
        title="sizes",
        title_fontsize=8,
    )


def _pattern_title(pattern: Pattern, size_list: Sequence[str], *, overlay: bool) -> str:
    """``"<style> — <n> pieces, size(s) <sizes>"``; more than six sizes show as a range."""
    n = len(pattern.piece_names)
    shown = ", ".join(size_list) if len(size_list) <= 6 else f"{size_list[0]} to {size_list[-1]}"
    if not overlay:
        return f"{pattern.style} — {n} pieces, size {shown}"
    return f"{pattern.style} — {n} pieces, sizes {shown} (sample {pattern.sample_size})"


def plot_pattern(
    pattern: Pattern,
    path: str | os.PathLike,
    *,
    sizes: str | Sequence[str] | None = None,
    title: str | None = None,
) -> Path:
    """Draw every piece of ``pattern`` to an SVG or PNG file (by suffix), atomically.

    Parameters
    ----------
    pattern : Pattern
    path : ``.svg``, ``.png`` (150 dpi) or ``.pdf``
    sizes : ``None``/``"sample"`` for the sample size, ``"all"`` or a list of
        sizes to overlay (graded from the rule table); the sample size is drawn
        in black with its details, the other sizes as coloured outlines.
    title : figure title; default ``"<style> — <sizes>"``.

    Returns
    -------
    The path written.

    Raises
    ------
    InputError
        For an unknown suffix or a size outside the size list.
    """
    path = Path(path)
    _format_for(path)
    size_list = _resolve_sizes(pattern, sizes)
    by_size = _pieces_by_size(pattern, size_list)
    sample = pattern.sample_size
    overlay = len(size_list) > 1 or size_list[0] != sample

    def piece_in(size: str, name: str) -> Piece:
        return next(p for p in by_size[size] if p.name == name)

    names = pattern.piece_names
    boxes = np.array([_bbox([piece_in(s, name) for s in size_list]) for name in names]).reshape(-1, 4)
    offsets, extent = _laid_out(boxes)
    fig, ax, cm_to_pt = _figure(extent, legend_rows=1 if overlay else 0)
    colours = dict(zip(size_list, _size_colours(len(size_list)), strict=True))
    for k, name in enumerate(names):
        for size in size_list:
            piece = piece_in(size, name)
            outline_only = overlay and size != sample
            style = _size_style(colours[size], outline_only=outline_only)
            label = None if outline_only else _piece_label(piece, size)
            _draw_piece(ax, piece, offsets[k], style, cm_to_pt=cm_to_pt, label=label)
        if overlay and sample not in size_list:  # no sample drawn: name the piece
            first = piece_in(size_list[0], name)
            at = _label_point(np.asarray(first.outline) + offsets[k])
            ax.text(*at, _short(first.name), fontsize=8, ha="center", va="center")
    if overlay:
        _size_legend(ax.figure, size_list, sample, colours)
    if title is None:
        title = _pattern_title(pattern, size_list, overlay=overlay)
    ax.set_title(_short(title, 2 * MAX_LABEL), fontsize=11, loc="left")
    return _save(fig, path)


def _change_text(a: Piece, b: Piece) -> str:
    """Name of ``a`` and the change of area and perimeter from ``a`` to ``b``."""
    from ..pattern.geometry import area, perimeter

    da = float(area(np.asarray(b.outline))) - float(area(np.asarray(a.outline)))
    dp = float(perimeter(np.asarray(b.outline))) - float(perimeter(np.asarray(a.outline)))
    return f"{a.name}\nΔarea {da:+.1f} cm²\nΔperimeter {dp:+.1f} cm"


_BEFORE = _Style(colour="#8c8c8c", width=1.0, fill="#ececec", details=False, zorder=2.0)
_AFTER = _Style(colour="#c0392b", width=1.2, fill=None, details=True, zorder=3.0)


def plot_overlay(
    original_pieces: Sequence[Piece],
    graded_pieces: Sequence[Piece],
    path: str | os.PathLike,
    *,
    labels: tuple[str, str] = ("original", "graded"),
    title: str | None = None,
) -> Path:
    """Overlay two versions of each piece (e.g. before and after grading).

    Pieces are matched by name (by position when names differ). The first
    version is drawn grey and filled, the second in colour with its grain line
    and notches; each piece is labelled with its name and the change of its
    area and perimeter.

    Parameters
    ----------
    original_pieces, graded_pieces : sequences of Piece of equal length
    path : ``.svg``, ``.png`` or ``.pdf``
    labels : legend names of the two versions

    Returns
    -------
    The path written.
    """
    from matplotlib.lines import Line2D

    path = Path(path)
    _format_for(path)
    original_pieces = tuple(original_pieces)
    graded_pieces = tuple(graded_pieces)
    if len(original_pieces) != len(graded_pieces):
        raise ValueError(f"plot_overlay: {len(original_pieces)} original pieces but {len(graded_pieces)} graded pieces")
    by_name = {p.name: p for p in graded_pieces}
    pairs = [(a, by_name.get(a.name, b)) for a, b in zip(original_pieces, graded_pieces, strict=True)]
    boxes = np.array([_bbox(pair) for pair in pairs]).reshape(-1, 4)
    offsets, extent = _laid_out(boxes)
    fig, ax, cm_to_pt = _figure(extent, legend_rows=1)
    for (a, b), off in zip(pairs, offsets, strict=True):
        _draw_piece(ax, a, off, _BEFORE, cm_to_pt=cm_to_pt, label=None)
        _draw_piece(ax, b, off, _AFTER, cm_to_pt=cm_to_pt, label=_change_text(a, b))
    fig.legend(
        handles=[
            Line2D([], [], color=_BEFORE.colour, linewidth=_BEFORE.width, label=_short(labels[0])),
            Line2D([], [], color=_AFTER.colour, linewidth=_AFTER.width, label=_short(labels[1])),
        ],
        loc="outside lower center",
        ncols=2,
        frameon=False,
        fontsize=8,
    )
    ax.set_title(
        _short(title or f"{labels[0]} vs {labels[1]} — {len(pairs)} pieces", 2 * MAX_LABEL),
        fontsize=11,
        loc="left",
    )
    return _save(fig, path)
