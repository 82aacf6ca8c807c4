"""Propose seams for a pattern without bridge data (a tailor's DXF).

The sew line of every piece is cut into *stretches* at its turn points and
notches (or, for files that mark neither, at corners sharper than
``CORNER_DEG``); runs of up to ``MAX_RUN`` consecutive stretches that turn no
sharp corner are candidate seam sides. Two runs are a candidate seam when
their lengths agree within ``max(LENGTH_TOL_CM, 3 %)`` (the room sleeve-crown
ease needs) with a difference that stays constant over the graded sizes,
their straightness and total bend are alike, and their inner notches sit at
matching fractions. Mirror-image matches (twin left/right pieces, the two
halves of a symmetric piece) count ``TWIN_FACTOR``; neighbouring runs of one
piece only pair at a dart point. Runs are then paired greedily, longest and
surest first, each stretch used once.

The result is a proposal, not a truth: ``patternbridge seams infer`` writes it
to a sidecar for the user to confirm or edit (``docs/library.md`` says what it
finds and misses).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ..pattern.geometry import interior_angles
from ..pattern.model import EdgeRange, Pattern, Seam, VertexKind
from .seams import sew_line

__all__ = ["SeamProposal", "Stretch", "infer_seams", "mirror_twins", "stretches", "with_proposals"]

CORNER_DEG = 30.0
LENGTH_TOL_CM = 0.3
MIN_STRETCH_CM = 2.0
#: longest run of consecutive stretches tried as one seam side
MAX_RUN = 5
#: a corner this sharp between two neighbouring stretches is a dart's point
DART_DEG = 40.0
#: mirror twins' areas and perimeters agree within this share of the larger
TWIN_TOL_SHARE = 0.005


@dataclass(frozen=True, slots=True, kw_only=True)
class Stretch:
    """A boundary stretch of one piece between two break vertices.

    start, end : vertex indices (outline order, wrapping)
    length_cm : sew-line length (sample size)
    graded_cm : the same length in every graded size
    parts : ids of the elementary stretches it spans (a run of up to ``MAX_RUN``)
    notch_fracs : where the notches inside it sit, as fractions of its length
    bend : total absolute turning along the stretch, radians
    straightness : chord / length (1 for a straight edge)
    """

    piece: str
    start: int
    end: int
    length_cm: float
    bend: float
    straightness: float
    graded_cm: tuple[float, ...] = ()
    parts: tuple[int, ...] = ()
    notch_fracs: tuple[float, ...] = ()
    ends_xy: tuple[tuple[float, float], tuple[float, float]] = ((0.0, 0.0), (0.0, 0.0))


@dataclass(frozen=True, slots=True, kw_only=True)
class SeamProposal:
    """A proposed seam: two stretches and how sure we are (0..1)."""

    a: Stretch
    b: Stretch
    confidence: float

    @property
    def seam_id(self) -> str:
        return f"{self.a.piece}_{self.a.start}_{self.b.piece}_{self.b.start}"


def _breaks(piece) -> np.ndarray:
    pts, _ = sew_line(piece)
    n = len(pts)
    brk = np.zeros(n, dtype=bool)
    kinds = piece.kinds
    brk |= np.array([k == VertexKind.TURN for k in kinds])
    for notch in piece.notches:
        brk[notch.vertex] = True
    ang = interior_angles(pts)  # outlines are stored CCW
    corner = np.abs(np.pi - ang) > np.radians(CORNER_DEG)
    if not brk.any() or all(k == VertexKind.PLAIN for k in kinds):
        brk |= corner
    return np.nonzero(brk)[0]


def stretches(pattern: Pattern, *, max_run: int = MAX_RUN) -> list[Stretch]:
    """Stretches of every piece: runs of 1..``max_run`` consecutive break-to-break stretches."""
    from .seams import graded_sew_lines

    lines = graded_sew_lines(pattern)
    out = []
    uid = 0
    for piece in pattern.pieces:
        pts, _ = sew_line(piece)
        n = len(pts)
        brk = _breaks(piece)
        if len(brk) < 2:
            continue
        notch_vertices = {nt.vertex for nt in piece.notches}
        corner_angles = interior_angles(pts)
        base_ids = list(range(uid, uid + len(brk)))
        uid += len(brk)
        for i in range(len(brk)):
            for run in range(1, min(max_run, len(brk) - 1) + 1):
                s, e = brk[i], brk[(i + run) % len(brk)]
                idx = np.arange(s, e + 1) if e > s else np.r_[s:n, 0 : e + 1]
                seg = pts[idx]
                d = np.diff(seg, axis=0)
                cum = np.concatenate([[0.0], np.cumsum(np.linalg.norm(d, axis=1))])
                length = float(cum[-1])
                if length < MIN_STRETCH_CM:
                    continue
                heading = np.unwrap(np.arctan2(d[:, 1], d[:, 0]))
                bend = (
                    float(np.abs(np.diff(heading)).sum()) if len(heading) > 1 else 0.0
                )
                chord = float(np.hypot(*(seg[-1] - seg[0])))
                graded = np.linalg.norm(
                    np.diff(lines[piece.name][:, idx], axis=1), axis=-1
                ).sum(axis=-1)
                fracs = tuple(
                    float(cum[k] / length)
                    for k in range(1, len(idx) - 1)
                    if int(idx[k]) in notch_vertices
                )
                if run > 1:
                    # a seam does not turn a corner: reject runs through a sharp inner break
                    inner = [brk[(i + k) % len(brk)] for k in range(1, run)]
                    if np.any(
                        np.abs(np.pi - corner_angles[inner]) > np.radians(CORNER_DEG)
                    ):
                        continue
                out.append(
                    Stretch(
                        piece=piece.name,
                        start=int(s),
                        end=int(e),
                        length_cm=length,
                        bend=bend,
                        straightness=chord / length,
                        graded_cm=tuple(float(x) for x in graded),
                        parts=tuple(base_ids[(i + k) % len(brk)] for k in range(run)),
                        notch_fracs=fracs,
                        ends_xy=(tuple(map(float, seg[0])), tuple(map(float, seg[-1]))),
                    )
                )
    return out


def _score(a: Stretch, b: Stretch) -> float:
    tol = max(LENGTH_TOL_CM, 0.03 * max(a.length_cm, b.length_cm))
    dl = abs(a.length_cm - b.length_cm)
    if a.graded_cm and len(a.graded_cm) == len(b.graded_cm):
        # a real seam keeps its two sides equal (up to a constant ease) in every graded size
        diff = np.asarray(a.graded_cm) - np.asarray(b.graded_cm)
        dl = max(dl, float(np.ptp(diff)) * 2.0)
    if dl > tol:
        return 0.0
    length_term = np.exp(-((dl / (0.35 * tol)) ** 2))
    shape_term = np.exp(-abs(a.straightness - b.straightness) / 0.05) * np.exp(
        -abs(a.bend - b.bend) / 1.0
    )
    # long matching stretches are less likely to be coincidences
    size_term = 1.0 - np.exp(-min(a.length_cm, b.length_cm) / 8.0)
    # notches inside the two sides must line up (b runs backwards along a)
    if len(a.notch_fracs) != len(b.notch_fracs):
        notch_term = 0.3
    elif a.notch_fracs:
        err = np.max(
            np.abs(np.asarray(a.notch_fracs) - (1.0 - np.asarray(b.notch_fracs[::-1])))
        )
        notch_term = 1.0 if err < 0.02 else 0.3
    else:
        notch_term = 0.9
    return float(length_term * shape_term * size_term * notch_term)


def mirror_twins(pattern: Pattern, *, tol_share: float = TWIN_TOL_SHARE) -> set[frozenset[str]]:
    """Pairs of pieces that are mirror images of each other (same area and perimeter).

    Two pieces are twins when their sew lines' areas and perimeters agree within
    ``tol_share`` of the larger one.
    """
    from ..pattern.geometry import area, perimeter

    stats = [(p.name, float(area(sew_line(p)[0])), float(perimeter(sew_line(p)[0]))) for p in pattern.pieces]
    return {
        frozenset((na, nb))
        for i, (na, aa, pa) in enumerate(stats)
        for nb, ab, pb in stats[i + 1 :]
        if abs(aa - ab) <= tol_share * max(aa, ab) and abs(pa - pb) <= tol_share * max(pa, pb)
    }


#: confidence factor for a match between mirror-twin pieces: the same edge on a
#: left and a right piece matches itself whether or not it is a centre seam
TWIN_FACTOR = 0.5


def _mirrored(a: Stretch, b: Stretch, cx: float, tol_cm: float = 0.3) -> bool:
    """True when ``b`` is ``a`` reflected across the vertical line ``x = cx`` (a symmetric piece's halves)."""
    (ax0, ay0), (ax1, ay1) = a.ends_xy
    (bx0, by0), (bx1, by1) = b.ends_xy
    return bool(
        np.hypot(2 * cx - ax0 - bx1, ay0 - by1) < tol_cm
        and np.hypot(2 * cx - ax1 - bx0, ay1 - by0) < tol_cm
    )


def infer_seams(pattern: Pattern, *, min_confidence: float = 0.2) -> list[SeamProposal]:
    """Propose seam pairs between stretches of equal length and compatible shape.

    Parameters
    ----------
    pattern : any pattern; only its sample-size sew lines (or outlines) are used
    min_confidence : proposals below this are dropped

    Returns
    -------
    Proposals sorted by decreasing confidence; every stretch appears at most once.
    """
    items = stretches(pattern)
    twins = mirror_twins(pattern)
    centre_x = {
        p.name: float(
            np.mean(
                sew_line(p)[0][:, 0][
                    [np.argmin(sew_line(p)[0][:, 0]), np.argmax(sew_line(p)[0][:, 0])]
                ]
            )
        )
        for p in pattern.pieces
    }
    sharp: dict[tuple[str, int], bool] = {}
    for piece in pattern.pieces:
        ang = interior_angles(sew_line(piece)[0])
        for v in range(piece.n_vertices):
            sharp[(piece.name, v)] = bool(ang[v] > np.radians(360.0 - DART_DEG))
    cands = []
    for i in range(len(items)):
        for j in range(i + 1, len(items)):
            a, b = items[i], items[j]
            if set(a.parts) & set(b.parts):
                continue
            if a.piece == b.piece:
                shared = {a.end} & {b.start} or {b.end} & {a.start}
                # neighbours on one piece only sew together at a dart point
                if shared and not sharp.get((a.piece, shared.pop()), False):
                    continue
            c = _score(a, b)
            if frozenset((a.piece, b.piece)) in twins or (
                a.piece == b.piece and _mirrored(a, b, centre_x[a.piece])
            ):
                c *= TWIN_FACTOR
            if c >= min_confidence:
                rank = c * (1.0 + 0.15 * (len(a.parts) + len(b.parts) - 2))
                cands.append((rank, c, i, j))
    cands.sort(key=lambda t: -t[0])
    used: set[int] = set()
    out = []
    for _rank, c, i, j in cands:
        parts = set(items[i].parts) | set(items[j].parts)
        if parts & used:
            continue
        used |= parts
        out.append(SeamProposal(a=items[i], b=items[j], confidence=round(c, 3)))
    out.sort(key=lambda p: -p.confidence)
    return out


def with_proposals(pattern: Pattern, proposals: list[SeamProposal]) -> Pattern:
    """``pattern`` with marks ``v<index>`` at the proposals' ends and one seam per proposal.

    Existing marks and seams are kept.
    """
    extra: dict[str, dict[str, int]] = {}
    for p in proposals:
        for s in (p.a, p.b):
            extra.setdefault(s.piece, {}).update(
                {f"v{s.start}": s.start, f"v{s.end}": s.end}
            )
    pieces = tuple(
        replace(pc, marks={**extra.get(pc.name, {}), **dict(pc.marks)})
        for pc in pattern.pieces
    )
    seams = tuple(
        Seam(
            id=p.seam_id,
            a=EdgeRange(piece=p.a.piece, start=f"v{p.a.start}", end=f"v{p.a.end}"),
            b=EdgeRange(piece=p.b.piece, start=f"v{p.b.start}", end=f"v{p.b.end}"),
            reverse=True,
        )
        for p in proposals
    )
    return replace(pattern, pieces=pieces, seams=pattern.seams + seams)
