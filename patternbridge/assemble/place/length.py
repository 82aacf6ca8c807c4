"""A piece drafted shorter than the body span it is worn over, stretched to its landmark as it is put on.

Leggings are cut shorter than the leg (``GLX4802S19``: 10.5 cm under the
outside leg of its sample body) and pulled down to the ankle when worn: the
knit stretches along the grain and the hem sits on the ankle, held there by
the leg's girth. Laid at its pattern length the hem would sit on the calf,
and the narrow ankle would be stretched round it.

The pattern says which landmark a hem belongs at: a length link
(:class:`~patternbridge.pattern.model.MeasurementLink` whose measurement is a
landmark chain of :data:`~patternbridge.measure.lengths.PATHS`) running from
the piece's anchor mark to a hem vertex, drafted short of its body span
(negative ``ease_cm``). Whether the hem is worn there is the fabric's: only a
fabric worn stretched along the grain (``FabricStretch.along_worn`` > 0, a
stretch knit) is pulled down, and only as far as it can stretch
(``along_limit``): a stretch-knit short whose hem would need more is a
style length (bike shorts) and hangs at its pattern length. A woven or a
plain knit is never stretched, whatever its length ease.

:func:`length_stretch` measures it on the body for one cut copy; the
placement lays the copy's rows below its lowest landmark mark (the crotch
point of a leg) stretched by that factor, so that the hem starts on its
landmark, and the dressing holds the hem there (:func:`hem_vertices`,
``pipeline.anchor_weights``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...measure.lengths import PATHS
from ...pattern.fabric import FabricClass
from ...pattern.model import Copy, Pattern

__all__ = [
    "CROTCH_CLEARANCE_CM",
    "HEM_HOLD_BAND_CM",
    "CrotchDrop",
    "LengthStretch",
    "crotch_drop",
    "crotch_height_on",
    "hem_vertices",
    "length_stretch",
    "length_stretches",
    "worn_lengths",
]

HEM_HOLD_BAND_CM = 2.0  # the hem held: boundary points within this of the hem along the placement's axis
CROTCH_CLEARANCE_CM = 2.0  # a leg piece's crotch point is laid at least this far below the body's crotch
CROTCH_LANDMARK = "crotch_point"  # the body's crotch: the cloth passes under it


@dataclass(frozen=True, slots=True)
class CrotchDrop:
    """How much lower than its pattern length puts it a leg piece's crotch mark is laid (:func:`crotch_drop`).

    crotch_y, anchor_y : pattern y of the crotch mark and of the anchor mark, cm
    stretch_cm : taken by the rise (the rows between the two marks) laid stretched evenly
    shift_cm : the rest, taken by the whole piece laid lower (its anchor below its landmark)
    """

    crotch_y: float = float("nan")
    anchor_y: float = float("nan")
    stretch_cm: float = 0.0
    shift_cm: float = 0.0

    @property
    def rise_scale(self) -> float:
        """The rise's length as laid over its pattern length (1: not stretched)."""
        return 1.0 + self.stretch_cm / (self.anchor_y - self.crotch_y) if self.stretch_cm > 0.0 else 1.0

    def lowered(self, y: np.ndarray) -> np.ndarray:
        """(n,) cm each pattern row ``y`` is laid lower: the shift everywhere, plus the stretch's share below
        the anchor (all of it at and below the crotch mark)."""
        y = np.asarray(y, dtype=np.float64)
        if self.stretch_cm <= 0.0:
            return np.full(len(y), self.shift_cm)
        share = np.clip((self.anchor_y - y) / (self.anchor_y - self.crotch_y), 0.0, 1.0)
        return self.shift_cm + self.stretch_cm * share


def crotch_drop(
    pattern: Pattern, piece_name: str, p2: np.ndarray, marks: dict[str, int], anchor_y: float, anchor_h: float, crotch_h
) -> CrotchDrop:
    """How much lower than drafted a leg piece's crotch mark is laid to pass under the body's crotch.

    A piece that hangs from a mark above the crotch (a trouser or leggings
    leg from its side waist) and carries a mark tied to the body's crotch
    (``crotch_point``) passes under the body there: the four rise and inseam
    corners meet between the thighs, :data:`CROTCH_CLEARANCE_CM` below the
    crotch. Drafted shorter than the body's rise (a knit worn stretched, a
    grading that gave the body a lower crotch) and laid at its pattern length,
    the mark sat on or above the crotch; the body pushed it out in front, 5-9
    cm from its partners (B, D, F and the leggings on E, B, D), and closing
    the inseam's top folded the crotch through itself. The rise takes as much
    of the drop as its fabric stretches along the grain
    (``FabricStretch.along_limit``, a woven 3 %, a stretch knit 30 %). The
    rest lowers the whole piece when the fabric is not worn stretched along
    the grain, as a woven rise too short is worn: lower on the hips. A knit
    worn stretched along the grain (``along_worn`` > 0, leggings) is pulled
    up into the crotch and held at the waist: it is never laid lower, its
    rise is laid stretched as far as the knit goes and the drape takes the
    rest (lowered, the leggings graded to B and D crumpled at the seat and
    slid down the hips: 259 and 1426 crossing triangles, the waists 7 and
    21 cm low; laid at its pattern length, the front's crotch corner sat in
    front of the body, 8 cm from the back's on E, and sewing folded the
    crotch through itself: 104 / 133 / 68 crossing triangles on E / B / D).
    The copy worn stretched wears its rise so (:func:`worn_lengths`).
    ``crotch_h``: the crotch's height on the placement's axis (None: no
    drop).
    """
    piece = pattern.piece(piece_name)
    mark = piece.landmarks.get(CROTCH_LANDMARK)
    if crotch_h is None or mark is None or mark not in marks:
        return CrotchDrop()
    crotch_y = float(p2[marks[mark], 1])
    drop = anchor_h + (crotch_y - anchor_y) - (float(crotch_h) - CROTCH_CLEARANCE_CM)
    if crotch_y >= anchor_y - 1.0 or drop <= 0.0:
        return CrotchDrop()
    fabric = FabricClass(piece.fabric_class or pattern.fabric_class).stretch
    stretch = min(float(drop), fabric.along_limit * (anchor_y - crotch_y))
    shift = 0.0 if fabric.along_worn > 0.0 else float(drop) - stretch  # a knit worn stretched is held at the waist
    return CrotchDrop(crotch_y=crotch_y, anchor_y=anchor_y, stretch_cm=stretch, shift_cm=shift)


@dataclass(frozen=True, slots=True, kw_only=True)
class LengthStretch:
    """How a cut copy is stretched along the placement's axis to reach its hem's landmark.

    key : instance key ; landmark : the landmark the hem goes on (mirrored for a mirror copy)
    hem_mark : the link's mark on the hem ; pivot_y : pattern y (cm) above which nothing stretches
        (the lowest landmark mark of the piece above the hem)
    hem_y : pattern y of the hem mark, cm
    need : the strain that takes the hem to its landmark (0.12: 12 % longer)
    limit : the fabric's stretch limit along the grain
    scale : 1 + need when the fabric is worn stretched along the grain and ``need`` is within ``limit``, else 1
    rise : how the copy's crotch is laid under the body's (:func:`crotch_drop`): a rise laid stretched is
        worn so when the copy is worn stretched
    """

    key: str
    landmark: str
    hem_mark: str
    pivot_y: float
    hem_y: float
    need: float
    limit: float
    scale: float
    rise: CrotchDrop = CrotchDrop()

    @property
    def stretched(self) -> bool:
        """Whether the copy is worn stretched (``scale`` > 1)."""
        return self.scale > 1.0

    def heights(self, y: np.ndarray) -> np.ndarray:
        """(n,) the pattern heights ``y`` (cm) as worn: stretched by ``scale`` below ``pivot_y``, and the rise by
        ``rise`` (:func:`crotch_drop`; its shift, which moves the whole copy, is not a length)."""
        y = np.asarray(y, dtype=np.float64)
        if not self.stretched:
            return y.copy()  # bit for bit: pivot + (y - pivot) need not be y
        worn = np.where(y < self.pivot_y, self.pivot_y + self.scale * (y - self.pivot_y), y)
        return worn - (self.rise.lowered(y) - self.rise.shift_cm)


def _hem_link(pattern: Pattern, piece_name: str, anchor: str, anchor_vertex: int) -> tuple[str, str, float] | None:
    """(hem mark, end landmark, ease_cm) of the length link from the piece's anchor down its hem, or None."""
    piece = pattern.piece(piece_name)
    for link in pattern.measurements:
        chain = PATHS.get(link.measurement)
        if chain is None or len(link.legs) != 1 or link.legs[0].piece != piece_name:
            continue
        leg = link.legs[0]
        ends = [m for m in (leg.start, leg.end) if m in piece.marks]
        if len(ends) != 2 or chain[0][0] != anchor:
            continue
        at = [piece.marks[m] == anchor_vertex for m in ends]
        if at.count(True) != 1:
            continue
        return ends[at.index(False)], chain[0][-1], link.ease_cm
    return None


def length_stretch(
    pattern: Pattern,
    inst,
    p2: np.ndarray,
    marks: dict[str, int],
    anchor_y: float,
    anchor_h: float,
    target_h: float | None,
    landmark: str,
    crotch_h: float | None = None,
) -> LengthStretch | None:
    """How far the cut copy ``inst`` is stretched to put its hem on its landmark, or None (no such link).

    Parameters
    ----------
    p2 : (n, 2) float64, cm — the copy's pattern coordinates (y up the placement's axis)
    marks : mark name -> vertex of the copy's mesh
    anchor_y, anchor_h : pattern y of the anchor mark and its height on the placement's axis, cm
    target_h : height of the hem's landmark on that axis (None: the character lacks it)
    landmark : the hem's landmark as named by the link (the caller mirrors it)
    crotch_h : height of the body's crotch on that axis: a rise too short to pass under it is laid stretched
        (:func:`crotch_drop`), and the hem's stretch is measured from the crotch mark so laid
    """
    piece = pattern.piece(inst.piece)
    pl = piece.placement
    if pl is None or pl.anchor_mark not in piece.marks:
        return None
    found = _hem_link(pattern, inst.piece, pl.anchor, piece.marks[pl.anchor_mark])
    if found is None or found[0] not in marks or target_h is None:
        return None
    hem_mark, _, ease_cm = found
    hem_y = float(p2[marks[hem_mark], 1])
    above = [float(p2[marks[m], 1]) for m in piece.landmarks.values() if m in marks]
    pivot_y = min((y for y in above if y > hem_y + 1.0), default=anchor_y)
    rise = crotch_drop(pattern, inst.piece, p2, marks, anchor_y, anchor_h, crotch_h)
    pivot_h = anchor_h + (pivot_y - anchor_y) - float(rise.lowered(np.array([pivot_y]))[0])
    need = float((pivot_h - target_h) / max(pivot_y - hem_y, 1e-9) - 1.0)
    stretch = FabricClass(piece.fabric_class or pattern.fabric_class).stretch
    worn = ease_cm < 0.0 and stretch.along_worn > 0.0 and 0.0 < need <= stretch.along_limit
    return LengthStretch(
        key=inst.key,
        landmark=landmark,
        hem_mark=hem_mark,
        pivot_y=pivot_y,
        hem_y=hem_y,
        need=need,
        limit=stretch.along_limit,
        scale=1.0 + need if worn else 1.0,
        rise=rise,
    )


def crotch_height_on(character, vertices: np.ndarray, cyl) -> float | None:
    """Height of the body's crotch landmark on the axis of ``cyl`` (a :class:`~.wrap.Cylinder`), or None."""
    from .wrap import landmark_position

    crotch = landmark_position(character, vertices, CROTCH_LANDMARK, False)
    return None if crotch is None else float(cyl.coordinates(crotch[None])[1][0])


def worn_lengths(ls: LengthStretch, uv: np.ndarray, edges: np.ndarray, target: np.ndarray) -> np.ndarray:
    """(E,) the spring lengths ``target`` of the copy's ``edges`` as worn: stretched by ``scale`` along the axis.

    An edge below ``pivot_y`` at angle θ to the placement's axis (the grain of
    an upright piece) rests at ``target`` × (1 + (scale − 1) cos² θ): the knit
    is worn pulled down to its landmark, and the solver keeps it at that
    length instead of springing it back up the leg (the wearer's pull and the
    friction of the tight leg, which hold it there, are not simulated). The
    verdict still measures every edge against its pattern length.

    Parameters
    ----------
    uv : (N, 2) float64, cm — pattern coordinates of the edges' vertices (y up the axis)
    edges : (E, 2) int64 ; target : (E,) float64, cm
    """
    uv = np.asarray(uv, dtype=np.float64)
    d = uv[edges[:, 1]] - uv[edges[:, 0]]
    cos2 = d[:, 1] ** 2 / np.maximum(np.einsum("ij,ij->i", d, d), 1e-30)
    mid = 0.5 * (uv[edges[:, 0], 1] + uv[edges[:, 1], 1])
    scale = np.where(mid < ls.pivot_y, ls.scale, 1.0)
    if ls.stretched and ls.rise.rise_scale > 1.0:  # the rise laid stretched under the crotch is worn so
        scale = np.where((mid >= ls.rise.crotch_y) & (mid < ls.rise.anchor_y), ls.rise.rise_scale, scale)
    return np.asarray(target, dtype=np.float64) * (1.0 + (scale - 1.0) * cos2)


def hem_vertices(ls: LengthStretch, p2: np.ndarray, n_boundary: int) -> np.ndarray:
    """(k,) int64 boundary vertices of the copy on its hem: within :data:`HEM_HOLD_BAND_CM` of the hem mark's y."""
    y = np.asarray(p2, dtype=np.float64)[:n_boundary, 1]
    return np.flatnonzero(y <= ls.hem_y + HEM_HOLD_BAND_CM).astype(np.int64)


def length_stretches(character, vertices: np.ndarray, pattern: Pattern, pmesh, cylinders) -> dict[str, LengthStretch]:
    """Instance key -> :class:`LengthStretch` of every cut copy with a length link down its hem.

    Parameters
    ----------
    character : the character (landmarks)
    vertices : (V, 3) float64, cm — the body in the dressing pose
    cylinders : body part -> :class:`~.wrap.Cylinder` (the placement's axes)
    """
    from .wrap import instance_part, instance_points2d, landmark_position, mirror_name

    out: dict[str, LengthStretch] = {}
    for inst in pmesh.instances:
        piece = pattern.piece(inst.piece)
        pl = piece.placement
        cyl = cylinders.get(instance_part(pattern, inst)) if pl is not None else None
        marks = pmesh.pieces[inst.piece].marks
        if cyl is None or pl.anchor_mark not in marks:
            continue
        mirrored = inst.copy is Copy.MIRROR
        anchor = landmark_position(character, vertices, pl.anchor, mirrored)
        found = _hem_link(pattern, inst.piece, pl.anchor, piece.marks[pl.anchor_mark])
        if anchor is None or found is None:
            continue
        target = landmark_position(character, vertices, found[1], mirrored)
        p2 = instance_points2d(pmesh, inst)
        ls = length_stretch(
            pattern,
            inst,
            p2,
            marks,
            anchor_y=float(p2[marks[pl.anchor_mark], 1]),
            anchor_h=float(cyl.coordinates(anchor[None])[1][0]),
            target_h=None if target is None else float(cyl.coordinates(target[None])[1][0]),
            landmark=mirror_name(found[1]) if mirrored else found[1],
            crotch_h=crotch_height_on(character, vertices, cyl),
        )
        if ls is not None:
            out[inst.key] = ls
    return out
