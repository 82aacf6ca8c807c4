"""The garment's openings: finished edges a band can be sewn along.

After the seams are assigned, the free boundary of every chosen piece is
grouped into maximal runs of free stretches (split at corners sharper than
``GROUP_CORNER_DEG``), and the groups are read as openings by where they lie on
the upright piece: the **neckline** (free groups of the fronts and backs at the
centre line, high up; a half on the fold or cut as a pair counts twice; its
parts too, for a neckline bound by several strips), an **armhole** per front
and back (free scooped groups high up), each **sleeve hem**, and the **waist**
(the top of legs and of skirt panels, whose tops are not scooped).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..library.seams import sew_line
from ..pattern.model import Pattern
from .edges import Run, breaks, turning
from .model import Orientation, Role, RoleGuess, Side

__all__ = ["GROUP_CORNER_DEG", "Opening", "free_groups", "openings", "run_side"]


@dataclass(frozen=True, slots=True, kw_only=True)
class Opening:
    """A finished edge of the garment: its free boundary groups and total length (every copy counted)."""

    kind: str
    sides: tuple[Side, ...]
    length_cm: float
    part: bool = False  # one part of an opening bound by several strips
    #: per side: the copies cut (2 for a half on the fold or cut as a pair), and whether the side
    #: starts (outline order) at the centre line rather than at its outer end
    copies: tuple[int, ...] = ()
    centre_first: tuple[bool, ...] = ()
    #: per side of an opening away from the centre line (an armhole): the copy that lies on the body's right
    #: side, ``mirror`` for a half drawn as the left half and cut twice (its drawn copy is worn on the left)
    right_copy: tuple[str, ...] = ()
    #: per side of an armhole: the upright height (cm) of its start and end vertex (where a band may close)
    heights: tuple[tuple[float, float], ...] = ()


def run_side(r: Run) -> Side:
    """The :class:`Side` a run covers."""
    return Side(piece=r.piece, start=r.start, end=r.end, length_cm=round(r.length_cm, 3))


#: a free group of stretches ends at a corner sharper than this
GROUP_CORNER_DEG = 60.0


def free_groups(pattern: Pattern, name: str, used: set[tuple[str, int]]) -> list[tuple[Side, float]]:
    """Maximal runs of free stretches of one piece, split at sharp corners: (side, total bend rad)."""
    piece = pattern.piece(name)
    pts = sew_line(piece)[0]
    n = len(pts)
    brk = breaks(piece)
    m = len(brk)
    if m < 2:
        return []
    turn = turning(pts)
    seg = np.linalg.norm(np.roll(pts, -1, axis=0) - pts, axis=1)
    free = [(name, k) not in used for k in range(m)]
    cut = [abs(turn[brk[k]]) > np.radians(GROUP_CORNER_DEG) or not free[k - 1] for k in range(m)]
    if all(free) and not any(cut):
        cut[0] = True
    groups = []
    for k in range(m):
        if not free[k] or not cut[k]:
            continue
        j = k
        while free[(j + 1) % m] and not cut[(j + 1) % m] and (j + 1) % m != k:
            j = (j + 1) % m
        s, e = int(brk[k]), int(brk[(j + 1) % m])
        idx = np.arange(s, e) if e > s else np.r_[s:n, 0:e]
        inner = idx[1:]
        groups.append(
            (Side(piece=name, start=s, end=e, length_cm=round(float(seg[idx].sum()), 3)), float(turn[inner].sum()))
        )
    return groups


def shapes_scooped(points: np.ndarray) -> bool:
    """Whether an upright piece's top is scooped (neckline, armholes) rather than a level waist."""
    turn = turning(points)
    top = points[:, 1] >= points[:, 1].max() - 0.4 * np.ptp(points[:, 1])
    smooth = np.abs(turn) < np.radians(30)
    return bool(-turn[top & smooth & (turn < 0)].sum() > 0.6)


def _side_points(pattern: Pattern, o: Orientation, side: Side) -> tuple[np.ndarray, np.ndarray]:
    pts = o.apply(sew_line(pattern.piece(side.piece))[0])
    n = len(pts)
    idx = np.arange(side.start, side.end + 1) if side.end > side.start else np.r_[side.start : n, 0 : side.end + 1]
    return pts, pts[idx]


def _end_heights(pattern: Pattern, o: Orientation, side: Side) -> tuple[float, float]:
    _, pts = _side_points(pattern, o, side)
    return float(pts[0, 1]), float(pts[-1, 1])


def _right_copy(pattern: Pattern, role: Role, o: Orientation, name: str) -> str:
    """The copy of a front or back worn on the body's right: ``mirror`` for a half drawn as the left half (its
    centre line on the side a left front or a right back has it) that is cut twice."""
    piece = pattern.piece(name)
    twice = o.fold is not None or piece.quantity.left > 0 or piece.quantity.right > 1
    drawn_left = not o.whole and o.centre_on_right != (role is Role.FRONT)
    return "mirror" if twice and drawn_left else "primary"


def openings(
    pattern: Pattern,
    used: set[tuple[str, int]],
    roles: dict[str, RoleGuess],
    orientations: dict[str, Orientation],
    chosen: set[str],
) -> list[Opening]:
    """The garment's openings among the free boundary of its chosen pieces."""
    neck: list[tuple[Side, float]] = []
    centre_first: dict[tuple[str, int, int], bool] = {}
    arm: dict[Role, list[tuple[float, Side]]] = {Role.FRONT: [], Role.BACK: []}
    waist: list[tuple[Side, float]] = []
    hems = []
    for name in pattern.piece_names:
        if name not in chosen:
            continue
        role, o, piece = roles[name].role, orientations[name], pattern.piece(name)
        copies = 2.0 if o.fold is not None or piece.quantity.left > 0 or piece.quantity.right > 1 else 1.0
        for side, bend in free_groups(pattern, name, used):
            pts, seg = _side_points(pattern, o, side)
            h, y0 = np.ptp(pts[:, 1]), pts[:, 1].min()
            skirt = role in (Role.FRONT, Role.BACK) and not shapes_scooped(pts)
            if skirt and seg[:, 1].min() >= y0 + 0.85 * h:
                waist.append((side, copies))
            elif role in (Role.FRONT, Role.BACK, Role.YOKE) and seg[:, 1].max() >= y0 + 0.7 * h:
                if np.abs(seg[:, 0]).min() < 0.5 and seg[:, 1].min() >= y0 + 0.6 * h:
                    neck.append((side, copies))
                    centre_first[side.key] = bool(abs(seg[0, 0]) < abs(seg[-1, 0]))
                elif bend < -0.3:
                    arm[role].append((float(seg[:, 0].mean()), side))
            elif role is Role.SLEEVE and seg[:, 1].max() <= y0 + 0.15 * h:
                hems.append(Opening(kind="sleeve_hem", sides=(side,), length_cm=side.length_cm))
            elif role in (Role.LEG, Role.LEG_FRONT, Role.LEG_BACK) and seg[:, 1].min() >= y0 + 0.8 * h:
                waist.append((side, copies))
    out = []
    if neck:
        # the whole neckline, and its parts for a neckline bound by several strips
        parts = [[t] for t in neck] + [[a, b] for i, a in enumerate(neck) for b in neck[i + 1 :]]
        for group in [neck] + (parts if len(neck) > 1 else []):
            out.append(
                Opening(
                    kind="neck",
                    sides=tuple(s for s, _ in group),
                    length_cm=sum(s.length_cm * c for s, c in group),
                    part=group is not neck,
                    copies=tuple(int(c) for _, c in group),
                    centre_first=tuple(centre_first[s.key] for s, _ in group),
                )
            )
    fronts = [s for _, s in sorted(arm[Role.FRONT], key=lambda t: t[0])]
    backs = [s for _, s in sorted(arm[Role.BACK], key=lambda t: -t[0])]
    for f, b in zip(fronts, backs, strict=False):
        right = tuple(_right_copy(pattern, roles[s.piece].role, orientations[s.piece], s.piece) for s in (f, b))
        ys = tuple(_end_heights(pattern, orientations[s.piece], s) for s in (f, b))
        out.append(
            Opening(kind="armhole", sides=(f, b), length_cm=f.length_cm + b.length_cm, right_copy=right, heights=ys)
        )
    if waist:
        out.append(
            Opening(kind="waist", sides=tuple(s for s, _ in waist), length_cm=sum(s.length_cm * c for s, c in waist))
        )
    return out + hems
