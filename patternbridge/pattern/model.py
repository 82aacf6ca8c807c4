"""The canonical pattern model: frozen dataclasses holding numpy geometry in cm.

A :class:`Pattern` is a style in its sample size plus a :class:`GradeRuleTable`
that produces every other size, and the *bridge data* DXF-AAMA cannot carry:
named boundary points (marks), seams, body landmarks, the body measurements
each pattern distance must match, and placement hints for the assembler.

Conventions
-----------
- Lengths in centimetres, angles in radians, 2D pattern coordinates with +y
  up as drawn by the CAD system (a grain line usually runs along +y or +x).
- Piece boundaries are closed (the first vertex is not repeated) and stored
  counter-clockwise; vertex ``i`` of the sample size corresponds to vertex ``i``
  of every graded size.
- Everything is referenced by stable string ids (piece names, mark names,
  landmark names, rule ids), never by list position, so bridge data survives
  re-sampling of a boundary as long as the marks are carried along.
- Objects are immutable: use :func:`dataclasses.replace` or the functions in
  ``patternbridge.pattern`` to derive changed copies.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from enum import Enum
from types import MappingProxyType

import numpy as np

from .._arrays import as_float_array, frozen
from .fabric import FabricClass

__all__ = [
    "BINDING_ROLES",
    "Annotation",
    "BodyPart",
    "Copy",
    "DrillHole",
    "EdgeRange",
    "FabricClass",
    "Flavor",
    "GradeRuleTable",
    "Leg",
    "Line",
    "MeasurementLink",
    "Notch",
    "NotchType",
    "Pattern",
    "Piece",
    "Placement",
    "Polyline",
    "Provenance",
    "Quantity",
    "Role",
    "Seam",
    "SeamKind",
    "Side",
    "Units",
    "VertexKind",
]


class _StrEnum(str, Enum):
    """``str`` enum usable on Python 3.10 (``StrEnum`` arrived in 3.11)."""

    def __str__(self) -> str:
        return str(self.value)


class Units(_StrEnum):
    """Units a DXF-AAMA/ASTM file declares (``Units:`` style text)."""

    METRIC = "METRIC"  # millimetres
    ENGLISH = "ENGLISH"  # inches


class Flavor(_StrEnum):
    """Dialect of the pattern exchange file."""

    AAMA = "aama"
    ASTM = "astm"


class VertexKind(_StrEnum):
    """Role of a polyline vertex: turn (corner), curve (on a curve) or plain."""

    PLAIN = "plain"
    TURN = "turn"
    CURVE = "curve"


class NotchType(_StrEnum):
    """Notch shapes; DXF layers 4 (slit, V), 80 (T), 81 (castle), 82 (check), 83 (U)."""

    SLIT = "slit"
    V = "V"
    T = "T"
    CASTLE = "castle"
    CHECK = "check"
    U = "U"


class SeamKind(_StrEnum):
    """How two boundary ranges are joined."""

    SEAM = "seam"  # sewn together
    FOLD = "fold"  # one piece of cloth folded on this line (cut on fold)


class Copy(_StrEnum):
    """Which cut copy of a piece: as drawn, or its mirror image."""

    PRIMARY = "primary"
    MIRROR = "mirror"


class BodyPart(_StrEnum):
    """Body region a piece wraps (assembler placement)."""

    TORSO = "torso"
    LEFT_ARM = "left_arm"
    RIGHT_ARM = "right_arm"
    LEFT_LEG = "left_leg"
    RIGHT_LEG = "right_leg"
    NECK = "neck"
    HEAD = "head"


class Side(_StrEnum):
    """Which face of the body part the piece covers."""

    FRONT = "front"
    BACK = "back"
    AROUND = "around"  # wraps all round (sleeve, cuff, waistband)


class Role(_StrEnum):
    """What a piece is in the garment (``formats/bridge.md``); inferred by ``patternbridge bridge infer``."""

    FRONT = "front"
    BACK = "back"
    SLEEVE = "sleeve"
    COLLAR = "collar"
    COLLAR_STAND = "collar_stand"
    CUFF = "cuff"
    NECKBAND = "neckband"
    NECK_BINDING = "neck_binding"
    ARMHOLE_BINDING = "armhole_binding"
    WAISTBAND = "waistband"
    YOKE = "yoke"
    PLACKET = "placket"
    POCKET = "pocket"
    HOOD = "hood"
    FACING = "facing"
    LEG_FRONT = "leg_front"
    LEG_BACK = "leg_back"
    LEG = "leg"
    GUSSET = "gusset"
    INTERLINING = "interlining"
    OTHER = "other"


#: pieces sewn flat along an opening by one long edge
BINDING_ROLES = frozenset({Role.NECK_BINDING, Role.ARMHOLE_BINDING})


def _vertex_kinds(kinds, n: int, name: str) -> tuple[VertexKind, ...]:
    if kinds is None:
        return (VertexKind.PLAIN,) * n
    out = tuple(VertexKind(k) for k in kinds)
    if len(out) != n:
        raise ValueError(f"{name}: expected {n} vertex kinds, got {len(out)}")
    return out


def _vertex_rules(rules, n: int, name: str) -> tuple[str | None, ...]:
    if rules is None:
        return (None,) * n
    out = tuple(None if r is None else str(r) for r in rules)
    if len(out) != n:
        raise ValueError(f"{name}: expected {n} rule ids, got {len(out)}")
    return out


def _text_map(mapping) -> MappingProxyType:
    """A read-only ``{str: str}`` copy (free text carried through from the source file)."""
    return MappingProxyType({str(k): str(v) for k, v in dict(mapping).items()})


def _arrays_equal(a, b) -> bool:
    return np.shape(a) == np.shape(b) and np.array_equal(a, b)


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class Polyline:
    """An open or closed polyline inside a piece (internal line, cutout, sew line).

    points : (n, 2) float64, cm
    kinds : n vertex kinds (turn / curve / plain)
    rules : n grade-rule ids or None
    closed : whether the last point joins the first
    label : text label drawn with it (AccuMark's ``B``/``O`` on layer 8), if any
    """

    points: np.ndarray
    kinds: tuple[VertexKind, ...] | None = None
    rules: tuple[str | None, ...] | None = None
    closed: bool = False
    label: str | None = None

    def __post_init__(self) -> None:
        pts = as_float_array(self.points, (None, 2), "polyline points")
        n = len(pts)
        object.__setattr__(self, "points", frozen(pts))
        object.__setattr__(self, "kinds", _vertex_kinds(self.kinds, n, "polyline kinds"))
        object.__setattr__(self, "rules", _vertex_rules(self.rules, n, "polyline rules"))

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Polyline):
            return NotImplemented
        return (
            _arrays_equal(self.points, other.points)
            and self.kinds == other.kinds
            and self.rules == other.rules
            and self.closed == other.closed
            and self.label == other.label
        )

    __hash__ = None  # type: ignore[assignment]


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class Line:
    """A straight two-point line (grain, grade reference, mirror/fold line).

    points : (2, 2) float64, cm — start then end; a grain line points from tail to head
    rules : grade-rule ids of the two ends (Richpeace grades grain-line ends)
    """

    points: np.ndarray
    rules: tuple[str | None, str | None] = (None, None)

    def __post_init__(self) -> None:
        object.__setattr__(self, "points", frozen(as_float_array(self.points, (2, 2), "line points")))
        object.__setattr__(self, "rules", _vertex_rules(self.rules, 2, "line rules"))

    @property
    def direction(self) -> np.ndarray:
        """Unit vector from start to end."""
        d = self.points[1] - self.points[0]
        norm = float(np.hypot(*d))
        return d / norm if norm > 0 else np.array([1.0, 0.0])

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Line):
            return NotImplemented
        return _arrays_equal(self.points, other.points) and self.rules == other.rules

    __hash__ = None  # type: ignore[assignment]


@dataclass(frozen=True, slots=True, kw_only=True)
class Notch:
    """A notch on the boundary.

    vertex : index of the boundary vertex the notch sits on (importers insert a
        vertex where a notch falls between two)
    type : notch shape
    depth_cm, width_cm : cut depth into the piece and opening width (0 = slit)
    angle : direction into the piece, radians CCW from +x, recomputed from the
        boundary on import (producers disagree on group 50)
    source_angle_deg : the file's group-50 value as read, kept for reference
    rule : grade-rule id of the notch itself (Boke grades notches), if any
    """

    vertex: int
    type: NotchType = NotchType.SLIT
    depth_cm: float = 0.5
    width_cm: float = 0.0
    angle: float = 0.0
    source_angle_deg: float | None = None
    rule: str | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "vertex", int(self.vertex))
        object.__setattr__(self, "type", NotchType(self.type))
        object.__setattr__(self, "depth_cm", float(self.depth_cm))
        object.__setattr__(self, "width_cm", float(self.width_cm))
        object.__setattr__(self, "angle", float(self.angle))


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class DrillHole:
    """A drill hole (layer 13).

    position : (2,) float64, cm
    diameter_cm : hole diameter, 0 when the file gives none
    """

    position: np.ndarray
    diameter_cm: float = 0.0
    rule: str | None = None
    label: str | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "position", frozen(as_float_array(self.position, (2,), "drill position")))
        object.__setattr__(self, "diameter_cm", float(self.diameter_cm))

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, DrillHole):
            return NotImplemented
        return (
            _arrays_equal(self.position, other.position)
            and self.diameter_cm == other.diameter_cm
            and self.rule == other.rule
            and self.label == other.label
        )

    __hash__ = None  # type: ignore[assignment]


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class Annotation:
    """A free text on the piece (layer 15, or a label on layer 8).

    position : (2,) float64, cm ; height_cm : text height ; angle : radians CCW
    """

    text: str
    position: np.ndarray
    height_cm: float = 0.5
    angle: float = 0.0
    layer: int = 15

    def __post_init__(self) -> None:
        object.__setattr__(self, "position", frozen(as_float_array(self.position, (2,), "annotation position")))
        object.__setattr__(self, "height_cm", float(self.height_cm))
        object.__setattr__(self, "angle", float(self.angle))
        object.__setattr__(self, "layer", int(self.layer))

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Annotation):
            return NotImplemented
        return (
            self.text == other.text
            and _arrays_equal(self.position, other.position)
            and (self.height_cm, self.angle, self.layer) == (other.height_cm, other.angle, other.layer)
        )

    __hash__ = None  # type: ignore[assignment]


@dataclass(frozen=True, slots=True, kw_only=True)
class Quantity:
    """How many copies are cut: ``right`` as drawn and ``left`` mirrored.

    AAMA files give a total (``Quantity: 2``), ASTM a pair (``Quantity: 1,1``);
    a total N reads as ``right = ceil(N/2), left = floor(N/2)``, which is how
    AccuMark writes the same piece in both flavours.
    """

    right: int = 1
    left: int = 0

    @property
    def total(self) -> int:
        return self.right + self.left

    @property
    def is_pair(self) -> bool:
        return self.left > 0

    @classmethod
    def from_total(cls, total: int) -> Quantity:
        return cls(right=(total + 1) // 2, left=total // 2)


@dataclass(frozen=True, slots=True, kw_only=True)
class Placement:
    """Where the primary copy of a piece sits on the body (assembler hint).

    The mirror copy (``Quantity.left``) goes on the mirrored body part.
    anchor : body landmark name fixing the piece's height (``"waist_side_right"``)
    anchor_mark : the piece mark that goes on ``anchor``
    drop_cm : how far below ``anchor`` the mark goes, cm along the limb's
        landmarks (shoulder, elbow, wrist; hip, knee, ankle): a band sewn to an
        edge that carries no landmark, the cuff of a short sleeve's hem
    """

    body_part: BodyPart
    side: Side
    anchor: str
    anchor_mark: str
    drop_cm: float = 0.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "body_part", BodyPart(self.body_part))
        object.__setattr__(self, "side", Side(self.side))
        object.__setattr__(self, "drop_cm", float(self.drop_cm))


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class Piece:
    """One pattern piece in one size.

    outline : (n, 2) float64, cm — the cut line (layer 1), closed, CCW, no repeat
    kinds : n vertex kinds ; rules : n grade-rule ids or None
    marks : mark name -> boundary vertex index (turn points, notch points and
        body landmarks referenced by seams, measurements and placement)
    landmarks : body landmark name (``../shared/characters/landmarks.json``
        names) -> mark name on this piece
    extra_text : piece system text we do not model, kept for the round trip
    role, role_confidence : what the piece is in the garment and how sure the
        inference that named it was (0..1; None when a person set it)
    fabric_class : the class of fabric the piece is cut from when it differs
        from the garment's (a rib collar on a jersey or woven body); None
        takes the pattern's ``fabric_class``
    """

    name: str
    outline: np.ndarray
    size: str = ""
    kinds: tuple[VertexKind, ...] | None = None
    rules: tuple[str | None, ...] | None = None
    quantity: Quantity = field(default_factory=Quantity)
    category: str = ""
    annotation: str = ""
    fabric: str = ""
    notches: tuple[Notch, ...] = ()
    grain_line: Line | None = None
    grade_reference: Line | None = None
    mirror_line: Line | None = None
    internal_lines: tuple[Polyline, ...] = ()
    cutouts: tuple[Polyline, ...] = ()
    drill_holes: tuple[DrillHole, ...] = ()
    sew_lines: tuple[Polyline, ...] = ()
    annotations: tuple[Annotation, ...] = ()
    marks: Mapping[str, int] = field(default_factory=dict)
    landmarks: Mapping[str, str] = field(default_factory=dict)
    placement: Placement | None = None
    extra_text: Mapping[str, str] = field(default_factory=dict)
    role: Role | None = None
    role_confidence: float | None = None
    fabric_class: FabricClass | None = None

    def __post_init__(self) -> None:
        if self.role is not None:
            object.__setattr__(self, "role", Role(self.role))
        if self.fabric_class is not None:
            object.__setattr__(self, "fabric_class", FabricClass(self.fabric_class))
        outline = as_float_array(self.outline, (None, 2), f"piece {self.name!r} outline")
        n = len(outline)
        if n < 3:
            raise ValueError(f"piece {self.name!r}: outline needs at least 3 vertices, got {n}")
        object.__setattr__(self, "outline", frozen(outline))
        object.__setattr__(self, "kinds", _vertex_kinds(self.kinds, n, f"piece {self.name!r} kinds"))
        object.__setattr__(self, "rules", _vertex_rules(self.rules, n, f"piece {self.name!r} rules"))
        for attr in ("notches", "internal_lines", "cutouts", "drill_holes", "sew_lines", "annotations"):
            object.__setattr__(self, attr, tuple(getattr(self, attr)))
        marks = {str(k): int(v) for k, v in dict(self.marks).items()}
        bad = {k: v for k, v in marks.items() if not 0 <= v < n}
        if bad:
            raise ValueError(f"piece {self.name!r}: marks outside the outline (n={n}): {bad}")
        for notch in self.notches:
            if not 0 <= notch.vertex < n:
                raise ValueError(f"piece {self.name!r}: notch on vertex {notch.vertex}, outline has {n}")
        landmarks = {str(k): str(v) for k, v in dict(self.landmarks).items()}
        missing = sorted(set(landmarks.values()) - set(marks))
        if missing:
            raise ValueError(f"piece {self.name!r}: landmarks name unknown marks {missing}")
        object.__setattr__(self, "marks", MappingProxyType(marks))
        object.__setattr__(self, "landmarks", MappingProxyType(landmarks))
        object.__setattr__(self, "extra_text", _text_map(self.extra_text))

    @property
    def n_vertices(self) -> int:
        return len(self.outline)

    @property
    def across_grain(self) -> np.ndarray:
        """Unit vector square to the grain line (the grain turned a quarter clockwise).

        A piece without a grain line takes its drawing's +y as the grain, so
        ``(1, 0)``. Girths measured ``along="across"`` are taken on it.
        """
        if self.grain_line is None:
            return np.array([1.0, 0.0])
        gx, gy = self.grain_line.direction
        return np.array([gy, -gx])

    def mark(self, name: str) -> int:
        """Boundary vertex index of mark ``name`` (KeyError names the piece)."""
        try:
            return self.marks[name]
        except KeyError:
            raise KeyError(f"piece {self.name!r} has no mark {name!r} (marks: {sorted(self.marks)})") from None

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Piece):
            return NotImplemented
        return all(
            _arrays_equal(getattr(self, f), getattr(other, f))
            if f == "outline"
            else getattr(self, f) == getattr(other, f)
            for f in Piece.__dataclass_fields__
        )

    __hash__ = None  # type: ignore[assignment]


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class GradeRuleTable:
    """Grade rules: rule id -> cumulative displacement from the sample size.

    deltas[rule] : (len(sizes), 2) float64, cm, in the frame of the piece's
    grade reference line (+x along it) or the drawing axes when it has none;
    the sample-size row is zero.
    """

    name: str = ""
    sizes: tuple[str, ...] = ()
    sample_size: str = ""
    deltas: Mapping[str, np.ndarray] = field(default_factory=dict)

    def __post_init__(self) -> None:
        sizes = tuple(str(s) for s in self.sizes)
        object.__setattr__(self, "sizes", sizes)
        table = {}
        for rule, d in dict(self.deltas).items():
            table[str(rule)] = frozen(as_float_array(d, (len(sizes), 2), f"rule {rule}"))
        object.__setattr__(self, "deltas", MappingProxyType(table))

    def size_index(self, size: str) -> int:
        try:
            return self.sizes.index(str(size))
        except ValueError:
            raise KeyError(f"size {size!r} not in the size list {list(self.sizes)}") from None

    def delta(self, rule: str, size: str) -> np.ndarray:
        """(2,) displacement of ``rule`` at ``size`` (cm)."""
        return self.deltas[rule][self.size_index(size)]

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, GradeRuleTable):
            return NotImplemented
        return (
            (self.name, self.sizes, self.sample_size) == (other.name, other.sizes, other.sample_size)
            and self.deltas.keys() == other.deltas.keys()
            and all(_arrays_equal(v, other.deltas[k]) for k, v in self.deltas.items())
        )

    __hash__ = None  # type: ignore[assignment]


@dataclass(frozen=True, slots=True, kw_only=True)
class Provenance:
    """Who made the file and how (style system text)."""

    producer: str = ""  # e.g. "GERBER TECHNOLOGY"
    product: str = ""  # e.g. "ACCUMARK"
    version: str = ""  # e.g. "10.0.1"
    author: str = ""
    created: str = ""  # as written, e.g. "12-12-2017 14:33"
    flavor: Flavor | None = None
    source_file: str = ""
    extra_text: Mapping[str, str] = field(default_factory=dict)

    def __post_init__(self) -> None:
        if self.flavor is not None:
            object.__setattr__(self, "flavor", Flavor(self.flavor))
        object.__setattr__(self, "extra_text", _text_map(self.extra_text))

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Provenance):
            return NotImplemented
        return all(
            (dict(getattr(self, f)) if f == "extra_text" else getattr(self, f))
            == (dict(getattr(other, f)) if f == "extra_text" else getattr(other, f))
            for f in Provenance.__dataclass_fields__
        )

    __hash__ = None  # type: ignore[assignment]


@dataclass(frozen=True, slots=True, kw_only=True)
class EdgeRange:
    """A stretch of one cut copy's boundary, from mark ``start`` to mark ``end``.

    The range runs in the outline's own (CCW) vertex order from ``start`` to
    ``end``, wrapping past the last vertex if needed.
    """

    piece: str
    start: str
    end: str
    copy: Copy = Copy.PRIMARY

    def __post_init__(self) -> None:
        object.__setattr__(self, "copy", Copy(self.copy))


@dataclass(frozen=True, slots=True, kw_only=True)
class Seam:
    """Two boundary ranges joined in the garment.

    reverse : True when ``b`` is sewn running opposite to ``a`` (the usual case
        for two pieces placed right sides together, both outlines CCW)
    ease_cm : intended excess length of ``b`` over ``a`` (sleeve-cap ease,
        gathering); 0 for a plain seam
    """

    id: str
    a: EdgeRange
    b: EdgeRange
    kind: SeamKind = SeamKind.SEAM
    reverse: bool = True
    ease_cm: float = 0.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "kind", SeamKind(self.kind))
        object.__setattr__(self, "ease_cm", float(self.ease_cm))


@dataclass(frozen=True, slots=True, kw_only=True)
class Leg:
    """One leg of a pattern distance: between two marks of one piece.

    along : ``"boundary"`` (along the outline from ``start`` to ``end`` in
        outline order), ``"chord"`` (straight line) or ``"across"`` (the
        straight line's span square to the grain: a girth taken straight
        across the piece, which a mark moved up or down does not lengthen)
    factor : multiplier, e.g. 2 for a half-front that is cut as a pair
    """

    piece: str
    start: str
    end: str
    along: str = "boundary"
    factor: float = 1.0

    def __post_init__(self) -> None:
        if self.along not in ("boundary", "chord", "across"):
            raise ValueError(f"leg along must be 'boundary', 'chord' or 'across', got {self.along!r}")
        object.__setattr__(self, "factor", float(self.factor))


@dataclass(frozen=True, slots=True, kw_only=True)
class MeasurementLink:
    """A pattern distance that must equal a body measurement plus ease.

    measurement : id from ``formats/measurements.md`` (``"waist_girth"``)
    legs : the pattern distance is ``sum(leg.factor * length(leg))``, possibly
        across pieces sewn together
    ease_cm : target = body measurement + ease_cm (negative for stretch fabric)
    proportional : the distance follows the body measurement in proportion
        instead of by a fixed ease: target = L₀ · body / (L₀ − ease_cm), where
        L₀ is the distance in the sample size and ``L₀ − ease_cm`` the sample
        body's measurement. For lengths no fitting measurement fixes (a
        skirt's length, a short sleeve): they keep the design's proportion
        to the body height they follow
    at_least : the distance must reach the target and may exceed it (a shirt's
        hem must pass over the hips; wider is a style, not an error)
    """

    measurement: str
    legs: tuple[Leg, ...]
    ease_cm: float = 0.0
    id: str = ""
    at_least: bool = False
    proportional: bool = False

    def __post_init__(self) -> None:
        object.__setattr__(self, "legs", tuple(self.legs))
        object.__setattr__(self, "proportional", bool(self.proportional))
        object.__setattr__(self, "ease_cm", float(self.ease_cm))
        object.__setattr__(self, "at_least", bool(self.at_least))
        if not self.id:
            object.__setattr__(self, "id", self.measurement)


@dataclass(frozen=True, slots=True, kw_only=True)
class Pattern:
    """A garment style: pieces in the sample size, grade rules and bridge data.

    fabric_class : the class of fabric the garment is cut from
        (:mod:`.fabric`), woven unless the pattern or its sidecar says
        otherwise ; fabric_why : the evidence for it (empty when a person set it)
    """

    style: str
    pieces: tuple[Piece, ...]
    units: Units = Units.METRIC
    sample_size: str = ""
    sizes: tuple[str, ...] = ()
    rules: GradeRuleTable = field(default_factory=GradeRuleTable)
    provenance: Provenance = field(default_factory=Provenance)
    description: str = ""
    seams: tuple[Seam, ...] = ()
    measurements: tuple[MeasurementLink, ...] = ()
    fabric_class: FabricClass = FabricClass.WOVEN
    fabric_why: str = ""

    def __post_init__(self) -> None:
        object.__setattr__(self, "units", Units(self.units))
        object.__setattr__(self, "fabric_class", FabricClass(self.fabric_class))
        object.__setattr__(self, "pieces", tuple(self.pieces))
        object.__setattr__(self, "sizes", tuple(str(s) for s in self.sizes))
        object.__setattr__(self, "seams", tuple(self.seams))
        object.__setattr__(self, "measurements", tuple(self.measurements))
        names = [p.name for p in self.pieces]
        dupes = sorted({n for n in names if names.count(n) > 1})
        if dupes:
            raise ValueError(f"pattern {self.style!r}: duplicate piece names {dupes}")

    def piece(self, name: str) -> Piece:
        for p in self.pieces:
            if p.name == name:
                return p
        raise KeyError(f"pattern {self.style!r} has no piece {name!r} (pieces: {[p.name for p in self.pieces]})")

    @property
    def piece_names(self) -> tuple[str, ...]:
        return tuple(p.name for p in self.pieces)

    @property
    def has_bridge_data(self) -> bool:
        """True when seams and measurement links are present (grader-ready)."""
        return bool(self.seams) and bool(self.measurements)

    __hash__ = None  # type: ignore[assignment]
