"""Bands along openings: bindings, neckbands, cuffs, waistbands and collars.

A band is a strip sewn along an *opening* of the garment: the neckline (the
free edges of the fronts and backs at their centre line, top), an armhole (the
free scooped edges of one front and one back), a sleeve hem or a waist. Each
opening's length counts every copy of its edges (a half piece on the fold or
cut as a pair contributes twice). A band's long edge is matched to the opening
whose length it fits, stretched by up to ``MAX_STRETCH`` or eased by up to
``MAX_EASE`` (bias bindings and rib are cut shorter than the edge they bind);
the band's role follows from the opening when its name does not say. The two
short ends of a loop (binding, neckband, cuff, waistband) are sewn together.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..library.seams import sew_line
from ..pattern.model import Pattern
from .edges import Run
from .model import Join, Orientation, Role, RoleGuess, Side

__all__ = ["Opening", "band_joins", "openings"]

MAX_STRETCH = 1.4
MAX_EASE = 0.78

_OPENING_ROLES = {
    "neck": (Role.NECK_BINDING, Role.NECKBAND, Role.COLLAR, Role.COLLAR_STAND),
    "armhole": (Role.ARMHOLE_BINDING,),
    "sleeve_hem": (Role.CUFF,),
    "waist": (Role.WAISTBAND,),
}


@dataclass(frozen=True, slots=True, kw_only=True)
class Opening:
    """A finished edge of the garment: its runs and total length (every copy counted)."""

    kind: str
    runs: tuple[Run, ...]
    length_cm: float


def _side(r: Run) -> Side:
    return Side(piece=r.piece, start=r.start, end=r.end, length_cm=round(r.length_cm, 3))


def _pts(pattern: Pattern, o: Orientation, r: Run) -> tuple[np.ndarray, np.ndarray]:
    pts = o.apply(sew_line(pattern.piece(r.piece))[0])
    n = len(pts)
    idx = np.arange(r.start, r.end + 1) if r.end > r.start else np.r_[r.start:n, 0 : r.end + 1]
    return pts, pts[idx]


def openings(
    pattern: Pattern,
    free: dict[str, list[Run]],
    roles: dict[str, RoleGuess],
    orientations: dict[str, Orientation],
    chosen: set[str],
) -> list[Opening]:
    """The garment's openings among the free runs of its chosen pieces."""
    found: dict[str, list[tuple[Run, float]]] = {"neck": [], "armhole": [], "waist": []}
    hems = []
    for name, rs in free.items():
        if name not in chosen:
            continue
        role, o, piece = roles[name].role, orientations[name], pattern.piece(name)
        copies = 2.0 if o.fold is not None or piece.quantity.left > 0 or piece.quantity.right > 1 else 1.0
        armhole_taken = False
        for r in sorted(rs, key=lambda r: -r.length_cm):
            pts, seg = _pts(pattern, o, r)
            h, y0 = np.ptp(pts[:, 1]), pts[:, 1].min()
            top = seg[:, 1].max() >= y0 + 0.75 * h
            if role in (Role.FRONT, Role.BACK) and top and np.abs(seg[:, 0]).min() < 0.5 and r.bend_rad < 0.2:
                found["neck"].append((r, copies))
            elif role in (Role.FRONT, Role.BACK) and top and r.bend_rad < -0.3 and not armhole_taken:
                found["armhole"].append((r, 1.0))
                armhole_taken = True
            elif role is Role.SLEEVE and seg[:, 1].max() <= y0 + 0.1 * h:
                hems.append(Opening(kind="sleeve_hem", runs=(r,), length_cm=r.length_cm))
            elif role in (Role.LEG, Role.LEG_FRONT, Role.LEG_BACK) and seg[:, 1].min() >= y0 + 0.85 * h:
                found["waist"].append((r, copies))
    out = [
        Opening(kind=k, runs=tuple(r for r, _ in v), length_cm=float(sum(r.length_cm * c for r, c in v)))
        for k, v in found.items()
        if v
    ]
    return out + hems


def _band_edges(rs: list[Run]) -> tuple[Run, Run | None, list[Run]]:
    """The band's longest run, the longest run apart from it, and its end runs."""
    longest = max(rs, key=lambda r: r.length_cm)
    rest = [r for r in rs if not set(r.parts) & set(longest.parts)]
    other = max(rest, key=lambda r: r.length_cm) if rest else None
    if other is None:
        return longest, None, []
    ends = [r for r in rs if (r.start, r.end) in ((longest.end, other.start), (other.end, longest.start))]
    return longest, other, ends


def band_joins(
    pattern: Pattern,
    runs: dict[str, list[Run]],
    roles: dict[str, RoleGuess],
    opened: list[Opening],
) -> tuple[list[Join], dict[str, RoleGuess]]:
    """Joins of every band piece to the opening it fits, its closure, and refined band roles."""
    joins, new_roles = [], {}
    taken: set[int] = set()
    for name, guess in roles.items():
        if not guess.role.is_band or not runs.get(name):
            continue
        edge, _, ends = _band_edges(runs[name])
        best = None
        for k, op in enumerate(opened):
            if k in taken and op.kind != "sleeve_hem":
                continue
            ratio = op.length_cm / edge.length_cm
            if not MAX_EASE <= ratio <= MAX_STRETCH:
                continue
            fits_role = guess.role in _OPENING_ROLES[op.kind] or guess.confidence < 0.7
            cost = abs(np.log(ratio / 1.05)) + (0.0 if fits_role else 1.0)
            if best is None or cost < best[0]:
                best = (cost, k, op, ratio)
        if best is None:
            continue
        cost, k, op, ratio = best
        taken.add(k)
        conf = round(float(np.clip(1.0 - cost, 0.3, 0.95)), 2)
        if guess.role not in _OPENING_ROLES[op.kind]:
            new_roles[name] = RoleGuess(
                role=_OPENING_ROLES[op.kind][0], confidence=conf, why=f"strip {edge.length_cm:.1f} cm along the {op.kind}"
            )
        for r in op.runs:
            joins.append(
                Join(
                    id=f"{name}_{op.kind}_{r.piece}_{r.start}",
                    a=_side(r),
                    b=_side(edge),
                    kind="band",
                    confidence=conf,
                    ease_cm=round(edge.length_cm - op.length_cm, 2),
                    why=f"band along the {op.kind}: {op.length_cm:.1f} cm of opening, band {edge.length_cm:.1f} cm",
                )
            )
        loop = guess.role not in (Role.COLLAR, Role.COLLAR_STAND)
        if loop and len(ends) >= 2:
            e1, e2 = sorted(ends, key=lambda r: -r.length_cm)[:2]
            if abs(e1.length_cm - e2.length_cm) <= 0.3 + 0.05 * e1.length_cm:
                joins.append(
                    Join(id=f"{name}_closure", a=_side(e1), b=_side(e2), kind="seam", confidence=0.8,
                         why="the band's two ends close the loop")
                )
    return joins, new_roles
