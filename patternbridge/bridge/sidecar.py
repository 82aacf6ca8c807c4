"""The inference as a bridge sidecar (``formats/bridge.md``): marks, roles, turns, seams.

Every seam end becomes a mark ``v<vertex>`` on the designer's own outline (the
file is not changed: the graded DXF sent back keeps its orientation, names and
half pieces); each piece records its role, the turn that stands it upright, its
named marks on body landmarks and its placement (:mod:`.landmarks`).
All inferred seams are written ``"status": "proposed"`` with their confidence;
a band sewn along an opening made of several ranges is written once per range
with ``"status": "band"`` (not applied as a seam until a person puts marks on
the band at the opening's joints).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from ..library.seams import sew_line
from ..library.sidecar import SIDECAR_FORMAT
from ..pattern.json import measurement_link_to_dict
from ..pattern.model import BINDING_ROLES, MeasurementLink, Pattern, Piece
from .alternatives import copies_cut
from .band_spans import split_bands
from .fabric import FabricInference, infer_fabric, pullover_neck_cm
from .landmarks import PieceLandmarks, piece_landmarks, worn_side
from .links import measurement_links
from .model import BridgeInference, Join, Trim, is_band
from .size_chart import choose_chart

__all__ = ["SIDECAR_VERSION", "inference_sidecar", "runs_against"]

SIDECAR_VERSION = "1.2"


def _edge(side, copy: str) -> dict[str, Any]:
    return {"piece": side.piece, "start": f"v{side.start}", "end": f"v{side.end}", "copy": copy}


def runs_against(pattern: Pattern, inference: BridgeInference, j: Join) -> bool:
    """Whether ``b`` runs against ``a`` when sewn (``a.start`` meets ``b.end``), from the upright pieces.

    Along a seam that runs up the body the two sides meet where their ends
    are level; across the body (a shoulder, a waist) where they are the same
    distance from the centre line. A seam up one side that rises on the other
    by a fifth of its run (an armhole against a flat sleeve cap, 9 cm high
    over 21 cm) runs up the body too: the cap's top meets the shoulder, and
    the distance from the centre line, which a sleeve does not have, would
    sew the cap upside down.
    """
    ends = []
    for side in (j.a, j.b):
        pts = inference.orientations[side.piece].apply(sew_line(pattern.piece(side.piece))[0])
        ends.append((pts[side.start], pts[side.end]))
    (a0, a1), (b0, b1) = ends
    da, db = a1 - a0, b1 - b0
    up_a, up_b = abs(da[1]) > 0.5 * abs(da[0]), abs(db[1]) > 0.5 * abs(db[0])
    rises_a, rises_b = abs(da[1]) > 0.2 * abs(da[0]), abs(db[1]) > 0.2 * abs(db[0])
    if (up_a and rises_b) or (up_b and rises_a):
        return bool(np.sign(da[1]) != np.sign(db[1]))
    return bool((abs(a1[0]) > abs(a0[0])) != (abs(b1[0]) > abs(b0[0])))


def _side_of(pattern: Pattern, inference: BridgeInference, name: str) -> str | None:
    return worn_side(pattern, inference, name)


def _seam(pattern: Pattern, inference: BridgeInference, j: Join) -> dict[str, Any]:
    """One seam; a half drawn as the left half meets a right-drawn piece's mirror copy (one body side).

    Pieces drawn for opposite sides and cut once each (a garment whose left
    and right pieces are drawn separately) meet as drawn.
    """
    mirror = centre = j.kind == "fold" or (j.kind == "centre" and j.a.piece == j.b.piece)
    if not mirror and j.kind != "band" and j.a.piece != j.b.piece:
        sa, sb = _side_of(pattern, inference, j.a.piece), _side_of(pattern, inference, j.b.piece)
        mirror = sa is not None and sb is not None and sa != sb and _has_mirror_copy(pattern, inference, j.b.piece)
    copy_a, copy_b = "primary", "mirror" if mirror else "primary"
    reverse = False if centre else runs_against(pattern, inference, j)
    if j.kind != "band" and (j.copy_a or j.copy_b):
        # a band's part placed on the copies it binds: pieces seen from outside run against each other
        copy_a, copy_b = j.copy_a or "primary", j.copy_b or "primary"
        reverse = copy_a == copy_b
    return {
        "id": j.id,
        "kind": "fold" if j.kind == "fold" else "seam",
        "reverse": reverse,
        "ease_cm": 0.0 if j.kind == "band" else j.ease_cm,
        "status": "band" if j.kind == "band" else "proposed",
        "confidence": j.confidence,
        "a": _edge(j.a, copy_a),
        "b": _edge(j.b, copy_b),
        "length_a_cm": j.a.length_cm,
        "length_b_cm": j.b.length_cm,
        "why": j.why,
    }


def _has_mirror_copy(pattern: Pattern, inference: BridgeInference, name: str) -> bool:
    return inference.orientations[name].fold is not None or copies_cut(pattern.piece(name)) > 1


def folded_double(pattern: Pattern, inference: BridgeInference, j: Join) -> bool:
    """Whether ``j`` is the fold of a band folded along its length (its fold edge at least half as long as the
    band along its principal axis): cut unfolded and folded double over the edge it is sewn by, it is worn as
    its drawn half, both layers together, so the drape sews no mirror half to it; its mirror copy is the band
    of the other body side (a short sleeve's rib cuff, drawn 2.2 cm wide on its fold for each sleeve)."""
    if j.kind != "fold" or not is_band(inference.roles[j.a.piece].role):
        return False
    pts = np.asarray(pattern.piece(j.a.piece).outline, dtype=np.float64)
    centred = pts - pts.mean(axis=0)
    length = float(np.ptp(centred @ np.linalg.svd(centred, full_matrices=False)[2][0]))
    return float(np.linalg.norm(pts[j.a.end] - pts[j.a.start])) >= 0.5 * length


def _with_twins(pattern: Pattern, inference: BridgeInference, seams: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """Each seam between pieces that both have a mirror copy, also on the other body side (copies swapped).

    A sleeve's underarm or a pair of fronts and backs is sewn on both copies; the
    seam inferred on the drawn pieces is written once per body side. A piece's
    seam to itself (a one-piece leg's inseam) is twinned when its mirror copy is
    sewn to another piece or cut anyway; a band's closure only when its mirror
    copy is sewn to another piece: closing a neck binding's mirror copy added a
    second binding, sewn to nothing else, that was draped as a loose loop at the
    neck (a band the file cuts more often than the garment wears it is written
    with ``worn_copies``, :func:`_worn_copies`).
    """
    swap = {"primary": "mirror", "mirror": "primary"}
    out = list(seams)
    sewn = {(e["piece"], e["start"], e["end"], e["copy"]) for s in seams for e in (s["a"], s["b"])}
    closures = []
    for s in seams:
        a, b = s["a"]["piece"], s["b"]["piece"]
        if s["kind"] == "fold" or s["status"] == "band" or (a == b and s["a"]["copy"] != s["b"]["copy"]):
            continue  # a fold or a centre seam joins the two copies already
        twin = [(e["piece"], e["start"], e["end"], swap[e["copy"]]) for e in (s["a"], s["b"])]
        if any(t in sewn for t in twin):
            continue  # the other copy's edge is sewn already (a band round both halves of a neckline)
        if _has_mirror_copy(pattern, inference, a) and _has_mirror_copy(pattern, inference, b):
            (closures if a == b else out).append(
                {
                    **s,
                    "id": f"{s['id']}_twin",
                    "a": {**s["a"], "copy": swap[s["a"]["copy"]]},
                    "b": {**s["b"], "copy": swap[s["b"]["copy"]]},
                }
            )
    placed = {(e["piece"], e["copy"]) for s in out if s["a"]["piece"] != s["b"]["piece"] for e in (s["a"], s["b"])}
    # a piece cut twice is worn twice (a one-piece leg's inseam on both legs), but a band only where it binds
    cut = {
        c["a"]["piece"]
        for c in closures
        if copies_cut(pattern.piece(c["a"]["piece"])) > 1 and not is_band(inference.roles[c["a"]["piece"]].role)
    }
    return out + [c for c in closures if (c["a"]["piece"], c["a"]["copy"]) in placed or c["a"]["piece"] in cut]


def _worn_copies(pattern: Pattern, inference: BridgeInference, seams: list[dict[str, Any]]) -> dict[str, list[str]]:
    """Band -> the copies the garment wears, for each band cut more often than it is sewn to other pieces.

    A neck binding cut twice (``2XFABRIC``, or a pair) binds the one neckline
    with one copy; the other has no opening to bind (it is the file's spare,
    or a second layer the file does not sew) and is not draped.
    """
    sewn: dict[str, set[str]] = {}
    for s in seams:
        if s["a"]["piece"] != s["b"]["piece"]:
            for e in (s["a"], s["b"]):
                sewn.setdefault(e["piece"], set()).add(e["copy"])
    out = {}
    for name in inference.chosen:
        if not is_band(inference.roles[name].role) or name not in sewn:
            continue
        if copies_cut(pattern.piece(name)) > len(sewn[name]):
            out[name] = sorted(sewn[name])
    return out


#: a binding is folded over the edge it binds, half outside and half inside: the drape wears its outer half
BINDING_FOLD = 0.5


def _trim_dict(t: Trim) -> dict[str, str]:
    """A band applied flat as the sidecar writes it: the marks of its two cut lines."""
    return {
        "start": f"v{t.start}",
        "start_across": f"v{t.start_across}",
        "end": f"v{t.end}",
        "end_across": f"v{t.end_across}",
    }


@dataclass(frozen=True, slots=True, kw_only=True)
class _PieceExtras:
    """What a piece's sidecar entry writes beside its role and turn.

    marks : piece -> outline vertices that carry a ``v<vertex>`` mark (seam ends, trims, links, folds)
    inserted : piece -> the marks that are new vertices (a band's joints between two of its vertices)
    found : piece -> its named marks on body landmarks and its placement
    trims : piece -> the band applied flat on it
    worn : band -> the copies the garment wears (those cut more often than sewn)
    bound : bindings sewn to other pieces (worn folded, half their width)
    fabric : the garment's fabric inference (the pieces whose own words name another class)
    """

    marks: dict[str, set[int]]
    inserted: dict[str, set[int]]
    found: dict[str, PieceLandmarks]
    trims: dict[str, Trim]
    worn: dict[str, list[str]]
    bound: set[str]
    fabric: FabricInference


def _seam_end_marks(
    pattern: Pattern, inference: BridgeInference, trims: dict[str, Trim], links: list[MeasurementLink]
) -> dict[str, set[int]]:
    """Piece -> the outline vertices marked: every join's and trim's ends, every link leg's ends, every fold."""
    marks: dict[str, set[int]] = {p.name: set() for p in pattern.pieces}
    for j in inference.joins:
        for side in (j.a, j.b):
            marks[side.piece] |= {side.start, side.end}
    for t in trims.values():
        marks[t.piece] |= {t.start, t.start_across, t.end, t.end_across}
    for link in links:
        for leg in link.legs:
            marks[leg.piece] |= {int(leg.start[1:]), int(leg.end[1:])}
    for p in pattern.pieces:
        fold = inference.orientations[p.name].fold
        if fold is not None:
            marks[p.name] |= set(fold)
    return marks


def _piece_entry(p: Piece, inference: BridgeInference, extras: _PieceExtras) -> dict[str, Any]:
    """The sidecar entry of piece ``p``: role, turn, marks, landmarks, placement and what it is worn as."""
    o = inference.orientations[p.name]
    guess = inference.roles[p.name]
    found, inserted = extras.found[p.name], extras.inserted.get(p.name, ())
    return {
        "name": p.name,
        "n_vertices": p.n_vertices,
        "role": guess.role.value,
        "role_confidence": guess.confidence,
        "role_why": guess.why,
        "orientation": {
            "turn_deg": round(o.turn_deg, 3),
            "offset_cm": [round(float(v), 4) for v in o.offset],
            "fold": None if o.fold is None else [f"v{o.fold[0]}", f"v{o.fold[1]}"],
            "centre_on_right": o.centre_on_right,
            "whole": o.whole,
            "confidence": round(o.confidence, 2),
        },
        "marks": {
            **{
                f"v{i}": {
                    "vertex": i,
                    "xy": [round(float(v), 4) for v in p.outline[i]],
                    **({"insert": True} if i in inserted else {}),
                }
                for i in sorted(extras.marks[p.name])
            },
            **{
                name: {"vertex": i, "xy": [round(float(v), 4) for v in p.outline[i]]} for name, i in found.marks.items()
            },
        },
        "landmarks": dict(found.landmarks),
        "placement": found.placement,
        **({"trim": _trim_dict(extras.trims[p.name])} if p.name in extras.trims else {}),
        **({"worn_copies": extras.worn[p.name]} if p.name in extras.worn else {}),
        **({"worn_width_share": BINDING_FOLD} if p.name in extras.bound else {}),
        **({"fabric_class": str(extras.fabric.pieces[p.name])} if p.name in extras.fabric.pieces else {}),
    }


def inference_sidecar(pattern: Pattern, inference: BridgeInference) -> dict[str, Any]:
    """The sidecar dict of ``inference`` for ``pattern`` (JSON-ready).

    Bands placed along several ranges of an opening are written as one seam
    per range, with marks at the joints on the band (:func:`.band_spans.split_bands`);
    a joint between two of the band's vertices is written with ``"insert": true``
    and becomes a vertex when the sidecar is applied.
    """
    neck = pullover_neck_cm(pattern, inference)  # before the bands become ordinary seams
    pattern, inference, inserted = split_bands(pattern, inference)
    trims = {t.piece: t for t in inference.trims}
    chart = choose_chart(pattern.sizes, pattern.sample_size)
    links = measurement_links(pattern, inference, chart)
    found = piece_landmarks(pattern, inference)
    joins = [j for j in inference.joins if not folded_double(pattern, inference, j)]
    seams = _with_twins(pattern, inference, [_seam(pattern, inference, j) for j in joins])
    sewn_to_others = {e["piece"] for s in seams if s["a"]["piece"] != s["b"]["piece"] for e in (s["a"], s["b"])}
    fabric = infer_fabric(pattern, inference.roles, inference.chosen, links, chart.body_cm, neck_cm=neck)
    extras = _PieceExtras(
        marks=_seam_end_marks(pattern, inference, trims, links),
        inserted=inserted,
        found=found,
        trims=trims,
        worn=_worn_copies(pattern, inference, seams),
        bound={n for n in sewn_to_others if inference.roles[n].role in BINDING_ROLES},
        fabric=fabric,
    )
    return {
        "format": SIDECAR_FORMAT,
        "format_version": SIDECAR_VERSION,
        "length_unit": "cm",
        "style": pattern.style,
        "description": f"inferred by patternbridge bridge infer ({len(inference.joins)} seams)",
        "sample_size": pattern.sample_size,
        "size_chart": chart.to_dict(),
        "fabric_class": str(fabric.fabric),
        "fabric_why": fabric.why,
        "garment_pieces": list(inference.chosen),
        "alternatives": [[list(option) for option in group] for group in inference.alternatives],
        "pieces": [_piece_entry(p, inference, extras) for p in pattern.pieces],
        "seams": seams,
        "measurements": [measurement_link_to_dict(m) for m in links],
    }
