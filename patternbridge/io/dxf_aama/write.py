"""Write a :class:`~patternbridge.pattern.model.Pattern` as DXF-AAMA or DXF-ASTM.

The output follows the exporter compatibility rules of the format reference
(``docs/formats.md``): DXF R12 ASCII with ``$ACADVER AC1009`` as the only
header variable, no TABLES, no handles, CRLF line ends, 7-bit ASCII text, and
a BLOCKS section that holds nothing but piece blocks (``8 0``, ``70 64``, base
0,0), each inserted once at the origin from ENTITIES.

Two grading forms are written:

- ``sizes="sample"``: one block per piece in the sample size, ``# n`` grade-rule
  texts at the graded points and, with ``rul_path``, the ``.RUL`` rule table;
- ``sizes="all"`` or a list of sizes: a *graded nest*, one block per piece per
  size in size-list order; only the sample-size block carries turn/curve
  points, notches, rule texts and the full piece text.

The tag writer is our own (a few lines): it gives exact control over what an
R12 pattern file may contain, which a general DXF library would add to.
"""

from __future__ import annotations

import datetime as _dt
import logging
import math
import os
import re
import unicodedata
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ... import __version__
from ...atomic import atomic_path
from ...errors import InputError
from ...pattern.model import (
    Flavor,
    Line,
    NotchType,
    Pattern,
    Piece,
    Polyline,
    Units,
    VertexKind,
)
from ...report import Report
from ...units import from_cm, to_cm
from ..rul import creation_time
from .layers import NOTCH_LAYER_BY_TYPE
from .links import notch_positions
from .reference import reference_line
from .sizes import rename_sizes, size_codes
from .tags import MAX_ABS_VALUE

__all__ = [
    "format_dxf",
    "sanitize_block_name",
    "to_ascii",
    "write_dxf",
]

log = logging.getLogger(__name__)

#: owner geometry layer -> its quality-validation curve layer (ASTM only)
_VALIDATION_LAYER = {1: 84, 8: 85, 11: 86, 14: 87}

_VENDOR = "PATTERNBRIDGE"
_PRODUCT = "PATTERNBRIDGE"
_ASTM_VERSION = "ASTM/D13Proposal 1 Version: D 6673-04"
_TEXT_HEIGHT = {Units.METRIC: 2.5, Units.ENGLISH: 0.1}  # file units
_CURVE_TOLERANCE = {Units.METRIC: ".152", Units.ENGLISH: ".006"}
_MAX_NAME = 20  # Gerber truncates piece/style names beyond this
_SAME_MOTION_CM = 1e-3  # two rules at one point agree when their deltas agree this well (0.01 mm)


# ---------------------------------------------------------------------------
# text and names
# ---------------------------------------------------------------------------


def to_ascii(text: str) -> tuple[str, bool]:
    """Return ``(ascii_text, changed)``: 7-bit ASCII for a DXF TEXT value.

    Accents are stripped (``"Ärmel"`` → ``"Armel"``), other non-ASCII
    characters become ``?``, and line breaks become spaces (a DXF value is
    one line).

    Examples
    --------
    >>> to_ascii("Ärmel vorn")
    ('Armel vorn', True)
    >>> to_ascii("BACK")
    ('BACK', False)
    """
    text = str(text)
    flat = text.replace("\r\n", " ").replace("\n", " ").replace("\r", " ")
    if flat.isascii() and flat == text:
        return text, False
    decomposed = unicodedata.normalize("NFKD", flat)
    out = "".join(ch if ch.isascii() else ("" if unicodedata.combining(ch) else "?") for ch in decomposed)
    return out, out != text


def sanitize_block_name(name: str) -> str:
    """Return an R12-safe block name: ASCII letters, digits, ``_ - $`` only.

    Examples
    --------
    >>> sanitize_block_name("ORILEG WB_36")
    'ORILEG_WB_36'
    """
    ascii_name, _ = to_ascii(name)
    safe = re.sub(r"[^A-Za-z0-9_\-$]", "_", ascii_name)
    return safe or "PIECE"


# ---------------------------------------------------------------------------
# low-level tag writer
# ---------------------------------------------------------------------------


class _Tags:
    """Collects DXF group-code/value pairs and renders them as R12 text."""

    __slots__ = ("claims", "decimals", "lines", "rules_seen")

    def __init__(self, decimals: int = 4) -> None:
        self.lines: list[str] = []
        self.decimals = decimals
        self.claims: dict[tuple[int, tuple[str, str]], list[list]] = {}  # (layer, position) -> [[text, on layer]]
        self.rules_seen: dict[tuple[str, str], dict[int, str]] = {}  # position -> layer -> rule text

    def rule(self, layer: int, at, value: str, height: float) -> str | None:
        """A ``# n`` rule text at ``at`` on ``layer``, once per position and layer within a block.

        Returns the different rule text already written at this position on
        this layer (a reader attaches rule texts by position, preferring the
        element's own layer, so only one can be there per layer).
        """
        seen = self.rules_seen.setdefault(self.key(at), {})
        if value in seen.values():
            return None
        if layer in seen:
            return seen[layer]
        seen[layer] = value
        self.text(layer, at, value, height)
        return None

    def key(self, at) -> tuple[str, str]:
        """A position as written (rule texts match by it)."""
        return (f"{float(at[0]):.{self.decimals}f}", f"{float(at[1]):.{self.decimals}f}")

    def claim(self, owner: int, at, value: str, height: float) -> bool:
        """Record that an element of layer ``owner`` has rule ``value`` at ``at``.

        The first element of a layer at a point returns False (write the text
        the usual way). A later one returns True after writing, on ``owner``
        and in element order, every claim of the point not yet written there
        and its own, unless all claims so far agree (the reader hands the k-th
        text of a layer at a point to the k-th element of that layer there).
        """
        claims = self.claims.setdefault((owner, self.key(at)), [])
        if not claims:
            claims.append([value, self.rules_seen.get(self.key(at), {}).get(owner) == value])
            return False
        claims.append([value, False])
        if all(c[0] == value for c in claims):
            return True
        for c in claims:
            if not c[1]:
                self.text(owner, at, c[0], height)
                c[1] = True
        return True

    def tag(self, code: int, value) -> None:
        self.lines.append(f"{code:>3}")
        self.lines.append(str(value))

    def num(self, code: int, value: float) -> None:
        text = f"{float(value):.{self.decimals}f}"
        if float(text) == 0.0:
            text = f"{0.0:.{self.decimals}f}"
        self.tag(code, text)

    def xy(self, point, code: int = 10) -> None:
        self.num(code, point[0])
        self.num(code + 10, point[1])

    def text(self, layer: int, at, value: str, height: float, angle_deg: float = 0.0) -> None:
        self.tag(0, "TEXT")
        self.tag(8, layer)
        self.xy(at)
        self.num(40, height)
        self.num(50, angle_deg)
        self.tag(1, value)
        self.tag(7, "STANDARD")

    def point(
        self,
        layer: int,
        at,
        *,
        z: float | None = None,
        thickness: float | None = None,
        angle_deg: float | None = None,
    ) -> None:
        self.tag(0, "POINT")
        self.tag(8, layer)
        self.xy(at)
        if z is not None:
            self.num(30, z)
        if thickness is not None:
            self.num(39, thickness)
        if angle_deg is not None:
            self.num(50, angle_deg)

    def attdef_link(self, layer: int, anchor, at, notch_layer: int, height: float) -> None:
        """AccuMark's ``Link:<layer>`` ATTDEF locating a notch in a nest size."""
        self.tag(0, "ATTDEF")
        self.tag(8, layer)
        self.xy(anchor)
        self.xy(at, 11)
        self.num(40, height)
        self.tag(1, f"Link:{notch_layer}")
        self.tag(2, "Dependency")
        self.tag(3, "")
        self.tag(70, 2)
        self.tag(72, 3)

    def line(self, layer: int, start, end) -> None:
        self.tag(0, "LINE")
        self.tag(8, layer)
        self.xy(start)
        self.xy(end, 11)

    def polyline(self, layer: int, points: np.ndarray, closed: bool) -> None:
        self.tag(0, "POLYLINE")
        self.tag(8, layer)
        self.tag(66, 1)
        self.tag(70, 1 if closed else 0)
        for p in points:
            self.tag(0, "VERTEX")
            self.tag(8, layer)
            self.xy(p)
        self.tag(0, "SEQEND")
        self.tag(8, layer)

    def render(self) -> str:
        return "\r\n".join(self.lines) + "\r\n"


# ---------------------------------------------------------------------------
# one block
# ---------------------------------------------------------------------------


@dataclass(frozen=True, slots=True, kw_only=True)
class _Context:
    flavor: Flavor
    units: Units
    scale: float  # file units per cm
    height: float  # text height in file units
    report: Report
    table: Mapping[str, np.ndarray]  # rule id -> deltas (cm), for conflict checks
    nest: bool = False  # a graded nest carries every size: rule texts only label points
    graded: bool = False  # the file grades (rules or a nest): every block gets a grade reference line
    pairs: bool = False  # the source wrote quantities as right,left pairs (ASTM): an AAMA export keeps them so


def _ascii(ctx: _Context, value: str, where: str) -> str:
    out, changed = to_ascii(value)
    if changed:
        ctx.report.add(
            "non-ascii-replaced",
            f"text {value!r} written as {out!r} (DXF-AAMA/ASTM allow 7-bit ASCII only)",
            where=where,
            fixed=True,
        )
    return out


def _rule_text(rule: str) -> str:
    return f"# {rule}"


def _put_rule(
    tags: _Tags,
    ctx: _Context,
    layer: int,
    at,
    rule: str,
    where: str,
    *,
    check: bool = True,
    owner_layer: int | None = None,
) -> None:
    """Write ``# rule`` at ``at`` unless the same rule already sits there.

    Coincident points (a notch on a graded vertex, a grade reference line on
    the grain line) normally share their motion. When another element's
    different rule already sits there, this one is written on the element's
    own layer (``owner_layer``), which the reader prefers for that element;
    when even that layer is taken the first rule wins and the conflict is
    reported.
    """
    text = _ascii(ctx, _rule_text(rule), where)
    owner = owner_layer if owner_layer is not None else layer
    if check and tags.claim(owner, at, text, ctx.height):
        return  # a later element of this layer at this point: written in element order
    other = tags.rule(layer, at, text, ctx.height)
    if other is not None and owner != layer:
        # the point layer holds another element's rule: this one goes on its own layer
        other = tags.rule(owner, at, text, ctx.height)
    if check:
        tags.claims[(owner, tags.key(at))][0][1] = tags.rules_seen[tags.key(at)].get(owner) == text
    if other is None or not check or ctx.nest:
        return
    first = other[2:]
    a, b = ctx.table.get(first), ctx.table.get(rule)
    if a is None or b is None or a.shape != b.shape or not np.allclose(a, b, atol=_SAME_MOTION_CM):
        ctx.report.add(
            "rule-position-conflict",
            f"rule {rule} and rule {first} sit on the same point and grade differently; "
            f"the file keeps rule {first} there",
            where=where,
        )


def _vertex_points(
    tags: _Tags,
    ctx: _Context,
    owner_layer: int,
    pts: np.ndarray,
    kinds: Sequence[VertexKind],
    rules: Sequence[str | None],
    where: str,
) -> None:
    """Turn/curve POINTs on 2/3 and ``# n`` texts of one polyline's vertices."""
    for p, kind, rule in zip(pts, kinds, rules, strict=True):
        point_layer = {VertexKind.TURN: 2, VertexKind.CURVE: 3}.get(VertexKind(kind))
        if ctx.flavor is Flavor.ASTM:
            # ASTM: the rule text sits on the geometry's own layer, before the point
            if rule is not None:
                _put_rule(tags, ctx, owner_layer, p, rule, where)
            if point_layer is not None:
                tags.point(point_layer, p)
        else:
            # AAMA: the rule text follows the point on layer 2/3; a graded vertex
            # that is neither turn nor curve point keeps it on its own layer
            if point_layer is not None:
                tags.point(point_layer, p)
            if rule is not None:
                _put_rule(
                    tags,
                    ctx,
                    point_layer if point_layer is not None else owner_layer,
                    p,
                    rule,
                    where,
                    owner_layer=owner_layer,
                )


def _line_rules(tags: _Tags, ctx: _Context, layer: int, line: Line, pts: np.ndarray, where: str) -> None:
    for p, rule in zip(pts, line.rules, strict=True):
        if rule is not None:
            _put_rule(tags, ctx, layer, p, rule, where)


def _label_anchor(piece_pts: np.ndarray) -> np.ndarray:
    """A point inside the piece's bounding box to hang the piece text on."""
    lo, hi = piece_pts.min(axis=0), piece_pts.max(axis=0)
    return np.array([lo[0] + 0.25 * (hi[0] - lo[0]), lo[1] + 0.5 * (hi[1] - lo[1])])


def _piece_text_lines(piece: Piece, size: str, ctx: _Context, full: bool, where: str) -> list[str]:
    name = _ascii(ctx, piece.name, where)
    lines = [f"Piece Name: {name}", f"Size: {_ascii(ctx, size, where)}"]
    if not full:
        return lines
    q = piece.quantity
    if ctx.flavor is Flavor.ASTM or ctx.pairs:
        lines.append(f"Quantity: {q.right},{q.left}")
    else:
        lines.append(f"Quantity: {q.total}")
        if q.right != (q.total + 1) // 2:
            ctx.report.add(
                "quantity-total-only",
                f"quantity right={q.right}, left={q.left} written as the AAMA total {q.total}; "
                "export as ASTM to keep the right/left split",
                where=where,
            )
    for key, value in (
        ("Category", piece.category),
        ("Annotation", piece.annotation),
        ("Fabric", piece.fabric),
    ):
        if value:
            lines.append(f"{key}: {_ascii(ctx, value, where)}")
    known = {"piece name", "size", "quantity", "category", "annotation", "fabric"}  # written above
    for key, value in piece.extra_text.items():
        if key.strip().lower() in known:
            continue
        lines.append(_ascii(ctx, f"{key}: {value}" if value else f"{key}:", where))
    return lines


def _write_polyline(
    tags: _Tags,
    ctx: _Context,
    layer: int,
    poly: Polyline,
    scale: float,
    full: bool,
    where: str,
) -> np.ndarray:
    pts = np.asarray(poly.points) * scale
    if len(pts) == 0:
        return pts
    tags.polyline(layer, pts, poly.closed)
    if poly.label and full:
        tags.text(layer, pts[0], _ascii(ctx, poly.label, where), ctx.height)
    return pts


def _block(
    tags: _Tags,
    ctx: _Context,
    piece: Piece,
    size: str,
    block_name: str,
    *,
    full: bool,
    validation: bool,
    notch_at: np.ndarray | None = None,
) -> None:
    """Write one BLOCK ... ENDBLK; ``full``: the sample-size block (points, rules).

    ``notch_at`` : (n_notches, 2) cm, where the ATTDEF links put the notches
    in this size (default: on their vertex).
    """
    s = ctx.scale
    where = f"{piece.name} ({size})"
    outline = np.asarray(piece.outline) * s
    tags.rules_seen.clear()
    tags.claims.clear()
    tags.tag(0, "BLOCK")
    tags.tag(8, 0)
    tags.tag(2, block_name)
    tags.tag(70, 64)
    tags.num(10, 0.0)
    tags.num(20, 0.0)

    # piece system text, layer 1
    anchor = _label_anchor(outline)
    step = 1.6 * ctx.height
    for i, text in enumerate(_piece_text_lines(piece, size, ctx, full, where)):
        tags.text(1, anchor - np.array([0.0, i * step]), text, ctx.height)

    _boundary(tags, ctx, piece, outline, full=full, validation=validation, notch_at=notch_at, where=where)
    _inside(tags, ctx, piece, full=full, validation=validation, where=where)
    tags.tag(0, "ENDBLK")
    tags.tag(8, 0)


def _boundary(
    tags: _Tags,
    ctx: _Context,
    piece: Piece,
    outline: np.ndarray,
    *,
    full: bool,
    validation: bool,
    notch_at: np.ndarray | None,
    where: str,
) -> None:
    """The cut line with its points, rule texts, notches, notch links and validation copy."""
    s = ctx.scale
    tags.polyline(1, outline, closed=True)
    if full:
        _vertex_points(tags, ctx, 1, outline, piece.kinds, piece.rules, where)
        for notch in piece.notches:
            layer = NOTCH_LAYER_BY_TYPE[NotchType(notch.type)]
            angle = math.degrees(notch.angle) % 360.0
            tags.point(
                layer,
                outline[notch.vertex],
                z=abs(notch.depth_cm) * s,
                thickness=abs(notch.width_cm) * s,
                angle_deg=angle,
            )
            if notch.rule is not None:
                # a notch rides on its boundary vertex: that vertex's rule governs
                _put_rule(
                    tags,
                    ctx,
                    layer,
                    outline[notch.vertex],
                    notch.rule,
                    where,
                    check=False,
                )
    if ctx.flavor is Flavor.ASTM:
        # AccuMark's notch dependency: where each notch sits in every size,
        # anchored on the boundary vertex before it
        at = np.asarray(notch_at) * s if notch_at is not None else outline[[n.vertex for n in piece.notches]]
        for notch, point in zip(piece.notches, at.reshape(-1, 2), strict=True):
            layer = NOTCH_LAYER_BY_TYPE[NotchType(notch.type)]
            tags.attdef_link(1, outline[notch.vertex - 1], point, layer, ctx.height)
    if validation:
        tags.polyline(_VALIDATION_LAYER[1], outline, closed=True)


def _inside(tags: _Tags, ctx: _Context, piece: Piece, *, full: bool, validation: bool, where: str) -> None:
    """Lines, internal lines, cutouts, sew lines, drill holes and annotations of one block."""
    s = ctx.scale
    # grain (7), grade reference (5), mirror (6); AccuMark marks grain-line ends as turn points
    for layer, line in (
        (7, piece.grain_line),
        (5, reference_line(piece, ctx.graded)),
        (6, piece.mirror_line),
    ):
        if line is None:
            continue
        pts = np.asarray(line.points) * s
        tags.line(layer, pts[0], pts[1])
        if full and layer == 7:
            for end in pts:
                tags.point(2, end)
        if full:
            _line_rules(tags, ctx, layer, line, pts, where)

    # internal lines (8), cutouts (11), sew lines (14)
    for layer, polys in (
        (8, piece.internal_lines),
        (11, piece.cutouts),
        (14, piece.sew_lines),
    ):
        for poly in polys:
            pts = _write_polyline(tags, ctx, layer, poly, s, full, where)
            if len(pts) == 0:
                continue
            if full:
                _vertex_points(tags, ctx, layer, pts, poly.kinds, poly.rules, where)
            if validation:
                tags.polyline(_VALIDATION_LAYER[layer], pts, poly.closed)

    # drill holes (13): POINT with Z = diameter, label and rule texts on 13
    for hole in piece.drill_holes:
        at = np.asarray(hole.position) * s
        tags.point(13, at, z=hole.diameter_cm * s)
        if full and hole.label:
            tags.text(13, at, _ascii(ctx, hole.label, where), ctx.height)
        if full and hole.rule is not None:
            _put_rule(tags, ctx, 13, at, hole.rule, where)

    # annotations (15, or the layer they came from)
    if full:
        for note in piece.annotations:
            tags.text(
                note.layer,
                np.asarray(note.position) * s,
                _ascii(ctx, note.text, where),
                note.height_cm * s,
                math.degrees(note.angle) % 360.0,
            )


# ---------------------------------------------------------------------------
# whole file
# ---------------------------------------------------------------------------


def _style_text_lines(pattern: Pattern, ctx: _Context, validation: bool, now: _dt.datetime) -> list[str]:
    where = f"style {pattern.style}"
    style = _ascii(ctx, pattern.style, where)
    if len(style) > _MAX_NAME:
        ctx.report.add(
            "name-too-long",
            f"style name {style!r} is longer than {_MAX_NAME} characters; Gerber AccuMark truncates it",
            where=where,
        )
    lines = [
        f"Style Name: {style}",
        f"Creation Date: {now:%d-%m-%Y}",
        f"Creation Time: {now:%H:%M}",
    ]
    if ctx.flavor is Flavor.ASTM:
        lines.append(f"Author: {_VENDOR} ; {_PRODUCT} ; {__version__}")
    else:
        lines += [
            f"Author: {_VENDOR}",
            f"PRODUCT: {_PRODUCT}",
            f"VERSION: {__version__}",
        ]
    lines += [
        f"Sample Size: {_ascii(ctx, pattern.sample_size, where)}",
        f"Grade Rule Table: {_ascii(ctx, pattern.rules.name, where)}".rstrip(),
        f"Units: {ctx.units}",
    ]
    tolerance = _tolerance(pattern, ctx.units)
    if ctx.flavor is Flavor.AAMA:
        lines.append(f"TOLERANCE: {tolerance}")
    elif validation:
        lines.append(f"Curve Tolerance: {tolerance}")
    if ctx.flavor is Flavor.ASTM:
        lines.append(_ASTM_VERSION)
    return lines


def _tolerance(pattern: Pattern, units: Units) -> str:
    """The source's ``TOLERANCE``/``Curve Tolerance`` (converted when the units change), else ours."""
    extra = pattern.provenance.extra_text
    value = extra.get("CURVE TOLERANCE") or extra.get("TOLERANCE") or ""
    try:
        number = float(value)
    except ValueError:
        return _CURVE_TOLERANCE[units]
    if not math.isfinite(number) or number < 0:
        return _CURVE_TOLERANCE[units]
    if units is pattern.units:
        return value.strip()
    converted = float(from_cm(to_cm(number, pattern.units.value), units.value))
    return f"{converted:.4f}".rstrip("0").rstrip(".").removeprefix("0") or "0"


def _unique_names(names: Iterable[str]) -> list[str]:
    seen: dict[str, int] = {}
    out = []
    for name in names:
        base = sanitize_block_name(name)
        key = base.upper()
        if key in seen:
            seen[key] += 1
            base = f"{base}_{seen[key]}"
            key = base.upper()
        seen.setdefault(key, 0)
        out.append(base)
    return out


def _resolve_sizes(pattern: Pattern, sizes, report: Report) -> list[str] | None:
    """``None`` for a sample-size file, else the nest's sizes in size-list order."""
    if sizes is None or (isinstance(sizes, str) and sizes.lower() == "sample"):
        return None
    size_list = list(pattern.sizes) or [pattern.sample_size]
    if isinstance(sizes, str):
        if sizes.lower() == "all":
            return size_list
        sizes = [s.strip() for s in sizes.split(",") if s.strip()]
    wanted = [str(s) for s in sizes]
    unknown = [s for s in wanted if s not in size_list]
    if unknown:
        raise InputError(
            f"{pattern.style}: sizes {unknown} are not in the size list {size_list}; choose from the pattern's sizes"
        )
    if pattern.sample_size not in wanted:
        report.add(
            "sample-size-added",
            f"sample size {pattern.sample_size!r} added to the nest (it carries the "
            "turn/curve points, notches and rule texts)",
            where=pattern.style,
            fixed=True,
        )
        wanted.append(pattern.sample_size)
    return [s for s in size_list if s in set(wanted)]


def _graded_pieces(pattern: Pattern, size: str) -> tuple[Piece, ...]:
    if size == pattern.sample_size:
        return pattern.pieces
    from ...pattern.grading import grade

    return grade(pattern, size).pieces


def _check_writable(pattern: Pattern, scale: float) -> None:
    """Refuse a pattern a CAD system could not read back: no pieces, or numbers that are not finite.

    Raises
    ------
    InputError
        No pieces; a coordinate, size or rule delta that is NaN, infinite or
        beyond ``MAX_ABS_VALUE`` file units.
    """
    if not pattern.pieces:
        raise InputError(
            f"pattern {pattern.style!r} has no pieces; a DXF-AAMA/ASTM file needs at least one piece, nothing written"
        )
    limit = MAX_ABS_VALUE / scale
    for piece in pattern.pieces:
        for what, values in _numbers(piece):
            bad = ~np.isfinite(values) | (np.abs(np.where(np.isfinite(values), values, 0.0)) > limit)
            if np.any(bad):
                value = float(np.asarray(values, dtype=np.float64).ravel()[np.flatnonzero(bad.ravel())[0]])
                raise InputError(
                    f"pattern {pattern.style!r}: piece {piece.name[:60]!r} {what} holds {value!r} "
                    f"(a DXF needs finite numbers within {MAX_ABS_VALUE:g} file units); "
                    "fix the pattern, nothing written"
                )
    for rule, deltas in pattern.rules.deltas.items():
        d = np.asarray(deltas, dtype=np.float64)
        if not np.all(np.isfinite(d)) or np.any(np.abs(d) > limit):
            raise InputError(
                f"pattern {pattern.style!r}: grade rule {rule} holds a delta that is not a finite "
                "number of sane size; fix the rules, nothing written"
            )


def _numbers(piece: Piece) -> Iterable[tuple[str, np.ndarray]]:
    yield "outline", np.asarray(piece.outline, dtype=np.float64)
    for name in ("grain_line", "grade_reference", "mirror_line"):
        line = getattr(piece, name)
        if line is not None:
            yield name.replace("_", " "), np.asarray(line.points, dtype=np.float64)
    for name in ("internal_lines", "cutouts", "sew_lines"):
        for poly in getattr(piece, name):
            yield name.replace("_", " "), np.asarray(poly.points, dtype=np.float64)
    for hole in piece.drill_holes:
        yield "drill hole", np.array([*hole.position, hole.diameter_cm], dtype=np.float64)
    for note in piece.annotations:
        yield "annotation", np.array([*note.position, note.height_cm, note.angle], dtype=np.float64)
    for notch in piece.notches:
        yield "notch", np.array([notch.depth_cm, notch.width_cm, notch.angle], dtype=np.float64)


def _layout(entries: Sequence[tuple[Piece, str, bool]], scale: float) -> dict[str, np.ndarray]:
    """INSERT position of each piece (file units): pieces side by side, the sizes of one piece stacked.

    Rows of pieces in file order, left to right with a 5 cm gap, a new row
    when the row would pass about twice the square root of the pieces' total
    box area; each piece's box covers all its sizes, so no two pieces overlap.
    """
    boxes: dict[str, tuple[np.ndarray, np.ndarray]] = {}
    for piece, _, _ in entries:
        pts = np.asarray(piece.outline) * scale
        lo, hi = pts.min(axis=0), pts.max(axis=0)
        if piece.name in boxes:
            lo, hi = np.minimum(lo, boxes[piece.name][0]), np.maximum(hi, boxes[piece.name][1])
        boxes[piece.name] = (lo, hi)
    gap = 5.0 * scale
    sizes = {name: hi - lo for name, (lo, hi) in boxes.items()}
    row_width = max(max(w for w, _ in sizes.values()), 2.0 * math.sqrt(sum(w * h for w, h in sizes.values())))
    offsets: dict[str, np.ndarray] = {}
    x = y = row_height = 0.0
    for name, (lo, _) in boxes.items():
        w, h = sizes[name]
        if x > 0 and x + w > row_width:
            x, y, row_height = 0.0, y + row_height + gap, 0.0
        offsets[name] = np.array([x, y]) - lo
        x += w + gap
        row_height = max(row_height, h)
    return offsets


def _file_entries(pattern: Pattern, nest_sizes: Sequence[str] | None) -> list[tuple[Piece, str, bool]]:
    """(piece, size, full) in file order: the sample pieces, or per nest size every graded piece."""
    if nest_sizes is None:
        return [(p, p.size or pattern.sample_size, True) for p in pattern.pieces]
    entries: list[tuple[Piece, str, bool]] = []
    for size in nest_sizes:
        entries += [(p, size, size == pattern.sample_size) for p in _graded_pieces(pattern, size)]
    return entries


def _blocks_section(
    tags: _Tags,
    ctx: _Context,
    pattern: Pattern,
    entries: list[tuple[Piece, str, bool]],
    block_names: list[str],
    validation: bool,
) -> None:
    """The BLOCKS section: one block per entry, notches placed on the graded pieces."""
    tags.tag(0, "SECTION")
    tags.tag(2, "BLOCKS")
    samples = {p.name: p for p in pattern.pieces}
    for (piece, size, full), block_name in zip(entries, block_names, strict=True):
        at = notch_positions(samples[piece.name], piece, pattern.rules, size) if piece.notches else None
        _block(tags, ctx, piece, size, block_name, full=full, validation=validation, notch_at=at)
    tags.tag(0, "ENDSEC")


def _entities_section(
    tags: _Tags, ctx: _Context, pattern: Pattern, codes: dict[str, str], validation: bool, now: _dt.datetime
) -> None:
    """Open the ENTITIES section with the style text and the full names of coded sizes."""
    tags.tag(0, "SECTION")
    tags.tag(2, "ENTITIES")
    for i, text in enumerate(_style_text_lines(pattern, ctx, validation, now)):
        tags.text(1, (0.0, -(i + 2) * 1.6 * ctx.height), text, ctx.height)
    for i, (name, code) in enumerate(codes.items()):  # the full names of coded sizes
        text = _ascii(ctx, f"Size {code}: {name}", f"size {name}")
        tags.text(15, (40.0 * ctx.height, -(i + 2) * 1.6 * ctx.height), text, ctx.height)


def format_dxf(
    pattern: Pattern,
    *,
    flavor: Flavor | str = Flavor.AAMA,
    sizes: str | Sequence[str] = "sample",
    units: Units | str | None = None,
    report: Report | None = None,
    now: _dt.datetime | None = None,
) -> str:
    """Return the DXF text of ``pattern`` (CRLF line ends, ASCII only).

    Parameters are those of :func:`write_dxf`; ``now`` fixes the creation
    date/time written in the style text (default :func:`~patternbridge.io.rul.creation_time`:
    ``SOURCE_DATE_EPOCH``, else the source's own date, else a fixed date).

    Raises
    ------
    InputError
        No pieces, numbers that are not finite, sizes outside the size list.
    """
    flavor = Flavor(str(flavor).lower())
    units = Units(str(units).upper()) if units is not None else pattern.units
    report = report if report is not None else Report()
    now = now or creation_time(pattern.provenance.created)
    codes = _coded_sizes(pattern, report)
    pattern = rename_sizes(pattern, codes)
    scale = float(from_cm(1.0, str(units)))
    _check_writable(pattern, scale)
    nest_sizes = _resolve_sizes(pattern, sizes, report)
    ctx = _Context(
        flavor=flavor,
        units=units,
        scale=scale,
        height=_TEXT_HEIGHT[units],
        report=report,
        table=pattern.rules.deltas,
        nest=nest_sizes is not None,
        graded=len(pattern.rules.sizes) > 1,
        pairs=pattern.provenance.flavor is Flavor.ASTM,
    )
    validation = flavor is Flavor.ASTM
    _report_long_names(pattern, report)
    entries = _file_entries(pattern, nest_sizes)
    block_names = _unique_names(f"{p.name}_{size}" for p, size, _ in entries)
    offsets = _layout(entries, scale)

    tags = _Tags()
    for code, value in ((0, "SECTION"), (2, "HEADER"), (9, "$ACADVER"), (1, "AC1009"), (0, "ENDSEC")):
        tags.tag(code, value)
    _blocks_section(tags, ctx, pattern, entries, block_names, validation)
    _entities_section(tags, ctx, pattern, codes, validation, now)
    for (piece, _, _), block_name in zip(entries, block_names, strict=True):
        tags.tag(0, "INSERT")
        tags.tag(8, 1)
        tags.tag(2, block_name)
        tags.xy(offsets[piece.name])
    tags.tag(0, "ENDSEC")
    tags.tag(0, "EOF")
    text = tags.render()
    if not text.isascii():  # pragma: no cover - every value went through to_ascii
        raise AssertionError("DXF text is not ASCII")
    return text


def _coded_sizes(pattern: Pattern, report: Report) -> dict[str, str]:
    codes = size_codes(tuple(pattern.sizes) or (pattern.sample_size,))
    for name, code in codes.items():
        report.add(
            "size-coded",
            f"size {name!r} written as {code} (CAD takes short size codes of one kind); "
            f"its name is kept in the note 'Size {code}: {name}' on layer 15",
            where=pattern.style,
        )
    return codes


def _report_long_names(pattern: Pattern, report: Report) -> None:
    for piece in pattern.pieces:
        name, _ = to_ascii(piece.name)
        if len(name) > _MAX_NAME:
            report.add(
                "name-too-long",
                f"piece name {name!r} is longer than {_MAX_NAME} characters; Gerber AccuMark truncates it",
                where=piece.name,
            )


def write_dxf(
    pattern: Pattern,
    path: str | os.PathLike,
    *,
    flavor: Flavor | str = Flavor.AAMA,
    sizes: str | Sequence[str] = "sample",
    rul_path: str | os.PathLike | None = None,
    units: Units | str | None = None,
    report: Report | None = None,
) -> Path:
    """Write ``pattern`` as a DXF-AAMA or DXF-ASTM file, atomically.

    Parameters
    ----------
    pattern : Pattern
        Geometry in cm; converted to mm (METRIC) or inches (ENGLISH) with 4
        decimals.
    path : path of the ``.dxf`` to write
    flavor : ``"aama"`` or ``"astm"``
        AAMA: ``Author``/``PRODUCT``/``VERSION`` style text, ``Quantity: N``
        totals, ``# n`` rule texts on layers 2/3. ASTM: the D 6673-04 version
        string, ``Author: vendor ; app ; release``, ``Quantity: R,L``, rule
        texts on the geometry's layer and validation curves on 84 to 87.
    sizes : ``"sample"``, ``"all"``, a comma-separated string or a list of sizes
        ``"sample"`` writes the sample size only (grade with ``rul_path``);
        anything else writes a graded nest of those sizes (the sample size is
        always included).
    rul_path : path of a ``.RUL`` to write beside the DXF (grade-rule table in
        the same units); the DXF and the RUL are both written or neither.
    units : ``"METRIC"`` or ``"ENGLISH"`` to override ``pattern.units``.
    report : findings (non-ASCII text replaced, long names, quantity split
        lost in AAMA) are appended here; without one they are logged as
        warnings.

    Returns
    -------
    Path of the DXF written.

    Raises
    ------
    InputError
        When a requested size is not in the pattern's size list, or a RUL is
        requested for a pattern without grade rules.
    """
    own_report = Report()
    units_ = Units(str(units).upper()) if units is not None else pattern.units
    text = format_dxf(pattern, flavor=flavor, sizes=sizes, units=units_, report=own_report)
    rul_text = None if rul_path is None else _rul_text(pattern, rul_path, units_, flavor)
    if report is not None:
        report.extend(own_report)
    else:
        for finding in own_report:
            log.warning("%s", finding)
    path = Path(path)
    with atomic_path(path) as tmp:
        tmp.write_bytes(text.encode("ascii"))
        if rul_text is not None:
            with atomic_path(rul_path) as rul_tmp:
                rul_tmp.write_bytes(_crlf(rul_text).encode("ascii", errors="replace"))
    return path


def _rul_text(pattern: Pattern, rul_path: str | os.PathLike, units: Units, flavor: Flavor | str) -> str:
    """The RUL text of the pattern's grade-rule table, its sizes written as codes.

    Raises
    ------
    InputError
        When the pattern has no rule table or the table cannot be written.
    """
    if not pattern.rules.deltas and not pattern.rules.sizes:
        raise InputError(f"{rul_path}: pattern {pattern.style!r} has no grade-rule table to write")
    from ..rul import format_rul

    try:
        coded = rename_sizes(pattern, size_codes(tuple(pattern.sizes) or (pattern.sample_size,)))
        return format_rul(coded.rules, units=units, flavor=flavor, created=creation_time(pattern.provenance.created))
    except ValueError as exc:
        raise InputError(
            f"{rul_path}: cannot write the grade-rule table ({exc}); fix the pattern's rules or export a graded nest"
        ) from None


def _crlf(text: str) -> str:
    r"""``text`` with CRLF line ends (unchanged when it has some already).

    Examples
    --------
    >>> _crlf("a\nb\n"), _crlf("a\r\nb")
    ('a\r\nb\r\n', 'a\r\nb')
    """
    return text if "\r\n" in text else text.replace("\n", "\r\n")
