"""Read DXF-AAMA and DXF-ASTM (D6673) pattern files into the canonical model.

The reader parses the DXF tag stream itself (R12 text files as every CAD
writes them; entity order inside blocks is kept), then

1. turns each piece BLOCK into a piece: the layer-1 boundary (one closed
   POLYLINE, or AccuMark's open segments chained end to end, or LINEs),
   duplicate vertices removed, oriented counter-clockwise; turn/curve points
   (layers 2/3) and ``# n`` rule texts matched to vertices by coordinates on
   any layer; notches (POINTs on 4/80-83, legacy short LINEs on 4) snapped to
   the boundary vertex they sit on, with a vertex inserted when they fall
   inside an edge, their direction recomputed from the boundary; grain (7),
   grade reference (5), mirror (6), internal lines (8), cutouts (11), drill
   holes (13), sew lines (14) and annotations (15);
2. groups blocks into pieces by ``Piece Name`` and sizes by ``Size``: the
   sample-size block becomes the piece, the other sizes form the graded nest;
3. takes the grade-rule table from the ``.RUL`` (given, or found beside the
   DXF with the same stem in any case), or derives it from the graded nest.

The work is layered the way ezdxf layers it: :mod:`.tags` checks the tag
stream (finite, sane numbers; value lengths; closed sections), :mod:`.entities`
says what each entity of a block means, :mod:`.build` assembles pieces and
:mod:`.unfold` mirrors half pieces; this module groups blocks into pieces and
sizes and attaches the grade rules.

Coordinates are converted to cm at the end of parsing (METRIC files are mm,
ENGLISH files inches). Everything recoverable becomes a
:class:`~patternbridge.report.Finding`; unusable input raises
:class:`~patternbridge.errors.DXFFormatError`, ``RULFormatError`` or
``UnitsError`` with one line naming the file and the problem.
"""

from __future__ import annotations

import dataclasses
import logging
import os
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...errors import DXFFormatError, RULFormatError, UnitsError
from ...pattern.geometry import area
from ...pattern.grading import graded_outlines, rules_from_nest
from ...pattern.model import Flavor, GradeRuleTable, Pattern, Piece, Provenance, Units
from ...report import Report
from ...units import unit_factor
from ..rul import declared_units, read_rul
from .build import SIZE_KEYS, PieceBuilder
from .entities import RawBlock, raw_block
from .layers import Layer
from .links import link_rules
from .reference import drop_implied_references
from .sizes import SIZE_NOTE, rename_sizes
from .tags import Block, Entity, parse_tags
from .text import ASTM_MARKER, parse_author, parse_quantity, parse_units, split_key
from .unfold import unfold_pattern

__all__ = ["INFO_FINDINGS", "read_dxf"]

log = logging.getLogger(__name__)

INFO_FINDINGS = frozenset(
    {
        "validation-curves-dropped",
        "duplicate-vertices-removed",
        "rules-derived-from-nest",
        "rul-found-beside",
        "nest-curve-deviation",
        "notch-vertex-inserted",
        "notch-on-sew-line",
        "attdef-read",
        "notch-links-kept",
        "nest-kept-exact",
    }
)
"""Finding codes that only inform (what was dropped or repaired as expected); ``strict`` ignores them."""
GARMENT_SIDE_CM = (10.0, 300.0)
"""Longest side of the largest piece of a plausible garment (a baby's bib to a floor-length cape)."""
GARMENT_AREA_M2 = 4.0
"""Largest plausible area of one garment piece."""
NEST_EXACT_MM = 0.5
"""Rules derived at the file's rule points that miss a nest's curves by more than this keep the nest exact."""


def _find_rul(path: Path) -> Path | None:
    """The .RUL beside ``path``: same stem (exact case first, then any case), suffix in any case."""
    try:
        cands = sorted(c for c in path.parent.iterdir() if c.suffix.lower() == ".rul" and c.is_file())
    except OSError:
        return None
    exact = [c for c in cands if c.stem == path.stem]
    loose = [c for c in cands if c.stem.lower() == path.stem.lower()]
    return (exact or loose or [None])[0]


def _units_override(units) -> Units | None:
    if units is None:
        return None
    u = parse_units(str(units.value if isinstance(units, Units) else units))
    if u is None:
        raise UnitsError(f"units override {units!r} is unknown; use METRIC or ENGLISH")
    return u


def read_dxf(
    path: str | os.PathLike,
    *,
    rul: str | os.PathLike | None = None,
    units: str | Units | None = None,
    unfold: bool = False,
    strict: bool = False,
    exact_nest: bool = False,
) -> tuple[Pattern, Report]:
    """Read a DXF-AAMA / DXF-ASTM pattern file.

    Parameters
    ----------
    path : the ``.dxf`` file
    rul : the ``.RUL`` grade-rule table; by default a file beside ``path``
        with the same stem and a ``.rul`` suffix in any case is used
    units : ``"METRIC"`` (mm) or ``"ENGLISH"`` (inch) to override the file's
        ``Units:`` text
    unfold : mirror half pieces about their mirror line (layer 6) into the
        whole piece
    strict : raise on any finding that is more than informational
    exact_nest : for a graded nest, make every boundary vertex a rule point so
        grading reproduces each size's own curves exactly (by default only the
        file's ``# n`` points are rule points and the others follow by arc
        length, as a CAD system grading from the .RUL would, unless that misses
        the nest's curves by more than ``NEST_EXACT_MM``: then the nest is kept
        exact and a ``nest-kept-exact`` note says so)

    Returns
    -------
    (Pattern, Report)
        Pieces in the sample size (cm, CCW outlines), the grade-rule table
        from the ``.RUL`` or derived from the graded nest, and the findings.

    Raises
    ------
    DXFFormatError
        Truncated or corrupted file, no piece, a boundary that does not close.
    RULFormatError
        The ``.RUL`` is malformed or disagrees with the DXF (sample size, size
        count).
    UnitsError
        ``Units:`` names unknown units (and no override is given).
    """
    path = Path(path)
    report = Report()
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise DXFFormatError(f"{path}: cannot read the file ({exc.strerror})") from None
    blocks, entities = parse_tags(path, data, report)
    return _build(path, blocks, entities, report, rul=rul, units=units, unfold=unfold, strict=strict,
                  exact_nest=exact_nest)


@dataclass(slots=True)
class _Style:
    """Style system text of the ENTITIES section and the blocks it inserts."""

    values: dict[str, str]
    order: list[tuple[str, str]]
    inserts: list[str]
    size_names: dict[str, str]  # size code -> full name (layer-15 "Size <code>: <name>" notes)


def _style(entities: list[Entity]) -> _Style:
    style = _Style(values={}, order=[], inserts=[], size_names={})
    for ent in entities:
        note = SIZE_NOTE.match(ent.tags.get(1, "")) if ent.type == "TEXT" and ent.layer == Layer.ANNOTATION else None
        if note is not None:
            style.size_names[note.group(1)] = note.group(2)
        elif ent.type == "TEXT" and ent.layer == Layer.BOUNDARY:
            kv = split_key(ent.tags.get(1, ""))
            if kv is not None:
                style.values.setdefault(kv[0], kv[1])
                style.order.append(kv)
        elif ent.type == "INSERT":
            style.inserts.append(ent.tags.get(2, ""))
    return style


def _piece_blocks(path: Path, blocks: list[Block], style: _Style, report: Report) -> list[Block]:
    piece_blocks = [b for b in blocks if b.name and not b.name.startswith(("*", "$"))]
    defined = {b.name for b in blocks}
    undefined = [name[:60] for name in style.inserts if name not in defined]
    if undefined:
        if not piece_blocks:
            raise DXFFormatError(f"{path}: every INSERT names an undefined block ({', '.join(undefined[:3])}); "
                                 "the file holds no pieces")
        report.add("insert-undefined-block", f"{len(undefined)} INSERT(s) name undefined blocks: "
                   f"{', '.join(undefined[:5])}", path.name)
    if not piece_blocks:
        raise DXFFormatError(f"{path}: no piece BLOCKs found (empty, truncated or not a DXF-AAMA/ASTM file); "
                             "export the pattern again as DXF-AAMA or DXF-ASTM")
    return piece_blocks


def _units(path: Path, style: _Style, units, report: Report) -> Units:
    override = _units_override(units)
    declared = style.values.get("UNITS")
    if override is not None:
        if declared is not None and parse_units(declared) not in (None, override):
            report.add("units-overridden", f"file says Units: {declared}, read as {override.value}", path.name)
        return override
    if declared is None:
        report.add("units-assumed", "no 'Units:' style text; METRIC (mm) assumed", path.name)
        return Units.METRIC
    unit = parse_units(declared)
    if unit is None:
        raise UnitsError(f"{path}: unknown units 'Units: {declared[:40]}' (expected METRIC or ENGLISH); "
                         "pass units='METRIC' or 'ENGLISH'")
    return unit


def _report_dropped(raws: list[RawBlock], report: Report, where: str) -> int:
    """Findings for what the model does not keep; returns the number of validation curves."""
    validation = sum(r.validation for r in raws)
    if validation:
        report.add("validation-curves-dropped", f"{validation} quality-validation curves (layers 84-87) "
                   "recognised and dropped", where, fixed=True)
    other = sorted(set().union(*(r.other_layers for r in raws)))
    if other:
        report.add("layers-ignored", f"content on layers we do not model ignored: {', '.join(other[:10])}", where)
    attdefs = sum(r.attdefs for r in raws)
    if attdefs:
        report.add("attdef-read", f"{attdefs} ATTDEF notch links read (notches follow their vertex unless a "
                   "link places them elsewhere in another size)", where)
    return validation


def _group(path: Path, raws: list[RawBlock], report: Report) -> dict[str, list[tuple[str, RawBlock]]]:
    """Blocks grouped by piece name, each with its size."""
    groups: dict[str, list[tuple[str, RawBlock]]] = {}
    for raw in raws:
        name = raw.text.get("PIECE NAME") or re.sub(r"[_-][^_-]*$", "", raw.name) or raw.name
        size = next((raw.text[k] for k in SIZE_KEYS if raw.text.get(k)), "")
        if not size:
            m = re.search(r"[_-]([^_-]+)$", raw.name)
            size = m.group(1) if m else ""
        if not raw.boundary:
            report.add("block-without-boundary", f"block {raw.name[:60]!r} has no layer-1 boundary; skipped",
                       path.name)
            continue
        groups.setdefault(name, []).append((size, raw))
    if not groups:
        raise DXFFormatError(f"{path}: no block has a layer-1 boundary; not a DXF-AAMA/ASTM pattern file")
    return groups


def _sample_size(path: Path, groups: dict, raws: list[RawBlock], style: _Style,
                 report: Report) -> tuple[list[str], str]:
    """The size list in file order and the sample size."""
    sizes: list[str] = []
    for items in groups.values():
        for size, _ in items:
            if size not in sizes:
                sizes.append(size)
    sample_size = style.values.get("SAMPLE SIZE", "")
    if not sample_size:
        if len(sizes) == 1:
            return sizes, sizes[0]
        richest = max(raws, key=lambda r: len(r.turn) + len(r.curve) + len(r.rule_texts))
        sample_size = next((s for items in groups.values() for s, r in items if r is richest), sizes[0])
        report.add("sample-size-assumed", f"no 'Sample Size:' style text; {sample_size} assumed", path.name)
    elif sample_size not in sizes:
        if len(sizes) != 1:
            raise DXFFormatError(f"{path}: Sample Size: {sample_size[:40]} has no block (sizes: "
                                 f"{' '.join(sizes)[:200]}); fix the style text")
        report.add("sample-size-mismatch", f"Sample Size: {sample_size} but the blocks are size {sizes[0]}; "
                   f"{sizes[0]} used", path.name)
        sample_size = sizes[0]
    return sizes, sample_size


def _pieces(path: Path, builder: PieceBuilder, groups: dict, sizes: list[str], sample_size: str,
            report: Report) -> tuple[list[Piece], dict[str, dict[str, Piece]], dict]:
    """The sample-size pieces, the other sizes of the nest (by size, then piece name) and the notch links."""
    where = path.name
    pieces: list[Piece] = []
    links: dict[str, dict[str, np.ndarray]] = {}
    nest: dict[str, dict[str, Piece]] = {s: {} for s in sizes if s != sample_size}
    for name, items in groups.items():
        by_size: dict[str, RawBlock] = {}
        for size, raw in items:
            if size in by_size:
                report.add("duplicate-block", f"piece {name!r} size {size} appears twice; the first is used", where)
                continue
            by_size[size] = raw
        if sample_size not in by_size:
            report.add("piece-without-sample", f"piece {name!r} has no block in the sample size {sample_size}; "
                       "skipped", where)
            continue
        piece, recipe = builder.sample(name, sample_size, by_size[sample_size])
        pieces.append(piece)
        links[name] = {size: np.array([a[1] for a in raw.attdef_texts if a[2].upper().startswith("LINK:")],
                                      dtype=np.float64).reshape(-1, 2) * builder.f for size, raw in by_size.items()}
        for size in nest:
            raw = by_size.get(size)
            graded = None if raw is None else builder.graded(name, size, raw, recipe)
            if raw is None:
                report.add("nest-size-missing", f"piece {name!r} has no block in size {size}", where)
            nest[size][name] = graded if graded is not None else piece
    if not pieces:
        raise DXFFormatError(f"{path}: no piece has a block in the sample size {sample_size}")
    if builder.missing_depth:
        report.add("notch-depth-missing", f"{builder.missing_depth} notches without a depth (group 30); "
                   "depth 0 kept", where)
    return pieces, nest, links


def _provenance(path: Path, style: _Style, raws: list[RawBlock], validation: int) -> Provenance:
    values = style.values
    author = values.get("AUTHOR", "")
    producer, product, version = parse_author(author)
    astm = ASTM_MARKER in values or validation > 0
    for r in raws:
        q = parse_quantity(r.text.get("QUANTITY", "")) if r.text.get("QUANTITY") else None
        astm = astm or bool(q and q[1])
    created = " ".join(x for x in (values.get("CREATION DATE", "").strip(),
                                   values.get("CREATION TIME", "").strip()) if x)
    known = {"STYLE NAME", "AUTHOR", "PRODUCT", "VERSION", "SAMPLE SIZE", "UNITS", "CREATION DATE", "CREATION TIME"}
    return Provenance(
        producer=producer,
        product=product or values.get("PRODUCT", ""),
        version=version or values.get("VERSION", ""),
        author=author,
        created=created,
        flavor=Flavor.ASTM if astm else Flavor.AAMA,
        source_file=path.name,
        extra_text={k: v for k, v in style.order if k not in known},
    )


def _build(path, blocks, entities, report, *, rul, units, unfold, strict, exact_nest) -> tuple[Pattern, Report]:
    style = _style(entities)
    piece_blocks = _piece_blocks(path, blocks, style, report)
    unit = _units(path, style, units, report)
    raws = [raw_block(b) for b in piece_blocks]
    validation = _report_dropped(raws, report, path.name)
    groups = _group(path, raws, report)
    sizes, sample_size = _sample_size(path, groups, raws, style, report)
    builder = PieceBuilder(path, report, unit_factor(unit.value))
    pieces, nest, links = _pieces(path, builder, groups, sizes, sample_size, report)
    is_nest = len(sizes) > 1
    pattern = Pattern(
        style=style.values.get("STYLE NAME", path.stem),
        pieces=tuple(pieces),
        units=unit,
        sample_size=sample_size,
        sizes=tuple(sizes),
        rules=GradeRuleTable(name=style.values.get("GRADE RULE TABLE", ""), sizes=tuple(sizes) if not is_nest
                             else (), sample_size=sample_size, deltas={}),
        provenance=_provenance(path, style, raws, validation),
    )
    _check_scale(path, pattern, report)
    pattern = _grade_rules(path, pattern, nest, report, rul=rul, exact_nest=exact_nest)
    if nest:
        pattern = link_rules(pattern, links, report)
    pattern = rename_sizes(pattern, {c: n for c, n in style.size_names.items() if c in pattern.sizes})
    pattern = drop_implied_references(pattern)
    if unfold:
        pattern = unfold_pattern(pattern, report)
    report.findings[:] = [
        dataclasses.replace(f, severity="info") if f.code in INFO_FINDINGS else f for f in report
    ]
    if strict:
        bad = report.warnings
        if bad:
            raise DXFFormatError(f"{path}: {bad[0].message} [{bad[0].code}] (strict mode, "
                                 f"{len(bad)} finding(s)); fix the file or read without strict")
    log.debug("read %s: %d pieces, %d sizes, %d findings", path, len(pattern.pieces), len(pattern.sizes),
              len(report))
    return pattern, report


def _check_scale(path: Path, pattern: Pattern, report: Report) -> None:
    """Warn when the pieces are too small or too large for a garment in the units read.

    The evidence is the largest piece (longest side of its bounding box and
    its area); the other ``Units:`` is suggested when it gives a garment size.
    """
    sides = [float(np.ptp(p.outline, axis=0).max()) for p in pattern.pieces]
    k = int(np.argmax(sides))
    side, big = sides[k], pattern.pieces[k]
    area_m2 = float(area(big.outline)) / 1e4
    small = side < GARMENT_SIDE_CM[0]
    if not (small or side > GARMENT_SIDE_CM[1] or area_m2 > GARMENT_AREA_M2):
        return
    other = Units.ENGLISH if pattern.units is Units.METRIC else Units.METRIC
    ratio = unit_factor(other.value) / unit_factor(pattern.units.value)
    fits = GARMENT_SIDE_CM[0] <= side * ratio <= GARMENT_SIDE_CM[1]
    advice = (f"if the file is in {other.value} units, read it with --units {other.value} "
              f"(largest piece {side * ratio:.1f} cm)" if fits else
              f"--units {other.value} would give {side * ratio:.1f} cm, no better; the file may be drawn to scale")
    report.add("units-implausible", f"read as {pattern.units.value}, the largest piece {big.name!r} is "
               f"{side:.1f} cm long with {area_m2:.3g} m^2 ({'too small' if small else 'too large'} for a "
               f"garment piece, expected {GARMENT_SIDE_CM[0]:g}-{GARMENT_SIDE_CM[1]:g} cm); {advice}", path.name)


def _grade_rules(path: Path, pattern: Pattern, nest: dict[str, dict[str, Piece]], report: Report, *,
                 rul, exact_nest: bool) -> Pattern:
    """Attach the rule table: from the .RUL when there is one, else derived from the nest."""
    where = path.name
    is_nest = bool(nest)
    rul_path = Path(rul) if rul is not None else _find_rul(path)
    if rul is not None and not rul_path.is_file():
        raise RULFormatError(f"{rul_path}: no such grade-rule file")
    if rul_path is not None:
        if rul is None:
            report.add("rul-found-beside", f"grade rules read from {rul_path.name}", where)
        return _rules_from_rul(path, rul_path, pattern, nest, report)
    if is_nest:
        return _rules_from_nest(path, pattern, nest, report, exact_nest=exact_nest)
    n_rule = sum(r is not None for p in pattern.pieces for r in p.rules)
    if n_rule:
        report.add("rul-missing", f"{n_rule} boundary points carry rule ids but no .RUL was found; only the "
                   f"sample size {pattern.sample_size} is available", where)
    return pattern


def _rules_from_nest(path: Path, pattern: Pattern, nest: dict[str, dict[str, Piece]], report: Report, *,
                     exact_nest: bool) -> Pattern:
    """Rules derived from the nest: at the file's rule points, or at every vertex when those miss its curves.

    Grading from the file's ``# n`` points alone moves the points between them
    by arc length, as a CAD system grading from a .RUL would; when that misses
    the nest's own curves by more than ``NEST_EXACT_MM`` the nest is kept
    exact (every boundary vertex a rule point), as ``exact_nest`` asks always.
    """
    where = path.name
    derived = rules_from_nest(pattern, nest, every_vertex=exact_nest)
    dev = _nest_deviation(derived, nest)
    if not exact_nest and dev > NEST_EXACT_MM / 10.0:
        exact = rules_from_nest(pattern, nest, every_vertex=True)
        report.add("rules-derived-from-nest", f"grade rules derived from the graded nest "
                   f"({len(exact.rules.deltas)} rules, {len(exact.sizes)} sizes)", where)
        report.add("nest-kept-exact", f"grading from the file's rule points alone misses the nest's own curves "
                   f"by up to {dev * 10:.3f} mm (over {NEST_EXACT_MM:g} mm); every boundary vertex is a rule point "
                   f"({len(exact.rules.deltas)} rules, exact to {_nest_deviation(exact, nest) * 10:.4f} mm)", where)
        return exact
    report.add("rules-derived-from-nest", f"grade rules derived from the graded nest "
               f"({len(derived.rules.deltas)} rules, {len(derived.sizes)} sizes)", where)
    if dev > 1e-3:  # cm: report what a pattern maker would notice (over 0.01 mm)
        report.add("nest-curve-deviation", f"points between rule points follow by arc length: up to "
                   f"{dev * 10:.3f} mm from the nest's own curves", where)
    return derived


def _check_rul_units(rul_path: Path, table: GradeRuleTable, dxf_units: Units, report: Report) -> None:
    """Warn when the .RUL and its DXF declare different units (each is read in its own)."""
    declared = declared_units(rul_path)
    if declared is None or declared is dxf_units:
        return
    largest = max((float(np.abs(d).max()) for d in table.deltas.values()), default=0.0)
    other = largest * unit_factor(dxf_units.value) / unit_factor(declared.value)
    report.add("rul-units-differ", f"{rul_path.name} says UNITS: {declared.value} but the DXF is "
               f"{dxf_units.value}; its deltas are read as {declared.value} (largest {largest:.3g} cm; "
               f"{other:.3g} cm if they were {dxf_units.value}); pass the .RUL exported with this DXF",
               rul_path.name)


def _rules_from_rul(path: Path, rul_path: Path, pattern: Pattern, nest: dict[str, dict[str, Piece]],
                    report: Report) -> Pattern:
    table, rul_report = read_rul(rul_path)
    report.extend(rul_report)
    _check_rul_units(rul_path, table, pattern.units, report)
    sizes = pattern.sizes
    if table.sample_size != pattern.sample_size:
        raise RULFormatError(f"{rul_path}: sample size {table.sample_size} differs from the DXF's "
                             f"{pattern.sample_size}; give the .RUL exported with this DXF")
    if nest and (len(table.sizes) != len(sizes) or set(table.sizes) != set(sizes)):
        raise RULFormatError(f"{rul_path}: {len(table.sizes)} sizes ({' '.join(table.sizes)}) but the DXF "
                             f"nest has {len(sizes)} ({' '.join(sizes)}); give the matching .RUL")
    used = {r for p in pattern.pieces for r in p.rules if r is not None}
    missing = sorted(used - set(table.deltas), key=lambda r: (len(r), r))
    if missing:
        report.add("rule-missing", f"{len(missing)} rule ids used in the DXF are not in the .RUL "
                   f"({', '.join(missing[:8])}); those points follow their neighbours", path.name)
    if not table.name:
        table = dataclasses.replace(table, name=pattern.rules.name)
    pattern = dataclasses.replace(pattern, sizes=table.sizes, rules=table)
    if nest:
        dev = _nest_deviation(pattern, nest, rule_points_only=True)
        if dev > 1e-3:
            report.add("rul-nest-mismatch", f"the .RUL grades the sample up to {dev * 10:.3f} mm away from "
                       "the nest's own sizes at rule points; the .RUL is used", path.name)
    return pattern


def _nest_deviation(pattern: Pattern, nest: dict[str, dict[str, Piece]], rule_points_only: bool = False) -> float:
    """Largest distance (cm) between the graded boundaries and the nest's own."""
    graded = graded_outlines(pattern)
    dev = 0.0
    for size, pieces in nest.items():
        for name, piece in pieces.items():
            g = graded.get(size, {}).get(name)
            if g is None or g.shape != piece.outline.shape:
                continue
            err = np.linalg.norm(g - piece.outline, axis=1)
            if rule_points_only:
                ruled = [r is not None and r in pattern.rules.deltas for r in pattern.piece(name).rules]
                err = err[np.array(ruled, dtype=bool)]
            if len(err):
                dev = max(dev, float(np.max(err)))
    return dev
