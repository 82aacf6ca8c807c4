"""``read_dxf(unfold=True)`` on real half pieces: each size of the whole mirrors the same size of the half.

The check is independent of the unfolding code: the half is graded on its
own, reflected about the line through its own two fold ends *in that size*
(AccuMark nests move, and in ``WM LOOSE SHAPE TANK.DXF`` even turn, the fold
between sizes), and compared vertex by vertex with the graded whole piece.
"""

from __future__ import annotations

import numpy as np
import pytest

from patternbridge.io.dxf_aama import read_dxf
from patternbridge.pattern.grading import graded_outlines

pytestmark = pytest.mark.shared

HALF_PIECE_FILES = ["WM LOOSE SHAPE TANK.DXF", "GLX0924S16_NEW.DXF", "GMH1004F15-2.DXF", "mirrored.DXF"]


def _reflect(points: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    u = (b - a) / np.hypot(*(b - a))
    d = points - a
    return a + 2 * (d @ u)[:, None] * u - d


@pytest.mark.parametrize("name", HALF_PIECE_FILES)
def test_unfolded_sizes_are_mirror_images(aama_dir, name):
    half, _ = read_dxf(aama_dir / name)
    whole, report = read_dxf(aama_dir / name, unfold=True)
    folded = [p for p in half.pieces if p.mirror_line is not None]
    assert folded and report.codes().count("piece-unfolded") == len(folded)
    g_half, g_whole = graded_outlines(half), graded_outlines(whole)
    for piece in folded:
        n_half = len(piece.outline)
        n_whole = len(whole.piece(piece.name).outline)
        n_kept = (n_whole + 2) // 2  # the half from fold end to fold end; its inner vertices are mirrored
        assert 2 * n_kept - 2 == n_whole and n_kept <= n_half
        for size in half.sizes:
            h, w = g_half[size][piece.name], g_whole[size][piece.name]
            # the whole piece starts with the half (one fold end round to the other) ...
            start = int(np.argmin(np.linalg.norm(h - w[0], axis=1)))
            kept = h[(start + np.arange(n_kept)) % n_half]
            np.testing.assert_allclose(w[: len(kept)], kept, atol=1e-6)
            # ... then the images of its inner vertices about this size's fold, in reverse
            a, b = w[0], w[len(kept) - 1]
            np.testing.assert_allclose(w[len(kept):], _reflect(kept[1:-1][::-1], a, b), atol=1e-3,
                                       err_msg=f"{name} {piece.name} size {size}")


def test_tank_perimeter_at_largest_size_is_twice_the_half(aama_dir):
    """The loose tank front at size 52: the whole piece's perimeter is twice the half's less the fold."""
    half, _ = read_dxf(aama_dir / "WM LOOSE SHAPE TANK.DXF")
    whole, _ = read_dxf(aama_dir / "WM LOOSE SHAPE TANK.DXF", unfold=True)
    name = "RELAXED TANK FR V2"
    h = graded_outlines(half)["52"][name]
    w = graded_outlines(whole)["52"][name]
    assert abs(_perimeter(w) - (2 * _perimeter(h) - 2 * _fold_length(h, half.piece(name)))) < 1e-3


def _perimeter(p: np.ndarray) -> float:
    return float(np.sum(np.linalg.norm(np.roll(p, -1, axis=0) - p, axis=1)))


def _fold_length(graded: np.ndarray, piece) -> float:
    line = piece.mirror_line.points
    u = (line[1] - line[0]) / np.hypot(*(line[1] - line[0]))
    on = np.flatnonzero(np.abs((piece.outline - line[0]) @ np.array([-u[1], u[0]])) < 1e-3)
    return float(np.hypot(*(graded[on[0]] - graded[on[-1]])))
