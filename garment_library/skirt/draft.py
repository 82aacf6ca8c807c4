"""Skirt: the straight skirt block with two darts a side and a waistband.

Construction after Aldrich, *Metric Pattern Cutting for Women's Wear*, "the
basic skirt block": hip line at waist-to-hip below the waist, half front
hip = (hip + 4) / 4 + 0.5 cm, half back hip = (hip + 4) / 4 − 0.5 cm; the waist
(+2 cm ease) is shaped by 3 cm at each side seam and two darts per quarter
(front darts 9 and 8 cm long, back 14 and 12 cm); length waist to knee.
The front is cut once on the fold (drawn whole), the back as a pair with a
centre-back seam (zip above the hip notch). Run
``python garment_library/skirt/draft.py`` to regenerate the files.
"""

from __future__ import annotations

from pathlib import Path

from patternbridge.library.draft import OutlineBuilder, hermite
from patternbridge.library.garment import (
    PieceDraft,
    band_draft,
    build_pattern,
    fold_front_skirt,
    leg,
    link,
    seam,
)
from patternbridge.library.sizes import WOMEN
from patternbridge.pattern.fabric import FabricClass
from patternbridge.pattern.model import Placement, Quantity

CHART = WOMEN.relabel("waist_girth")
HIP_EASE, WAIST_EASE = 4.0, 2.0
SIDE_SHAPING = 3.0
HEM_ALLOWANCE, CB_ALLOWANCE = 4.0, 1.5
BAND_CM = 3.5


def _geometry(b):
    g = {"y_hip": -b["waist_to_hip"], "y_hem": -b["waist_to_knee"]}
    g["hf"] = (b["hip_girth"] + HIP_EASE) / 4 + 0.5
    g["hb"] = (b["hip_girth"] + HIP_EASE) / 4 - 0.5
    g["fw"] = (b["waist_girth"] + WAIST_EASE) / 4 + 0.5
    g["bw"] = (b["waist_girth"] + WAIST_EASE) / 4 - 0.5
    g["xf"], g["xb"] = g["hf"] - SIDE_SHAPING, g["hb"] - SIDE_SHAPING
    g["dart_f"] = (g["xf"] - g["fw"]) / 2
    g["dart_b"] = (g["xb"] - g["bw"]) / 2
    return g


def front(b, g) -> PieceDraft:
    xs, hf, df = g["xf"], g["hf"], g["dart_f"]
    c1, c2 = 0.36 * xs, 0.62 * xs
    o = OutlineBuilder()
    o.start((0.0, g["y_hem"]), "cf_hem")
    o.line((hf, g["y_hem"]), "side_hem_left", allowance_cm=HEM_ALLOWANCE)
    o.line((hf, g["y_hip"]), "side_hip_left", notch=True)
    o.polyline(
        hermite(o.current, (0.0, 1.0), (xs, 0.0), (-0.3, 1.0), 8), "side_waist_left"
    )
    o.darted_line(
        (0.0, 0.0),
        "cf_waist",
        [(xs - c2, df, 8.0, "dart2_left"), (xs - c1, df, 9.0, "dart1_left")],
    )
    o.darted_line(
        (-xs, 0.0),
        "side_waist_right",
        [(c1, df, 9.0, "dart1_right"), (c2, df, 8.0, "dart2_right")],
    )
    o.polyline(
        hermite(o.current, (-0.3, -1.0), (-hf, g["y_hip"]), (0.0, -1.0), 8),
        "side_hip_right",
        notch=True,
    )
    o.line((-hf, g["y_hem"]), "side_hem_right")
    net = o.close(allowance_cm=HEM_ALLOWANCE)
    return fold_front_skirt("front", net, g["y_hem"], g["y_hip"])


def back(b, g) -> PieceDraft:
    xs, hb, db = g["xb"], g["hb"], g["dart_b"]
    c1, c2 = 0.36 * xs, 0.62 * xs
    o = OutlineBuilder()
    o.start((0.0, g["y_hip"]), "cb_hip", notch=True)
    o.line((0.0, g["y_hem"]), "cb_hem", allowance_cm=CB_ALLOWANCE)
    o.line((hb, g["y_hem"]), "side_hem", allowance_cm=HEM_ALLOWANCE)
    o.line((hb, g["y_hip"]), "side_hip", notch=True)
    o.polyline(hermite(o.current, (0.0, 1.0), (xs, 0.0), (-0.3, 1.0), 8), "side_waist")
    o.darted_line(
        (0.0, 0.0),
        "cb_waist",
        [(xs - c2, db, 12.0, "dart2"), (xs - c1, db, 14.0, "dart1")],
    )
    net = o.close(allowance_cm=CB_ALLOWANCE)
    return PieceDraft(
        name="back",
        net=net,
        quantity=Quantity(right=1, left=1),
        grain=((hb / 2, g["y_hem"] + 10), (hb / 2, g["y_hip"])),
        placement=Placement(
            body_part="torso", side="back", anchor="waist_back", anchor_mark="cb_waist"
        ),
        landmarks={
            "waist_back": "cb_waist",
            "waist_side_right": "side_waist",
            "hip_side_right": "side_hip",
        },
        category="BACK",
        annotation="SKIRT BACK",
    )


def _band(fr, bk):
    parts = [
        (bk, "primary", "dart1_b", "cb_waist", None),
        (bk, "primary", "dart2_b", "dart1_a", None),
        (bk, "primary", "side_waist", "dart2_a", "side_right"),
        (fr, "primary", "dart2_right_b", "side_waist_right", None),
        (fr, "primary", "dart1_right_b", "dart2_right_a", None),
        (fr, "primary", "cf_waist", "dart1_right_a", "cf"),
        (fr, "primary", "dart1_left_b", "cf_waist", None),
        (fr, "primary", "dart2_left_b", "dart1_left_a", None),
        (fr, "primary", "side_waist_left", "dart2_left_a", "side_left"),
        (bk, "mirror", "side_waist", "dart2_a", None),
        (bk, "mirror", "dart2_b", "dart1_a", None),
        (bk, "mirror", "dart1_b", "cb_waist", None),
    ]
    return band_draft(
        "waistband",
        parts,
        BAND_CM,
        placement=Placement(
            body_part="torso", side="around", anchor="waist_front", anchor_mark="cf"
        ),
        landmarks={
            "waist_front": "cf",
            "waist_side_right": "side_right",
            "waist_side_left": "side_left",
        },
        ends=("cb_right", "cb_left"),
        annotation="WAISTBAND (CUT 1, OPENS AT CENTRE BACK)",
    )


def draft(b):
    g = _geometry(b)
    fr, bk = front(b, g), back(b, g)
    band, _ = _band(fr, bk)
    return [fr, bk, band]


def seams():
    g = _geometry(CHART.body(CHART.sample_size))
    fr, bk = front(None, g), back(None, g)
    _, band_seams = _band(fr, bk)
    out = [
        seam(
            "side_right",
            ("front", "side_waist_right", "side_hem_right"),
            ("back", "side_hem", "side_waist"),
        ),
        seam(
            "side_left",
            ("front", "side_hem_left", "side_waist_left"),
            ("back", "side_hem", "side_waist", "mirror"),
        ),
        seam(
            "centre_back",
            ("back", "cb_waist", "cb_hem"),
            ("back", "cb_waist", "cb_hem", "mirror"),
        ),
    ]
    for d in ("dart1_left", "dart2_left", "dart1_right", "dart2_right"):
        out.append(
            seam(
                f"front_{d}",
                ("front", f"{d}_a", f"{d}_apex"),
                ("front", f"{d}_apex", f"{d}_b"),
            )
        )
    for d in ("dart1", "dart2"):
        for side, copy in (("right", "primary"), ("left", "mirror")):
            out.append(
                seam(
                    f"back_{d}_{side}",
                    ("back", f"{d}_a", f"{d}_apex", copy),
                    ("back", f"{d}_apex", f"{d}_b", copy),
                )
            )
    return out + band_seams


def _waist_legs():
    legs = []
    for s, e in (
        ("side_waist_left", "dart2_left_a"),
        ("dart2_left_b", "dart1_left_a"),
        ("dart1_left_b", "cf_waist"),
        ("cf_waist", "dart1_right_a"),
        ("dart1_right_b", "dart2_right_a"),
        ("dart2_right_b", "side_waist_right"),
    ):
        legs.append(leg("front", s, e, "boundary"))
    for s, e in (
        ("side_waist", "dart2_a"),
        ("dart2_b", "dart1_a"),
        ("dart1_b", "cb_waist"),
    ):
        legs.append(leg("back", s, e, "boundary", 2))
    return legs


LINKS = [
    link("waist_girth", WAIST_EASE, *_waist_legs()),
    link(
        "hip_girth",
        HIP_EASE,
        leg("front", "side_hip_right", "side_hip_left"),
        leg("back", "cb_hip", "side_hip", factor=2),
    ),
    link(
        "waist_to_hip",
        None,
        leg("front", "side_waist_right", "side_hip_right", "boundary"),
    ),
    # the length (waist to knee) no fitting measurement fixes: it keeps the
    # design's proportion to the body's height
    link(
        "stature",
        None,
        leg("front", "side_waist_right", "side_hem_right", "boundary"),
        link_id="skirt_length",
        proportional=True,
    ),
]

DESCRIPTION = "Straight skirt: front cut on the fold, back pair with centre-back zip, two darts a side, waistband"


def build():
    return build_pattern(
        style="skirt",
        description=DESCRIPTION,
        chart=CHART,
        draft=draft,
        seams=seams(),
        links=LINKS,
        fabric_class=FabricClass.WOVEN,
        fabric_why="drafted for a woven: darts and a zip",
    )


if __name__ == "__main__":
    from patternbridge.library.catalogue import write_garment

    write_garment(build(), Path(__file__).resolve().parent)
