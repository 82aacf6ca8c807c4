"""The measurement picture: front, back and side views with every tape drawn and labelled."""

from __future__ import annotations

import numpy as np

from ..mesh.character import Character
from .model import Measurements

__all__ = ["measurement_picture"]

_GIRTH = (200, 40, 40)
_LENGTH = (30, 90, 200)
_HEIGHT = (40, 140, 60)


def _short(mid: str) -> str:
    return (
        mid.replace("_girth", "")
        .replace("_left", " L")
        .replace("_right", " R")
        .replace("_", " ")
    )


def measurement_picture(
    character: Character,
    result: Measurements,
    *,
    size: tuple[int, int] = (560, 900),
    show_landmarks: bool = True,
) -> np.ndarray:
    """(H, 3W, 3) uint8: the character front, back and side with the tapes.

    Girths are red, surface lengths blue, heights green; every curve is
    labelled with its short name and value in cm. Landmarks are drawn as small
    black crosses when ``show_landmarks``.
    """
    from ..mesh.render import render_views

    polylines, labels, colors = [], [], []
    for mid, m in result.measurements.items():
        if len(m.polyline) < 2:
            continue
        polylines.append(m.polyline)
        labels.append(f"{_short(mid)} {m.value_cm:.1f}")
        colors.append(
            _GIRTH
            if m.kind == "girth"
            else (_HEIGHT if m.method == "vertical" else _LENGTH)
        )
    if show_landmarks:
        r = 0.004 * character.stature_cm
        for lm in result.landmarks.values():
            p = lm.position
            for axis in (np.array([r, 0, 0]), np.array([0, r, 0])):
                polylines.append(np.array([p - axis, p + axis]))
                labels.append("")
                colors.append((0, 0, 0))
    return render_views(
        character.vertices,
        character.faces,
        polylines=polylines,
        labels=labels,
        polyline_colors=colors,
        size=size,
        title=character.name,
        line_width_px=1.6,
    )
