"""Pictures of a grading run: the Pareto front (``pareto.png``) and the before/after overlay."""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np

from ..atomic import atomic_path
from ..pattern.model import Piece

__all__ = ["plot_fit_overlay", "plot_pareto"]

_NAMES = ("measurement error (cm)", "seam error", "shape error (rad)")


_PAIRS = ((0, 1), (0, 2), (1, 2))
_BASELINE_MARKERS = ("s", "D", "v", "P", "X")


def _member_groups(refined: np.ndarray, within: np.ndarray) -> list[tuple[np.ndarray, str, str, bool]]:
    """(rows, marker, legend label, filled) of the four kinds of front member."""
    return [
        (~refined & within, "o", "NSGA-II member, within tolerance", True),
        (~refined & ~within, "o", "NSGA-II member", False),
        (refined & within, "^", "refined, within tolerance", True),
        (refined & ~within, "^", "refined", False),
    ]


def _pareto_axes(plt, n_members: int) -> tuple:
    """The figure, its three projection axes and one thumbnail axes per member (below them)."""
    if not n_members:
        fig, axes = plt.subplots(1, 3, figsize=(13.5, 5.0))
        return fig, axes, []
    fig = plt.figure(figsize=(13.5, 8.4))
    rows = fig.add_gridspec(3, 1, height_ratios=(5.0, 0.9, 2.4))
    top = rows[0].subgridspec(1, 3, wspace=0.38)
    bottom = rows[2].subgridspec(1, n_members, wspace=0.15)
    axes = [fig.add_subplot(top[0, c]) for c in range(3)]
    thumbs = [fig.add_subplot(bottom[0, c]) for c in range(n_members)]
    return fig, axes, thumbs


def _projection(
    ax,
    F: np.ndarray,
    i: int,
    j: int,
    groups: list,
    *,
    chosen: np.ndarray | None,
    final: np.ndarray | None,
    baselines: Mapping[str, np.ndarray],
    member_rows: Sequence[int],
) -> None:
    """Objective ``j`` over objective ``i`` (symlog axes): the members, the choices, the baselines."""
    for mask, marker, label, filled in groups:
        if not mask.any():
            continue
        colour = "#2a9d8f" if marker == "^" else "#4c72b0"
        ax.scatter(
            F[mask, i],
            F[mask, j],
            s=26 if marker == "^" else 14,
            marker=marker,
            facecolors=colour if filled else "none",
            edgecolors=colour,
            alpha=0.8,
            label=label,
        )
    if chosen is not None:
        ax.scatter(
            [chosen[i]],
            [chosen[j]],
            s=110,
            facecolors="none",
            edgecolors="#dd8452",
            linewidths=2,
            label="NSGA-II's own choice",
        )
    if final is not None:
        ax.scatter(
            [final[i]],
            [final[j]],
            s=150,
            marker="*",
            c="#c44e52",
            zorder=5,
            label="chosen: least shape error within tolerance",
        )
    for k, (name, f) in enumerate(baselines.items()):
        ax.scatter(
            [f[i]],
            [f[j]],
            s=50,
            marker=_BASELINE_MARKERS[k % len(_BASELINE_MARKERS)],
            c="#555555",
            alpha=0.8,
            label=name,
        )
    for row in member_rows:
        ax.annotate(
            str(row), (F[row, i], F[row, j]), fontsize=7, color="#1d3557", xytext=(3, 3), textcoords="offset points"
        )
    ax.set_xlabel(_NAMES[i])
    ax.set_ylabel(_NAMES[j])
    ax.set_xscale("symlog", linthresh=_linear_below(F[:, i]))
    ax.set_yscale("symlog", linthresh=_linear_below(F[:, j]))
    ax.grid(True, alpha=0.3)


def _legend_and_title(fig, axes, *, has_members: bool, title: str | None) -> None:
    """The legend of the first projection below the plots (above the thumbnails, with their caption)."""
    handles, names = axes[0].get_legend_handles_labels()
    if has_members:
        fig.legend(handles, names, loc="center", ncol=4, fontsize=8, frameon=False, bbox_to_anchor=(0.5, 0.335))
        fig.text(
            0.5,
            0.285,
            "gradings within tolerance (front row: measurement error, shape error); fit --choose K takes row K",
            ha="center",
            fontsize=9,
        )
        if title:
            fig.suptitle(title)
        fig.subplots_adjust(left=0.06, right=0.98, top=0.93, bottom=0.02)
    else:
        fig.legend(handles, names, loc="lower center", ncol=4, fontsize=8, frameon=False)
        if title:
            fig.suptitle(title)
        fig.tight_layout(rect=(0, 0.13, 1, 1))


def plot_pareto(
    F: np.ndarray,
    path: str | os.PathLike,
    *,
    chosen: np.ndarray | None = None,
    final: np.ndarray | None = None,
    refined: np.ndarray | None = None,
    within: np.ndarray | None = None,
    baselines: Mapping[str, np.ndarray] | None = None,
    members: Sequence[tuple[int, Sequence[Piece]]] | None = None,
    title: str | None = None,
) -> Path:
    """Three pairwise projections of the final front, the choice and the baselines, and member thumbnails.

    Parameters
    ----------
    F : (n, 3) objectives of the final front
    chosen : (3,) NSGA-II's own choice on its front
    final : (3,) the solution chosen on the final front
    refined : (n,) bool, the rows the final constrained step produced (drawn as
        triangles; the others are NSGA-II's own members)
    within : (n,) bool, the rows within the fit tolerance (filled; the others
        are drawn hollow)
    baselines : name -> (3,) objectives of each baseline
    members : ``(row, pieces)`` of the front members to show as small
        pattern thumbnails under the plots (e.g. the gradings within
        tolerance, :func:`patternbridge.grade.run.front_members`); their rows
        are numbered on the plots, the number ``fit --choose K`` takes
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    F = np.atleast_2d(np.asarray(F, dtype=np.float64))
    n = len(F)
    refined = np.zeros(n, dtype=bool) if refined is None else np.asarray(refined, dtype=bool)
    within = np.zeros(n, dtype=bool) if within is None else np.asarray(within, dtype=bool)
    groups = _member_groups(refined, within)
    members = list(members or [])
    fig, axes, thumbs = _pareto_axes(plt, len(members))
    for ax, (i, j) in zip(axes, _PAIRS, strict=True):
        _projection(
            ax,
            F,
            i,
            j,
            groups,
            chosen=chosen,
            final=final,
            baselines=baselines or {},
            member_rows=[row for row, _pieces in members],
        )
    for ax, (row, pieces) in zip(thumbs, members, strict=True):
        _thumbnail(ax, pieces)
        ax.set_title(f"{row}: {F[row, 0]:.3f} cm, {F[row, 2]:.4f} rad", fontsize=8)
    _legend_and_title(fig, axes, has_members=bool(members), title=title)
    path = Path(path)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=110, format=path.suffix.lstrip(".") or "png")
    plt.close(fig)
    return path


def _linear_below(values: np.ndarray) -> float:
    """The symlog axis's linear range for one objective: up to its smallest positive value.

    Objectives differ by orders of magnitude (measurement error in cm, shape
    error in thousandths of a radian); a fixed range put a whole objective in
    the linear part, where the axis labels only its ends.
    """
    positive = values[np.isfinite(values) & (values > 0)]
    return float(positive.min()) if positive.size else 1e-2


def _thumbnail(ax, pieces: Sequence[Piece]) -> None:
    """Every piece's outline side by side, left to right, on one small axes."""
    x0 = 0.0
    for piece in pieces:
        pts = np.asarray(piece.outline, dtype=np.float64)
        lo, hi = pts.min(axis=0), pts.max(axis=0)
        shifted = pts - [lo[0] - x0, lo[1]]
        closed = np.vstack([shifted, shifted[:1]])
        ax.plot(closed[:, 0], closed[:, 1], lw=0.6, color="#264653")
        x0 += (hi[0] - lo[0]) * 1.08
    ax.set_aspect("equal")
    ax.axis("off")


def plot_fit_overlay(
    original: Sequence[Piece],
    graded: Sequence[Piece],
    path: str | os.PathLike,
    *,
    labels: tuple[str, str] = ("original", "graded"),
    title: str | None = None,
) -> Path:
    """Original and graded pieces overlaid (``pattern.png``).

    Drawn by :func:`patternbridge.io.plot.plot_overlay` (grain lines, marks and
    notches of both versions).
    """
    from .plot import plot_overlay

    return plot_overlay(original, graded, path, labels=labels, title=title)
