"""Shorts: the trouser block cut 20 cm below the crotch (front, back with dart, waistband).

The top of the classic trouser block (``garment_library/trousers/draft.py``,
after Aldrich) is kept: crotch depth, seat line, forks, back dart, waistband;
the leg runs nearly straight from the seat to a hem 20 cm below the crotch
line, with a thigh line (notched) half-way. Ease: seat +6 cm, waist +2 cm.
Run ``python garment_library/shorts/draft.py`` to regenerate the files.
"""

from __future__ import annotations

import runpy
from pathlib import Path

from patternbridge.library.garment import build_pattern, leg, link
from patternbridge.library.sizes import MEN
from patternbridge.pattern.fabric import FabricClass

_TROUSERS = runpy.run_path(
    str(Path(__file__).resolve().parents[1] / "trousers" / "draft.py")
)
CHART = MEN.relabel("waist_girth")
LEG_BELOW_CROTCH = 20.0


def _geometry(b):
    g = _TROUSERS["_geometry"](b)
    g["y_knee"] = -LEG_BELOW_CROTCH / 2
    g["y_hem"] = -LEG_BELOW_CROTCH
    g["kf"] = g["hf"] + g["ef"] - 2.0
    g["kb"] = (
        g["kf"] + 8.0
    )  # a fuller back thigh keeps the short back inside leg from slanting
    g["hemf"] = g["kf"] - 1.0
    g["hemb"] = g["kb"] - 1.0
    return g


def draft(b):
    g = _geometry(b)
    f = _TROUSERS["front"](b, g, knee="thigh", style="SHORTS")
    k = _TROUSERS["back"](b, g, knee="thigh", style="SHORTS")
    return [f, k, _TROUSERS["waistband"](b, g, f, k)]


SEAMS = list(_TROUSERS["SEAMS"])

LINKS = [
    link(
        "waist_girth",
        _TROUSERS["WAIST_EASE"],
        leg("front", "cf_waist", "side_waist", "boundary", 2),
        leg("back", "side_waist", "dart_side", "boundary", 2),
        leg("back", "dart_cb", "cb_waist", "boundary", 2),
    ),
    link(
        "hip_girth",
        _TROUSERS["HIP_EASE"],
        leg("front", "cf_hip", "side_hip", factor=2),
        leg("back", "cb_hip", "side_hip", factor=2),
    ),
    link(
        "crotch_length",
        None,
        leg("front", "crotch_point", "cf_waist", "boundary"),
        leg("back", "cb_waist", "crotch_point", "boundary"),
    ),
    link("waist_to_hip", None, leg("front", "side_waist", "side_hip", "boundary")),
    # the leg's length below the crotch keeps the design's proportion to the
    # body's outside leg
    link(
        "outside_leg_right",
        None,
        leg("front", "side_waist", "side_hem", "boundary"),
        link_id="side_length",
        proportional=True,
    ),
    link(
        "thigh_girth_right",
        None,
        leg("front", "side_crotch", "crotch_point"),
        leg("back", "crotch_point", "side_crotch"),
    ),
]

DESCRIPTION = "Shorts: trouser-block front and back (back dart) ending 20 cm below the crotch, straight waistband"


def build():
    return build_pattern(
        style="shorts",
        description=DESCRIPTION,
        chart=CHART,
        draft=draft,
        seams=SEAMS,
        links=LINKS,
        fabric_class=FabricClass.WOVEN,
        fabric_why="drafted for a woven twill",
    )


if __name__ == "__main__":
    from patternbridge.library.catalogue import write_garment

    write_garment(build(), Path(__file__).resolve().parent)
