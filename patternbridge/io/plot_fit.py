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


def plot_pareto(
    F: np.ndarray,
    path: str | os.PathLike,
    *,
    chosen: np.ndarray | None = None,
    final: np.ndarray | None = None,
    baselines: Mapping[str, np.ndarray] | None = None,
    title: str | None = None,
) -> Path:
    """Three pairwise projections of the final front, chosen point and baselines.

    Parameters
    ----------
    F : (n, 3) objectives of the Pareto front
    chosen : (3,) the front member chosen (before the final step)
    final : (3,) the solution after the final constrained step
    baselines : name -> (3,) objectives of each baseline
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    F = np.atleast_2d(np.asarray(F, dtype=np.float64))
    pairs = ((0, 1), (0, 2), (1, 2))
    fig, axes = plt.subplots(1, 3, figsize=(13.5, 4.4))
    markers = ["s", "^", "D", "v", "P"]
    for ax, (i, j) in zip(axes, pairs, strict=True):
        ax.scatter(F[:, i], F[:, j], s=14, c="#4c72b0", alpha=0.7, label="Pareto front")
        if chosen is not None:
            ax.scatter([chosen[i]], [chosen[j]], s=90, facecolors="none", edgecolors="#dd8452",
                       linewidths=2, label="chosen (NSGA-II)")
        if final is not None:
            ax.scatter([final[i]], [final[j]], s=90, marker="*", c="#c44e52", label="final (least shape under the fit)")
        for k, (name, f) in enumerate((baselines or {}).items()):
            ax.scatter([f[i]], [f[j]], s=50, marker=markers[k % len(markers)], c="#555555",
                       alpha=0.8, label=name)
        ax.set_xlabel(_NAMES[i])
        ax.set_ylabel(_NAMES[j])
        ax.set_xscale("symlog", linthresh=1e-2)
        ax.set_yscale("symlog", linthresh=1e-2)
        ax.grid(True, alpha=0.3)
    axes[0].legend(fontsize=7, loc="best")
    if title:
        fig.suptitle(title)
    fig.tight_layout()
    path = Path(path)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=110, format=path.suffix.lstrip(".") or "png")
    plt.close(fig)
    return path


def plot_fit_overlay(
    original: Sequence[Piece],
    graded: Sequence[Piece],
    path: str | os.PathLike,
    *,
    labels: tuple[str, str] = ("original", "graded"),
    title: str | None = None,
) -> Path:
    """Original and graded pieces overlaid (``pattern.png``).

    Uses :func:`patternbridge.io.plot.plot_overlay` when it is available and
    draws a plain overlay otherwise.
    """
    try:
        from .plot import plot_overlay
    except ImportError:  # pragma: no cover - the pattern plotter ships with io
        plot_overlay = None
    if plot_overlay is not None:
        return plot_overlay(original, graded, path, labels=labels, title=title)
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    n = len(original)
    fig, axes = plt.subplots(1, max(n, 1), figsize=(3.2 * max(n, 1), 4.2))
    axes = np.atleast_1d(axes)
    for ax, a, b in zip(axes, original, graded, strict=False):
        for piece, colour, label in ((a, "#888888", labels[0]), (b, "#c44e52", labels[1])):
            ring = np.vstack([piece.outline, piece.outline[:1]])
            ax.plot(ring[:, 0], ring[:, 1], color=colour, label=label)
        ax.set_aspect("equal")
        ax.set_title(a.name)
    axes[0].legend(fontsize=7)
    if title:
        fig.suptitle(title)
    fig.tight_layout()
    path = Path(path)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=110)
    plt.close(fig)
    return path
