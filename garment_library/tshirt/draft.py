"""T-shirt: the knit T-shirt block (front and back cut on the fold, short sleeve, rib neckband).

Construction after Aldrich, *Metric Pattern Cutting for Menswear*, "the basic
T-shirt block (jersey)": a flat block with chest ease +8 cm, scye depth + 2 cm
from the nape, back neck width = neck / 5, front neck depth = neck / 5 + 1.5 cm,
a shoulder 1.5 cm longer than the body's with a 4 cm slope, a flat sleeve crown
fitted to the armhole without ease, and a 2 x 1 rib neckband 1 cm shorter than
the neckline in each quarter (stretched on). Body length nape + 27 cm below the
waist. Run ``python garment_library/tshirt/draft.py`` to regenerate the files.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from patternbridge.library.blocks import (
    armhole_controls,
    neckline_controls,
    sleeve_cap_controls,
)
from patternbridge.library.draft import OutlineBuilder, bezier
from patternbridge.library.garment import (
    PieceDraft,
    band_draft,
    build_pattern,
    leg,
    link,
    seam,
    set_in_sleeve,
)
from patternbridge.library.sizes import MEN
from patternbridge.pattern.fabric import FabricClass
from patternbridge.pattern.model import Placement, Quantity, VertexKind

CHART = MEN
CHEST_EASE, BICEP_EASE = 8.0, 10.0
NECKBAND_STRETCH = 1.0  # per quarter of the neckline
HEM_ALLOWANCE, SLEEVE_HEM = 2.5, 2.5
SLEEVE_LENGTH = 21.0
CURVE = VertexKind.CURVE
FLIP = np.array([-1.0, 1.0])


def _geometry(b):
    g = {"y_nape": b["scye_depth"] + 2.0}
    g["y_waist"] = g["y_nape"] - b["back_length"]
    g["y_hem"] = g["y_waist"] - 27.0
    g["half"] = (b["chest_girth"] + CHEST_EASE) / 4
    g["nw"] = b["neck_girth"] / 5
    sl = b["shoulder_length_right"] + 1.5
    g["snp"] = np.array([g["nw"], g["y_nape"] + 1.5])
    g["sp"] = g["snp"] + np.array([np.sqrt(sl**2 - 4.0**2), -4.0])
    g["ab"] = np.array([b["back_width"] / 2 + 1.5, 0.42 * g["sp"][1]])
    g["ac"] = np.array([b["back_width"] / 2 + 0.5, 0.40 * g["sp"][1]])
    g["y_cfn"] = g["snp"][1] - (b["neck_girth"] / 5 + 1.5)
    g["y_cbn"] = g["y_nape"]
    return g


def _body(name, g, centre_neck_y, across, side, landmarks, placement, annotation):
    """A whole front or back: right half walked from the centre neck, then its mirror."""
    neck = neckline_controls((0.0, centre_neck_y), g["snp"], g["sp"] - g["snp"])
    arm_upper, arm_lower = armhole_controls(g["sp"], across, (g["half"], 0.0))
    # a CCW walk from the centre neck goes to -x first: the body's right half on a front seen
    # from outside, its left half on a back
    first, second = ("right", "left") if side == "front" else ("left", "right")
    f = -1.0
    fx = np.array([f, 1.0])
    o = OutlineBuilder()
    o.start((0.0, centre_neck_y), "centre_neck", notch=True)
    o.polyline(bezier(*(neck * fx), 8), f"neck_side_{first}")
    o.line(g["sp"] * fx, f"shoulder_point_{first}")
    o.polyline(
        bezier(*(arm_upper * fx), 8),
        f"armhole_notch_{first}",
        notch=True,
        end_kind=CURVE,
    )
    o.polyline(bezier(*(arm_lower * fx), 8), f"side_underarm_{first}")
    o.line((f * g["half"], g["y_hem"]), f"side_hem_{first}", allowance_cm=HEM_ALLOWANCE)
    o.line((0.0, g["y_hem"]), "centre_hem", allowance_cm=HEM_ALLOWANCE, notch=True)
    o.line((-f * g["half"], g["y_hem"]), f"side_hem_{second}")
    o.line((-f * g["half"], 0.0), f"side_underarm_{second}")
    ox = np.array([-f, 1.0])
    o.polyline(
        bezier(*(arm_lower[::-1] * ox), 8),
        f"armhole_notch_{second}",
        notch=True,
        end_kind=CURVE,
    )
    o.polyline(bezier(*(arm_upper[::-1] * ox), 8), f"shoulder_point_{second}")
    o.line(g["snp"] * ox, f"neck_side_{second}")
    o.polyline(bezier(*(neck[::-1] * ox), 8)[:-1], end_kind=CURVE)
    net = o.close()
    return PieceDraft(
        name=name,
        net=net,
        quantity=Quantity(right=1, left=0),
        grain=((0.0, g["y_hem"] + 8), (0.0, centre_neck_y - 8)),
        placement=placement,
        landmarks=landmarks,
        category=name.upper(),
        annotation=annotation,
    )


def front(b, g):
    return _body(
        "front",
        g,
        g["y_cfn"],
        g["ac"],
        "front",
        {
            "front_neck_point": "centre_neck",
            "neck_shoulder_point_right": "neck_side_right",
            "neck_shoulder_point_left": "neck_side_left",
            "shoulder_point_right": "shoulder_point_right",
            "shoulder_point_left": "shoulder_point_left",
        },
        Placement(
            body_part="torso",
            side="front",
            anchor="front_neck_point",
            anchor_mark="centre_neck",
        ),
        "T-SHIRT FRONT (CUT 1 ON FOLD)",
    )


def back(b, g):
    return _body(
        "back",
        g,
        g["y_cbn"],
        g["ab"],
        "back",
        {
            "back_neck_point": "centre_neck",
            "neck_shoulder_point_right": "neck_side_right",
            "neck_shoulder_point_left": "neck_side_left",
            "shoulder_point_right": "shoulder_point_right",
            "shoulder_point_left": "shoulder_point_left",
        },
        Placement(
            body_part="torso",
            side="back",
            anchor="back_neck_point",
            anchor_mark="centre_neck",
        ),
        "T-SHIRT BACK (CUT 1 ON FOLD)",
    )


def sleeve(b, g, fr, bk):
    lf = fr.net.length("shoulder_point_right", "side_underarm_right")
    lb = bk.net.length("side_underarm_right", "shoulder_point_right")
    a = (b["upper_arm_girth_right"] + BICEP_EASE) / 2
    cap_f, cap_b, h = sleeve_cap_controls(a, lf, lb)
    (nf,) = fr.net.notch_offsets("shoulder_point_right", "side_underarm_right")
    (nb,) = bk.net.notch_offsets("side_underarm_right", "shoulder_point_right")
    hem_half = 0.88 * a
    y_hem = h - SLEEVE_LENGTH
    xt = cap_f[3][0]
    o = OutlineBuilder()
    o.start((a, 0.0), "underarm_front")
    o.bezier(
        cap_f,
        "cap_top",
        n=14,
        notch=True,
        at=[(lf - nf, "front_notch", True)],
        end_kind=CURVE,
    )
    o.bezier(cap_b, "underarm_back", n=14, at=[(lb - nb, "back_notch", True)])
    o.line((-hem_half, y_hem), "hem_back")
    o.line((xt, y_hem), "hem_mid", allowance_cm=SLEEVE_HEM)
    o.line((hem_half, y_hem), "hem_front", allowance_cm=SLEEVE_HEM)
    net = o.close()
    return set_in_sleeve(net, ((xt, y_hem + 4), (xt, h - 5)))


def _neckband(fr, bk):
    parts = [
        (bk, "primary", "neck_side_right", "centre_neck", "snp_right"),
        (fr, "primary", "centre_neck", "neck_side_right", "cf"),
        (fr, "primary", "neck_side_left", "centre_neck", "snp_left"),
        (bk, "primary", "centre_neck", "neck_side_left", None),
    ]
    return band_draft(
        "neckband",
        parts,
        2.0,
        ends=("cb_right", "cb_left"),
        part_ease_cm=NECKBAND_STRETCH,
        placement=Placement(
            body_part="neck", side="around", anchor="front_neck_point", anchor_mark="cf"
        ),
        landmarks={"front_neck_point": "cf"},
        annotation="RIB NECKBAND (CUT 1)",
        category="RIB",
    )


def draft(b):
    g = _geometry(b)
    fr, bk = front(b, g), back(b, g)
    band, _ = _neckband(fr, bk)
    return [fr, bk, sleeve(b, g, fr, bk), band]


def seams():
    b = CHART.body(CHART.sample_size)
    g = _geometry(b)
    _, band_seams = _neckband(front(b, g), back(b, g))
    out = []
    for side, copy in (("right", "primary"), ("left", "mirror")):
        if side == "right":
            f_arm, b_arm = (
                ("front", "shoulder_point_right", "side_underarm_right"),
                ("back", "side_underarm_right", "shoulder_point_right"),
            )
            f_sh, b_sh = (
                ("front", "neck_side_right", "shoulder_point_right"),
                ("back", "shoulder_point_right", "neck_side_right"),
            )
            f_sd, b_sd = (
                ("front", "side_underarm_right", "side_hem_right"),
                ("back", "side_hem_right", "side_underarm_right"),
            )
        else:
            f_arm, b_arm = (
                ("front", "side_underarm_left", "shoulder_point_left"),
                ("back", "shoulder_point_left", "side_underarm_left"),
            )
            f_sh, b_sh = (
                ("front", "shoulder_point_left", "neck_side_left"),
                ("back", "neck_side_left", "shoulder_point_left"),
            )
            f_sd, b_sd = (
                ("front", "side_hem_left", "side_underarm_left"),
                ("back", "side_underarm_left", "side_hem_left"),
            )
        out += [
            seam(f"shoulder_{side}", f_sh, b_sh),
            seam(f"side_{side}", f_sd, b_sd),
            seam(
                f"armhole_front_{side}",
                f_arm,
                ("sleeve", "underarm_front", "cap_top", copy),
            ),
            seam(
                f"armhole_back_{side}",
                b_arm,
                ("sleeve", "cap_top", "underarm_back", copy),
            ),
            seam(
                f"sleeve_{side}",
                ("sleeve", "hem_front", "underarm_front", copy),
                ("sleeve", "underarm_back", "hem_back", copy),
            ),
        ]
    return out + band_seams


LINKS = [
    link(
        "chest_girth",
        CHEST_EASE,
        leg("front", "side_underarm_right", "side_underarm_left"),
        leg("back", "side_underarm_left", "side_underarm_right"),
    ),
    link(
        "neck_girth",
        None,
        leg("front", "centre_neck", "neck_side_right", "boundary", 2),
        leg("back", "neck_side_right", "centre_neck", "boundary", 2),
    ),
    link(
        "shoulder_width",
        None,
        leg("back", "shoulder_point_left", "shoulder_point_right"),
    ),
    link("back_width", None, leg("back", "armhole_notch_left", "armhole_notch_right")),
    link(
        "shoulder_length_right",
        None,
        leg("front", "neck_side_right", "shoulder_point_right"),
    ),
    link(
        "upper_arm_girth_right",
        BICEP_EASE,
        leg("sleeve", "underarm_front", "underarm_back"),
    ),
    # lengths no fitting measurement fixes keep the design's proportion to the
    # body height they follow: the body's length to the hem, the short sleeve's
    link(
        "stature",
        None,
        leg("front", "side_underarm_right", "side_hem_right", "boundary"),
        link_id="body_length",
        proportional=True,
    ),
    link(
        "arm_length_right",
        None,
        leg("sleeve", "hem_front", "underarm_front", "boundary"),
        link_id="sleeve_length",
        proportional=True,
    ),
]

DESCRIPTION = (
    "Jersey T-shirt: front and back cut on the fold, short set-in sleeves, rib neckband"
)


def build():
    return build_pattern(
        style="tshirt",
        description=DESCRIPTION,
        chart=CHART,
        draft=draft,
        seams=seams(),
        links=LINKS,
        fabric_class=FabricClass.KNIT,
        fabric_why="drafted for single jersey with a rib neckband",
    )


if __name__ == "__main__":
    from patternbridge.library.catalogue import write_garment

    write_garment(build(), Path(__file__).resolve().parent)
