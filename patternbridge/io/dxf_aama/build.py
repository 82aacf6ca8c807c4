"""Piece building: a piece BLOCK's raw content (file units) becomes a model :class:`Piece` (cm).

The layer above :mod:`.entities`: chains the boundary segments, drops repeated
vertices, orients the outline counter-clockwise, places notches on the outline,
matches turn/curve points and ``# n`` rule texts to vertices by coordinates and
builds the piece's lines, holes, annotations and text fields. The steps taken
on the sample size are kept as a :class:`BoundaryRecipe` and repeated on every
other size of a graded nest, so vertex *i* means the same point in every size.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...errors import DXFFormatError
from ...pattern.geometry import is_simple, orient_ccw
from ...pattern.grading import inward_angles
from ...pattern.model import Annotation, DrillHole, Line, Notch, Piece, Polyline, Quantity, VertexKind
from ...report import Report
from .entities import RawBlock
from .layers import NOTCH_LAYERS, Layer
from .notches import locate_on_boundary, notch_type
from .text import parse_quantity

__all__ = ["MATCH_TOL", "MAX_QUANTITY", "PIECE_KEYS", "SIZE_KEYS", "BoundaryRecipe", "PieceBuilder", "chain"]

MATCH_TOL = 1e-3  # file units: a text or POINT "sits on" a vertex within this
_NOTCH_SNAP_MM = 0.5  # a notch this close to an edge is on it (no finding)
SIZE_KEYS = ("SIZE", "SIZE NAME", "SAMPLE SIZE")
MAX_QUANTITY = 1000
"""Most copies of one piece a ``Quantity:`` may ask for (right plus left)."""
PIECE_KEYS = {"PIECE NAME", "QUANTITY", "ANNOTATION", "CATEGORY", "FABRIC", "MATERIAL", *SIZE_KEYS}


def chain(segments: list[tuple[np.ndarray, bool]], tol: float) -> tuple[np.ndarray, bool, float, int]:
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
class BoundaryRecipe:
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


def _sew_line_match(outline: np.ndarray, sew: np.ndarray, pos: np.ndarray, dist: float, tol: float) -> int | None:
    """The cut-line vertex matching the sew-line vertex a notch sits on, or ``None``.

    A notch ``dist`` inside the cut line that sits on a sew-line vertex belongs
    to the cut-line vertex nearest that sew vertex, when it is no farther than
    1.5 ``dist`` (the allowance, mitred at corners): no vertex is inserted, so
    cut-line and sew-line vertices keep matching.
    """
    if not len(sew) or np.min(np.hypot(*(sew - pos).T)) > tol:
        return None
    d = np.hypot(*(outline - pos).T)
    v = int(np.argmin(d))
    return v if d[v] <= 1.5 * dist + tol else None


def _polylines(items) -> list[tuple[np.ndarray, bool]]:
    return [(np.asarray(p, dtype=np.float64), c) for p, c in items if len(p) >= 2]


def _sew_lines(raw: RawBlock, tol: float) -> list[tuple[np.ndarray, bool]]:
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


class PieceBuilder:
    """Builds model pieces from raw blocks of one piece (file units -> cm)."""

    def __init__(self, path: Path, report: Report, factor: float) -> None:
        self.path = path
        self.report = report
        self.f = factor
        self.tol = MATCH_TOL
        self.missing_depth = 0
        self._claims: dict[tuple[int, int], dict[tuple[int, int], int]] = {}  # (block, layer) -> point -> taken

    def where(self, name: str) -> str:
        return f"{self.path.name}: piece {name}"

    # ---- sample block -------------------------------------------------------------------------
    def sample(self, name: str, size: str, raw: RawBlock) -> tuple[Piece, BoundaryRecipe]:
        """The piece of the sample-size block and the recipe that made its outline."""
        where = self.where(name)
        pts, raw_len, keep, order = self._outline(name, raw)
        notch_locs, inserts = self._locate_notches(pts, raw, where)
        pts, old_to_new, new_index = _insert_points(pts, inserts)
        if inserts:
            self.report.add("notch-vertex-inserted", f"{len(inserts)} boundary vertices inserted under notches",
                            where, fixed=True)
        recipe = BoundaryRecipe(raw_len=raw_len, keep=keep, order=order, inserts=inserts)
        kinds, rules = self._kinds_rules(pts, raw)
        if not is_simple(pts):
            self.report.add("boundary-self-intersects", "the boundary intersects itself; areas and grading "
                            "may be wrong", where)
        outline_cm = pts * self.f
        vertices = [int(old_to_new[k]) if kind == "vertex" else new_index[k] for kind, k, *_ in notch_locs]
        angles = inward_angles(outline_cm, vertices) if vertices else []
        rule_pts, rule_ids = self._rule_arrays(raw, prefer=4)
        notches = []
        for v, a, (_, _, layer, depth, width, ang, pos) in zip(vertices, angles, notch_locs, strict=True):
            m = _match(np.asarray(pos, float)[None], rule_pts, self.tol)[0]
            notches.append(Notch(vertex=v, type=notch_type(layer, width), depth_cm=depth * self.f,
                                 width_cm=width * self.f, angle=float(a), source_angle_deg=ang,
                                 rule=None if m < 0 else rule_ids[m]))
        self.missing_depth += sum(loc[3] == 0 for loc in notch_locs)
        piece = Piece(name=name, size=size, outline=outline_cm, kinds=kinds, rules=rules, notches=tuple(notches),
                      **self._elements(raw, name, full=True), **self._text_fields(raw, name))
        return piece, recipe

    def _outline(self, name: str, raw: RawBlock) -> tuple[np.ndarray, int, np.ndarray, np.ndarray]:
        """The chained, de-duplicated, CCW outline (file units), raw length, kept indices and order."""
        where = self.where(name)
        pts, closed, gap, unjoined = chain(raw.boundary, self.tol)
        if unjoined:
            raise DXFFormatError(
                f"{self.path}: boundary of piece {name[:60]!r} does not close ({unjoined} of {len(raw.boundary)} "
                f"layer-1 segments do not join the chain; gap {gap:.4g} file units); repair the piece outline"
            )
        if not closed and len(raw.boundary) > 0 and gap > self.tol:
            self.report.add("boundary-not-closed",
                            f"boundary is open (gap {gap:.4g} file units between its ends); closed with a "
                            "straight edge", where, fixed=True)
        keep = _dedupe_keep(pts, self.tol)
        removed = len(pts) - len(keep)
        raw_len = len(pts)
        pts = pts[keep]
        if len(pts) < 3:
            raise DXFFormatError(f"{self.path}: piece {name[:60]!r} has a boundary of {len(pts)} distinct "
                                 "vertices; a piece needs at least 3")
        if removed:
            self.report.add("duplicate-vertices-removed", f"{removed} repeated boundary vertices removed",
                            where, fixed=True)
        pts, order = orient_ccw(pts)
        return pts, raw_len, keep, order

    def _locate_notches(self, pts: np.ndarray, raw: RawBlock, where: str) -> tuple[list, list]:
        """Where each notch sits on the outline: on a vertex, or on an edge (a vertex to insert)."""
        notch_locs = []
        inserts: list[tuple[int, float]] = []
        snap = _NOTCH_SNAP_MM / (10.0 * self.f)  # file units
        sew = np.vstack([p for p, _ in _sew_lines(raw, self.tol)] or [np.zeros((0, 2))])
        on_sew = 0
        for layer, pos, depth, width, ang, end in raw.notches:
            e, t, dist = locate_on_boundary(pts, pos, self.tol)
            if end is not None:  # a LINE notch: the end on the boundary is the position
                e2, t2, dist2 = locate_on_boundary(pts, end, self.tol)
                if dist2 < dist:
                    pos, end = end, pos
                    e, t, dist = e2, t2, dist2
                depth = float(np.hypot(*(end - pos)))
            v = _sew_line_match(pts, sew, pos, dist, self.tol) if dist > snap else None
            if v is not None:  # allowance included: the notch marks the sew line; its cut-line twin carries it
                notch_locs.append(("vertex", v, layer, depth, width, ang, pts[v]))
                on_sew += 1
                continue
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
        if on_sew:
            self.report.add("notch-on-sew-line", f"{on_sew} notches lie on a sew-line vertex inside the cut line "
                            "(allowance included); each is placed on the matching cut-line vertex", where,
                            fixed=True)
        return notch_locs, inserts

    def _rule_arrays(self, raw: RawBlock, layers=None, prefer: int | None = None) -> tuple[np.ndarray, list[str]]:
        """Rule-text positions and ids (only on ``layers`` if given; ``prefer``'s texts first)."""
        items = [t for t in raw.rule_texts if layers is None or t[3] in layers]
        if prefer is not None:
            items.sort(key=lambda t: (t[3] != prefer) and not (prefer == 4 and t[3] in NOTCH_LAYERS))
        pts = np.array([(x, y) for x, y, _, _ in items], dtype=np.float64).reshape(-1, 2)
        return pts, [r for _, _, r, _ in items]

    def _kinds_rules(self, pts: np.ndarray, raw: RawBlock, layer: int = 1) -> tuple[list, list]:
        turn = _match(pts, raw.turn, self.tol) >= 0
        curve = _match(pts, raw.curve, self.tol) >= 0
        kinds = [
            VertexKind.TURN if a else VertexKind.CURVE if b else VertexKind.PLAIN
            for a, b in zip(turn, curve, strict=True)
        ]
        rule_pts, rule_ids = self._rule_arrays(raw, prefer=layer)
        m = _match(pts, rule_pts, self.tol)
        rules = [None if j < 0 else rule_ids[j] for j in m]
        return kinds, self._claim(pts, raw, layer, rules)

    def _claim(self, pts: np.ndarray, raw: RawBlock, layer: int, rules: list) -> list:
        """Rules where several texts on ``layer`` share one point: the elements take them in file order.

        Two elements of one layer that meet at a point but grade apart (an
        internal line ending where another starts) each need their own rule
        there; the writer puts one text per element on the element's layer, in
        element order, and the k-th element of that layer at the point takes
        the k-th text. A point with a single text on the layer keeps it for all.
        """
        own = [(x, y, r) for x, y, r, lay in raw.rule_texts if lay == layer]
        if len(own) < 2:
            return rules
        xy = np.array([(x, y) for x, y, _ in own])
        claims = self._claims.setdefault((id(raw), layer), {})
        out = list(rules)
        for i, p in enumerate(pts):
            near = np.flatnonzero(np.hypot(*(xy - p).T) <= self.tol)
            if len(near) < 2:
                continue
            key = (round(float(p[0]) / self.tol), round(float(p[1]) / self.tol))
            k = claims.get(key, 0)
            out[i] = own[near[min(k, len(near) - 1)]][2]
            claims[key] = k + 1
        return out

    def _elements(self, raw: RawBlock, name: str, full: bool) -> dict:
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

    def _text_fields(self, raw: RawBlock, name: str) -> dict:
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
                if quantity.total > MAX_QUANTITY:
                    raise DXFFormatError(f"{self.path}: piece {name[:60]!r} asks for Quantity: {q[:30]} copies "
                                         f"(at most {MAX_QUANTITY}); fix the piece text")
        fabric = t.get("FABRIC", t.get("MATERIAL", ""))
        extra = {k: v for k, v in raw.text_order if k not in PIECE_KEYS}
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
    def graded(self, name: str, size: str, raw: RawBlock, recipe: BoundaryRecipe) -> Piece | None:
        raw_pts, _, _, unjoined = chain(raw.boundary, self.tol)
        pts = None if unjoined else recipe.apply(raw_pts)
        if pts is None:
            self.report.add("nest-size-mismatch",
                            f"size {size}: boundary has {len(raw_pts)} raw vertices, the sample "
                            f"{recipe.raw_len}; this size is not used to derive rules", self.where(name))
            return None
        elements = self._elements(raw, name, full=False)
        return Piece(name=name, size=size, outline=pts * self.f, **elements)

