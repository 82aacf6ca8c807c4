"""The measurement picture: front, back and side views with every tape drawn and labelled."""

from __future__ import annotations

import numpy as np

from ..mesh.character import Character
from .model import Measurements

__all__ = ["measurement_picture"]

_GIRTH = (200, 40, 40)
_LENGTH = (30, 90, 200)
_HEIGHT = (40, 140, 60)
_LOW = (235, 130, 0)  # landmarks of low confidence


def _short(mid: str) -> str:
    return (
        mid.replace("_girth", "")
        .replace("_left", " L")
        .replace("_right", " R")
        .replace("_", " ")
    )


def _landmark_mark(name: str, lm, r: float):
    """A small black cross; a low-confidence landmark gets a larger orange ring and its name."""
    p = lm.position
    lines = [np.array([p - a, p + a]) for a in (np.array([r, 0, 0]), np.array([0, r, 0]))]
    labels, colors = ["", ""], [(0, 0, 0), (0, 0, 0)]
    if lm.is_low_confidence:
        t = np.linspace(0.0, 2.0 * np.pi, 17)
        ring = p + 2.5 * r * np.column_stack([np.cos(t), np.sin(t), np.zeros_like(t)])
        lines.append(ring)
        labels.append(f"? {_short(name)} {lm.confidence:.2f}")
        colors.append(_LOW)
    return lines, labels, colors


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
    black crosses when ``show_landmarks``; a landmark of low confidence
    (:data:`~patternbridge.mesh.character.LOW_CONFIDENCE`) is circled in orange
    and labelled ``? name confidence``.
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
        for name, lm in result.landmarks.items():
            polylines_, labels_, colors_ = _landmark_mark(name, lm, r)
            polylines += polylines_
            labels += labels_
            colors += colors_
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
