"""Marks on body landmarks and the assembler's placement of every piece, from its role and its upright shape.

Each piece is stood upright (:mod:`.orient`: +y up the body, the centre line at
x = 0) and its sew line read by level, as a pattern maker reads a block:

- **bodice** (a front or back whose top is scooped): the centre neck is the
  highest point on the centre line, the side neck the highest point of the
  body's right half, the shoulder point the outermost point less than 12 % of the height below
  the side neck,
  the underarm the outermost point between 45 % and 85 % of the height;
  placed on the torso at the front or back neck point;
- **skirt panel** (a front or back with a straight top): the centre waist and the
  outermost top corner; placed at the front or back waist;
- **leg** (front, back or one piece): the waist is the top (the highest 3 % of
  the leg's height); the crotch point is the
  tip of the side that reaches out furthest beyond its waist corner, the side
  waist the highest point of the outer quarter on the other side (on a one-piece leg, whose side seam is folded
  away, half way along the waist line from the top of the back rise to the top of the front rise); placed on the
  right leg at the side waist;
- **sleeve**: the cap top (highest point) on the shoulder point, right arm (a sleeve cut once and sewn
  into a left bodice half: the left arm);
- **band** (neckband, binding, collar, cuff, waistband): the middle of its long
  edge, on the neck, the arm, the wrist or the waist.

On a half piece the body's right half is the whole piece (its mirror copy is
the left); on a piece drawn whole it is the half on the viewer's left for a
front and on the viewer's right for a back (seen from outside). Marks are named
after what they are (``centre_neck``, ``cap_top`` …) and index the designer's
own outline.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..library.seams import sew_line
from ..pattern.model import Pattern, Role
from .alternatives import copies_cut
from .band_anchor import LANDMARK_PART, band_anchor, band_below
from .model import BridgeInference, Orientation
from .openings import shapes_scooped

__all__ = [
    "PieceLandmarks",
    "drawn_side",
    "leg_landmarks",
    "piece_landmarks",
    "skirt_panel_landmarks",
    "waist_line",
    "waist_middle",
    "worn_side",
]

_LEGS = (Role.LEG_FRONT, Role.LEG_BACK, Role.LEG)
#: band roles -> (body part, anchor landmark)
_BAND_PLACE = {
    Role.NECKBAND: ("neck", "back_neck_point"),
    Role.NECK_BINDING: ("neck", "back_neck_point"),
    Role.COLLAR: ("neck", "back_neck_point"),
    Role.COLLAR_STAND: ("neck", "back_neck_point"),
    Role.HOOD: ("neck", "back_neck_point"),
    Role.ARMHOLE_BINDING: ("right_arm", "shoulder_point_right"),
    Role.CUFF: ("right_arm", "wrist_point_right"),
    Role.WAISTBAND: ("torso", "waist_back"),
}


@dataclass(frozen=True, slots=True, kw_only=True)
class PieceLandmarks:
    """Named marks (name -> outline vertex), body landmarks (landmark -> mark) and placement of one piece."""

    marks: dict[str, int] = field(default_factory=dict)
    landmarks: dict[str, str] = field(default_factory=dict)
    placement: dict[str, str | float] | None = None


def _right_half(up: np.ndarray, o: Orientation, back: bool) -> np.ndarray:
    """(n,) distance from the centre line, negative on the body's left half of a piece drawn whole."""
    if not o.whole:
        return np.abs(up[:, 0])
    return up[:, 0] if back else -up[:, 0]


def _bodice(up: np.ndarray, o: Orientation, back: bool) -> PieceLandmarks:
    d, y = _right_half(up, o, back), up[:, 1]
    y0, h = y.min(), np.ptp(y)
    centre = np.nonzero(np.abs(up[:, 0]) < 0.5)[0]
    right = np.nonzero(d > 0.5)[0]
    if not len(centre) or not len(right):
        return PieceLandmarks()
    neck_side = int(right[np.argmax(y[right])])
    top = np.nonzero((y >= y[neck_side] - 0.12 * h) & (d > 0.5))[0]
    band = np.nonzero((y >= y0 + 0.45 * h) & (y <= y0 + 0.85 * h))[0]
    marks = {
        "centre_neck": int(centre[np.argmax(y[centre])]),
        "centre_hem": int(centre[np.argmin(y[centre])]),
        "neck_side": neck_side,
        "shoulder_point": int(top[np.argmax(d[top])]),
    }
    side = "back" if back else "front"
    landmarks = {
        f"{side}_neck_point": "centre_neck",
        "neck_shoulder_point_right": "neck_side",
        "shoulder_point_right": "shoulder_point",
    }
    if len(band):
        marks["underarm"] = int(band[np.argmax(d[band])])
        landmarks["armpit_point_right"] = "underarm"
    placement = {"body_part": "torso", "side": side, "anchor": f"{side}_neck_point", "anchor_mark": "centre_neck"}
    return PieceLandmarks(marks=marks, landmarks=landmarks, placement=placement)


def skirt_panel_landmarks(up: np.ndarray, o: Orientation, back: bool) -> PieceLandmarks:
    d, y = _right_half(up, o, back), up[:, 1]
    top = np.nonzero(y >= y.max() - 0.1 * np.ptp(y))[0]
    centre = top[np.argmin(np.abs(up[top, 0]))]
    side = "back" if back else "front"
    marks = {"centre_waist": int(centre), "side_waist": int(top[np.argmax(d[top])])}
    landmarks = {f"waist_{side}": "centre_waist", "waist_side_right": "side_waist"}
    placement = {"body_part": "torso", "side": side, "anchor": f"waist_{side}", "anchor_mark": "centre_waist"}
    return PieceLandmarks(marks=marks, landmarks=landmarks, placement=placement)


def leg_landmarks(up: np.ndarray, role: Role) -> PieceLandmarks:
    x, y = up[:, 0], up[:, 1]
    top = np.nonzero(y >= y.max() - 0.03 * np.ptp(y))[0]  # the waist line, above the hip's bulge
    left, right = top[np.argmin(x[top])], top[np.argmax(x[top])]
    reach_left, reach_right = x[left] - x.min(), x.max() - x[right]
    crotch = int(np.argmin(x)) if reach_left > reach_right else int(np.argmax(x))
    marks = {"crotch_point": crotch}
    if role is Role.LEG:
        side_waist = waist_middle(up)
        side = "around"
    else:
        # the side waist: the highest point of the outer quarter on the side away from the crotch
        s = 1.0 if reach_left > reach_right else -1.0
        outer = np.nonzero(s * x >= np.max(s * x) - 0.25 * np.ptp(x))[0]
        side_waist, centre = outer[np.argmax(y[outer])], (left if s > 0 else right)
        side = "back" if role is Role.LEG_BACK else "front"
        marks["centre_waist"] = int(centre)
    marks["side_waist"] = int(side_waist)
    landmarks = {"waist_side_right": "side_waist", "crotch_point": "crotch_point"}
    if "centre_waist" in marks:
        landmarks[f"waist_{side}"] = "centre_waist"
    placement = {"body_part": "right_leg", "side": side, "anchor": "waist_side_right", "anchor_mark": "side_waist"}
    return PieceLandmarks(marks=marks, landmarks=landmarks, placement=placement)


#: a waist line's segments rise or fall less than this against their run (tan 45°); the rises are steeper
WAIST_SLOPE = 1.0


def waist_line(up: np.ndarray) -> np.ndarray:
    """(k,) vertex indices of the top edge through the highest point, in outline order, up to its two corners.

    From the highest vertex the outline is followed both ways while its
    segments stay flatter than ``WAIST_SLOPE``; where it turns down (the top
    of a rise, a side seam) the waist ends.
    """
    n = len(up)
    step = np.roll(up, -1, axis=0) - up  # segment k runs from vertex k to k + 1
    flat = np.abs(step[:, 1]) <= WAIST_SLOPE * np.abs(step[:, 0]) + 1e-9
    top = int(np.argmax(up[:, 1]))
    first, last = top, top
    while flat[(last) % n] and (last - first) < n - 1:
        last += 1
    while flat[(first - 1) % n] and (last - first) < n - 1:
        first -= 1
    return np.arange(first, last + 1) % n


def waist_middle(up: np.ndarray) -> int:
    """The vertex at half the length of the waist line (:func:`waist_line`): a one-piece leg's side waist.

    A one-piece leg's waist runs from the top of the back rise to the top of
    the front rise; its side seam, folded away, lies half way along.
    """
    idx = waist_line(up)
    pts = up[idx]
    cum = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(pts, axis=0), axis=1))])
    return int(idx[np.argmin(np.abs(cum - 0.5 * cum[-1]))])


def _band(up: np.ndarray, role: Role) -> PieceLandmarks:
    """The middle of the band's lower long edge, on the role's body landmark: a band not sewn to a piece
    with landmarks (:func:`.band_anchor.band_anchor` places the others where their opening lies)."""
    part, anchor = _BAND_PLACE[role]
    x, y = up[:, 0], up[:, 1]
    low = np.nonzero(y <= y.min() + 0.25 * np.ptp(y))[0]
    mid = int(low[np.argmin(np.abs(x[low] - 0.5 * (x.min() + x.max())))])
    placement = {"body_part": part, "side": "around", "anchor": anchor, "anchor_mark": "band_middle"}
    return PieceLandmarks(marks={"band_middle": mid}, placement=placement)


def _sleeve(up: np.ndarray) -> PieceLandmarks:
    cap = int(np.argmax(up[:, 1]))
    placement = {"body_part": "right_arm", "side": "around", "anchor": "shoulder_point_right", "anchor_mark": "cap_top"}
    return PieceLandmarks(marks={"cap_top": cap}, landmarks={"shoulder_point_right": "cap_top"}, placement=placement)


def _other(up: np.ndarray, role: Role) -> PieceLandmarks:
    """A yoke, placket, pocket or lining: its top middle on the neck point of its side."""
    side = "back" if role is Role.YOKE else "front"
    x, y = up[:, 0], up[:, 1]
    top = np.nonzero(y >= y.max() - 0.1 * np.ptp(y))[0]
    mid = int(top[np.argmin(np.abs(x[top]))])
    placement = {"body_part": "torso", "side": side, "anchor": f"{side}_neck_point", "anchor_mark": "top_middle"}
    return PieceLandmarks(marks={"top_middle": mid}, placement=placement)


def drawn_side(up: np.ndarray, role: Role, o: Orientation) -> str | None:
    """``right`` or ``left``: the body half a half piece's copy as drawn covers (None: drawn whole or not a half).

    Seen from outside, a right front has its centre line on its +x side and a
    right back on its -x side; a right leg's crotch reaches toward +x on the
    front and toward -x on the back. Sleeves and one-piece legs are drafted as
    the right one.
    """
    if o.whole:
        return None
    if role in (Role.FRONT, Role.BACK):
        return "right" if o.centre_on_right == (role is Role.FRONT) else "left"
    if role in (Role.LEG_FRONT, Role.LEG_BACK):
        m = leg_landmarks(up, role).marks
        toward_plus = up[m["crotch_point"], 0] > up[m["side_waist"], 0]
        return "right" if toward_plus == (role is Role.LEG_FRONT) else "left"
    if role in (Role.SLEEVE, Role.LEG):
        return "right"
    return None


def worn_side(pattern: Pattern, inference: BridgeInference, name: str) -> str | None:
    """``right`` or ``left``: the body side the piece as drawn is worn on (None: drawn whole or not a half).

    :func:`drawn_side`, except for a sleeve cut once (a garment whose left and
    right pieces are drawn separately): it is worn on the side of the bodice
    its cap is sewn to.
    """
    o, role = inference.orientations[name], inference.roles[name].role
    side = drawn_side(o.apply(sew_line(pattern.piece(name))[0]), role, o)
    if role is not Role.SLEEVE or copies_cut(pattern.piece(name)) > 1 or o.fold is not None:
        return side
    for j in inference.joins:
        if j.kind == "band" or (j.a.piece == name) == (j.b.piece == name):
            continue
        other = j.b.piece if j.a.piece == name else j.a.piece
        if inference.roles[other].role in (Role.FRONT, Role.BACK):
            oo = inference.orientations[other]
            worn = drawn_side(oo.apply(sew_line(pattern.piece(other))[0]), inference.roles[other].role, oo)
            if worn is not None:
                return worn
    return side


def _sided(found: PieceLandmarks, side: str | None) -> PieceLandmarks:
    """A piece drawn as the left half names the left landmarks and is placed on the left limb."""
    if side != "left":
        return found
    landmarks = {k.replace("_right", "_left"): v for k, v in found.landmarks.items()}
    placement = found.placement
    if placement is not None:
        placement = {
            **placement,
            "body_part": placement["body_part"].replace("right_", "left_"),
            "anchor": placement["anchor"].replace("_right", "_left"),
        }
    return PieceLandmarks(marks=found.marks, landmarks=landmarks, placement=placement)


def piece_landmarks(pattern: Pattern, inference: BridgeInference) -> dict[str, PieceLandmarks]:
    """Marks, landmarks and placement of every piece of ``pattern`` from its inferred role and turn."""
    out = {}
    for piece in pattern.pieces:
        o, role = inference.orientations[piece.name], inference.roles[piece.name].role
        up = o.apply(sew_line(piece)[0])
        if role in (Role.FRONT, Role.BACK):
            scooped = shapes_scooped(up) or o.fold is not None
            builder = _bodice if scooped else skirt_panel_landmarks
            found = builder(up, o, role is Role.BACK)
            found = _sided(found, drawn_side(up, role, o))
            out[piece.name] = found if found.placement else _other(up, role)
        elif role in _LEGS:
            out[piece.name] = _sided(leg_landmarks(up, role), drawn_side(up, role, o))
        elif role is Role.SLEEVE:
            out[piece.name] = _sided(_sleeve(up), worn_side(pattern, inference, piece.name))
        elif role in _BAND_PLACE:
            out[piece.name] = _band(up, role)
        else:
            out[piece.name] = _other(up, role)
    for piece in pattern.pieces:
        if inference.roles[piece.name].role in _BAND_PLACE:
            out[piece.name] = _band_on_opening(pattern, inference, piece.name, out)
    return out


def _band_on_opening(pattern: Pattern, inference: BridgeInference, name: str, found: dict) -> PieceLandmarks:
    """A band placed where the opening it is sewn to lies (:mod:`.band_anchor`): on a landmark of that
    opening, else below the anchor of the limb piece it is sewn to, else by its role."""
    anchored = band_anchor(pattern, inference, name, found)
    if anchored is None:
        below = band_below(pattern, inference, name, found)
        if below is None:
            return found[name]
        placement = {
            "body_part": below.body_part,
            "side": "around",
            "anchor": below.anchor,
            "anchor_mark": "band_anchor",
            "drop_cm": below.drop_cm,
        }
        return PieceLandmarks(marks={"band_anchor": below.vertex}, placement=placement)
    landmark, vertex = anchored
    part = LANDMARK_PART[landmark.replace("_left", "_right")]
    if landmark.endswith("_left"):
        part = part.replace("right_", "left_")
    placement = {"body_part": part, "side": "around", "anchor": landmark, "anchor_mark": "band_anchor"}
    return PieceLandmarks(marks={"band_anchor": vertex}, placement=placement)
