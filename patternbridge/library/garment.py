"""Turn per-size drafts into one graded :class:`Pattern` with bridge data.

A garment's ``draft.py`` gives a function ``body dimensions -> [PieceDraft]``
and its seams and measurement links; :func:`build_pattern` drafts every size
of a size chart with it, checks that each piece keeps its vertex count, and
stores the sample size plus one grade rule per vertex (the per-size
displacement of that vertex from the sample size, drawing axes, cm) — the
same rule table an AccuMark graded nest yields.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace

import numpy as np

from ..pattern.fabric import FabricClass
from ..pattern.model import (
    Copy,
    EdgeRange,
    GradeRuleTable,
    Leg,
    Line,
    MeasurementLink,
    Notch,
    NotchType,
    Pattern,
    Piece,
    Placement,
    Polyline,
    Provenance,
    Quantity,
    Seam,
    SeamKind,
)
from .draft import NetOutline, offset_outline
from .sizes import SizeChart

__all__ = [
    "PieceDraft",
    "band_draft",
    "build_pattern",
    "fold_front_skirt",
    "leg",
    "link",
    "seam",
    "set_in_sleeve",
]

NOTCH_DEPTH_CM = 0.6


@dataclass
class PieceDraft:
    """One drafted piece in one size (sew line, allowances, metadata).

    grain : ((2,), (2,)) tail and head of the grain line, cm
    landmarks : body landmark name -> mark name
    internal : extra open polylines ``(points (k, 2), label)`` (fold lines, pocket marks)
    """

    name: str
    net: NetOutline
    quantity: Quantity
    grain: tuple
    placement: Placement
    landmarks: dict[str, str] = field(default_factory=dict)
    category: str = ""
    annotation: str = ""
    fabric: str = "SELF"
    internal: list = field(default_factory=list)
    mirror_line: tuple | None = None


def set_in_sleeve(net: NetOutline, grain: tuple) -> PieceDraft:
    """A set-in sleeve cut as a pair, placed by its cap top on the shoulder point.

    ``net`` must name the mark ``cap_top``; drafted as the right sleeve.
    """
    return PieceDraft(
        name="sleeve",
        net=net,
        quantity=Quantity(right=1, left=1),
        grain=grain,
        placement=Placement(
            body_part="right_arm",
            side="around",
            anchor="shoulder_point_right",
            anchor_mark="cap_top",
        ),
        landmarks={"shoulder_point_right": "cap_top"},
        category="SLEEVE",
        annotation="SLEEVE",
    )


def fold_front_skirt(name: str, net: NetOutline, y_hem: float, y_hip: float) -> PieceDraft:
    """A skirt front cut once on the fold (drawn whole), hung from the centre-front waist.

    ``net`` must name ``cf_waist``, ``side_waist_*`` and ``side_hip_*``; the grain
    line runs up the centre front from 10 cm above the hem to the hip line.
    """
    return PieceDraft(
        name=name,
        net=net,
        quantity=Quantity(right=1, left=0),
        grain=((0.0, y_hem + 10), (0.0, y_hip)),
        placement=Placement(
            body_part="torso",
            side="front",
            anchor="waist_front",
            anchor_mark="cf_waist",
        ),
        landmarks={
            "waist_front": "cf_waist",
            "waist_side_right": "side_waist_right",
            "waist_side_left": "side_waist_left",
            "hip_side_right": "side_hip_right",
            "hip_side_left": "side_hip_left",
        },
        category="FRONT",
        annotation="SKIRT FRONT (CUT 1 ON FOLD)",
    )


def seam(
    seam_id: str,
    a: Sequence[str],
    b: Sequence[str],
    *,
    ease_cm: float = 0.0,
    kind: str = "seam",
) -> Seam:
    """A seam between ``a`` and ``b`` given as ``(piece, start, end[, copy])``.

    ``reverse`` is set by the library convention (every piece seen from the
    outside, outlines CCW): two copies of the same handedness meet running
    opposite ways, a primary and a mirror copy run the same way.
    """
    ea = EdgeRange(piece=a[0], start=a[1], end=a[2], copy=a[3] if len(a) > 3 else Copy.PRIMARY)
    eb = EdgeRange(piece=b[0], start=b[1], end=b[2], copy=b[3] if len(b) > 3 else Copy.PRIMARY)
    return Seam(
        id=seam_id,
        a=ea,
        b=eb,
        kind=SeamKind(kind),
        reverse=ea.copy == eb.copy,
        ease_cm=ease_cm,
    )


def leg(piece: str, start: str, end: str, along: str = "chord", factor: float = 1.0) -> Leg:
    """Shorthand for :class:`Leg`."""
    return Leg(piece=piece, start=start, end=end, along=along, factor=factor)


def link(
    measurement: str,
    ease_cm: float | None,
    *legs: Leg,
    link_id: str = "",
    at_least: bool = False,
    proportional: bool = False,
) -> tuple:
    """A measurement link; ``ease_cm=None`` takes the ease the sample size realises.

    ``at_least``: the graded distance may exceed body + ease; ``proportional``:
    it follows the body measurement in proportion (see
    :class:`~patternbridge.pattern.model.MeasurementLink`).
    """
    return (measurement, ease_cm, tuple(legs), link_id, at_least, proportional)


def _inward_angle(cut: np.ndarray, i: int) -> float:
    n = len(cut)
    e1 = cut[i] - cut[i - 1]
    e2 = cut[(i + 1) % n] - cut[i]
    # inward normal of a CCW edge (dx, dy) is (-dy, dx)
    n1 = np.array([-e1[1], e1[0]]) / max(np.hypot(*e1), 1e-12)
    n2 = np.array([-e2[1], e2[0]]) / max(np.hypot(*e2), 1e-12)
    v = n1 + n2
    return float(np.arctan2(v[1], v[0]))


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class _PieceGeometry:
    """The points of one drafted piece in one size, cm.

    outline : (n, 2) cut line ; sew : (n, 2) sew line ; grain : (2, 2)
    internal : (k_i, 2) per internal line ; mirror : (2, 2) or None
    """

    outline: np.ndarray
    sew: np.ndarray
    grain: np.ndarray
    internal: tuple[np.ndarray, ...]
    mirror: np.ndarray | None


@dataclass(frozen=True, slots=True, kw_only=True)
class _PieceRules:
    """Grade rule ids of every point of a piece's geometry, in the order of :class:`_PieceGeometry`."""

    outline: tuple[str, ...]
    sew: tuple[str, ...]
    grain: tuple[str, ...]
    internal: tuple[tuple[str, ...], ...]
    mirror: tuple[str, ...] | None


def _piece_geometry(d: PieceDraft) -> _PieceGeometry:
    return _PieceGeometry(
        outline=offset_outline(d.net.points, d.net.allowance, d.net.darts),
        sew=d.net.points,
        grain=np.asarray(d.grain, dtype=np.float64),
        internal=tuple(np.asarray(pts, dtype=np.float64) for pts, _label in d.internal),
        mirror=None if d.mirror_line is None else np.asarray(d.mirror_line, dtype=np.float64),
    )


def _size_geometries(style: str, sample: PieceDraft, per_size: Sequence[PieceDraft], sizes) -> list[_PieceGeometry]:
    """The geometry of a piece in every size, which must keep the sample's vertex count and marks."""
    geos = []
    for size, other in zip(sizes, per_size, strict=True):
        if len(other.net.points) != len(sample.net.points) or other.net.marks != sample.net.marks:
            raise ValueError(
                f"{style}/{sample.name}: size {size} has {len(other.net.points)} vertices or other "
                f"marks than the sample ({len(sample.net.points)})"
            )
        geos.append(_piece_geometry(other))
    return geos


def _number_rules(per_size: list[np.ndarray], k_sample: int, first: int) -> dict[str, np.ndarray]:
    """One rule per point, numbered from ``first``: rule id -> (n_sizes, 2) displacement from the sample size."""
    stack = np.stack(per_size)  # (n_sizes, m, 2)
    rel = stack - stack[k_sample]
    return {str(first + j): rel[:, j, :] for j in range(stack.shape[1])}


def _piece_rules(geos: list[_PieceGeometry], k_sample: int, first: int) -> tuple[_PieceRules, dict[str, np.ndarray]]:
    """Rule ids for every point of a piece (numbered from ``first``) and their displacements."""
    deltas: dict[str, np.ndarray] = {}

    def ids(per_size: list[np.ndarray]) -> tuple[str, ...]:
        new = _number_rules(per_size, k_sample, first + len(deltas))
        deltas.update(new)
        return tuple(new)

    rules = _PieceRules(
        outline=ids([g.outline for g in geos]),
        sew=ids([g.sew for g in geos]),
        grain=ids([g.grain for g in geos]),
        internal=tuple(ids([g.internal[k] for g in geos]) for k in range(len(geos[0].internal))),
        mirror=None if geos[0].mirror is None else ids([g.mirror for g in geos]),
    )
    return rules, deltas


def _notches(d: PieceDraft, outline: np.ndarray, outline_rules: tuple[str, ...]) -> tuple[Notch, ...]:
    """Slit notches at the draft's notch marks, pointing inward, sorted by vertex."""
    notches = tuple(
        Notch(
            vertex=d.net.marks[m],
            type=NotchType.SLIT,
            depth_cm=NOTCH_DEPTH_CM,
            angle=_inward_angle(outline, d.net.marks[m]),
            rule=outline_rules[d.net.marks[m]],
        )
        for m in d.net.notches
    )
    return tuple(sorted(notches, key=lambda n: n.vertex))


def _graded_piece(d: PieceDraft, g0: _PieceGeometry, rules: _PieceRules, sample_size: str) -> Piece:
    """The sample-size piece of draft ``d`` with geometry ``g0`` and its rule ids."""
    internal = tuple(
        Polyline(points=pts, rules=ids, label=label)
        for pts, ids, (_pts, label) in zip(g0.internal, rules.internal, d.internal, strict=True)
    )
    mirror = None if g0.mirror is None else Line(points=g0.mirror, rules=rules.mirror)
    return Piece(
        name=d.name,
        size=sample_size,
        outline=g0.outline,
        kinds=tuple(d.net.kinds),
        rules=rules.outline,
        quantity=d.quantity,
        category=d.category or d.name,
        annotation=d.annotation,
        fabric=d.fabric,
        notches=_notches(d, g0.outline, rules.outline),
        grain_line=Line(points=g0.grain, rules=rules.grain),
        mirror_line=mirror,
        internal_lines=internal,
        sew_lines=(Polyline(points=g0.sew, kinds=tuple(d.net.kinds), rules=rules.sew, closed=True),),
        marks=d.net.marks,
        landmarks=d.landmarks,
        placement=d.placement,
    )


def _measurement_links(
    pattern: Pattern, links: Sequence[tuple], body: dict[str, float], k_sample: int
) -> tuple[MeasurementLink, ...]:
    """The links of :func:`link`; an ease of None becomes what the sample size achieves over ``body``."""
    from .seams import link_lengths

    provisional = tuple(
        MeasurementLink(measurement=m, legs=legs_, ease_cm=0.0, id=lid or m, at_least=least, proportional=prop)
        for m, _e, legs_, lid, least, prop in links
    )
    achieved = link_lengths(replace(pattern, measurements=provisional))
    measurements = []
    for (m, ease, *_rest), ml in zip(links, provisional, strict=True):
        if ease is None:
            ease = round(float(achieved[ml.id][k_sample]) - body[m], 1)
        measurements.append(replace(ml, ease_cm=float(ease)))
    return tuple(measurements)


def build_pattern(
    *,
    style: str,
    description: str,
    chart: SizeChart,
    draft: Callable[[dict[str, float]], list[PieceDraft]],
    seams: Sequence[Seam],
    links: Sequence[tuple],
    fabric_class: FabricClass = FabricClass.WOVEN,
    fabric_why: str = "",
) -> Pattern:
    """Draft every size of ``chart`` and return the graded pattern.

    ``fabric_class`` and ``fabric_why`` state the fabric the garment is drafted for.

    Raises
    ------
    ValueError
        When a piece changes vertex count or marks between sizes (a drafting bug).
    """
    drafts = {size: {d.name: d for d in draft(chart.body(size))} for size in chart.sizes}
    k_sample = chart.sizes.index(chart.sample_size)
    deltas: dict[str, np.ndarray] = {}
    pieces = []
    for name, d in drafts[chart.sample_size].items():
        geos = _size_geometries(style, d, [drafts[size][name] for size in chart.sizes], chart.sizes)
        rules, piece_deltas = _piece_rules(geos, k_sample, first=len(deltas) + 1)
        deltas.update(piece_deltas)
        pieces.append(_graded_piece(d, geos[k_sample], rules, chart.sample_size))
    pattern = Pattern(
        style=style,
        pieces=tuple(pieces),
        sample_size=chart.sample_size,
        sizes=chart.sizes,
        rules=GradeRuleTable(name=style.upper(), sizes=chart.sizes, sample_size=chart.sample_size, deltas=deltas),
        provenance=Provenance(
            producer="PATTERNBRIDGE",
            product="patternbridge garment library",
            author="patternbridge",
            source_file=f"garment_library/{style}/draft.py",
        ),
        description=description,
        seams=tuple(seams),
        fabric_class=fabric_class,
        fabric_why=fabric_why,
    )
    measurements = _measurement_links(pattern, links, chart.body(chart.sample_size), k_sample)
    return replace(pattern, measurements=measurements)


def band_draft(
    name: str,
    parts: Sequence[tuple[PieceDraft, str, str, str, str | None]],
    height_cm: float,
    *,
    placement: Placement,
    landmarks: dict[str, str] | None = None,
    ends: tuple[str, str] = ("end_start", "end_finish"),
    annotation: str = "",
    category: str = "",
    part_ease_cm: float = 0.0,
) -> tuple[PieceDraft, list[Seam]]:
    """A straight band (waistband, neckband) sewn to a chain of piece edges.

    parts : ``(piece draft, copy, start mark, end mark, band mark)`` in the
        order the band's lower edge meets them (left to right); each range is
        given in its piece's outline order and runs *against* the band (the
        library convention), ``band mark`` names the band point at the end of
        that part (``None``: an automatic ``j<k>`` name). Darts between parts
        close to a single band point.
    height_cm : band height
    part_ease_cm : how much longer each piece edge is than its band part
        (stretch rib bands: the band is ``part_ease_cm`` shorter per part,
        the same in every size, declared as the seams' ease)

    Returns
    -------
    The band's draft and one seam per part (``band_<k>`` ids are replaced by
    ``<name>_<piece>_<start>`` ids).
    """
    from .draft import OutlineBuilder

    lengths = [p.net.length(s, e) - part_ease_cm for p, _c, s, e, _m in parts]
    x = np.concatenate([[0.0], np.cumsum(lengths)])
    o = OutlineBuilder()
    o.start((0.0, 0.0), ends[0])
    names = [ends[0]]
    for k, (_p, _c, _s, _e, mark) in enumerate(parts):
        nm = mark or f"j{k + 1}"
        if k == len(parts) - 1:
            nm = ends[1]
        o.line((x[k + 1], 0.0), nm, notch=k < len(parts) - 1)
        names.append(nm)
    o.line((x[-1], height_cm), f"top_{ends[1]}")
    o.line((0.0, height_cm), f"top_{ends[0]}")
    net = o.close()
    band = PieceDraft(
        name=name,
        net=net,
        quantity=Quantity(right=1, left=0),
        grain=((x[-1] * 0.3, height_cm / 2), (x[-1] * 0.7, height_cm / 2)),
        placement=placement,
        landmarks=landmarks or {},
        annotation=annotation,
        category=category or name.upper(),
    )
    seams = []
    for k, (p, copy, s, e, _m) in enumerate(parts):
        sid = f"{name}_{p.name}_{s}" + ("_left" if copy == "mirror" else "")
        seams.append(
            seam(
                sid,
                (name, names[k], names[k + 1]),
                (p.name, s, e, copy),
                ease_cm=part_ease_cm,
            )
        )
    seams.append(
        seam(
            f"{name}_closure",
            (name, f"top_{ends[0]}", ends[0]),
            (name, ends[1], f"top_{ends[1]}"),
        )
    )
    return band, seams
