"""Dress: a fitted (tight) sleeveless sheath dress with a waist seam.

Construction after Aldrich, *Metric Pattern Cutting for Women's Wear*, the
close-fitting bodice block and the straight skirt block joined at the waist:
scye depth + 1 cm from the nape, half back at the chest = bust / 4 − 1 cm,
half front = bust / 4 + 1 cm, back neck width = neck / 5 − 0.5 cm, front neck
depth = neck / 6 + 2 cm, one waist dart a side in front (on the bust line, half
the bust span from the centre front, 2 cm below the bust point) and behind;
the skirt darts continue the bodice darts so the waist seam matches, the hip
has +2 cm ease and the hem is pegged 1 cm a side. Ease: bust 0, waist 0 (a
stretch fabric: the dress is tight). Front pieces are cut on the fold, backs
as pairs with a centre-back zip seam. Run ``python garment_library/dress/draft.py``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from patternbridge.library.blocks import armhole_controls, neckline_controls
from patternbridge.library.draft import OutlineBuilder, bezier, hermite
from patternbridge.library.garment import (
    PieceDraft,
    build_pattern,
    fold_front_skirt,
    leg,
    link,
    seam,
)
from patternbridge.library.sizes import WOMEN
from patternbridge.pattern.fabric import FabricClass
from patternbridge.pattern.model import Placement, Quantity, VertexKind

CHART = WOMEN
BUST_EASE, WAIST_EASE, HIP_EASE = 0.0, 0.0, 2.0
SIDE_SHAPING = 1.5
EDGE_ALLOWANCE, HEM_ALLOWANCE, CB_ALLOWANCE = 0.6, 3.0, 1.5
CURVE = VertexKind.CURVE
LEFT = np.array([-1.0, 1.0])


def _geometry(b):
    g = {"y_nape": b["scye_depth"] + 1.0}
    g["y_w"] = g["y_nape"] - b["back_length"]
    g["fwc"] = (b["chest_girth"] + BUST_EASE) / 4 + 1.0
    g["bwc"] = (b["chest_girth"] + BUST_EASE) / 4 - 1.0
    g["xsf"], g["xsb"] = g["fwc"] - SIDE_SHAPING, g["bwc"] - SIDE_SHAPING
    g["dart_f"] = g["xsf"] - ((b["waist_girth"] + WAIST_EASE) / 4 + 0.5)
    g["dart_b"] = g["xsb"] - ((b["waist_girth"] + WAIST_EASE) / 4 - 0.5)
    g["dart_fx"] = b["bust_span"] / 2
    g["dart_bx"] = 0.5 * g["xsb"]
    g["nw"] = b["neck_girth"] / 5 - 0.5
    sl = b["shoulder_length_right"]
    g["b_snp"] = np.array([g["nw"], g["y_nape"] + 2.0])
    g["b_sp"] = g["b_snp"] + np.array([np.sqrt(sl**2 - 4.0**2), -4.0])
    g["f_snp"] = g["b_snp"].copy()
    g["f_sp"] = g["f_snp"] + np.array([np.sqrt(sl**2 - 5.0**2), -5.0])
    g["y_cfn"] = g["y_w"] + b["front_length"]
    g["b_ab"] = np.array([b["back_width"] / 2, 0.42 * g["b_sp"][1]])
    g["f_ac"] = np.array([b["back_width"] / 2 - 1.0, 0.40 * g["f_sp"][1]])
    g["y_apex"] = -2.0
    # skirt
    g["hf"] = (b["hip_girth"] + HIP_EASE) / 4 + 1.0
    g["hb"] = (b["hip_girth"] + HIP_EASE) / 4 - 1.0
    g["y_hip"] = -b["waist_to_hip"]
    g["y_hem"] = -b["waist_to_knee"]
    return g


def bodice_front(b, g) -> PieceDraft:
    neck = neckline_controls((0.0, g["y_cfn"]), g["f_snp"], g["f_sp"] - g["f_snp"])
    up, low = armhole_controls(g["f_sp"], g["f_ac"], (g["fwc"], 0.0))
    dl = g["y_apex"] - g["y_w"]
    o = OutlineBuilder()
    o.start((0.0, g["y_cfn"]), "centre_neck", notch=True)
    o.polyline(
        bezier(*(neck * LEFT), 8), "neck_side_right", allowance_cm=EDGE_ALLOWANCE
    )
    o.line(g["f_sp"] * LEFT, "shoulder_point_right")
    o.polyline(
        bezier(*(up * LEFT), 8),
        "armhole_notch_right",
        notch=True,
        end_kind=CURVE,
        allowance_cm=EDGE_ALLOWANCE,
    )
    o.polyline(
        bezier(*(low * LEFT), 8), "side_underarm_right", allowance_cm=EDGE_ALLOWANCE
    )
    o.line((-g["xsf"], g["y_w"]), "side_waist_right")
    w, x = g["dart_f"], g["dart_fx"]
    o.darted_line((0.0, g["y_w"]), "cf_waist", [(g["xsf"] - x, w, dl, "dart_right")])
    o.darted_line((g["xsf"], g["y_w"]), "side_waist_left", [(x, w, dl, "dart_left")])
    o.line((g["fwc"], 0.0), "side_underarm_left")
    o.polyline(
        bezier(*low[::-1], 8),
        "armhole_notch_left",
        notch=True,
        end_kind=CURVE,
        allowance_cm=EDGE_ALLOWANCE,
    )
    o.polyline(bezier(*up[::-1], 8), "shoulder_point_left", allowance_cm=EDGE_ALLOWANCE)
    o.line(g["f_snp"], "neck_side_left")
    o.polyline(bezier(*neck[::-1], 8)[:-1], end_kind=CURVE, allowance_cm=EDGE_ALLOWANCE)
    net = o.close(allowance_cm=EDGE_ALLOWANCE)
    return PieceDraft(
        name="bodice_front",
        net=net,
        quantity=Quantity(right=1, left=0),
        grain=((0.0, g["y_w"] + 4), (0.0, g["y_cfn"] - 4)),
        placement=Placement(
            body_part="torso",
            side="front",
            anchor="front_neck_point",
            anchor_mark="centre_neck",
        ),
        landmarks={
            "front_neck_point": "centre_neck",
            "neck_shoulder_point_right": "neck_side_right",
            "neck_shoulder_point_left": "neck_side_left",
            "shoulder_point_right": "shoulder_point_right",
            "shoulder_point_left": "shoulder_point_left",
            "waist_front": "cf_waist",
            "waist_side_right": "side_waist_right",
            "waist_side_left": "side_waist_left",
        },
        category="FRONT",
        annotation="BODICE FRONT (CUT 1 ON FOLD)",
    )


def bodice_back(b, g) -> PieceDraft:
    neck = neckline_controls((0.0, g["y_nape"]), g["b_snp"], g["b_sp"] - g["b_snp"])
    up, low = armhole_controls(g["b_sp"], g["b_ab"], (g["bwc"], 0.0))
    o = OutlineBuilder()
    o.start((0.0, g["y_nape"]), "cb_neck", notch=True)
    o.line((0.0, 0.0), "cb_chest", allowance_cm=CB_ALLOWANCE)
    o.line((0.0, g["y_w"]), "cb_waist", allowance_cm=CB_ALLOWANCE)
    o.darted_line(
        (g["xsb"], g["y_w"]), "side_waist", [(g["dart_bx"], g["dart_b"], 14.0, "dart")]
    )
    o.line((g["bwc"], 0.0), "side_underarm")
    o.polyline(
        bezier(*low[::-1], 8),
        "armhole_notch",
        notch=True,
        end_kind=CURVE,
        allowance_cm=EDGE_ALLOWANCE,
    )
    o.polyline(bezier(*up[::-1], 8), "shoulder_point", allowance_cm=EDGE_ALLOWANCE)
    o.line(g["b_snp"], "neck_side")
    o.polyline(bezier(*neck[::-1], 8)[:-1], end_kind=CURVE, allowance_cm=EDGE_ALLOWANCE)
    net = o.close(allowance_cm=EDGE_ALLOWANCE)
    return PieceDraft(
        name="bodice_back",
        net=net,
        quantity=Quantity(right=1, left=1),
        grain=((g["bwc"] / 2, g["y_w"] + 4), (g["bwc"] / 2, g["y_nape"] - 8)),
        placement=Placement(
            body_part="torso",
            side="back",
            anchor="back_neck_point",
            anchor_mark="cb_neck",
        ),
        landmarks={
            "back_neck_point": "cb_neck",
            "neck_shoulder_point_right": "neck_side",
            "shoulder_point_right": "shoulder_point",
            "waist_back": "cb_waist",
            "waist_side_right": "side_waist",
        },
        category="BACK",
        annotation="BODICE BACK",
    )


def skirt_front(b, g) -> PieceDraft:
    xs, hf, w, x = g["xsf"], g["hf"], g["dart_f"], g["dart_fx"]
    o = OutlineBuilder()
    o.start((0.0, g["y_hem"]), "cf_hem")
    o.line((hf - 1.0, g["y_hem"]), "side_hem_left", allowance_cm=HEM_ALLOWANCE)
    o.line((hf, g["y_hip"]), "side_hip_left", notch=True)
    o.polyline(
        hermite(o.current, (0.0, 1.0), (xs, 0.0), (-0.3, 1.0), 8), "side_waist_left"
    )
    o.darted_line((0.0, 0.0), "cf_waist", [(xs - x, w, 9.0, "dart_left")])
    o.darted_line((-xs, 0.0), "side_waist_right", [(x, w, 9.0, "dart_right")])
    o.polyline(
        hermite(o.current, (-0.3, -1.0), (-hf, g["y_hip"]), (0.0, -1.0), 8),
        "side_hip_right",
        notch=True,
    )
    o.line((-hf + 1.0, g["y_hem"]), "side_hem_right")
    net = o.close(allowance_cm=HEM_ALLOWANCE)
    return fold_front_skirt("skirt_front", net, g["y_hem"], g["y_hip"])


def skirt_back(b, g) -> PieceDraft:
    xs, hb = g["xsb"], g["hb"]
    o = OutlineBuilder()
    o.start((0.0, g["y_hip"]), "cb_hip", notch=True)
    o.line((0.0, g["y_hem"]), "cb_hem", allowance_cm=CB_ALLOWANCE)
    o.line((hb - 1.0, g["y_hem"]), "side_hem", allowance_cm=HEM_ALLOWANCE)
    o.line((hb, g["y_hip"]), "side_hip", notch=True)
    o.polyline(hermite(o.current, (0.0, 1.0), (xs, 0.0), (-0.3, 1.0), 8), "side_waist")
    o.darted_line(
        (0.0, 0.0), "cb_waist", [(xs - g["dart_bx"], g["dart_b"], 13.0, "dart")]
    )
    net = o.close(allowance_cm=CB_ALLOWANCE)
    return PieceDraft(
        name="skirt_back",
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


def draft(b):
    g = _geometry(b)
    return [bodice_front(b, g), bodice_back(b, g), skirt_front(b, g), skirt_back(b, g)]


def _seams():
    out = [
        seam(
            "shoulder_right",
            ("bodice_front", "neck_side_right", "shoulder_point_right"),
            ("bodice_back", "shoulder_point", "neck_side"),
        ),
        seam(
            "shoulder_left",
            ("bodice_front", "shoulder_point_left", "neck_side_left"),
            ("bodice_back", "shoulder_point", "neck_side", "mirror"),
        ),
        seam(
            "bodice_side_right",
            ("bodice_front", "side_underarm_right", "side_waist_right"),
            ("bodice_back", "side_waist", "side_underarm"),
        ),
        seam(
            "bodice_side_left",
            ("bodice_front", "side_waist_left", "side_underarm_left"),
            ("bodice_back", "side_waist", "side_underarm", "mirror"),
        ),
        seam(
            "skirt_side_right",
            ("skirt_front", "side_waist_right", "side_hem_right"),
            ("skirt_back", "side_hem", "side_waist"),
        ),
        seam(
            "skirt_side_left",
            ("skirt_front", "side_hem_left", "side_waist_left"),
            ("skirt_back", "side_hem", "side_waist", "mirror"),
        ),
        seam(
            "bodice_centre_back",
            ("bodice_back", "cb_neck", "cb_waist"),
            ("bodice_back", "cb_neck", "cb_waist", "mirror"),
        ),
        seam(
            "skirt_centre_back",
            ("skirt_back", "cb_waist", "cb_hem"),
            ("skirt_back", "cb_waist", "cb_hem", "mirror"),
        ),
        seam(
            "waist_front_right",
            ("bodice_front", "side_waist_right", "dart_right_a"),
            ("skirt_front", "dart_right_b", "side_waist_right"),
        ),
        seam(
            "waist_front_centre",
            ("bodice_front", "dart_right_b", "dart_left_a"),
            ("skirt_front", "dart_left_b", "dart_right_a"),
        ),
        seam(
            "waist_front_left",
            ("bodice_front", "dart_left_b", "side_waist_left"),
            ("skirt_front", "side_waist_left", "dart_left_a"),
        ),
    ]
    for side, copy in (("right", "primary"), ("left", "mirror")):
        out += [
            seam(
                f"waist_back_centre_{side}",
                ("bodice_back", "cb_waist", "dart_a", copy),
                ("skirt_back", "dart_b", "cb_waist", copy),
            ),
            seam(
                f"waist_back_side_{side}",
                ("bodice_back", "dart_b", "side_waist", copy),
                ("skirt_back", "side_waist", "dart_a", copy),
            ),
            seam(
                f"bodice_back_dart_{side}",
                ("bodice_back", "dart_a", "dart_apex", copy),
                ("bodice_back", "dart_apex", "dart_b", copy),
            ),
            seam(
                f"skirt_back_dart_{side}",
                ("skirt_back", "dart_a", "dart_apex", copy),
                ("skirt_back", "dart_apex", "dart_b", copy),
            ),
        ]
    for piece in ("bodice_front", "skirt_front"):
        for d in ("dart_right", "dart_left"):
            out.append(
                seam(
                    f"{piece}_{d}",
                    (piece, f"{d}_a", f"{d}_apex"),
                    (piece, f"{d}_apex", f"{d}_b"),
                )
            )
    return out


SEAMS = _seams()

LINKS = [
    link(
        "chest_girth",
        BUST_EASE,
        leg("bodice_front", "side_underarm_right", "side_underarm_left"),
        leg("bodice_back", "cb_chest", "side_underarm", factor=2),
    ),
    link(
        "waist_girth",
        WAIST_EASE,
        leg("bodice_front", "side_waist_right", "dart_right_a", "boundary"),
        leg("bodice_front", "dart_right_b", "dart_left_a", "boundary"),
        leg("bodice_front", "dart_left_b", "side_waist_left", "boundary"),
        leg("bodice_back", "cb_waist", "dart_a", "boundary", 2),
        leg("bodice_back", "dart_b", "side_waist", "boundary", 2),
    ),
    link(
        "hip_girth",
        HIP_EASE,
        leg("skirt_front", "side_hip_right", "side_hip_left"),
        leg("skirt_back", "cb_hip", "side_hip", factor=2),
    ),
    link("back_length", None, leg("bodice_back", "cb_neck", "cb_waist", "boundary")),
    link("front_length", None, leg("bodice_front", "centre_neck", "cf_waist")),
    link(
        "shoulder_length_right",
        None,
        leg("bodice_front", "neck_side_right", "shoulder_point_right"),
    ),
    link(
        "waist_to_hip",
        None,
        leg("skirt_front", "side_waist_right", "side_hip_right", "boundary"),
    ),
    # the skirt's length keeps the design's proportion to the body's height
    link(
        "stature",
        None,
        leg("skirt_front", "side_waist_right", "side_hem_right", "boundary"),
        link_id="skirt_length",
        proportional=True,
    ),
]

DESCRIPTION = (
    "Fitted sleeveless sheath dress (stretch, no ease): "
    "darted bodice and skirt joined at the waist, centre-back zip"
)


def build():
    return build_pattern(
        style="dress",
        description=DESCRIPTION,
        chart=CHART,
        draft=draft,
        seams=SEAMS,
        links=LINKS,
        fabric_class=FabricClass.WOVEN,
        fabric_why="drafted for a woven with a little stretch: darts and a zip",
    )


if __name__ == "__main__":
    from patternbridge.library.catalogue import write_garment

    write_garment(build(), Path(__file__).resolve().parent)
