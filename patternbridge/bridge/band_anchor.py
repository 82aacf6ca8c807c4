"""Where a band goes on the body: where the opening it is sewn to lies, read off the seam graph.

A band (binding, neckband, collar, cuff, waistband) has no shape of its own
that says where it sits: an armhole binding of a deep tank armhole lies on
the torso down to the underarm, a neck binding round a scoop far below the
neck. So the band takes its anchor from the pieces it is sewn to. Every seam
of the band's drawn copy to a piece with body landmarks (a front's
``centre_neck``, ``neck_side``, ``shoulder_point``, ``underarm``) names, for
each landmark mark inside the seam's range, the vertex of the band that meets
it (the two sides run from opposite ends when the seam is ``reverse``). Of
these, the band vertex nearest the middle of the band's sewn span anchors it
(a landmark's distance from the seam counts against it):
that vertex goes on that landmark, on the body part the landmark belongs to
(:data:`LANDMARK_PART`). A band whose partners carry no landmark on its seams
(a cuff on a sleeve hem) hangs from its partner's anchor instead
(:func:`band_below`): on a limb piece (a sleeve, a leg) the band vertex
meeting the middle of the sewn edge goes as far below the partner's anchor
landmark (the sleeve's cap top on the shoulder point) as that edge lies below
the partner's anchor mark in the upright drawing, down the limb's landmarks
(``Placement.drop_cm``): a short sleeve's cuff sits at its hem, a long
sleeve's near the wrist. Only a band sewn to nothing with a place keeps the
role's place (:data:`.landmarks` ``_BAND_PLACE``).

Only the band's drawn copy is read; the mirror copy is placed mirrored, on
the mirrored landmark.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..library.seams import sew_line
from ..pattern.model import Pattern
from .model import BridgeInference, Join, is_band

__all__ = ["LANDMARK_PART", "MAX_SNAP_CM", "BandBelow", "band_anchor", "band_below"]

#: a body landmark a band meets -> the body part (assembler proxy) the band is wrapped on; a landmark of the
#: body's right side is named here, its left twin maps to the left limb
LANDMARK_PART = {
    "front_neck_point": "neck",
    "back_neck_point": "neck",
    "neck_shoulder_point_right": "neck",
    "shoulder_point_right": "torso",
    "armpit_point_right": "torso",
    "waist_front": "torso",
    "waist_back": "torso",
    "waist_side_right": "torso",
    "wrist_point_right": "right_arm",
}
#: a landmark farther than this (cm along the outline) from the seam range, or from the band vertex it meets,
#: does not anchor the band (an armhole range may start a step of the side seam away from the underarm mark)
MAX_SNAP_CM = 3.0


def _swap_side(landmark: str) -> str:
    """The landmark's twin on the other body side (``shoulder_point_right`` <-> ``shoulder_point_left``)."""
    if landmark.endswith("_right"):
        return landmark[: -len("_right")] + "_left"
    if landmark.endswith("_left"):
        return landmark[: -len("_left")] + "_right"
    return landmark


def _arc(pattern: Pattern, piece: str) -> tuple[np.ndarray, float]:
    """(n,) sew-line arc length of every vertex from vertex 0, and the perimeter."""
    pts = sew_line(pattern.piece(piece))[0]
    seg = np.linalg.norm(np.roll(pts, -1, axis=0) - pts, axis=1)
    return np.concatenate([[0.0], np.cumsum(seg)])[:-1], float(seg.sum())


def _along(arc: np.ndarray, total: float, start: int, end: int) -> tuple[np.ndarray, float]:
    """(n,) distance of every vertex from ``start`` in outline order, and the range's length to ``end``."""
    d = np.mod(arc - arc[start], total)
    return d, float(d[end]) if end != start else total


def _reverse(pattern: Pattern, inference: BridgeInference, j: Join) -> bool:
    """Whether ``a.start`` meets ``b.end``, as the sidecar writes the seam."""
    if j.copy_a or j.copy_b:
        return (j.copy_a or "primary") == (j.copy_b or "primary")
    from .sidecar import runs_against

    return runs_against(pattern, inference, j)


def _meets(pattern: Pattern, inference: BridgeInference, j: Join, vertex: int) -> tuple[float, float] | None:
    """Where partner vertex ``vertex`` meets the band range ``j.b`` (band cm from vertex 0) and how far outside
    the range ``j.a`` it lies (cm); None when farther than ``MAX_SNAP_CM`` (one just outside, the corner
    beside an armhole's end, counts as that end)."""
    arc_a, total_a = _arc(pattern, j.a.piece)
    d_a, len_a = _along(arc_a, total_a, j.a.start, j.a.end)
    d, outside = float(d_a[vertex]), 0.0
    if d > len_a + 1e-6:
        after, before = d - len_a, total_a - d
        outside = min(after, before)
        if outside > MAX_SNAP_CM:
            return None
        d = len_a if after < before else 0.0
    t = d / len_a if len_a > 0 else 0.0
    arc_b, total_b = _arc(pattern, j.b.piece)
    _, len_b = _along(arc_b, total_b, j.b.start, j.b.end)
    s = (1.0 - t) if _reverse(pattern, inference, j) else t
    return float(np.mod(arc_b[j.b.start] + s * len_b, total_b)), outside


def _sewn_middle(starts: np.ndarray, lengths: np.ndarray, total: float) -> tuple[float, float]:
    """(start, middle) of the band's sewn span, cm from vertex 0: the ranges' union, open at its largest gap."""
    order = np.argsort(starts)
    s, e = starts[order], starts[order] + lengths[order]
    gaps = np.mod(np.roll(s, -1) - e, total)
    k = int(np.argmax(gaps))
    origin = float(s[(k + 1) % len(s)])
    return origin, origin + 0.5 * (total - float(gaps[k]))


def band_anchor(pattern: Pattern, inference: BridgeInference, band: str, found: dict) -> tuple[str, int] | None:
    """(landmark, band vertex): the landmark of a partner piece the band's drawn copy is sewn to, nearest the
    middle of its sewn span, and the band vertex that meets it; None when no seam of the band meets one.

    ``found`` maps the partner pieces to their :class:`~.landmarks.PieceLandmarks`.
    """
    seams = [
        j
        for j in inference.joins
        if j.b.piece == band
        and j.a.piece != band
        and j.kind != "band"
        and (j.copy_b or "primary") == "primary"
        and not is_band(inference.roles[j.a.piece].role)
    ]
    if not seams:
        return None
    arc_b, total_b = _arc(pattern, band)
    origin, middle = _sewn_middle(
        np.array([arc_b[j.b.start] for j in seams]),
        np.array([_along(arc_b, total_b, j.b.start, j.b.end)[1] for j in seams]),
        total_b,
    )
    best: tuple[float, str, int] | None = None
    for j in seams:
        partner = found.get(j.a.piece)
        if partner is None:
            continue
        mirrored = (j.copy_a or "primary") == "mirror"
        for landmark, mark in partner.landmarks.items():
            name = _swap_side(landmark) if mirrored else landmark
            if _swap_side(name) not in LANDMARK_PART and name not in LANDMARK_PART:
                continue
            met = _meets(pattern, inference, j, partner.marks[mark])
            if met is None:
                continue
            pos, outside = met
            gap = np.abs(np.mod(arc_b - pos + 0.5 * total_b, total_b) - 0.5 * total_b)
            v = int(np.argmin(gap))
            if gap[v] > MAX_SNAP_CM:
                continue
            # nearest the middle; of landmarks meeting one vertex (a strap's side neck and shoulder point,
            # 2 cm apart), the one nearest the seam
            off = abs(float(np.mod(pos - origin, total_b)) - (middle - origin)) + outside + float(gap[v])
            if best is None or off < best[0] - 1e-6:
                best = (off, name, v)
    return None if best is None else (best[1], best[2])


#: the body parts of a limb piece, below whose anchor a band sewn to it hangs
_LIMBS = ("right_arm", "left_arm", "right_leg", "left_leg")


@dataclass(frozen=True, slots=True, kw_only=True)
class BandBelow:
    """A band hung from its partner's anchor: the band vertex that goes ``drop_cm`` below the partner's anchor
    landmark on the partner's limb."""

    vertex: int
    body_part: str
    anchor: str
    drop_cm: float


def band_below(pattern: Pattern, inference: BridgeInference, band: str, found: dict) -> BandBelow | None:
    """Where a band sewn to a limb piece's edge without landmarks hangs: the middle of that edge, as far
    below the partner's anchor landmark as it lies below the partner's anchor mark upright (sample size).

    Of the band's drawn copy's seams to a non-band piece placed on a limb, the one to a piece of the default
    garment first (a cuff sewn to a sleeve and to its alternative), then the longest; None when there is none.
    """
    chosen = set(inference.chosen)
    seams = []
    for j in inference.joins:
        if j.b.piece != band or j.a.piece == band or j.kind == "band" or (j.copy_b or "primary") != "primary":
            continue
        partner = found.get(j.a.piece)
        pl = None if partner is None else partner.placement
        if pl is None or pl.get("body_part") not in _LIMBS or pl.get("anchor_mark") not in partner.marks:
            continue
        if is_band(inference.roles[j.a.piece].role):
            continue
        arc_a, total_a = _arc(pattern, j.a.piece)
        d_a, len_a = _along(arc_a, total_a, j.a.start, j.a.end)
        seams.append((j.a.piece in chosen, len_a, j, d_a))
    if not seams:
        return None
    _, len_a, j, d_a = max(seams, key=lambda s: (s[0], s[1]))
    inside = np.flatnonzero(d_a <= len_a + 1e-6)
    mid = int(inside[np.argmin(np.abs(d_a[inside] - 0.5 * len_a))])
    met = _meets(pattern, inference, j, mid)
    if met is None:  # pragma: no cover - the middle of the range lies inside it
        return None
    arc_b, total_b = _arc(pattern, band)
    gap = np.abs(np.mod(arc_b - met[0] + 0.5 * total_b, total_b) - 0.5 * total_b)
    partner = found[j.a.piece]
    up = inference.orientations[j.a.piece].apply(sew_line(pattern.piece(j.a.piece))[0])
    drop = float(up[partner.marks[partner.placement["anchor_mark"]], 1] - up[mid, 1])
    return BandBelow(
        vertex=int(np.argmin(gap)),
        body_part=partner.placement["body_part"],
        anchor=partner.placement["anchor"],
        drop_cm=round(max(drop, 0.0), 3),
    )
