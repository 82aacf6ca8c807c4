"""Trousers: the classic men's trouser block (front, back with one dart, waistband).

Construction after Aldrich, *Metric Pattern Cutting for Menswear*, "the classic
trouser block": crotch line at body rise + 1.5 cm below the waist, seat line at
waist-to-hip, front fork ≈ seat/18, back fork ≈ seat/9, knee line half-way down
the inside leg less 5 cm, crease line centred between side seam and fork.
Ease: seat +6 cm, waist +2 cm. Back and front side seams and inside legs are
drafted as mirror images of each other so they sew to equal length in every
size. Run ``python garment_library/trousers/draft.py`` to regenerate the files.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from patternbridge.library.draft import OutlineBuilder, hermite
from patternbridge.library.garment import PieceDraft, build_pattern, leg, link, seam
from patternbridge.library.sizes import MEN
from patternbridge.pattern.fabric import FabricClass
from patternbridge.pattern.model import Placement, Quantity

CHART = MEN.relabel("waist_girth")
HIP_EASE, WAIST_EASE = 6.0, 2.0
HEM_ALLOWANCE, SEAM_ALLOWANCE = 4.0, 1.0
WAISTBAND_CM = 4.0


def _geometry(b: dict[str, float]) -> dict[str, float]:
    g = {}
    g["y_waist"] = b["body_rise"] + 1.5
    g["y_hip"] = g["y_waist"] - b["waist_to_hip"]
    g["y_knee"] = -(b["inside_leg_right"] / 2 - 5.0)
    g["y_hem"] = -(b["inside_leg_right"] - 3.0)
    hip = b["hip_girth"] + HIP_EASE
    g["hf"] = hip / 4 - 1.0
    g["hb"] = hip / 4 + 1.0
    g["ef"] = b["hip_girth"] / 18
    g["eb"] = b["hip_girth"] / 9
    g["kf"] = 0.12 * b["hip_girth"] + 10.0
    g["kb"] = g["kf"] + 4.0
    g["hemf"] = g["kf"] - 2.0
    g["hemb"] = g["kb"] - 2.0
    g["fw"] = g["hf"] - 3.0  # front waist: 1 cm off centre front, 2 cm off the side
    g["bw"] = (b["waist_girth"] + WAIST_EASE) / 2 - g["fw"]
    return g


def front(b, g, knee: str = "knee", style: str = "TROUSER") -> PieceDraft:
    x_c = (-g["hf"] + g["ef"]) / 2
    side_knee = np.array([x_c - g["kf"] / 2, g["y_knee"]])
    side_hip = np.array([-g["hf"], g["y_hip"]])
    side_crotch = side_hip + (side_knee - side_hip) * (
        g["y_hip"] / (g["y_hip"] - g["y_knee"])
    )
    o = OutlineBuilder()
    o.start((-1.0, g["y_waist"]), "cf_waist")
    o.line((-g["hf"] + 2.0, g["y_waist"]), "side_waist")
    o.polyline(
        hermite(o.current, (-0.3, -1.0), side_hip, (0.0, -1.0), 8),
        "side_hip",
        notch=True,
    )
    o.line(side_crotch, "side_crotch")
    o.line(side_knee, f"side_{knee}", notch=True)
    o.line((x_c - g["hemf"] / 2, g["y_hem"]), "side_hem", allowance_cm=SEAM_ALLOWANCE)
    o.line((x_c, g["y_hem"]), "hem_crease", allowance_cm=HEM_ALLOWANCE)
    o.line((x_c + g["hemf"] / 2, g["y_hem"]), "inside_hem", allowance_cm=HEM_ALLOWANCE)
    o.line((x_c + g["kf"] / 2, g["y_knee"]), f"inside_{knee}", notch=True)
    o.line((g["ef"], 0.0), "crotch_point")
    ef, yh = g["ef"], g["y_hip"]
    o.curve((ef * 0.45, -0.05), (0.0, yh * 0.3), (0.0, yh), "cf_hip", n=12, notch=True)
    net = o.close(allowance_cm=SEAM_ALLOWANCE)
    return PieceDraft(
        name="front",
        net=net,
        quantity=Quantity(right=1, left=1),
        grain=((x_c, max(g["y_knee"] - 15.0, g["y_hem"] + 3.0)), (x_c, g["y_hip"])),
        placement=Placement(
            body_part="right_leg",
            side="front",
            anchor="waist_side_right",
            anchor_mark="side_waist",
        ),
        landmarks={
            "waist_front": "cf_waist",
            "waist_side_right": "side_waist",
            "hip_side_right": "side_hip",
            "crotch_point": "crotch_point",
        },
        category="FRONT",
        annotation=f"{style} FRONT",
    )


def back(b, g, knee: str = "knee", style: str = "TROUSER") -> PieceDraft:
    # side seam mirrors the front's: same heights, same horizontal travel
    x_cf = (-g["hf"] + g["ef"]) / 2
    travel_knee = (x_cf - g["kf"] / 2) + g["hf"]
    x_c = g["hb"] - travel_knee - g["kb"] / 2
    side_hip = np.array([g["hb"], g["y_hip"]])
    side_knee = np.array([x_c + g["kb"] / 2, g["y_knee"]])
    side_crotch = side_hip + (side_knee - side_hip) * (
        g["y_hip"] / (g["y_hip"] - g["y_knee"])
    )
    side_waist = np.array([g["hb"] - 2.0, g["y_waist"]])
    cb_waist = np.array([3.0, g["y_waist"] + 2.5])
    cb_hip = np.array([0.0, g["y_hip"]])
    # back inside leg: same lengths as the front's (crotch->knee, knee->hem)
    inside_knee = np.array([x_c - g["kb"] / 2, g["y_knee"]])
    f_crotch = np.array([g["ef"], 0.0])
    f_knee = np.array([x_cf + g["kf"] / 2, g["y_knee"]])
    upper = float(np.hypot(*(f_crotch - f_knee)))
    slope = (cb_waist[0] - cb_hip[0]) / (cb_waist[1] - cb_hip[1])
    x_crotch = cb_hip[0] - slope * cb_hip[1] - g["eb"]
    dx = inside_knee[0] - x_crotch
    crotch = np.array([x_crotch, inside_knee[1] + np.sqrt(upper**2 - dx**2)])
    # waist: side -> dart -> centre back; the dart takes what the waist does not need
    edge = cb_waist - side_waist
    edge_len = float(np.hypot(*edge))
    dart_w = edge_len - g["bw"]
    u = edge / edge_len
    mid = side_waist + u * (edge_len / 2)
    normal = np.array([u[1], -u[0]])  # pointing down into the piece
    if normal[1] > 0:
        normal = -normal
    o = OutlineBuilder()
    o.start(cb_waist, "cb_waist")
    o.line(cb_hip, "cb_hip", notch=True)
    yc = crotch[1]
    o.curve(
        (cb_hip[0] - slope * (cb_hip[1] - yc) * 0.55, yc + (cb_hip[1] - yc) * 0.35),
        (crotch[0] + g["eb"] * 0.5, yc - 0.3),
        crotch,
        "crotch_point",
        n=12,
    )
    o.line(inside_knee, f"inside_{knee}", notch=True)
    o.line((x_c - g["hemb"] / 2, g["y_hem"]), "inside_hem")
    o.line((x_c, g["y_hem"]), "hem_crease", allowance_cm=HEM_ALLOWANCE)
    o.line((x_c + g["hemb"] / 2, g["y_hem"]), "side_hem", allowance_cm=HEM_ALLOWANCE)
    o.line(side_knee, f"side_{knee}", notch=True)
    o.line(side_crotch, "side_crotch")
    o.line(side_hip, "side_hip", notch=True)
    o.polyline(hermite(side_hip, (0.0, 1.0), side_waist, (-0.3, 1.0), 8), "side_waist")
    o.line(mid - u * (dart_w / 2), "dart_side", notch=True)
    o.line(mid + normal * 11.0, "dart_apex", dart_apex=True)
    o.line(mid + u * (dart_w / 2), "dart_cb", notch=True)
    net = o.close(allowance_cm=SEAM_ALLOWANCE)
    return PieceDraft(
        name="back",
        net=net,
        quantity=Quantity(right=1, left=1),
        grain=((x_c, max(g["y_knee"] - 15.0, g["y_hem"] + 3.0)), (x_c, g["y_hip"])),
        placement=Placement(
            body_part="right_leg",
            side="back",
            anchor="waist_side_right",
            anchor_mark="side_waist",
        ),
        landmarks={
            "waist_back": "cb_waist",
            "waist_side_right": "side_waist",
            "hip_side_right": "side_hip",
            "crotch_point": "crotch_point",
        },
        category="BACK",
        annotation=f"{style} BACK",
    )


def waistband(b, g, front_piece: PieceDraft, back_piece: PieceDraft) -> PieceDraft:
    def seg(p: PieceDraft, s: str, e: str) -> float:
        pts, m = p.net.points, p.net.marks
        i, j = m[s], m[e]
        idx = np.arange(i, j + 1) if j >= i else np.r_[i : len(pts), 0 : j + 1]
        return float(np.linalg.norm(np.diff(pts[idx], axis=0), axis=1).sum())

    f = seg(front_piece, "cf_waist", "side_waist")
    bs = seg(back_piece, "side_waist", "dart_side")
    bc = seg(back_piece, "dart_cb", "cb_waist")
    h = WAISTBAND_CM
    xs = {"cb": 0.0, "dart_right": bc, "side_right": bc + bs, "cf_right": bc + bs + f}
    o = OutlineBuilder()
    o.start((-xs["cf_right"], 0.0), "cf_left")
    o.line((-xs["side_right"], 0.0), "side_left", notch=True)
    o.line((-xs["dart_right"], 0.0), "dart_left")
    o.line((0.0, 0.0), "cb", notch=True)
    o.line((xs["dart_right"], 0.0), "dart_right")
    o.line((xs["side_right"], 0.0), "side_right", notch=True)
    o.line((xs["cf_right"], 0.0), "cf_right")
    o.line((xs["cf_right"], h), "top_right")
    o.line((0.0, h), "top_cb")
    o.line((-xs["cf_right"], h), "top_left")
    net = o.close()
    return PieceDraft(
        name="waistband",
        net=net,
        quantity=Quantity(right=1, left=0),
        grain=((-20.0, h / 2), (20.0, h / 2)),
        placement=Placement(
            body_part="torso", side="around", anchor="waist_back", anchor_mark="cb"
        ),
        landmarks={
            "waist_back": "cb",
            "waist_side_right": "side_right",
            "waist_side_left": "side_left",
            "waist_front": "cf_right",
        },
        category="WAISTBAND",
        annotation="WAISTBAND (CUT 1, CENTRE BACK AT MIDDLE)",
    )


def draft(b: dict[str, float]) -> list[PieceDraft]:
    g = _geometry(b)
    f, k = front(b, g), back(b, g)
    return [f, k, waistband(b, g, f, k)]


SEAMS = [
    seam(
        "side_right",
        ("front", "side_waist", "side_hem"),
        ("back", "side_hem", "side_waist"),
    ),
    seam(
        "side_left",
        ("front", "side_waist", "side_hem", "mirror"),
        ("back", "side_hem", "side_waist", "mirror"),
    ),
    seam(
        "inside_leg_right",
        ("front", "inside_hem", "crotch_point"),
        ("back", "crotch_point", "inside_hem"),
    ),
    seam(
        "inside_leg_left",
        ("front", "inside_hem", "crotch_point", "mirror"),
        ("back", "crotch_point", "inside_hem", "mirror"),
    ),
    seam(
        "front_rise",
        ("front", "crotch_point", "cf_waist"),
        ("front", "crotch_point", "cf_waist", "mirror"),
    ),
    seam(
        "back_rise",
        ("back", "cb_waist", "crotch_point"),
        ("back", "cb_waist", "crotch_point", "mirror"),
    ),
    seam(
        "dart_right",
        ("back", "dart_side", "dart_apex"),
        ("back", "dart_apex", "dart_cb"),
    ),
    seam(
        "dart_left",
        ("back", "dart_side", "dart_apex", "mirror"),
        ("back", "dart_apex", "dart_cb", "mirror"),
    ),
    seam(
        "waist_front_right",
        ("front", "cf_waist", "side_waist"),
        ("waistband", "side_right", "cf_right"),
    ),
    seam(
        "waist_back_right_side",
        ("back", "side_waist", "dart_side"),
        ("waistband", "dart_right", "side_right"),
    ),
    seam(
        "waist_back_right_cb",
        ("back", "dart_cb", "cb_waist"),
        ("waistband", "cb", "dart_right"),
    ),
    seam(
        "waist_front_left",
        ("front", "cf_waist", "side_waist", "mirror"),
        ("waistband", "cf_left", "side_left"),
    ),
    seam(
        "waist_back_left_side",
        ("back", "side_waist", "dart_side", "mirror"),
        ("waistband", "side_left", "dart_left"),
    ),
    seam(
        "waist_back_left_cb",
        ("back", "dart_cb", "cb_waist", "mirror"),
        ("waistband", "dart_left", "cb"),
    ),
    seam(
        "waistband_closure",
        ("waistband", "top_left", "cf_left"),
        ("waistband", "cf_right", "top_right"),
    ),
]

LINKS = [
    link(
        "waist_girth",
        WAIST_EASE,
        leg("front", "cf_waist", "side_waist", "boundary", 2),
        leg("back", "side_waist", "dart_side", "boundary", 2),
        leg("back", "dart_cb", "cb_waist", "boundary", 2),
    ),
    link(
        "hip_girth",
        HIP_EASE,
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
    link("outside_leg_right", None, leg("front", "side_waist", "side_hem", "boundary")),
    link(
        "inside_leg_right", None, leg("front", "inside_hem", "crotch_point", "boundary")
    ),
    link(
        "thigh_girth_right",
        None,
        leg("front", "side_crotch", "crotch_point"),
        leg("back", "crotch_point", "side_crotch"),
    ),
    link(
        "knee_girth_right",
        None,
        leg("front", "side_knee", "inside_knee"),
        leg("back", "inside_knee", "side_knee"),
    ),
]

DESCRIPTION = (
    "Classic straight-leg trousers: front, back with waist dart, straight waistband"
)


def build():
    return build_pattern(
        style="trousers",
        description=DESCRIPTION,
        chart=CHART,
        draft=draft,
        seams=SEAMS,
        links=LINKS,
        fabric_class=FabricClass.WOVEN,
        fabric_why="drafted for a woven suiting or twill",
    )


if __name__ == "__main__":
    from patternbridge.library.catalogue import write_garment

    write_garment(build(), Path(__file__).resolve().parent)
