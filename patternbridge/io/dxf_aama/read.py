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
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ...errors import DXFFormatError, RULFormatError, UnitsError
from ...pattern.geometry import is_simple, orient_ccw
from ...pattern.grading import frame_angle, graded_outlines, inward_angles, rules_from_nest
from ...pattern.model import (
    Annotation,
    DrillHole,
    Flavor,
    GradeRuleTable,
    Line,
    Notch,
    Pattern,
    Piece,
    Polyline,
    Provenance,
    Quantity,
    Units,
    VertexKind,
)
from ...report import Report
from ...units import unit_factor
from ..rul import read_rul
from .layers import NOTCH_LAYERS, VALIDATION_LAYERS, Layer, layer_number
from .notches import locate_on_boundary, notch_type
from .text import ASTM_MARKER, decode, parse_author, parse_quantity, parse_rule_text, parse_units, split_key

__all__ = ["INFO_FINDINGS", "read_dxf"]

log = logging.getLogger(__name__)

_MATCH_TOL = 1e-3  # file units: a text or POINT "sits on" a vertex within this
_NOTCH_SNAP_MM = 0.5  # a notch this close to an edge is on it (no finding)
INFO_FINDINGS = frozenset(
    {
        "validation-curves-dropped",
        "duplicate-vertices-removed",
        "rules-derived-from-nest",
        "rul-found-beside",
        "nest-curve-deviation",
        "notch-vertex-inserted",
        "attdef-ignored",
    }
)
"""Finding codes that only inform (what was dropped or repaired as expected); ``strict`` ignores them."""
_SIZE_KEYS = ("SIZE", "SIZE NAME", "SAMPLE SIZE")
_PIECE_KEYS = {"PIECE NAME", "QUANTITY", "ANNOTATION", "CATEGORY", "FABRIC", "MATERIAL", *_SIZE_KEYS}
_KNOWN_LAYERS = {int(x) for x in Layer} | {0}


# --------------------------------------------------------------------------- tag stream


@dataclass(slots=True)
class _Entity:
    type: str
    layer: int | None
    layer_name: str
    tags: dict[int, str]
    line: int  # 1-based line number of the entity's "0" tag
    vertices: list = field(default_factory=list)  # POLYLINE: [(x, y), ...]

    def f(self, code: int, default: float | None = 0.0) -> float | None:
        v = self.tags.get(code)
        if v is None:
            return default
        try:
            return float(v)
        except ValueError:
            raise _BadNumber(code, v, self.line) from None

    @property
    def closed(self) -> bool:
        try:
            return bool(int(float(self.tags.get(70, "0"))) & 1)
        except ValueError:
            return False


class _BadNumber(Exception):
    def __init__(self, code, value, line):
        super().__init__(code, value, line)
        self.code, self.value, self.line = code, value, line


@dataclass(slots=True)
class _Block:
    name: str
    entities: list[_Entity]
    line: int


def _tag_stream(path: Path, data: bytes) -> tuple[list[int], list[str]]:
    if data.startswith(b"AutoCAD Binary DXF"):
        raise DXFFormatError(f"{path}: binary DXF is not supported; export DXF-AAMA/ASTM as text (R12)")
    if b"\x00" in data[:4096]:
        raise DXFFormatError(f"{path}: not a text DXF (binary content near the start); export it again as text")
    text = decode(data)
    lines = text.replace("\r\n", "\n").replace("\r", "\n").split("\n")
    while lines and not lines[-1].strip():
        lines.pop()
    if len(lines) % 2:
        # an odd number of lines: the file ends between a group code and its value
        raise DXFFormatError(
            f"{path}: truncated DXF (ends after group code {lines[-1].strip()!r} on line {len(lines)} "
            "without its value); export the file again"
        )
    raw_codes = lines[0::2]
    try:
        codes = [int(c) for c in raw_codes]
    except ValueError:
        for k, c in enumerate(raw_codes):
            try:
                int(c)
            except ValueError:
                raise DXFFormatError(
                    f"{path}: corrupted DXF (line {2 * k + 1}: group code {c.strip()[:30]!r} is not an "
                    "integer); export the file again"
                ) from None
        raise
    values = [v.strip() for v in lines[1::2]]
    return codes, values


def _parse(path: Path, data: bytes, report: Report) -> tuple[list[_Block], list[_Entity]]:
    codes, values = _tag_stream(path, data)
    n = len(codes)
    starts = [k for k in range(n) if codes[k] == 0]
    if not starts:
        raise DXFFormatError(f"{path}: no DXF entities found (empty or not a DXF file)")
    blocks: list[_Block] = []
    entities: list[_Entity] = []
    section: str | None = None
    sections_seen: list[str] = []
    block: _Block | None = None
    poly: _Entity | None = None
    saw_eof = False
    starts.append(n)
    for j in range(len(starts) - 1):
        s, e = starts[j], starts[j + 1]
        kind = values[s].upper()
        tags: dict[int, str] = {}
        for k in range(s + 1, e):
            tags.setdefault(codes[k], values[k])
        line = 2 * s + 1
        if kind == "SECTION":
            if section is not None:
                raise DXFFormatError(f"{path}: truncated or corrupted DXF (section {section} not closed before "
                                     f"the SECTION on line {line}); export the file again")
            section = tags.get(2, "").upper()
            sections_seen.append(section)
            continue
        if kind == "ENDSEC":
            if block is not None:
                raise DXFFormatError(f"{path}: corrupted DXF (BLOCK {block.name!r} not closed by ENDBLK); "
                                     "export the file again")
            section = None
            poly = None
            continue
        if kind == "EOF":
            saw_eof = True
            break
        if section not in ("BLOCKS", "ENTITIES"):
            continue
        if kind == "BLOCK":
            block = _Block(name=tags.get(2, ""), entities=[], line=line)
            poly = None
            continue
        if kind == "ENDBLK":
            if block is not None:
                blocks.append(block)
            block = None
            poly = None
            continue
        target = block.entities if block is not None else entities
        layer_name = tags.get(8, "")
        if kind == "VERTEX":
            if poly is not None:
                try:
                    poly.vertices.append((float(tags.get(10, "0")), float(tags.get(20, "0"))))
                except ValueError:
                    raise DXFFormatError(f"{path}: corrupted DXF (line {line}: VERTEX coordinate is not a "
                                         "number); export the file again") from None
            continue
        if kind == "SEQEND":
            poly = None
            continue
        ent = _Entity(type=kind, layer=layer_number(layer_name), layer_name=layer_name, tags=tags, line=line)
        if kind == "POLYLINE":
            poly = ent
        else:
            poly = None
        if kind == "LWPOLYLINE":
            xs = [values[k] for k in range(s + 1, e) if codes[k] == 10]
            ys = [values[k] for k in range(s + 1, e) if codes[k] == 20]
            try:
                ent.vertices = [(float(x), float(y)) for x, y in zip(xs, ys, strict=False)]
            except ValueError:
                raise DXFFormatError(f"{path}: corrupted DXF (line {line}: LWPOLYLINE coordinate is not a "
                                     "number); export the file again") from None
            ent.type = "POLYLINE"
        target.append(ent)
    if section is not None or block is not None:
        what = f"section {section}" if section else "a BLOCK"
        raise DXFFormatError(f"{path}: truncated DXF ({what} not closed, no EOF); export the file again")
    if not saw_eof:
        if "ENTITIES" not in sections_seen:
            raise DXFFormatError(f"{path}: truncated DXF (no ENTITIES section and no EOF); export the file again")
        report.add("no-eof", "no EOF marker at the end of the file (sections are complete)", str(path.name))
    if "BLOCKS" not in sections_seen and "ENTITIES" not in sections_seen:
        raise DXFFormatError(f"{path}: no BLOCKS or ENTITIES section (empty or not a DXF-AAMA/ASTM file)")
    return blocks, entities


# --------------------------------------------------------------------------- one block


@dataclass(slots=True)
class _RawBlock:
    """A block's content in file units, before units and nest handling."""

    name: str
    text: dict[str, str]
    text_order: list[tuple[str, str]]
    boundary: list[tuple[np.ndarray, bool]]  # segments (k, 2), closed flag
    turn: np.ndarray
    curve: np.ndarray
    rule_texts: list[tuple[float, float, str, int | None]]  # x, y, id, layer
    notches: list[tuple[int, np.ndarray, float, float, float | None, np.ndarray | None]]
    lines: dict[int, list[np.ndarray]]  # layer 5/6/7 -> (2, 2) lines
    internal: list[tuple[np.ndarray, bool]]
    cutouts: list[tuple[np.ndarray, bool]]
    sew: list[tuple[np.ndarray, bool]]
    drills: list[tuple[np.ndarray, float]]
    texts: list[tuple[int, str, np.ndarray, float, float]]  # layer, text, pos, height, angle_deg
    validation: int
    other_layers: set
    attdefs: int


def _raw_block(block: _Block) -> _RawBlock:
    text: dict[str, str] = {}
    order: list[tuple[str, str]] = []
    boundary: list = []
    turn, curve = [], []
    rule_texts: list = []
    notches: list = []
    lines: dict[int, list] = {5: [], 6: [], 7: []}
    internal, cutouts, sew, drills, texts = [], [], [], [], []
    validation = 0
    attdefs = 0
    other: set = set()
    for ent in block.entities:
        layer = ent.layer
        t = ent.type
        if t == "ATTDEF":
            attdefs += 1
            continue
        if layer in VALIDATION_LAYERS:
            if t in ("POLYLINE", "LINE"):
                validation += 1
            if t == "TEXT" and parse_rule_text(ent.tags.get(1, "")) is not None:
                rid = parse_rule_text(ent.tags.get(1, ""))
                rule_texts.append((ent.f(10), ent.f(20), rid[0], layer))
            continue
        if t == "TEXT" or t == "MTEXT":
            s = ent.tags.get(1, "")
            pos = np.array([ent.f(10), ent.f(20)])
            rid = parse_rule_text(s)
            if rid is not None:
                rule_texts.append((pos[0], pos[1], rid[0], layer))
                continue
            if layer == Layer.BOUNDARY:
                kv = split_key(s)
                if kv is not None:
                    text.setdefault(kv[0], kv[1])
                    order.append(kv)
                    continue
            texts.append((layer if layer is not None else 0, s, pos, ent.f(40), ent.f(50)))
            continue
        if t in ("POLYLINE", "LINE"):
            if t == "LINE":
                pts = np.array([[ent.f(10), ent.f(20)], [ent.f(11), ent.f(21)]])
                closed = False
            else:
                pts = np.array(ent.vertices, dtype=np.float64).reshape(-1, 2)
                closed = ent.closed
            if layer == Layer.BOUNDARY:
                if len(pts):
                    boundary.append((pts, closed))
            elif layer in (5, 6, 7):
                if len(pts) >= 2:
                    lines[layer].append(pts[[0, -1]])
            elif layer == Layer.INTERNAL:
                internal.append((pts, closed))
            elif layer == Layer.CUTOUT:
                cutouts.append((pts, True))
            elif layer == Layer.SEW:
                sew.append((pts, closed))
            elif layer == Layer.NOTCH and len(pts) >= 2:
                notches.append((4, pts[0], 0.0, 0.0, None, pts[-1]))
            elif layer in NOTCH_LAYERS and len(pts) >= 2:
                notches.append((layer, pts[0], 0.0, 0.0, None, pts[-1]))
            else:
                other.add(ent.layer_name)
            continue
        if t == "POINT":
            pos = np.array([ent.f(10), ent.f(20)])
            if layer == Layer.TURN_POINTS:
                turn.append(pos)
            elif layer == Layer.CURVE_POINTS:
                curve.append(pos)
            elif layer in NOTCH_LAYERS:
                notches.append((layer, pos, abs(ent.f(30)), abs(ent.f(39)), ent.f(50, None), None))
            elif layer == Layer.DRILL:
                drills.append((pos, abs(ent.f(30))))
            else:
                other.add(ent.layer_name)
            continue
        if t in ("SEQEND", "VERTEX"):
            continue
        other.add(f"{ent.layer_name} ({t})")
    return _RawBlock(
        name=block.name,
        text=text,
        text_order=order,
        boundary=boundary,
        turn=np.array(turn, dtype=np.float64).reshape(-1, 2),
        curve=np.array(curve, dtype=np.float64).reshape(-1, 2),
        rule_texts=rule_texts,
        notches=notches,
        lines=lines,
        internal=internal,
        cutouts=cutouts,
        sew=sew,
        drills=drills,
        texts=texts,
        validation=validation,
        other_layers=other,
        attdefs=attdefs,
    )


def _chain(segments: list[tuple[np.ndarray, bool]], tol: float) -> tuple[np.ndarray, bool, float, int]:
    """Chain segments end to end.

    Returns ``(points, closed, gap, n_unjoined)``: ``closed`` when the chain
    returns to its start (the repeated end point dropped) or a single polyline
    is flagged closed; ``gap`` the distance from end to start otherwise;
    ``n_unjoined`` how many segments could not be attached.
    """
    if not segments:
        return np.zeros((0, 2)), False, 0.0, 0
    if len(segments) == 1:
        pts, closed = segments[0]
        pts = np.asarray(pts, dtype=np.float64)
    else:
        pts = np.asarray(segments[0][0], dtype=np.float64)
        closed = False
        remaining = [np.asarray(s[0], dtype=np.float64) for s in segments[1:]]
        unjoined = 0
        while remaining:
            end = pts[-1]
            for j, seg in enumerate(remaining):  # noqa: B007 (j is popped after the loop)
                if np.hypot(*(seg[0] - end)) <= tol:
                    pts = np.vstack([pts, seg[1:]])
                    break
                if np.hypot(*(seg[-1] - end)) <= tol:
                    pts = np.vstack([pts, seg[::-1][1:]])
                    break
            else:
                unjoined = len(remaining)
                break
            remaining.pop(j)
        if unjoined:
            return pts, False, float(np.hypot(*(pts[-1] - pts[0]))), unjoined
    if len(pts) > 1 and np.hypot(*(pts[-1] - pts[0])) <= tol:
        return pts[:-1], True, 0.0, 0
    gap = float(np.hypot(*(pts[-1] - pts[0]))) if len(pts) else 0.0
    return pts, closed, gap, 0


def _dedupe_keep(pts: np.ndarray, tol: float, closed: bool = True) -> np.ndarray:
    """Indices of vertices kept after dropping repeats of the previous vertex."""
    if len(pts) == 0:
        return np.zeros(0, dtype=np.int64)
    d = np.linalg.norm(np.diff(pts, axis=0), axis=1)
    keep = np.concatenate([[True], d > tol])
    idx = np.flatnonzero(keep)
    if closed and len(idx) > 1 and np.hypot(*(pts[idx[-1]] - pts[idx[0]])) <= tol:
        idx = idx[:-1]
    return idx


def _match(points: np.ndarray, targets: np.ndarray, tol: float) -> np.ndarray:
    """For each point, the index of a target within ``tol`` or -1."""
    if len(points) == 0 or len(targets) == 0:
        return np.full(len(points), -1, dtype=np.int64)
    d = np.linalg.norm(points[:, None, :] - targets[None, :, :], axis=-1)
    j = np.argmin(d, axis=1)
    return np.where(d[np.arange(len(points)), j] <= tol, j, -1)


# --------------------------------------------------------------------------- assembling a piece


@dataclass(slots=True)
class _BoundaryRecipe:
    """How the sample's raw chain became its outline, re-applied to every size."""

    raw_len: int
    keep: np.ndarray
    order: np.ndarray
    inserts: list[tuple[int, float]]  # (edge index in the oriented outline, t)

    def apply(self, raw: np.ndarray) -> np.ndarray | None:
        if len(raw) != self.raw_len:
            return None
        pts = raw[self.keep][self.order]
        return _insert_points(pts, self.inserts)[0]


def _insert_points(pts: np.ndarray, inserts: list[tuple[int, float]]) -> tuple[np.ndarray, np.ndarray, list[int]]:
    """Insert points on edges; returns (new points, old->new index map, new index of each insert)."""
    n = len(pts)
    by_edge: dict[int, list[tuple[float, int]]] = {}
    for k, (e, t) in enumerate(inserts):
        by_edge.setdefault(e, []).append((t, k))
    out = []
    old_to_new = np.zeros(n, dtype=np.int64)
    new_index = [0] * len(inserts)
    for i in range(n):
        old_to_new[i] = len(out)
        out.append(pts[i])
        for t, k in sorted(by_edge.get(i, [])):
            new_index[k] = len(out)
            out.append(pts[i] + t * (pts[(i + 1) % n] - pts[i]))
    return np.array(out, dtype=np.float64).reshape(-1, 2), old_to_new, new_index


def _polylines(items) -> list[tuple[np.ndarray, bool]]:
    return [(np.asarray(p, dtype=np.float64), c) for p, c in items if len(p) >= 2]


def _sew_lines(raw: _RawBlock, tol: float) -> list[tuple[np.ndarray, bool]]:
    """Layer-14 segments chained into lines (AccuMark splits them like the boundary)."""
    segs = [(np.asarray(p, dtype=np.float64), c) for p, c in raw.sew if len(p) >= 2]
    out = []
    while segs:
        pts, closed = segs.pop(0)
        if not closed:
            grown = True
            while grown:
                grown = False
                for j, (q, qc) in enumerate(segs):
                    if qc:
                        continue
                    if np.hypot(*(q[0] - pts[-1])) <= tol:
                        pts = np.vstack([pts, q[1:]])
                    elif np.hypot(*(q[-1] - pts[-1])) <= tol:
                        pts = np.vstack([pts, q[::-1][1:]])
                    else:
                        continue
                    segs.pop(j)
                    grown = True
                    break
            if len(pts) > 2 and np.hypot(*(pts[-1] - pts[0])) <= tol:
                pts, closed = pts[:-1], True
        out.append((pts, closed))
    return out


class _PieceBuilder:
    """Builds model pieces from raw blocks of one piece (file units -> cm)."""

    def __init__(self, path: Path, report: Report, factor: float) -> None:
        self.path = path
        self.report = report
        self.f = factor
        self.tol = _MATCH_TOL
        self.missing_depth = 0

    def where(self, name: str) -> str:
        return f"{self.path.name}: piece {name}"

    # ---- sample block -------------------------------------------------------------------------
    def sample(self, name: str, size: str, raw: _RawBlock) -> tuple[Piece, _BoundaryRecipe]:
        where = self.where(name)
        chain, closed, gap, unjoined = _chain(raw.boundary, self.tol)
        if unjoined:
            raise DXFFormatError(
                f"{self.path}: boundary of piece {name!r} does not close ({unjoined} of {len(raw.boundary)} "
                f"layer-1 segments do not join the chain; gap {gap:.4g} file units); repair the piece outline"
            )
        if not closed and len(raw.boundary) > 0 and gap > self.tol:
            self.report.add("boundary-not-closed",
                            f"boundary is open (gap {gap:.4g} file units between its ends); closed with a "
                            "straight edge", where, fixed=True)
        keep = _dedupe_keep(chain, self.tol)
        removed = len(chain) - len(keep)
        pts = chain[keep]
        if len(pts) < 3:
            raise DXFFormatError(f"{self.path}: piece {name!r} has a boundary of {len(pts)} distinct vertices; "
                                 "a piece needs at least 3")
        if removed:
            self.report.add("duplicate-vertices-removed", f"{removed} repeated boundary vertices removed",
                            where, fixed=True)
        pts, order = orient_ccw(pts)
        # notches: where each sits on the oriented outline
        notch_locs = []
        inserts: list[tuple[int, float]] = []
        snap = _NOTCH_SNAP_MM / (10.0 * self.f)  # file units
        for layer, pos, depth, width, ang, end in raw.notches:
            e, t, dist = locate_on_boundary(pts, pos, self.tol)
            if end is not None:  # a LINE notch: the end on the boundary is the position
                e2, t2, dist2 = locate_on_boundary(pts, end, self.tol)
                if dist2 < dist:
                    pos, end = end, pos
                    e, t, dist = e2, t2, dist2
                depth = float(np.hypot(*(end - pos)))
            if dist > snap:
                self.report.add("notch-off-boundary",
                                f"notch at ({pos[0]:.4f}, {pos[1]:.4f}) is {dist:.4g} file units off the "
                                "boundary; snapped to it", where, fixed=True)
            if t <= 0.0:
                notch_locs.append(("vertex", e, layer, depth, width, ang, pos))
            elif t >= 1.0:
                notch_locs.append(("vertex", (e + 1) % len(pts), layer, depth, width, ang, pos))
            else:
                notch_locs.append(("insert", len(inserts), layer, depth, width, ang, pos))
                inserts.append((e, t))
        pts, old_to_new, new_index = _insert_points(pts, inserts)
        if inserts:
            self.report.add("notch-vertex-inserted", f"{len(inserts)} boundary vertices inserted under notches",
                            where, fixed=True)
        recipe = _BoundaryRecipe(raw_len=len(chain), keep=keep, order=order, inserts=inserts)
        # vertex kinds and rule ids by coordinates
        kinds, rules = self._kinds_rules(pts, raw)
        if not is_simple(pts):
            self.report.add("boundary-self-intersects", "the boundary intersects itself; areas and grading "
                            "may be wrong", where)
        outline_cm = pts * self.f
        notches = []
        rule_pts, rule_ids = self._rule_arrays(raw, prefer=4)
        for kind, k, layer, depth, width, ang, pos in notch_locs:
            v = int(old_to_new[k]) if kind == "vertex" else new_index[k]
            m = _match(np.asarray(pos, float)[None], rule_pts, self.tol)[0]
            notches.append(
                Notch(
                    vertex=v,
                    type=notch_type(layer, width),
                    depth_cm=depth * self.f,
                    width_cm=width * self.f,
                    angle=float(inward_angles(outline_cm, [v])[0]),
                    source_angle_deg=ang,
                    rule=None if m < 0 else rule_ids[m],
                )
            )
        self.missing_depth += sum(d == 0 for _, _, _, d, _, _, _ in notch_locs)
        piece = Piece(
            name=name,
            size=size,
            outline=outline_cm,
            kinds=kinds,
            rules=rules,
            notches=tuple(notches),
            **self._elements(raw, name, full=True),
            **self._text_fields(raw, name),
        )
        return piece, recipe

    def _rule_arrays(self, raw: _RawBlock, layers=None, prefer: int | None = None) -> tuple[np.ndarray, list[str]]:
        """Rule-text positions and ids (only on ``layers`` if given; ``prefer``'s texts first)."""
        items = [t for t in raw.rule_texts if layers is None or t[3] in layers]
        if prefer is not None:
            items.sort(key=lambda t: (t[3] != prefer) and not (prefer == 4 and t[3] in NOTCH_LAYERS))
        pts = np.array([(x, y) for x, y, _, _ in items], dtype=np.float64).reshape(-1, 2)
        return pts, [r for _, _, r, _ in items]

    def _kinds_rules(self, pts: np.ndarray, raw: _RawBlock, layer: int = 1) -> tuple[list, list]:
        turn = _match(pts, raw.turn, self.tol) >= 0
        curve = _match(pts, raw.curve, self.tol) >= 0
        kinds = [
            VertexKind.TURN if a else VertexKind.CURVE if b else VertexKind.PLAIN
            for a, b in zip(turn, curve, strict=True)
        ]
        rule_pts, rule_ids = self._rule_arrays(raw, prefer=layer)
        m = _match(pts, rule_pts, self.tol)
        rules = [None if j < 0 else rule_ids[j] for j in m]
        return kinds, rules

    def _elements(self, raw: _RawBlock, name: str, full: bool) -> dict:
        f = self.f
        out: dict = {}

        def poly(pts, closed, label=None, layer=8) -> Polyline:
            if full:
                kinds, rules = self._kinds_rules(pts, raw, layer)
            else:
                kinds, rules = None, None
            return Polyline(points=pts * f, kinds=kinds, rules=rules, closed=closed, label=label)

        def line(layer) -> Line | None:
            items = raw.lines.get(layer) or []
            if not items:
                return None
            if len(items) > 1 and full:
                self.report.add("extra-lines-dropped", f"{len(items)} lines on layer {layer}; the first is kept",
                                self.where(name))
            pts = items[0]
            rules = (None, None)
            if full:
                rp, ri = self._rule_arrays(raw, prefer=layer)
                m = _match(pts, rp, self.tol)
                rules = tuple(None if j < 0 else ri[j] for j in m)
            return Line(points=pts * f, rules=rules)

        out["grade_reference"] = line(5)
        out["mirror_line"] = line(6)
        out["grain_line"] = line(7)
        # internal lines with their labels (a layer-8 TEXT at the line's first point)
        labels = [k for k, (lay, _, _, _, _) in enumerate(raw.texts) if lay == Layer.INTERNAL]
        used_labels: set[int] = set()
        internal = []
        for pts, closed in _polylines(raw.internal):
            label = None
            for k in labels:
                if k not in used_labels and np.hypot(*(raw.texts[k][2] - pts[0])) <= self.tol:
                    label = raw.texts[k][1]
                    used_labels.add(k)
                    break
            internal.append(poly(pts, closed, label))
        out["internal_lines"] = tuple(internal)
        out["cutouts"] = tuple(poly(p, True, layer=11) for p, _ in _polylines(raw.cutouts))
        out["sew_lines"] = tuple(poly(p, c, layer=14) for p, c in _sew_lines(raw, self.tol))
        drill_texts = [(s, pos) for lay, s, pos, _, _ in raw.texts if lay == Layer.DRILL]
        holes = []
        rp, ri = self._rule_arrays(raw, prefer=13)
        for pos, z in raw.drills:
            label = next((s for s, p in drill_texts if np.hypot(*(p - pos)) <= self.tol), None)
            m = _match(pos[None], rp, self.tol)[0] if full else -1
            holes.append(DrillHole(position=pos * f, diameter_cm=z * f, rule=None if m < 0 else ri[m],
                                   label=label))
        out["drill_holes"] = tuple(holes)
        ann = []
        for k, (lay, s, pos, h, a) in enumerate(raw.texts):
            if k in used_labels or lay == Layer.DRILL:
                continue
            ann.append(Annotation(text=s, position=pos * f, height_cm=(h or 0.0) * f,
                                  angle=float(np.deg2rad(a or 0.0)), layer=lay))
        out["annotations"] = tuple(ann)
        return out

    def _text_fields(self, raw: _RawBlock, name: str) -> dict:
        t = raw.text
        quantity = Quantity()
        q = t.get("QUANTITY")
        if q is not None:
            parsed = parse_quantity(q)
            if parsed is None:
                self.report.add("quantity-unreadable", f"Quantity: {q!r} not understood; 1 assumed",
                                self.where(name))
            else:
                quantity = parsed[0]
        fabric = t.get("FABRIC", t.get("MATERIAL", ""))
        extra = {k: v for k, v in raw.text_order if k not in _PIECE_KEYS}
        if "FABRIC" in t and "MATERIAL" in t:
            extra["MATERIAL"] = t["MATERIAL"]
        return {
            "quantity": quantity,
            "category": t.get("CATEGORY", ""),
            "annotation": t.get("ANNOTATION", ""),
            "fabric": fabric,
            "extra_text": extra,
        }

    # ---- other sizes of a nest ----------------------------------------------------------------
    def graded(self, name: str, size: str, raw: _RawBlock, recipe: _BoundaryRecipe) -> Piece | None:
        chain, _, _, unjoined = _chain(raw.boundary, self.tol)
        pts = None if unjoined else recipe.apply(chain)
        if pts is None:
            self.report.add("nest-size-mismatch",
                            f"size {size}: boundary has {len(chain)} raw vertices, the sample "
                            f"{recipe.raw_len}; this size is not used to derive rules", self.where(name))
            return None
        elements = self._elements(raw, name, full=False)
        return Piece(name=name, size=size, outline=pts * self.f, **elements)


# --------------------------------------------------------------------------- mirror / unfold


def _reflect(points: np.ndarray, line: np.ndarray) -> np.ndarray:
    a = line[0]
    u = line[1] - line[0]
    u = u / np.hypot(*u)
    d = points - a
    along = d @ u
    return a + 2 * along[:, None] * u - d


def _unfold(piece: Piece, table: GradeRuleTable, report: Report, where: str,
            fresh: Callable[[], str]) -> tuple[Piece, dict[str, np.ndarray]]:
    """Mirror a half piece about its mirror line into the whole piece.

    Returns the whole piece and the new rules (mirrored deltas) to add.
    """
    line = piece.mirror_line.points
    u = line[1] - line[0]
    if np.hypot(*u) == 0:
        report.add("mirror-line-degenerate", "mirror line has zero length; piece not unfolded", where)
        return piece, {}
    outline = piece.outline
    n = len(outline)
    un = u / np.hypot(*u)
    dist = np.abs((outline - line[0]) @ np.array([-un[1], un[0]]))
    tol = max(1e-3, 1e-4 * float(np.ptp(outline, axis=0).max()))
    on = dist <= tol
    if on.sum() < 2 or on.all():
        report.add("mirror-line-off-boundary", "mirror line does not lie on the boundary; piece not unfolded",
                   where)
        return piece, {}
    # the fold is the run of consecutive on-line vertices; the half runs from its end round to its start
    idx = np.flatnonzero(on)
    # find a vertex on the line whose successor is off the line: start of the half
    starts = [i for i in idx if not on[(i + 1) % n]]
    ends = [i for i in idx if not on[(i - 1) % n]]
    if len(starts) != 1 or len(ends) != 1:
        report.add("mirror-line-ambiguous", "boundary touches the mirror line more than once; not unfolded",
                   where)
        return piece, {}
    s, e = starts[0], ends[0]
    half = [(s + k) % n for k in range((e - s) % n + 1)]  # s ... e, CCW, off the line in between
    inner = half[1:-1]
    mirrored_pts = _reflect(outline[inner[::-1]], line)
    new_outline = np.vstack([outline[half], mirrored_pts])
    new_index_of_old = {old: k for k, old in enumerate(half)}
    mirror_index_of_old = {old: len(half) + k for k, old in enumerate(inner[::-1])}
    theta = frame_angle(piece)
    rot = np.array([[np.cos(theta), -np.sin(theta)], [np.sin(theta), np.cos(theta)]])

    def reflect_delta(d: np.ndarray) -> np.ndarray:
        world = d @ rot.T
        along = world @ un
        refl = 2 * along[:, None] * un - world
        return refl @ rot

    new_rules: dict[str, np.ndarray] = {}
    mirrored_rule: dict[str, str] = {}

    def mirror_rule(r: str | None) -> str | None:
        if r is None or r not in table.deltas:
            return None
        if r not in mirrored_rule:
            rid = fresh()
            mirrored_rule[r] = rid
            new_rules[rid] = reflect_delta(np.asarray(table.deltas[r]))
        return mirrored_rule[r]

    kinds = [piece.kinds[i] for i in half] + [piece.kinds[i] for i in inner[::-1]]
    rules = [piece.rules[i] for i in half] + [mirror_rule(piece.rules[i]) for i in inner[::-1]]
    notches = []
    for notch in piece.notches:
        if notch.vertex in new_index_of_old:
            notches.append(dataclasses.replace(notch, vertex=new_index_of_old[notch.vertex]))
        if notch.vertex in mirror_index_of_old:
            notches.append(dataclasses.replace(notch, vertex=mirror_index_of_old[notch.vertex],
                                               rule=mirror_rule(notch.rule)))
    angles = inward_angles(new_outline, [nt.vertex for nt in notches])
    notches = [dataclasses.replace(nt, angle=float(a)) for nt, a in zip(notches, angles, strict=True)]
    internal = list(piece.internal_lines)
    for pl in piece.internal_lines:
        on_fold = np.all(np.abs((pl.points - line[0]) @ np.array([-un[1], un[0]])) <= tol)
        if pl.label == "NM" or on_fold:
            continue
        internal.append(Polyline(points=_reflect(pl.points, line), kinds=pl.kinds,
                                 rules=[mirror_rule(r) for r in pl.rules], closed=pl.closed, label=pl.label))
    holes = list(piece.drill_holes)
    for h in piece.drill_holes:
        p = _reflect(h.position[None], line)[0]
        if np.hypot(*(p - h.position)) > tol:
            holes.append(DrillHole(position=p, diameter_cm=h.diameter_cm, rule=mirror_rule(h.rule), label=h.label))
    whole = dataclasses.replace(
        piece, outline=new_outline, kinds=kinds, rules=rules, notches=tuple(notches),
        internal_lines=tuple(internal), drill_holes=tuple(holes), mirror_line=None, marks={}, landmarks={},
        extra_text={**dict(piece.extra_text), "UNFOLDED FROM MIRROR LINE": "Y"},
    )
    report.add("piece-unfolded", f"half piece mirrored about its mirror line ({n} -> {len(new_outline)} "
               "vertices)", where, fixed=True)
    return whole, new_rules


# --------------------------------------------------------------------------- entry point


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
        length, as a CAD system grading from the .RUL would)

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
    try:
        blocks, entities = _parse(path, data, report)
        return _build(path, blocks, entities, report, rul=rul, units=units, unfold=unfold, strict=strict,
                      exact_nest=exact_nest)
    except _BadNumber as exc:
        raise DXFFormatError(f"{path}: corrupted DXF (line {exc.line}: group {exc.code} value {exc.value!r} "
                             "is not a number); export the file again") from None


def _build(path, blocks, entities, report, *, rul, units, unfold, strict, exact_nest) -> tuple[Pattern, Report]:
    where = path.name
    # style system text
    style: dict[str, str] = {}
    style_order: list[tuple[str, str]] = []
    inserts = []
    for ent in entities:
        if ent.type == "TEXT" and ent.layer == Layer.BOUNDARY:
            kv = split_key(ent.tags.get(1, ""))
            if kv is not None:
                style.setdefault(kv[0], kv[1])
                style_order.append(kv)
        elif ent.type == "INSERT":
            inserts.append(ent.tags.get(2, ""))
    piece_blocks = [b for b in blocks if b.name and not b.name.startswith(("*", "$"))]
    defined = {b.name for b in blocks}
    undefined = [name for name in inserts if name not in defined]
    if undefined:
        if not piece_blocks:
            raise DXFFormatError(f"{path}: every INSERT names an undefined block ({', '.join(undefined[:3])}); "
                                 "the file holds no pieces")
        report.add("insert-undefined-block", f"{len(undefined)} INSERT(s) name undefined blocks: "
                   f"{', '.join(undefined[:5])}", where)
    if not piece_blocks:
        raise DXFFormatError(f"{path}: no piece BLOCKs found (empty, truncated or not a DXF-AAMA/ASTM file); "
                             "export the pattern again as DXF-AAMA or DXF-ASTM")
    # units
    override = _units_override(units)
    declared = style.get("UNITS")
    if override is not None:
        unit = override
        if declared is not None and parse_units(declared) not in (None, override):
            report.add("units-overridden", f"file says Units: {declared}, read as {override.value}", where)
    elif declared is None:
        unit = Units.METRIC
        report.add("units-assumed", "no 'Units:' style text; METRIC (mm) assumed", where)
    else:
        unit = parse_units(declared)
        if unit is None:
            raise UnitsError(f"{path}: unknown units 'Units: {declared}' (expected METRIC or ENGLISH); "
                             "pass units='METRIC' or 'ENGLISH'")
    factor = unit_factor(unit.value)
    raws = [_raw_block(b) for b in piece_blocks]
    # report layers we do not model, once
    validation = sum(r.validation for r in raws)
    if validation:
        report.add("validation-curves-dropped", f"{validation} quality-validation curves (layers 84-87) "
                   "recognised and dropped", where, fixed=True)
    other = sorted(set().union(*(r.other_layers for r in raws)))
    if other:
        report.add("layers-ignored", f"content on layers we do not model ignored: {', '.join(other[:10])}", where)
    attdefs = sum(r.attdefs for r in raws)
    if attdefs:
        report.add("attdef-ignored", f"{attdefs} ATTDEF notch links ignored (notches follow their vertex)", where)
    # group blocks into pieces and sizes
    groups: dict[str, list[tuple[str, _RawBlock]]] = {}
    for raw in raws:
        name = raw.text.get("PIECE NAME") or re.sub(r"[_-][^_-]*$", "", raw.name) or raw.name
        size = next((raw.text[k] for k in _SIZE_KEYS if raw.text.get(k)), "")
        if not size:
            m = re.search(r"[_-]([^_-]+)$", raw.name)
            size = m.group(1) if m else ""
        if not raw.boundary:
            report.add("block-without-boundary", f"block {raw.name!r} has no layer-1 boundary; skipped", where)
            continue
        groups.setdefault(name, []).append((size, raw))
    if not groups:
        raise DXFFormatError(f"{path}: no block has a layer-1 boundary; not a DXF-AAMA/ASTM pattern file")
    sizes: list[str] = []
    for items in groups.values():
        for size, _ in items:
            if size not in sizes:
                sizes.append(size)
    sample_size = style.get("SAMPLE SIZE", "")
    if not sample_size:
        if len(sizes) == 1:
            sample_size = sizes[0]
        else:
            richest = max(raws, key=lambda r: len(r.turn) + len(r.curve) + len(r.rule_texts))
            sample_size = next((s for items in groups.values() for s, r in items if r is richest), sizes[0])
            report.add("sample-size-assumed", f"no 'Sample Size:' style text; {sample_size} assumed", where)
    elif sample_size not in sizes:
        if len(sizes) == 1:
            report.add("sample-size-mismatch", f"Sample Size: {sample_size} but the blocks are size {sizes[0]}; "
                       f"{sizes[0]} used", where)
            sample_size = sizes[0]
        else:
            raise DXFFormatError(f"{path}: Sample Size: {sample_size} has no block (sizes: {' '.join(sizes)}); "
                                 "fix the style text")
    builder = _PieceBuilder(path, report, factor)
    pieces: list[Piece] = []
    nest: dict[str, dict[str, Piece]] = {s: {} for s in sizes if s != sample_size}
    is_nest = len(sizes) > 1
    for name, items in groups.items():
        by_size: dict[str, _RawBlock] = {}
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
    # flavour and provenance
    author = style.get("AUTHOR", "")
    producer, product, version = parse_author(author)
    product = product or style.get("PRODUCT", "")
    version = version or style.get("VERSION", "")
    astm = ASTM_MARKER in style or validation > 0
    quantities = [r.text.get("QUANTITY", "") for r in raws]
    if any(q and parse_quantity(q) and parse_quantity(q)[1] for q in quantities):
        astm = True
    created = " ".join(x for x in (style.get("CREATION DATE", "").strip(), style.get("CREATION TIME", "").strip()) if x)
    known_style = {"STYLE NAME", "AUTHOR", "PRODUCT", "VERSION", "SAMPLE SIZE", "UNITS", "CREATION DATE",
                   "CREATION TIME"}
    provenance = Provenance(
        producer=producer,
        product=product,
        version=version,
        author=author,
        created=created,
        flavor=Flavor.ASTM if astm else Flavor.AAMA,
        source_file=path.name,
        extra_text={k: v for k, v in style_order if k not in known_style},
    )
    pattern = Pattern(
        style=style.get("STYLE NAME", path.stem),
        pieces=tuple(pieces),
        units=unit,
        sample_size=sample_size,
        sizes=tuple(sizes),
        rules=GradeRuleTable(name=style.get("GRADE RULE TABLE", ""), sizes=tuple(sizes) if not is_nest else (),
                             sample_size=sample_size, deltas={}),
        provenance=provenance,
    )
    # grade rules
    rul_path = Path(rul) if rul is not None else _find_rul(path)
    if rul is not None and not rul_path.is_file():
        raise RULFormatError(f"{rul_path}: no such grade-rule file")
    if rul_path is not None:
        if rul is None:
            report.add("rul-found-beside", f"grade rules read from {rul_path.name}", where)
        table, rul_report = read_rul(rul_path)
        report.extend(rul_report)
        if table.sample_size != sample_size:
            raise RULFormatError(f"{rul_path}: sample size {table.sample_size} differs from the DXF's "
                                 f"{sample_size}; give the .RUL exported with this DXF")
        if is_nest and (len(table.sizes) != len(sizes) or set(table.sizes) != set(sizes)):
            raise RULFormatError(f"{rul_path}: {len(table.sizes)} sizes ({' '.join(table.sizes)}) but the DXF "
                                 f"nest has {len(sizes)} ({' '.join(sizes)}); give the matching .RUL")
        used = {r for p in pieces for r in p.rules if r is not None}
        missing = sorted(used - set(table.deltas), key=lambda r: (len(r), r))
        if missing:
            report.add("rule-missing", f"{len(missing)} rule ids used in the DXF are not in the .RUL "
                       f"({', '.join(missing[:8])}); those points follow their neighbours", where)
        if not table.name:
            table = dataclasses.replace(table, name=pattern.rules.name)
        pattern = dataclasses.replace(pattern, sizes=table.sizes, rules=table)
        if is_nest:
            dev = _nest_deviation(pattern, nest, rule_points_only=True)
            if dev > 1e-3:
                report.add("rul-nest-mismatch", f"the .RUL grades the sample up to {dev * 10:.3f} mm away from "
                           "the nest's own sizes at rule points; the .RUL is used", where)
    elif is_nest:
        pattern = rules_from_nest(pattern, nest, every_vertex=exact_nest)
        report.add("rules-derived-from-nest", f"grade rules derived from the graded nest "
                   f"({len(pattern.rules.deltas)} rules, {len(sizes)} sizes)", where)
        dev = _nest_deviation(pattern, nest)
        if dev > 1e-3:  # cm: report what a pattern maker would notice (over 0.01 mm)
            report.add("nest-curve-deviation", f"points between rule points follow by arc length: up to "
                       f"{dev * 10:.3f} mm from the nest's own curves", where)
    else:
        n_rule = sum(r is not None for p in pieces for r in p.rules)
        if n_rule:
            report.add("rul-missing", f"{n_rule} boundary points carry rule ids but no .RUL was found; only the "
                       f"sample size {sample_size} is available", where)
    if unfold:
        pattern = _unfold_pattern(pattern, report)
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


def _unfold_pattern(pattern: Pattern, report: Report) -> Pattern:
    ints = [int(r) for r in pattern.rules.deltas if re.fullmatch(r"-?\d+", r)]
    counter = [max(ints, default=0) + 1]

    def fresh() -> str:
        rid = str(counter[0])
        counter[0] += 1
        return rid

    if all(piece.mirror_line is None for piece in pattern.pieces):
        report.add("nothing-to-unfold", "unfold asked for, but no piece has a mirror line (layer 6); "
                   "pieces kept as drawn", pattern.provenance.source_file, severity="info")
        return pattern
    pieces = []
    extra: dict[str, np.ndarray] = {}
    for piece in pattern.pieces:
        if piece.mirror_line is None:
            pieces.append(piece)
            continue
        whole, new_rules = _unfold(piece, pattern.rules, report, f"{pattern.provenance.source_file}: piece "
                                   f"{piece.name}", fresh)
        pieces.append(whole)
        extra.update(new_rules)
    if not extra:
        return dataclasses.replace(pattern, pieces=tuple(pieces))
    table = dataclasses.replace(pattern.rules, deltas={**dict(pattern.rules.deltas), **extra})
    return dataclasses.replace(pattern, pieces=tuple(pieces), rules=table)
