"""The review picture of an inference: pieces upright, coloured by role, seams numbered.

Each piece is drawn turned upright (its :class:`~.model.Orientation`), filled
with its role's colour and labelled with its name, role and confidence; each
seam is drawn in one colour on both of its edges with the same number; fold
edges are dashed; anything below ``LOW_CONFIDENCE`` is labelled in red. A
person checks a garment by finding every number twice on edges that sew.
Rendered with Pillow (no matplotlib outside ``io/plot.py``); returns PNG bytes.
"""

from __future__ import annotations

import io

import numpy as np

from ..library.seams import sew_line
from ..pattern.model import Pattern
from .model import BridgeInference, Role

__all__ = ["LOW_CONFIDENCE", "review_png"]

LOW_CONFIDENCE = 0.6
_ROLE_FILL = {
    Role.FRONT: (214, 234, 248),
    Role.BACK: (213, 245, 227),
    Role.SLEEVE: (252, 243, 207),
    Role.LEG: (232, 218, 239),
    Role.LEG_FRONT: (232, 218, 239),
    Role.LEG_BACK: (215, 219, 239),
    Role.COLLAR: (250, 219, 216),
    Role.NECKBAND: (250, 229, 211),
    Role.NECK_BINDING: (250, 229, 211),
    Role.ARMHOLE_BINDING: (246, 221, 204),
    Role.CUFF: (237, 187, 153),
    Role.WAISTBAND: (237, 187, 153),
}
_PALETTE = [
    (31, 119, 180),
    (255, 127, 14),
    (44, 160, 44),
    (148, 103, 189),
    (140, 86, 75),
    (227, 119, 194),
    (127, 127, 127),
    (188, 189, 34),
    (23, 190, 207),
    (57, 59, 121),
    (99, 121, 57),
    (140, 109, 49),
]
RED = (214, 39, 40)


def _range(points: np.ndarray, s: int, e: int) -> np.ndarray:
    n = len(points)
    idx = np.arange(s, e + 1) if e > s else np.r_[s:n, 0 : e + 1]
    return points[idx]


def review_png(pattern: Pattern, inference: BridgeInference, *, px_per_cm: float = 6.0, title: str = "") -> bytes:
    """PNG bytes of the review picture of ``inference``."""
    from PIL import Image, ImageDraw

    upright = {p.name: inference.orientations[p.name].apply(sew_line(p)[0]) for p in pattern.pieces}
    # lay the pieces out left to right in rows, each in its own box
    gap, row_w, x, y, row_h = 8.0, 260.0, 0.0, 0.0, 0.0
    origin = {}
    for p in pattern.pieces:
        pts = upright[p.name]
        w, h = np.ptp(pts[:, 0]), np.ptp(pts[:, 1])
        if x > 0 and x + w > row_w:
            x, y, row_h = 0.0, y + row_h + gap + 6.0, 0.0
        origin[p.name] = np.array([x, -y]) - np.array([pts[:, 0].min(), pts[:, 1].max()])
        x, row_h = x + w + gap, max(row_h, h)
    width_cm, height_cm = row_w + 2 * gap, y + row_h + 2 * gap + 10.0
    k = px_per_cm
    img = Image.new("RGB", (int(width_cm * k), int(height_cm * k)), "white")
    draw = ImageDraw.Draw(img)

    def to_px(p_name: str, pts: np.ndarray) -> list[tuple[float, float]]:
        q = pts + origin[p_name]
        return [((gap + u) * k, (gap + 10.0 - v) * k) for u, v in q]

    chosen = set(inference.chosen)
    for p in pattern.pieces:
        guess = inference.roles[p.name]
        fill = _ROLE_FILL.get(guess.role, (235, 235, 235)) if p.name in chosen else (245, 245, 245)
        poly = to_px(p.name, upright[p.name])
        draw.polygon(poly, fill=fill, outline=(60, 60, 60))
        cx = float(np.mean([a for a, _ in poly]))
        cy = float(np.mean([b for _, b in poly]))
        colour = RED if guess.confidence < LOW_CONFIDENCE else (0, 0, 0)
        tag = "" if p.name in chosen else " (alternative)"
        draw.text((cx - 40, cy - 12), p.name[:24], fill=(0, 0, 0))
        draw.text((cx - 40, cy), f"{guess.role.value} {guess.confidence:.2f}{tag}", fill=colour)
    for number, j in enumerate(inference.joins, start=1):
        colour = _PALETTE[number % len(_PALETTE)]
        label_colour = RED if j.confidence < LOW_CONFIDENCE else colour
        sides = (j.a,) if j.a.key == j.b.key else (j.a, j.b)
        for side in sides:
            seg = to_px(side.piece, _range(upright[side.piece], side.start, side.end))
            if j.kind == "fold":
                for a, b in zip(seg[:-1:2], seg[1::2], strict=False):
                    draw.line([a, b], fill=(90, 90, 90), width=3)
                continue
            draw.line(seg, fill=colour, width=4)
            for end in (seg[0], seg[-1]):
                draw.ellipse([end[0] - 3, end[1] - 3, end[0] + 3, end[1] + 3], fill=colour)
            mid = seg[len(seg) // 2]
            text = f"{number}" + ("" if j.confidence >= LOW_CONFIDENCE else f" ({j.confidence:.2f})")
            draw.text((mid[0] + 4, mid[1] - 6), text, fill=label_colour)
    heading = (
        title or f"{pattern.style}: {len(inference.joins)} seams, lowest confidence {inference.lowest_confidence:.2f}"
    )
    draw.text((gap * k, 2 * k), heading, fill=(0, 0, 0))
    buf = io.BytesIO()
    img.save(buf, format="PNG", optimize=True)
    return buf.getvalue()
