"""Pictures of the dressed character: front, back and side views."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

__all__ = ["PIECE_COLOURS", "render_fit", "write_pictures"]

#: cloth colours per piece instance (muted fabric tones)
PIECE_COLOURS = np.array(
    [
        (70, 110, 160),
        (90, 130, 175),
        (60, 100, 140),
        (110, 140, 180),
        (80, 120, 150),
        (100, 120, 165),
        (75, 105, 150),
        (95, 125, 170),
        (85, 115, 155),
        (105, 135, 175),
    ],
    dtype=np.uint8,
)
_SKIN = np.array([222, 196, 178], dtype=np.uint8)
_FLAGGED = np.array([220, 30, 30], dtype=np.uint8)  # faces the verdict names


def render_fit(garment, character, view: str, size: tuple[int, int] = (700, 1000)) -> np.ndarray:
    """(H, W, 3) uint8 picture of the character wearing ``garment`` from ``view``.

    The faces the verdict names (``garment.flagged``: open seams, cloth
    through itself or the skin, torn stretch, cloth turned over) are red.
    """
    from ..mesh.render import render

    gv, gf = garment.vertices, garment.faces
    # draw the cloth a hair outside its true place so the skin never shows through coplanar spots
    bv = np.asarray(character.vertices)
    v = np.concatenate([bv, gv])
    f = np.concatenate([character.faces, gf + len(bv)])
    cloth = PIECE_COLOURS[garment.instance[gf[:, 0]] % len(PIECE_COLOURS)]
    if garment.flagged is not None:
        cloth = np.where(np.asarray(garment.flagged)[:, None], _FLAGGED, cloth)
    colours = np.concatenate([np.tile(_SKIN, (len(character.faces), 1)), cloth])
    lo, hi = bv.min(axis=0), bv.max(axis=0)
    c, half = (lo + hi) / 2, (hi - lo) / 2
    half[[0, 2]] = half[[0, 2]].max()
    return render(
        v,
        f,
        face_colors=colours,
        view=view,
        size=size,
        bounds=np.array([c - half, c + half]),
        title=f"{character.name} - {view}" + (f" - {garment.report.verdict}" if garment.report else ""),
    )


def write_pictures(out_dir: str | os.PathLike, garment, character) -> list[str]:
    """Write ``fit_front.png``, ``fit_back.png`` and ``fit_side.png``; return their names."""
    from ..mesh.render import save_png

    names = []
    for view in ("front", "back", "side"):
        name = f"fit_{view}.png"
        save_png(Path(out_dir) / name, render_fit(garment, character, view))
        names.append(name)
    return names
