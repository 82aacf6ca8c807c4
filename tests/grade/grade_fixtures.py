"""Hand-made two-piece skirt with bridge data, for the grader tests (imported by them)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from patternbridge.io.pattern_json import save_pattern_json
from patternbridge.pattern.model import (
    EdgeRange,
    Leg,
    Line,
    MeasurementLink,
    Notch,
    Pattern,
    Piece,
    Seam,
    VertexKind,
)


def skirt_piece(name: str, *, waist: float = 36.0, hem: float = 50.0, length: float = 60.0,
                hip_drop: float = 20.0, hip: float = 48.0) -> Piece:
    """A front/back skirt panel, CCW: hem left, hem right, up the right side, waist, down the left side."""
    hl, hr = (0.0, 0.0), (hem, 0.0)
    c = hem / 2
    side_r = [(c + hip / 2, length - hip_drop), (c + (hip / 2 + waist / 2) / 2 + 0.8, length - hip_drop / 2)]
    wr, wl = (c + waist / 2, length), (c - waist / 2, length)
    side_l = [(c - (hip / 2 + waist / 2) / 2 - 0.8, length - hip_drop / 2), (c - hip / 2, length - hip_drop)]
    mid_r = (c + (hem / 2 + hip / 2) / 2, (length - hip_drop) / 2)
    mid_l = (c - (hem / 2 + hip / 2) / 2, (length - hip_drop) / 2)
    pts = [hl, (c, 0.0), hr, mid_r, side_r[0], side_r[1], wr, (c, length), wl, side_l[0], side_l[1], mid_l]
    kinds = ["turn", "plain", "turn", "plain", "curve", "curve", "turn", "plain", "turn", "curve", "curve", "plain"]
    marks = {"hem_l": 0, "hem_r": 2, "hip_r": 4, "waist_r": 6, "waist_l": 8, "hip_l": 10}
    return Piece(
        name=name, outline=np.array(pts), kinds=[VertexKind(k) for k in kinds], marks=marks,
        notches=(Notch(vertex=4), Notch(vertex=10)),
        grain_line=Line(points=[[c, 10.0], [c, length - 10.0]]),
    )


def skirt_pattern(*, links: bool = True, seams: bool = True) -> Pattern:
    front = skirt_piece("front")
    back = skirt_piece("back")
    seam_list = (
        Seam(id="side_right", a=EdgeRange(piece="front", start="hem_r", end="waist_r"),
             b=EdgeRange(piece="back", start="waist_l", end="hem_l")),
        Seam(id="side_left", a=EdgeRange(piece="front", start="waist_l", end="hem_l"),
             b=EdgeRange(piece="back", start="hem_r", end="waist_r")),
    ) if seams else ()
    link_list = (
        MeasurementLink(measurement="waist_girth", ease_cm=2.0, legs=(
            Leg(piece="front", start="waist_r", end="waist_l"),
            Leg(piece="back", start="waist_r", end="waist_l"))),
        MeasurementLink(measurement="hip_girth", ease_cm=4.0, legs=(
            Leg(piece="front", start="hip_r", end="hip_l", along="chord"),
            Leg(piece="back", start="hip_r", end="hip_l", along="chord"))),
        MeasurementLink(measurement="waist_to_knee", legs=(
            Leg(piece="front", start="hem_r", end="waist_r"),)),
    ) if links else ()
    return Pattern(style="skirt", pieces=(front, back), seams=seam_list, measurements=link_list)


BODY = {"waist_girth": 84.0, "hip_girth": 104.0, "waist_to_knee": 55.0}


def write_skirt_inputs(folder: Path) -> tuple[Path, Path]:
    """``skirt.json`` (the skirt pattern) and ``hero.json`` (``BODY``) written into ``folder``: their paths."""
    pattern_path = folder / "skirt.json"
    save_pattern_json(skirt_pattern(), pattern_path)
    body_path = folder / "hero.json"
    body_path.write_text(json.dumps(BODY))
    return pattern_path, body_path



def half_panel(name: str, *, waist: float = 36.0, hem: float = 50.0, length: float = 60.0,
               hip_drop: float = 20.0, hip: float = 48.0) -> Piece:
    """Half a skirt panel with a straight centre edge on x = 0 (a centre front or back on the grain).

    CCW: centre hem, side hem, up the side, side waist, centre waist, down the centre line.
    """
    pts = [
        (0.0, 0.0), (hem / 4, 0.0), (hem / 2, 0.0),
        ((hem / 2 + hip / 2) / 2, (length - hip_drop) / 2), (hip / 2, length - hip_drop),
        ((hip / 2 + waist / 2) / 2 + 0.8, length - hip_drop / 2), (waist / 2, length),
        (0.0, length), (0.0, length - hip_drop), (0.0, (length - hip_drop) / 2),
    ]
    kinds = ["turn", "plain", "turn", "plain", "curve", "curve", "turn", "turn", "plain", "plain"]
    marks = {"centre_hem": 0, "side_hem": 2, "side_hip": 4, "side_waist": 6, "centre_waist": 7, "centre_hip": 8}
    return Piece(
        name=name, outline=np.array(pts), kinds=[VertexKind(k) for k in kinds], marks=marks,
        notches=(Notch(vertex=4),), grain_line=Line(points=[[5.0, 10.0], [5.0, length - 10.0]]),
    )


def half_skirt_pattern() -> Pattern:
    """Front and back halves cut with a straight centre edge; same measurements as :func:`skirt_pattern`."""
    front = half_panel("front")
    back = half_panel("back")
    seams = (
        Seam(id="side", a=EdgeRange(piece="front", start="side_hem", end="side_waist"),
             b=EdgeRange(piece="back", start="side_hem", end="side_waist")),
    )
    links = (
        MeasurementLink(measurement="waist_girth", ease_cm=2.0, legs=(
            Leg(piece="front", start="side_waist", end="centre_waist", factor=2.0),
            Leg(piece="back", start="side_waist", end="centre_waist", factor=2.0))),
        MeasurementLink(measurement="hip_girth", ease_cm=4.0, legs=(
            Leg(piece="front", start="side_hip", end="centre_hip", along="chord", factor=2.0),
            Leg(piece="back", start="side_hip", end="centre_hip", along="chord", factor=2.0))),
        MeasurementLink(measurement="waist_to_knee", legs=(
            Leg(piece="front", start="side_hem", end="side_waist"),)),
    )
    return Pattern(style="half_skirt", pieces=(front, back), seams=seams, measurements=links)
