"""Shirt: the classic men's shirt block (front, back, yoke, sleeve, collar, cuff).

Construction after Aldrich, *Metric Pattern Cutting for Menswear*, "the shirt
block": scye depth + 3 cm from the nape to the chest line, half back = across
back / 2 + 1 cm, back neck width = neck / 5 − 0.2 cm rising 2 cm, shoulder
length + 1 cm with a 4.5 cm (back) and 5.5 cm (front) slope, front neck depth =
neck / 5 + 1 cm; back yoke cut 8 cm below the nape; one-piece sleeve whose
crown is fitted to the armhole with 1 cm ease; straight cuff and a one-piece
collar. Ease: chest +12 cm, bicep +12 cm, wrist +6 cm (cuff). The centre-front
closure is drafted on the centre-front line; its 3 cm allowance holds the
button overlap. Run ``python garment_library/shirt/draft.py`` to regenerate.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from scipy.optimize import brentq

from patternbridge.library.blocks import (
    armhole_controls,
    neckline_controls,
    sleeve_cap_controls,
)
from patternbridge.library.draft import (
    OutlineBuilder,
    bezier,
    bezier_length,
    bezier_split,
    bezier_t_at,
)
from patternbridge.library.garment import (
    PieceDraft,
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
CHEST_EASE, BICEP_EASE, WRIST_EASE = 12.0, 12.0, 6.0
CAP_EASE = 1.0
CUFF_PLEATS = 4.0
CUFF_DEPTH = 6.0
CF_ALLOWANCE, HEM_ALLOWANCE = 3.0, 1.5
CURVE = VertexKind.CURVE


def _geometry(b):
    g = {}
    g["y_nape"] = b["scye_depth"] + 3.0
    g["y_waist"] = g["y_nape"] - b["back_length"]
    g["y_hem"] = g["y_nape"] - (b["back_length"] + 33.0)
    g["y_yoke"] = g["y_nape"] - 8.0
    half = (b["chest_girth"] + CHEST_EASE) / 4
    g["bwc"], g["fwc"] = half + 0.5, half - 0.5
    g["nw"] = b["neck_girth"] / 5 - 0.2
    g["sl"] = b["shoulder_length_right"] + 1.0
    # back: side-neck point, shoulder point, across-back point
    g["b_snp"] = np.array([g["nw"], g["y_nape"] + 2.0])
    g["b_sp"] = g["b_snp"] + np.array([np.sqrt(g["sl"] ** 2 - 4.5**2), -4.5])
    g["b_ab"] = np.array([b["back_width"] / 2 + 1.0, 0.42 * (g["b_sp"][1])])
    # front (drawn with the centre front at x = 0 and the side at -x)
    g["f_snp"] = np.array([-g["nw"], g["y_nape"] + 0.5])
    g["f_sp"] = g["f_snp"] + np.array([-np.sqrt(g["sl"] ** 2 - 5.5**2), -5.5])
    g["f_ac"] = np.array([-(g["fwc"] - 5.2), 0.40 * g["f_sp"][1]])
    g["y_cfn"] = g["f_snp"][1] - (b["neck_girth"] / 5 + 1.0)
    return g


def _back_armhole(g):
    """Right back armhole, shoulder point down to underarm, split at the yoke line."""
    upper, lower = armhole_controls(g["b_sp"], g["b_ab"], (g["bwc"], 0.0))
    t = bezier_t_at(upper, 1, g["y_yoke"])
    yoke_part, back_upper = bezier_split(upper, t)
    return yoke_part, back_upper, lower


def front(b, g) -> PieceDraft:
    o = OutlineBuilder()
    o.start((0.0, g["y_cfn"]), "cf_neck")
    o.bezier(
        neckline_controls((0.0, g["y_cfn"]), g["f_snp"], g["f_sp"] - g["f_snp"]),
        "neck_side",
        n=10,
    )
    o.line(g["f_sp"], "shoulder_point")
    upper, lower = armhole_controls(g["f_sp"], g["f_ac"], (-g["fwc"], 0.0))
    o.bezier(upper, "armhole_notch", n=8, notch=True, end_kind=CURVE)
    o.bezier(lower, "side_underarm", n=8)
    o.line((-g["fwc"] + 1.0, g["y_waist"]), "side_waist", notch=True)
    o.line((-g["fwc"] + 0.5, g["y_hem"] + 6.0), "side_hem")
    o.curve(
        (-g["fwc"] * 0.55, g["y_hem"] + 6.0),
        (-g["fwc"] * 0.35, g["y_hem"]),
        (0.0, g["y_hem"]),
        "cf_hem",
        n=10,
        allowance_cm=HEM_ALLOWANCE,
    )
    o.line((0.0, g["y_waist"]), "cf_waist", allowance_cm=CF_ALLOWANCE)
    o.line((0.0, 0.0), "cf_chest", allowance_cm=CF_ALLOWANCE)
    net = o.close(allowance_cm=CF_ALLOWANCE)
    return PieceDraft(
        name="front",
        net=net,
        quantity=Quantity(right=1, left=1),
        grain=((-g["fwc"] / 2, g["y_waist"] - 10), (-g["fwc"] / 2, g["f_sp"][1] - 8)),
        placement=Placement(
            body_part="torso",
            side="front",
            anchor="neck_shoulder_point_right",
            anchor_mark="neck_side",
        ),
        landmarks={
            "front_neck_point": "cf_neck",
            "neck_shoulder_point_right": "neck_side",
            "shoulder_point_right": "shoulder_point",
            "waist_front": "cf_waist",
            "waist_side_right": "side_waist",
        },
        category="FRONT",
        annotation="SHIRT FRONT",
    )


def back(b, g) -> PieceDraft:
    _yoke_part, b_upper, b_lower = _back_armhole(g)
    # the right armhole is walked upwards (underarm -> yoke), the left one downwards (its mirror)
    flip = np.array([-1.0, 1.0])
    up_lower, up_upper = b_lower[::-1], b_upper[::-1]
    down_upper, down_lower = b_upper * flip, b_lower * flip
    lower_len = bezier_length(b_lower)
    bwc = g["bwc"]
    o = OutlineBuilder()
    yoke_x = b_upper[0][0]
    o.start((-yoke_x, g["y_yoke"]), "yoke_left")
    # down the left armhole: notches at the across-back point and 1 cm below it
    o.bezier(down_upper, "ab_notch_left", n=6, notch=True, end_kind=CURVE)
    o.bezier(down_lower, "side_underarm_left", n=9, at=[(1.0, "ab_notch2_left", True)])
    o.line((-bwc + 1.0, g["y_waist"]), "side_waist_left", notch=True)
    o.line((-bwc + 0.5, g["y_hem"] + 6.0), "side_hem_left")
    o.curve(
        (-bwc * 0.55, g["y_hem"] + 6.0),
        (-bwc * 0.35, g["y_hem"] - 2.0),
        (0.0, g["y_hem"] - 2.0),
        "cb_hem",
        n=10,
        allowance_cm=HEM_ALLOWANCE,
    )
    o.curve(
        (bwc * 0.35, g["y_hem"] - 2.0),
        (bwc * 0.55, g["y_hem"] + 6.0),
        (bwc - 0.5, g["y_hem"] + 6.0),
        "side_hem_right",
        n=10,
        allowance_cm=HEM_ALLOWANCE,
    )
    o.line((bwc - 1.0, g["y_waist"]), "side_waist_right", notch=True)
    o.line((bwc, 0.0), "side_underarm_right")
    # up the right armhole: the notch 1 cm below the across-back point, then the across-back point
    o.bezier(
        up_lower,
        "ab_notch",
        n=9,
        notch=True,
        end_kind=CURVE,
        at=[(lower_len - 1.0, "ab_notch2", True)],
    )
    o.bezier(up_upper, "yoke_right", n=6)
    o.line((0.0, g["y_yoke"]), "cb_yoke", notch=True)
    net = o.close()
    return PieceDraft(
        name="back",
        net=net,
        quantity=Quantity(right=1, left=0),
        grain=((0.0, g["y_waist"] - 10), (0.0, g["y_yoke"] - 6)),
        placement=Placement(
            body_part="torso",
            side="back",
            anchor="waist_side_right",
            anchor_mark="side_waist_right",
        ),
        landmarks={
            "waist_side_right": "side_waist_right",
            "waist_side_left": "side_waist_left",
        },
        category="BACK",
        annotation="SHIRT BACK (CUT 1, CENTRE BACK AT MIDDLE)",
    )


def yoke(b, g) -> PieceDraft:
    yoke_part, _u, _l = _back_armhole(g)
    right_up = bezier(*yoke_part[::-1], 6)  # yoke line -> shoulder point
    left_down = right_up[::-1] * np.array([-1.0, 1.0])
    neck = neckline_controls((0.0, g["y_nape"]), g["b_snp"], g["b_sp"] - g["b_snp"])
    neck_right = bezier(*neck[::-1], 8)  # side neck -> centre back
    neck_left = neck_right[::-1] * np.array([-1.0, 1.0])
    yx = right_up[0][0]
    o = OutlineBuilder()
    o.start((-yx, g["y_yoke"]), "yoke_left")
    o.line((0.0, g["y_yoke"]), "cb_yoke", notch=True)
    o.line((yx, g["y_yoke"]), "yoke_right")
    o.polyline(right_up, "shoulder_point_right")
    o.line(g["b_snp"], "neck_side_right")
    o.polyline(neck_right, "cb_neck", notch=True, end_kind=CURVE)
    o.polyline(neck_left, "neck_side_left")
    o.line(g["b_sp"] * np.array([-1.0, 1.0]), "shoulder_point_left")
    o.polyline(
        left_down[:-1], end_kind=CURVE
    )  # close() joins the last edge to yoke_left
    net = o.close()
    return PieceDraft(
        name="yoke",
        net=net,
        quantity=Quantity(right=1, left=0),
        grain=((0.0, g["y_yoke"] + 1.5), (0.0, g["y_nape"] - 2.0)),
        placement=Placement(
            body_part="torso",
            side="back",
            anchor="back_neck_point",
            anchor_mark="cb_neck",
        ),
        landmarks={
            "back_neck_point": "cb_neck",
            "neck_shoulder_point_right": "neck_side_right",
            "neck_shoulder_point_left": "neck_side_left",
            "shoulder_point_right": "shoulder_point_right",
            "shoulder_point_left": "shoulder_point_left",
        },
        category="YOKE",
        annotation="BACK YOKE (CUT 1)",
    )


def sleeve(b, g, fr: PieceDraft, bk: PieceDraft, yk: PieceDraft) -> PieceDraft:
    lf = fr.net.length("shoulder_point", "side_underarm")
    ly = yk.net.length("yoke_right", "shoulder_point_right")
    lb = bk.net.length("side_underarm_right", "yoke_right")
    total = lf + ly + lb
    ef, ey, eb = (CAP_EASE * x / total for x in (lf, ly, lb))
    a = (b["upper_arm_girth_right"] + BICEP_EASE) / 2
    cap_f, cap_b, h = sleeve_cap_controls(a, lf + ef, ly + ey + lb + eb)
    # notch positions, proportional along each seam (b of a seam runs opposite to a)
    (nf,) = fr.net.notch_offsets("shoulder_point", "side_underarm")
    s_front = (lf - nf) * (lf + ef) / lf
    nb = bk.net.notch_offsets(
        "side_underarm_right", "yoke_right"
    )  # from the underarm upwards
    s_back = [
        (ly + ey) + (lb - s) * (lb + eb) / lb for s in nb
    ]  # from the crown downwards
    cuff_len = b["wrist_girth_right"] + WRIST_EASE
    hem_w = cuff_len + CUFF_PLEATS
    length = b["arm_length_right"] + 2.0 - CUFF_DEPTH
    y_hem = h - length
    xt = cap_f[3][0]
    o = OutlineBuilder()
    o.start((a, 0.0), "underarm_front")
    o.bezier(
        cap_f,
        "cap_top",
        n=14,
        notch=True,
        at=[(s_front, "front_notch", True)],
        end_kind=CURVE,
    )
    o.bezier(
        cap_b,
        "underarm_back",
        n=18,
        at=[
            (ly + ey, "yoke_notch", True),
            (s_back[0], "back_notch", True),
            (s_back[1], "back_notch2", True),
        ],
    )
    o.line((-hem_w / 2, y_hem), "hem_back")
    o.line((xt, y_hem), "hem_mid", notch=True)
    o.line((hem_w / 2, y_hem), "hem_front")
    net = o.close()
    return set_in_sleeve(net, ((xt, y_hem + 8.0), (xt, h - 8.0))), (ef, ey, eb)


def cuff(b, g, sl: PieceDraft) -> PieceDraft:
    hem = sl.net.length("hem_back", "hem_front")
    w = hem - CUFF_PLEATS
    # the notch meets the sleeve's hem notch proportionally (pleats spread evenly)
    x_notch = w / 2 - sl.net.length("hem_mid", "hem_front") * w / hem
    o = OutlineBuilder()
    o.start((-w / 2, CUFF_DEPTH), "top_left")
    o.line((-w / 2, 0.0), "bottom_left")
    o.line((w / 2, 0.0), "bottom_right")
    o.line((w / 2, CUFF_DEPTH), "top_right")
    o.line((x_notch, CUFF_DEPTH), "top_mid", notch=True)
    net = o.close()
    return PieceDraft(
        name="cuff",
        net=net,
        quantity=Quantity(right=1, left=1),
        grain=((-w / 4, CUFF_DEPTH / 2), (w / 4, CUFF_DEPTH / 2)),
        placement=Placement(
            body_part="right_arm",
            side="around",
            anchor="wrist_point_right",
            anchor_mark="bottom_right",
        ),
        category="CUFF",
        annotation="CUFF",
    )


def collar(b, g, fr: PieceDraft, yk: PieceDraft) -> PieceDraft:
    half_back = yk.net.length("neck_side_right", "cb_neck")
    front_neck = fr.net.length("cf_neck", "neck_side")
    rise, height = 1.5, 7.0

    def end_curve(d):
        p0 = np.array([half_back, 0.0])
        return np.array(
            [
                p0,
                p0 + [d * 0.5, 0.0],
                [half_back + d * 0.8, rise * 0.4],
                [half_back + d, rise],
            ]
        )

    d = brentq(
        lambda d: bezier_length(end_curve(d)) - front_neck, 0.5 * front_neck, front_neck
    )
    right = bezier(*end_curve(d), 8)
    left = (right * [-1.0, 1.0])[::-1]
    xe = half_back + d
    o = OutlineBuilder()
    o.start(left[0], "end_left")
    o.polyline(left, "snp_left", notch=True)
    o.line((0.0, 0.0), "cb", notch=True)
    o.line(right[0], "snp_right", notch=True)
    o.polyline(right, "end_right")
    o.line((xe + 2.0, rise + height), "tip_right")
    o.curve((xe * 0.6, height + 0.4), (xe * 0.3, height), (0.0, height), "top_cb", n=6)
    o.curve(
        (-xe * 0.3, height),
        (-xe * 0.6, height + 0.4),
        (-xe - 2.0, rise + height),
        "tip_left",
        n=6,
    )
    net = o.close()
    return PieceDraft(
        name="collar",
        net=net,
        quantity=Quantity(right=1, left=0),
        grain=((-8.0, height / 2), (8.0, height / 2)),
        placement=Placement(
            body_part="neck", side="around", anchor="back_neck_point", anchor_mark="cb"
        ),
        landmarks={"back_neck_point": "cb"},
        category="COLLAR",
        annotation="COLLAR (CUT 1, CENTRE BACK AT MIDDLE)",
    )


_EASES: dict[str, tuple[float, float, float]] = {}


def draft(b):
    g = _geometry(b)
    fr, bk, yk = front(b, g), back(b, g), yoke(b, g)
    sl, eases = sleeve(b, g, fr, bk, yk)
    _EASES[str(b["chest_girth"])] = eases
    return [fr, bk, yk, sl, cuff(b, g, sl), collar(b, g, fr, yk)]


def seams():
    # cap ease shares are proportional to the armhole parts and the same in every size up to 0.1 mm
    body = CHART.body(CHART.sample_size)
    draft(body)
    ef, ey, eb = _EASES[str(body["chest_girth"])]
    out = []
    for side, copy in (("right", "primary"), ("left", "mirror")):
        back_arm = (
            ("back", "side_underarm_right", "yoke_right")
            if side == "right"
            else ("back", "yoke_left", "side_underarm_left")
        )
        yoke_arm = (
            ("yoke", "yoke_right", "shoulder_point_right")
            if side == "right"
            else ("yoke", "shoulder_point_left", "yoke_left")
        )
        yoke_sh = (
            ("yoke", "shoulder_point_right", "neck_side_right")
            if side == "right"
            else ("yoke", "neck_side_left", "shoulder_point_left")
        )
        back_side = (
            ("back", "side_hem_right", "side_underarm_right")
            if side == "right"
            else ("back", "side_underarm_left", "side_hem_left")
        )
        out += [
            seam(
                f"shoulder_{side}",
                ("front", "neck_side", "shoulder_point", copy),
                yoke_sh,
            ),
            seam(
                f"side_{side}", ("front", "side_underarm", "side_hem", copy), back_side
            ),
            seam(
                f"armhole_front_{side}",
                ("front", "shoulder_point", "side_underarm", copy),
                ("sleeve", "underarm_front", "cap_top", copy),
                ease_cm=round(ef, 4),
            ),
            seam(
                f"armhole_yoke_{side}",
                yoke_arm,
                ("sleeve", "cap_top", "yoke_notch", copy),
                ease_cm=round(ey, 4),
            ),
            seam(
                f"armhole_back_{side}",
                back_arm,
                ("sleeve", "yoke_notch", "underarm_back", copy),
                ease_cm=round(eb, 4),
            ),
            seam(
                f"sleeve_{side}",
                ("sleeve", "hem_front", "underarm_front", copy),
                ("sleeve", "underarm_back", "hem_back", copy),
            ),
            seam(
                f"cuff_{side}",
                ("cuff", "top_right", "top_left", copy),
                ("sleeve", "hem_back", "hem_front", copy),
                ease_cm=CUFF_PLEATS,
            ),
            seam(
                f"cuff_closure_{side}",
                ("cuff", "top_left", "bottom_left", copy),
                ("cuff", "bottom_right", "top_right", copy),
            ),
        ]
    out += [
        seam(
            "yoke",
            ("yoke", "yoke_left", "yoke_right"),
            ("back", "yoke_right", "yoke_left"),
        ),
        seam(
            "centre_front",
            ("front", "cf_hem", "cf_neck"),
            ("front", "cf_hem", "cf_neck", "mirror"),
        ),
        seam(
            "collar_back",
            ("yoke", "neck_side_right", "neck_side_left"),
            ("collar", "snp_left", "snp_right"),
        ),
        seam(
            "collar_front_right",
            ("front", "cf_neck", "neck_side"),
            ("collar", "snp_right", "end_right"),
        ),
        seam(
            "collar_front_left",
            ("front", "cf_neck", "neck_side", "mirror"),
            ("collar", "end_left", "snp_left"),
        ),
        seam(
            "collar_closure",
            ("collar", "tip_left", "end_left"),
            ("collar", "end_right", "tip_right"),
        ),
    ]
    return out


LINKS = [
    link(
        "chest_girth",
        CHEST_EASE,
        leg("front", "side_underarm", "cf_chest", "across", 2),
        leg("back", "side_underarm_left", "side_underarm_right", "across"),
    ),
    link(
        "waist_girth",
        None,
        leg("front", "side_waist", "cf_waist", "across", 2),
        leg("back", "side_waist_left", "side_waist_right", "across"),
    ),
    link(
        "neck_girth",
        None,
        leg("front", "cf_neck", "neck_side", "boundary", 2),
        leg("yoke", "neck_side_right", "neck_side_left", "boundary"),
    ),
    link(
        "shoulder_width",
        None,
        leg("yoke", "shoulder_point_left", "shoulder_point_right"),
    ),
    # the hem lies below the seat: at least as wide as the hips with the
    # sample's ease, or the tail grips them and curls under the buttocks; a
    # wider hem (a V-shaped body's) keeps the side seam straight
    link(
        "hip_girth",
        None,
        leg("front", "side_hem", "cf_hem", "across", 2),
        leg("back", "side_hem_left", "side_hem_right", "across"),
        at_least=True,
    ),
    # the side seam's lengths above and below the waist follow the body's,
    # so a chest much wider than the waist neither lifts the underarm toward
    # the neck nor stretches the tail to the knees
    link("side_length", None, leg("front", "side_underarm", "side_waist", "boundary")),
    link("waist_to_hip", None, leg("front", "side_waist", "side_hem", "boundary")),
    link("back_width", None, leg("back", "ab_notch_left", "ab_notch")),
    link("shoulder_length_right", 1.0, leg("front", "neck_side", "shoulder_point")),
    link("front_length", None, leg("front", "cf_neck", "cf_waist")),
    link(
        "arm_length_right",
        None,
        leg("sleeve", "cap_top", "hem_mid"),
        leg("cuff", "top_right", "bottom_right"),
    ),
    link(
        "upper_arm_girth_right",
        BICEP_EASE,
        leg("sleeve", "underarm_front", "underarm_back"),
    ),
    link("wrist_girth_right", WRIST_EASE, leg("cuff", "bottom_left", "bottom_right")),
]

DESCRIPTION = "Classic shirt: fronts, back with yoke, one-piece sleeves with cuffs, one-piece collar"


def build():
    return build_pattern(
        style="shirt",
        description=DESCRIPTION,
        chart=CHART,
        draft=draft,
        seams=seams(),
        links=LINKS,
        fabric_class=FabricClass.WOVEN,
        fabric_why="drafted for woven shirting",
    )


if __name__ == "__main__":
    from patternbridge.library.catalogue import write_garment

    write_garment(build(), Path(__file__).resolve().parent)
