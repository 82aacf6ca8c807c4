"""The review picture of an inference: pieces upright, coloured by role, seams numbered.

Each piece is drawn turned upright (its :class:`~.model.Orientation`), filled
with its role's colour and labelled with its name, role and confidence; each
seam is drawn in its own colour on both of its edges with the same number,
written just outside the edge (``n mirror`` for an edge sewn to the piece's
mirror copy); folds are dashed and marked ``fold``; the body landmarks the fit uses
are dots with their names, and a small front view of the body lists the
chosen pieces at the part each is placed on. A band the file draws along its grain (a cuff or
collar standing on its short side) is shown lying along the body; its
recorded orientation is unchanged. Anything below ``LOW_CONFIDENCE`` is written in
red with its value, and the list under the pieces repeats every seam with its
two pieces, kind and confidence. A person checks a garment by finding every
number twice on edges that sew. The pieces are packed in rows about as wide as
the picture is tall, so the canvas holds no empty band. Rendered with Pillow
(no matplotlib outside ``io/plot.py``); returns PNG bytes.
"""

from __future__ import annotations

import colorsys
import io
from dataclasses import dataclass

import numpy as np

from ..library.seams import sew_line
from ..pattern.model import Pattern
from .band_spans import split_bands
from .model import BridgeInference, Join, Role, is_band
from .size_chart import choose_chart

__all__ = ["LOW_CONFIDENCE", "review_png", "seam_colour", "seam_numbers"]

LOW_CONFIDENCE = 0.6
_ROLE_FILL = {
    Role.FRONT: (214, 234, 248),
    Role.BACK: (213, 245, 227),
    Role.SLEEVE: (252, 243, 207),
    Role.LEG: (232, 218, 239),
    Role.LEG_FRONT: (232, 218, 239),
    Role.LEG_BACK: (215, 219, 239),
    Role.COLLAR: (250, 219, 216),
    Role.COLLAR_STAND: (250, 219, 216),
    Role.NECKBAND: (250, 229, 211),
    Role.NECK_BINDING: (250, 229, 211),
    Role.ARMHOLE_BINDING: (246, 221, 204),
    Role.CUFF: (237, 206, 180),
    Role.WAISTBAND: (237, 206, 180),
    Role.YOKE: (226, 239, 218),
}
_OTHER_FILL = (232, 232, 232)
_ALTERNATIVE_FILL = (248, 248, 248)
RED = (214, 39, 40)
INK = (30, 30, 30)
GREY = (110, 110, 110)
#: cm between pieces, and around the drawing
GAP_CM = 6.0
#: a piece lower than this (cm) has its name written under it, in this much room (cm)
SMALL_CM = 8.0
LABEL_CM = 10.0


def seam_colour(number: int) -> tuple[int, int, int]:
    """A colour of its own for seam ``number`` (hues a golden angle apart, dark enough on a pale fill).

    Examples
    --------
    >>> seam_colour(1) != seam_colour(2)
    True
    """
    hue = (0.61803398875 * number) % 1.0
    value = 0.78 if number % 2 else 0.58
    r, g, b = colorsys.hsv_to_rgb(hue, 0.9, value)
    return int(255 * r), int(255 * g), int(255 * b)


def _font(size: int):
    from PIL import ImageFont

    try:
        return ImageFont.load_default(size=size)
    except TypeError:  # Pillow < 10.1 has only the bitmap font
        return ImageFont.load_default()


def _range(points: np.ndarray, s: int, e: int) -> np.ndarray:
    n = len(points)
    idx = np.arange(s, e + 1) if e > s else np.r_[s:n, 0 : e + 1]
    return points[idx]


def _shown(piece, inference: BridgeInference) -> np.ndarray:
    """The piece's upright sew line as drawn: a band standing on its short side is laid along the body."""
    pts = inference.orientations[piece.name].apply(sew_line(piece)[0])
    if is_band(inference.roles[piece.name].role) and np.ptp(pts[:, 1]) > np.ptp(pts[:, 0]):
        pts = pts[:, ::-1] * np.array([-1.0, 1.0])  # a quarter turn counter-clockwise
    return pts


def _outside(shape: np.ndarray, label_cm: float) -> bool:
    """Whether a piece's name goes under it: the piece is too low or too narrow to hold it."""
    return bool(np.ptp(shape[:, 1]) < SMALL_CM or np.ptp(shape[:, 0]) < label_cm)


def _layout(shapes: dict[str, np.ndarray], label_cm: dict[str, float]) -> tuple[dict[str, np.ndarray], float, float]:
    """Offsets (cm) packing the upright pieces in rows, tallest first; the drawing's width and height (cm).

    The row width is chosen so the drawing is about 1.6 times as wide as tall.
    """
    size = {n: (float(np.ptp(p[:, 0])), float(np.ptp(p[:, 1]))) for n, p in shapes.items()}
    size = {
        n: (max(w, label_cm[n]), h + LABEL_CM) if _outside(shapes[n], label_cm[n]) else (w, h)
        for n, (w, h) in size.items()
    }
    order = sorted(shapes, key=lambda n: -size[n][1])
    area = sum((w + GAP_CM) * (h + GAP_CM) for w, h in size.values())
    row_w = max(max(w for w, _ in size.values()), float(np.sqrt(1.6 * area)))
    origin, x, y, row_h, width = {}, 0.0, 0.0, 0.0, 0.0
    for n in order:
        w, h = size[n]
        if x > 0 and x + w > row_w:
            x, y, row_h = 0.0, y + row_h + GAP_CM, 0.0
        pts = shapes[n]
        origin[n] = np.array([x - pts[:, 0].min(), -y - pts[:, 1].max()])
        x, row_h = x + w + GAP_CM, max(row_h, h)
        width = max(width, x - GAP_CM)
    return origin, width, y + row_h


@dataclass(frozen=True, slots=True)
class _Canvas:
    """Centimetres on the drawing to pixels."""

    k: float
    top_px: float

    def px(self, pts: np.ndarray) -> list[tuple[float, float]]:
        return [((GAP_CM + u) * self.k, self.top_px - v * self.k) for u, v in pts]


def _label_at(draw, xy, text: str, fill, font) -> None:
    """``text`` centred on ``xy`` on a white box."""
    left, top, right, bottom = draw.textbbox((0, 0), text, font=font)
    w, h = right - left, bottom - top
    x, y = xy[0] - w / 2, xy[1] - h / 2
    draw.rectangle([x - 2, y - 1, x + w + 2, y + h + 2], fill=(255, 255, 255))
    draw.text((x - left, y - top), text, fill=fill, font=font)


def _outward(seg: list[tuple[float, float]], centre: tuple[float, float], gap_px: float) -> tuple[float, float]:
    """A point ``gap_px`` outside the middle of the drawn edge ``seg``, away from the piece's centre."""
    mid = np.array(seg[len(seg) // 2], dtype=np.float64)
    if len(seg) % 2 == 0 and len(seg) > 1:
        mid = (np.array(seg[len(seg) // 2 - 1]) + mid) / 2
    away = mid - np.array(centre)
    norm = float(np.linalg.norm(away))
    return tuple(mid + (away / norm if norm > 1e-9 else np.array([0.0, -1.0])) * gap_px)


def _piece_texts(name: str, inference: BridgeInference) -> tuple[str, str]:
    """The two lines written on a piece: its name, and its role with confidence (and whether it is an alternative)."""
    guess = inference.roles[name]
    tag = "" if name in inference.chosen else "  (alternative)"
    text = f"{guess.role.value} {guess.confidence:.2f}{tag}"
    return name[:28], text


def _draw_pieces(draw, pattern, inference, shapes, canvas, fonts, centres, label_cm) -> None:
    from shapely.geometry import Polygon

    chosen = set(inference.chosen)
    for p in pattern.pieces:
        guess = inference.roles[p.name]
        poly = canvas.px(shapes[p.name])
        fill = _ROLE_FILL.get(guess.role, _OTHER_FILL) if p.name in chosen else _ALTERNATIVE_FILL
        draw.polygon(poly, fill=fill, outline=(70, 70, 70))
        inside = Polygon(poly).buffer(0)
        spot = inside.representative_point() if not inside.is_empty else None
        cx, cy = (spot.x, spot.y) if spot is not None else poly[0]
        if _outside(shapes[p.name], label_cm[p.name]):  # too small to hold its name: written under it
            cx = float(np.mean([a for a, _ in poly]))
            cy = max(b for _, b in poly) + 38.0  # below the numbers of its lower edge
        centres[p.name] = (float(np.mean([a for a, _ in poly])), float(np.mean([b for _, b in poly])))
        role_ink = RED if guess.confidence < LOW_CONFIDENCE else INK
        name, role = _piece_texts(p.name, inference)
        _label_at(draw, (cx, cy - 9), name, INK, fonts["piece"])
        _label_at(draw, (cx, cy + 9), role, role_ink, fonts["piece"])


def _landmarks(pattern: Pattern, inference: BridgeInference) -> dict:
    """The inferred marks, landmarks and placement of every piece."""
    from .landmarks import piece_landmarks

    return piece_landmarks(pattern, inference)


#: where each body part sits on the placement diagram (x, y in px from its corner; front view, so the body's
#: right arm and leg are on the left)
_BODY_SPOTS = {
    ("neck", None): (60, 36),
    ("torso", "front"): (60, 62),
    ("torso", "back"): (60, 92),
    ("torso", "around"): (60, 112),
    ("right_arm", None): (22, 100),
    ("left_arm", None): (98, 100),
    ("right_leg", None): (46, 165),
    ("left_leg", None): (74, 165),
}
BODY_PX = (430, 210)


def _draw_body(draw, x0: float, y0: float, found: dict, inference: BridgeInference, fonts) -> None:
    """A small front view of the body with the chosen pieces listed at the part each is placed on."""
    line = {"fill": (150, 150, 150), "width": 3}
    draw.ellipse([x0 + 46, y0 + 4, x0 + 74, y0 + 32], outline=line["fill"], width=3)
    draw.rectangle([x0 + 35, y0 + 40, x0 + 85, y0 + 120], outline=line["fill"], width=3)
    for seg in (((35, 45), (15, 115)), ((85, 45), (105, 115)), ((48, 120), (44, 195)), ((72, 120), (76, 195))):
        draw.line([(x0 + u, y0 + v) for u, v in seg], **line)
    draw.text((x0, y0 - 16), "placement (front view)", fill=INK, font=fonts["small"])
    listed: dict[tuple[str, str | None], list[str]] = {}
    for name in inference.chosen:
        place = found.get(name).placement if found.get(name) is not None else None
        if place:
            part = place.get("body_part", "")
            key = (part, place.get("side")) if part == "torso" else (part, None)
            listed.setdefault(key, []).append(name)
    shown = [(key, spot) for key, spot in _BODY_SPOTS.items() if listed.get(key)]
    for row, (key, (u, v)) in enumerate(shown):
        names = listed[key]
        colour = _ROLE_FILL.get(inference.roles[names[0]].role, _OTHER_FILL)
        draw.ellipse([x0 + u - 5, y0 + v - 5, x0 + u + 5, y0 + v + 5], fill=colour, outline=INK)
        ty = y0 + 20 + 30 * row
        draw.line([(x0 + u + 5, y0 + v), (x0 + 125, ty + 7)], fill=(190, 190, 190), width=1)
        label = " ".join(k for k in key if k).replace("_", " ")
        draw.text((x0 + 128, ty), f"{label}: " + ", ".join(names), fill=INK, font=fonts["small"])


def _draw_landmarks(draw, found: dict, shapes, canvas, fonts) -> None:
    """Landmark dots with their names; a name that would overprint an earlier one moves down a line."""
    taken: list[tuple[float, float, float, float]] = []
    for name, lm in found.items():
        pts = canvas.px(shapes[name])
        for landmark, mark in lm.landmarks.items():
            vertex = lm.marks.get(mark)
            if vertex is None or vertex >= len(pts):
                continue
            x, y = pts[vertex]
            draw.ellipse([x - 3, y - 3, x + 3, y + 3], fill=INK)
            text = landmark.replace("_", " ")
            left, top, right, bottom = draw.textbbox((x + 5, y + 2), text, font=fonts["small"])
            shift = 0.0
            while shift < 60 and any(
                left < r and right > q and top + shift < b and bottom + shift > t for q, t, r, b in taken
            ):
                shift += bottom - top + 2
            taken.append((left, top + shift, right, bottom + shift))
            draw.text((x + 5, y + 2 + shift), text, fill=GREY, font=fonts["small"])


def _dashes(seg: list[tuple[float, float]], k: int, of: int, dash_px: float = 10.0) -> list[list[tuple[float, float]]]:
    """The ``k``-th of ``of`` interleaved dash sets along the polyline ``seg`` (an edge several seams share)."""
    pts = np.asarray(seg, dtype=np.float64)
    if of == 1 or len(pts) < 2:
        return [seg]
    d = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(pts, axis=0), axis=1))]
    out = []
    for s in np.arange(k * dash_px, d[-1], of * dash_px):
        t = np.r_[s, d[(d > s) & (d < s + dash_px)], min(s + dash_px, d[-1])]
        out.append(
            [(float(x), float(y)) for x, y in zip(np.interp(t, d, pts[:, 0]), np.interp(t, d, pts[:, 1]), strict=True)]
        )
    return out


def _draw_join(draw, number: int, j: Join, shapes, canvas, fonts, centres, shared) -> None:
    """One join on both of its edges; an edge sewn by several seams (a half cut twice) carries them dashed in turn."""
    colour = seam_colour(number)
    low = j.confidence < LOW_CONFIDENCE
    sides = (j.a,) if j.a.key == j.b.key else (j.a, j.b)
    for side in sides:
        seg = canvas.px(_range(shapes[side.piece], side.start, side.end))
        if j.kind == "fold":
            for a, b in zip(seg[:-1:2], seg[1::2], strict=False):
                draw.line([a, b], fill=GREY, width=3)
            _label_at(draw, _outward(seg, centres[side.piece], 12), "fold", GREY, fonts["seam"])
            continue
        numbers = shared.get(side.key, [number])
        for dash in _dashes(seg, numbers.index(number), len(numbers)):
            draw.line(dash, fill=colour, width=4 if j.kind != "band" else 3)
        for end in (seg[0], seg[-1]):
            draw.ellipse([end[0] - 3, end[1] - 3, end[0] + 3, end[1] + 3], fill=colour)
        if numbers[0] != number:
            continue  # the first of the seams sharing the edge writes all their numbers
        text = " / ".join(str(n) for n in numbers) + (" mirror" if len(sides) == 1 else "")
        text += f" ({j.confidence:.2f})" if low else ""
        _label_at(draw, _outward(seg, centres[side.piece], 14), text, RED if low else colour, fonts["seam"])


def seam_numbers(inference: BridgeInference) -> dict[str, int]:
    """Join id -> the number the review picture writes on both of its edges (folds are not numbered)."""
    return {j.id: n for n, j in _numbered(inference) if n}


def _numbered(inference: BridgeInference) -> list[tuple[int, Join]]:
    """The joins with the number the picture gives them: seams 1, 2, … in order; folds 0 (not numbered)."""
    out, number = [], 0
    for j in inference.joins:
        if j.kind != "fold":
            number += 1
        out.append((number if j.kind != "fold" else 0, j))
    return out


def _seam_list(inference: BridgeInference) -> list[tuple[str, tuple[int, int, int]]]:
    """One line per seam for the list under the pieces, red when uncertain."""
    lines = []
    for number, j in _numbered(inference):
        if j.kind == "fold":
            continue
        other = "its mirror copy" if j.a.key == j.b.key else f"{j.b.piece} {j.b.start}-{j.b.end}"
        text = f"{number}  {j.a.piece} {j.a.start}-{j.a.end}  ~  {other}   {j.kind} {j.confidence:.2f}"
        lines.append((text, RED if j.confidence < LOW_CONFIDENCE else seam_colour(number)))
    return lines


def review_png(pattern: Pattern, inference: BridgeInference, *, px_per_cm: float = 6.0, title: str = "") -> bytes:
    """PNG bytes of the review picture of ``inference`` (pieces upright, seams numbered on both edges).

    Bands are drawn as the sidecar writes them (:func:`.band_spans.split_bands`):
    one seam per range of the opening, numbered on the band's vertices with
    the joints inserted.
    """
    from PIL import Image, ImageDraw

    pattern, inference, _ = split_bands(pattern, inference)
    upright = {p.name: _shown(p, inference) for p in pattern.pieces}
    fonts = {"title": _font(18), "piece": _font(14), "seam": _font(14), "small": _font(11)}
    measure = ImageDraw.Draw(Image.new("RGB", (1, 1)))
    label_cm = {
        p.name: (max(measure.textlength(t, font=fonts["piece"]) for t in _piece_texts(p.name, inference)) + 8)
        / px_per_cm
        for p in pattern.pieces
    }
    origin, width_cm, height_cm = _layout(upright, label_cm)
    shapes = {n: pts + origin[n] for n, pts in upright.items()}
    k = px_per_cm
    listed = _seam_list(inference)
    head_px, line_px = 64.0, 17
    columns = max(1, int((width_cm + 2 * GAP_CM) * k - BODY_PX[0]) // 430)
    list_px = max((len(listed) + columns - 1) // columns * line_px + 20 if listed else 0, BODY_PX[1] + 30)
    n_seams = sum(j.kind != "fold" for j in inference.joins)
    heading = title or (
        f"{pattern.style}: {len(inference.chosen)} of {len(pattern.pieces)} pieces, "
        f"{n_seams} seam{'' if n_seams == 1 else 's'}, "
        f"lowest confidence {inference.lowest_confidence:.2f} (red: below {LOW_CONFIDENCE})"
    )
    title_px = ImageDraw.Draw(Image.new("RGB", (1, 1))).textlength(heading, font=fonts["title"])
    width_px = int(max((width_cm + 2 * GAP_CM) * k, title_px + 2 * GAP_CM * k, GAP_CM * k + columns * 430 + BODY_PX[0]))
    height_px = int(head_px + (height_cm + GAP_CM) * k + list_px)
    img = Image.new("RGB", (width_px, height_px), "white")
    draw = ImageDraw.Draw(img)
    canvas = _Canvas(k=k, top_px=head_px)
    centres: dict[str, tuple[float, float]] = {}
    _draw_pieces(draw, pattern, inference, shapes, canvas, fonts, centres, label_cm)
    shared: dict[tuple[str, int, int], list[int]] = {}
    for number, j in _numbered(inference):
        for side in {j.a.key: j.a, j.b.key: j.b}.values() if number else ():
            shared.setdefault(side.key, []).append(number)
    for number, j in _numbered(inference):
        _draw_join(draw, number, j, shapes, canvas, fonts, centres, shared)
    found = _landmarks(pattern, inference)
    _draw_landmarks(draw, found, shapes, canvas, fonts)
    draw.text((GAP_CM * k, 10), heading, fill=INK, font=fonts["title"])
    chart = choose_chart(pattern.sizes, pattern.sample_size)
    draw.text((GAP_CM * k, 36), f"ease read against {chart.why}", fill=INK, font=fonts["small"])
    y0 = head_px + (height_cm + GAP_CM) * k
    rows = (len(listed) + columns - 1) // columns if listed else 0
    for i, (text, colour) in enumerate(listed):
        col, row = divmod(i, rows)
        draw.text((GAP_CM * k + col * 430, y0 + row * line_px), text, fill=colour, font=fonts["small"])
    _draw_body(draw, GAP_CM * k + columns * 430, y0 + 16, found, inference, fonts)
    buf = io.BytesIO()
    img.save(buf, format="PNG", optimize=True)
    return buf.getvalue()
