"""Grading by rules: any size of a pattern from its sample size and grade-rule table.

A *rule point* is a vertex that carries a grade-rule id; it moves by the rule's
cumulative displacement for the target size, rotated from the frame of the
piece's grade reference line (+x along the line) into drawing axes. Every other
vertex of a polyline follows by arc length: its displacement is interpolated
linearly, by its sample-size arc-length position, between the displacements of
the rule points before and after it (wrapping round a closed boundary). Points
of internal elements that have no rule point at all move with the nearest
boundary vertex. Notches ride on their boundary vertex and get their direction
recomputed from the graded boundary.

The reverse direction, :func:`rules_from_nest` / :func:`derive_rules`, reads
the rules off a graded nest (the same piece drawn in every size, vertex ``i``
corresponding across sizes), and :func:`add_size` appends a freely shaped size
as one more column of the table.

Everything here is pure: no file I/O, inputs are never modified.
"""

from __future__ import annotations

import dataclasses
import functools
import re
from collections.abc import Iterable, Mapping, Sequence

import numpy as np

from .geometry import arc_lengths
from .model import GradeRuleTable, Pattern, Piece, Polyline, VertexKind

__all__ = [
    "add_size",
    "derive_rules",
    "frame_angle",
    "grade",
    "grade_piece",
    "graded_outlines",
    "inward_angles",
    "piece_displacements",
    "rebase_rules",
    "rules_from_nest",
    "single_size",
]

_SAME_RULE_CM = 5e-4  # cm (0.005 mm): two points share a rule id when their deltas agree this well


# --------------------------------------------------------------------------- geometry helpers


def _rotation(theta: float) -> np.ndarray:
    c, s = np.cos(theta), np.sin(theta)
    return np.array([[c, -s], [s, c]])


def frame_angle(piece: Piece) -> float:
    """Angle (radians, CCW from +x) of the frame the piece's grade rules are written in.

    The grade reference line's direction when the piece has one, otherwise 0
    (drawing axes).
    """
    line = piece.grade_reference
    if line is None:
        return 0.0
    d = line.points[1] - line.points[0]
    if not np.any(d):
        return 0.0
    return float(np.arctan2(d[1], d[0]))


def _left(e: np.ndarray) -> np.ndarray:
    """Inward normal of an edge of a CCW outline (its left side)."""
    return np.array([-e[1], e[0]])


def inward_angles(outline: np.ndarray, vertices: Iterable[int]) -> np.ndarray:
    """Direction into the piece at boundary vertices, radians CCW from +x.

    The bisector of the inward normals of the two edges meeting at the vertex
    (``outline`` is CCW, so inward is to the left of each edge). Zero-length
    edges are skipped to the next distinct neighbour.

    Parameters
    ----------
    outline : (n, 2) float64, CCW
    vertices : indices into ``outline``

    Returns
    -------
    (k,) float64, radians

    Examples
    --------
    >>> sq = np.array([[0, 0], [2, 0], [2, 2], [0, 2]], float)
    >>> round(float(inward_angles(sq, [0])[0] / np.pi), 6)  # into the square: 45 degrees
    0.25
    """
    outline = np.asarray(outline, dtype=np.float64)
    n = len(outline)
    out = []
    for v in vertices:
        p = outline[v]
        prev_dir = next_dir = None
        for k in range(1, n):
            d = p - outline[(v - k) % n]
            if np.hypot(*d) > 1e-12:
                prev_dir = d / np.hypot(*d)
                break
        for k in range(1, n):
            d = outline[(v + k) % n] - p
            if np.hypot(*d) > 1e-12:
                next_dir = d / np.hypot(*d)
                break
        if prev_dir is None or next_dir is None:
            out.append(0.0)
            continue
        b = _left(prev_dir) + _left(next_dir)
        if np.hypot(*b) < 1e-9:  # a cusp: the edges fold back on each other
            b = -prev_dir + next_dir if np.hypot(*(-prev_dir + next_dir)) > 1e-9 else _left(next_dir)
        out.append(float(np.arctan2(b[1], b[0])))
    return np.array(out, dtype=np.float64)


def _interp_weights(points: np.ndarray, rule_idx: np.ndarray, closed: bool):
    """For every vertex: the rule vertex before, the one after and the arc-length weight.

    Returns ``(prev, nxt, t)`` with ``displacement = (1 - t) * d[prev] + t * d[nxt]``.
    ``rule_idx`` must be sorted and non-empty.
    """
    n = len(points)
    idx = np.arange(n)
    s = arc_lengths(points, closed=closed)
    m = len(rule_idx)
    k = np.searchsorted(rule_idx, idx, side="right") - 1  # last rule vertex <= i
    if closed:
        perim = s[-1]
        prev = rule_idx[k % m]
        nxt = rule_idx[(k + 1) % m]
        span = np.mod(s[nxt] - s[prev], perim) if perim > 0 else np.zeros(n)
        span = np.where((m == 1) | ((nxt == prev) & (perim > 0)), perim, span)
        dist = np.mod(s[idx] - s[prev], perim) if perim > 0 else np.zeros(n)
    else:
        s = s[:n]
        before = k >= 0
        prev = np.where(before, rule_idx[np.clip(k, 0, m - 1)], rule_idx[0])
        after_k = np.clip(k + 1, 0, m - 1)
        nxt = np.where(k + 1 < m, rule_idx[after_k], rule_idx[m - 1])
        nxt = np.where(before, nxt, rule_idx[0])
        span = s[nxt] - s[prev]
        dist = s[idx] - s[prev]
    with np.errstate(invalid="ignore", divide="ignore"):
        t = np.where(span > 1e-12, dist / np.where(span > 1e-12, span, 1.0), 0.0)
    t = np.clip(t, 0.0, 1.0)
    t = np.where(idx == prev, 0.0, t)
    return prev, nxt, t


def _rule_matrix(rules: tuple, table: GradeRuleTable) -> tuple[np.ndarray, np.ndarray]:
    """(mask (n,), deltas (n, n_sizes, 2)) for the vertices whose rule is in ``table``."""
    n = len(rules)
    n_sizes = len(table.sizes)
    mask = np.array([r is not None and r in table.deltas for r in rules], dtype=bool)
    deltas = np.zeros((n, n_sizes, 2))
    for i in np.flatnonzero(mask):
        deltas[i] = table.deltas[rules[i]]
    return mask, deltas


def _polyline_displacement(
    points: np.ndarray,
    rules: tuple,
    table: GradeRuleTable,
    rot: np.ndarray,
    closed: bool,
    fallback: np.ndarray | None,
) -> np.ndarray:
    """Displacement (n_sizes, n, 2), drawing axes, of every vertex of a polyline.

    ``fallback`` (n_sizes, n, 2) is used when the polyline has no rule point;
    ``None`` means no movement.
    """
    n = len(points)
    mask, deltas = _rule_matrix(rules, table)
    n_sizes = len(table.sizes)
    if not mask.any():
        return np.zeros((n_sizes, n, 2)) if fallback is None else fallback
    world = np.einsum("ij,nsj->sni", rot, deltas)  # (n_sizes, n, 2)
    rule_idx = np.flatnonzero(mask)
    prev, nxt, t = _interp_weights(points, rule_idx, closed)
    disp = (1.0 - t)[None, :, None] * world[:, prev] + t[None, :, None] * world[:, nxt]
    disp[:, rule_idx] = world[:, rule_idx]
    return disp


def _nearest_vertex(points: np.ndarray, outline: np.ndarray) -> np.ndarray:
    d = np.linalg.norm(points[:, None, :] - outline[None, :, :], axis=-1)
    return np.argmin(d, axis=1)


def _point_displacement(points, rules, table, rot, outline, boundary_disp) -> np.ndarray:
    """(n_sizes, k, 2): each point by its rule, or with its nearest boundary vertex."""
    points = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    mask, deltas = _rule_matrix(tuple(rules), table)
    near = _nearest_vertex(points, outline)
    disp = boundary_disp[:, near].copy()
    if mask.any():
        world = np.einsum("ij,nsj->sni", rot, deltas)
        disp[:, mask] = world[:, mask]
    return disp


# --------------------------------------------------------------------------- grading


def piece_displacements(piece: Piece, table: GradeRuleTable) -> dict:
    """Displacements for every size of ``table``: a dict of element -> (n_sizes, ..., 2).

    Keys: ``outline``, ``internal_lines``, ``cutouts``, ``sew_lines``, ``grain_line``,
    ``grade_reference``, ``mirror_line`` and, when the piece has them, ``drill_holes`` and
    ``annotations``; each array is in cm.
    """
    rot = _rotation(frame_angle(piece))
    outline = piece.outline
    b = _polyline_displacement(outline, piece.rules, table, rot, True, None)
    out: dict = {"outline": b}

    def poly(p: Polyline) -> np.ndarray:
        fb = b[:, _nearest_vertex(p.points, outline)] if len(p.points) else None
        return _polyline_displacement(p.points, p.rules, table, rot, p.closed, fb)

    for attr in ("internal_lines", "cutouts", "sew_lines"):
        out[attr] = [poly(p) for p in getattr(piece, attr)]
    for attr in ("grain_line", "grade_reference", "mirror_line"):
        line = getattr(piece, attr)
        out[attr] = None if line is None else _point_displacement(line.points, line.rules, table, rot, outline, b)
    if piece.drill_holes:
        pos = np.array([h.position for h in piece.drill_holes])
        out["drill_holes"] = _point_displacement(pos, [h.rule for h in piece.drill_holes], table, rot, outline, b)
    if piece.annotations:
        pos = np.array([a.position for a in piece.annotations])
        out["annotations"] = b[:, _nearest_vertex(pos, outline)]
    return out


def _apply(piece: Piece, disp: dict, k: int, size: str) -> Piece:
    """The piece moved by size row ``k`` of ``disp``."""
    outline = piece.outline + disp["outline"][k]
    changes: dict = {"outline": outline, "size": size}
    for attr in ("internal_lines", "cutouts", "sew_lines"):
        changes[attr] = tuple(
            dataclasses.replace(p, points=p.points + d[k])
            for p, d in zip(getattr(piece, attr), disp[attr], strict=True)
        )
    for attr in ("grain_line", "grade_reference", "mirror_line"):
        line = getattr(piece, attr)
        if line is not None:
            changes[attr] = dataclasses.replace(line, points=line.points + disp[attr][k])
    if piece.drill_holes:
        changes["drill_holes"] = tuple(
            dataclasses.replace(h, position=h.position + d)
            for h, d in zip(piece.drill_holes, disp["drill_holes"][k], strict=True)
        )
    if piece.annotations:
        changes["annotations"] = tuple(
            dataclasses.replace(a, position=a.position + d)
            for a, d in zip(piece.annotations, disp["annotations"][k], strict=True)
        )
    if piece.notches:
        angles = inward_angles(outline, [n.vertex for n in piece.notches])
        changes["notches"] = tuple(
            dataclasses.replace(n, angle=float(a)) for n, a in zip(piece.notches, angles, strict=True)
        )
    return dataclasses.replace(piece, **changes)


def grade_piece(piece: Piece, table: GradeRuleTable, size: str) -> Piece:
    """The piece (given in the table's sample size) in ``size``.

    Parameters
    ----------
    piece : Piece in ``table.sample_size``
    table : GradeRuleTable holding the piece's rule ids
    size : a size of ``table.sizes``

    Returns
    -------
    Piece
        Same vertex count and order, every element moved; ``size`` set.

    Raises
    ------
    KeyError
        When ``size`` is not in the table's size list.

    Notes
    -----
    Rule points move by ``R(theta) @ delta`` with ``theta`` the direction of
    the grade reference line (:func:`frame_angle`); other vertices follow by
    arc length between the rule points around them. Rule ids missing from the
    table count as no rule.
    """
    k = table.size_index(size)
    return _apply(piece, piece_displacements(piece, table), k, str(size))


def rebase_rules(table: GradeRuleTable, size: str) -> GradeRuleTable:
    """The same rules expressed from ``size`` as sample size (its row becomes zero)."""
    k = table.size_index(size)
    deltas = {r: d - d[k] for r, d in table.deltas.items()}
    return dataclasses.replace(table, sample_size=str(size), deltas=deltas)


def grade(pattern: Pattern, size: str) -> Pattern:
    """Every piece of ``pattern`` in ``size``; the result has ``size`` as its sample size.

    The rule table is re-based on ``size`` (:func:`rebase_rules`), so grading
    the result to another size lands where grading the original would (exactly
    at rule points).

    Raises
    ------
    KeyError
        When ``size`` is not in the size list.
    """
    table = pattern.rules
    size = str(size)
    if size == pattern.sample_size or (not table.sizes and size == table.sample_size):
        pieces = tuple(dataclasses.replace(p, size=size) for p in pattern.pieces)
        return dataclasses.replace(pattern, pieces=pieces)
    k = table.size_index(size)
    pieces = tuple(_apply(p, piece_displacements(p, table), k, size) for p in pattern.pieces)
    return dataclasses.replace(pattern, pieces=pieces, sample_size=size, rules=rebase_rules(table, size))


def single_size(pattern: Pattern, size: str) -> Pattern:
    """``pattern`` as a one-size pattern named ``size``, with no grade rules left.

    For a shape that grading did not produce (a pattern fitted to a character):
    the rule ids would otherwise promise a grading the shape no longer follows.
    Geometry is unchanged; every rule reference (outline, notches, lines,
    polylines, drill holes) is cleared and the rule table holds ``size`` only.
    """
    size = str(size)

    def plain(polylines: tuple[Polyline, ...]) -> tuple[Polyline, ...]:
        return tuple(dataclasses.replace(pl, rules=None) for pl in polylines)

    def plain_line(line):
        return None if line is None else dataclasses.replace(line, rules=(None, None))

    pieces = tuple(
        dataclasses.replace(
            p,
            size=size,
            rules=None,
            notches=tuple(dataclasses.replace(n, rule=None) for n in p.notches),
            internal_lines=plain(p.internal_lines),
            cutouts=plain(p.cutouts),
            sew_lines=plain(p.sew_lines),
            grain_line=plain_line(p.grain_line),
            grade_reference=plain_line(p.grade_reference),
            mirror_line=plain_line(p.mirror_line),
            drill_holes=tuple(dataclasses.replace(h, rule=None) for h in p.drill_holes),
        )
        for p in pattern.pieces
    )
    return dataclasses.replace(
        pattern,
        pieces=pieces,
        sample_size=size,
        sizes=(size,),
        rules=GradeRuleTable(sizes=(size,), sample_size=size),
    )


def graded_outlines(pattern: Pattern) -> dict[str, dict[str, np.ndarray]]:
    """Boundary of every piece in every size: ``{size: {piece name: (n, 2) cm}}``.

    Sizes in size-list order; a pattern without rules gives its sample size only.
    """
    table = pattern.rules
    if not table.sizes:
        return {pattern.sample_size: {p.name: p.outline.copy() for p in pattern.pieces}}
    disp = {p.name: piece_displacements(p, table)["outline"] for p in pattern.pieces}
    return {size: {p.name: p.outline + disp[p.name][k] for p in pattern.pieces} for k, size in enumerate(table.sizes)}


# --------------------------------------------------------------------------- rules from a nest


class _RuleBook:
    """Collects derived deltas per rule id, splitting ids whose points move differently.

    Points at the same sample location that move the same way share one id,
    so coincident points of different elements (a grain-line end on the grade
    reference line, two internal lines meeting) get one rule, as a CAD file
    that matches rule texts by coordinates would give them.
    """

    def __init__(self, used_ids: Iterable[str], atol_cm: float) -> None:
        ints = [int(r) for r in used_ids if r is not None and re.fullmatch(r"-?\d+", str(r))]
        self.next_id = max(ints, default=0) + 1
        self.atol = atol_cm
        self.deltas: dict[str, np.ndarray] = {}
        self.variants: dict[str, list[str]] = {}
        self.origin: dict[str, str | None] = {}
        self.at: dict[tuple, list[str]] = {}

    def fresh(self) -> str:
        rid = str(self.next_id)
        self.next_id += 1
        return rid

    def _same(self, rid: str, delta: np.ndarray) -> bool:
        return bool(np.max(np.abs(self.deltas[rid] - delta)) <= self.atol)

    def assign(self, rule: str | None, delta: np.ndarray, key: tuple | None = None) -> str:
        """Id under which ``delta`` (n_sizes, 2) is stored: ``rule`` or a split-off id.

        ``key`` identifies the point's sample location (piece, x, y).
        """
        if key is not None:
            for rid in self.at.get(key, []):
                if (rule is None or rule in (rid, self.origin[rid])) and self._same(rid, delta):
                    return rid
        if rule is None:
            rid = self.fresh()
        else:
            for rid in self.variants.setdefault(rule, []):
                if self._same(rid, delta):
                    break
            else:
                rid = rule if not self.variants[rule] else self.fresh()
                self.variants[rule].append(rid)
        if rid not in self.deltas:
            self.deltas[rid] = delta
            self.origin[rid] = rule
        if key is not None:
            self.at.setdefault(key, []).append(rid)
        return rid


def _key(name: str, p: np.ndarray) -> tuple:
    return (name, round(float(p[0]) * 1e4), round(float(p[1]) * 1e4))


def _used_rule_ids(pattern: Pattern) -> set:
    ids = set(pattern.rules.deltas)
    for p in pattern.pieces:
        ids.update(r for r in p.rules if r is not None)
        for attr in ("internal_lines", "cutouts", "sew_lines"):
            for pl in getattr(p, attr):
                ids.update(r for r in pl.rules if r is not None)
        for attr in ("grain_line", "grade_reference", "mirror_line"):
            line = getattr(p, attr)
            if line is not None:
                ids.update(r for r in line.rules if r is not None)
        ids.update(h.rule for h in p.drill_holes if h.rule is not None)
        ids.update(n.rule for n in p.notches if n.rule is not None)
    return ids


def _nest_sizes(sample: Pattern, nest: Mapping) -> tuple[str, ...]:
    keys = [str(s) for s in nest]
    if sample.sizes and set(keys) <= set(sample.sizes):
        sizes = tuple(sample.sizes)
    else:
        sizes = tuple(keys)
        if sample.sample_size and sample.sample_size not in sizes:
            sizes = (*sizes, sample.sample_size)
    return sizes


def _stack(sample_pts: np.ndarray, per_size: list) -> np.ndarray | None:
    """(n_sizes, n, 2) from a list of arrays or None (None = take the sample)."""
    out = []
    for pts in per_size:
        if pts is None:
            out.append(sample_pts)
            continue
        pts = np.asarray(pts, dtype=np.float64)
        if pts.shape != sample_pts.shape:
            return None
        out.append(pts)
    return np.stack(out) if out else None


def _nest_entries(piece: Piece, nest: Mapping, sizes: Sequence[str], sample_size: str) -> list:
    """The piece in every size of the nest (an outline or a Piece); None for a sample size the nest lacks."""
    per_size = []
    for size in sizes:
        if size == sample_size and size not in nest:
            per_size.append(None)
            continue
        try:
            per_size.append(nest[size][piece.name])
        except KeyError:
            raise ValueError(f"graded nest: piece {piece.name!r} missing in size {size!r}") from None
    return per_size


def _outline_stack(piece: Piece, per_size: list, sizes: Sequence[str]) -> np.ndarray:
    """(n_sizes, n, 2) the piece's outline in every size; ValueError when a vertex count differs."""
    outlines = [v.outline if isinstance(v, Piece) else v for v in per_size]
    stack = _stack(piece.outline, outlines)
    if stack is None:
        counts = {s: len(np.asarray(o)) for s, o in zip(sizes, outlines, strict=True) if o is not None}
        raise ValueError(
            f"graded nest: piece {piece.name!r} has {piece.n_vertices} vertices in the sample but {counts} across sizes"
        )
    return stack


def _in_rule_frame(inv: np.ndarray, pts_stack: np.ndarray, base: np.ndarray) -> np.ndarray:
    """(n, n_sizes, 2) deltas in the rule frame of (n_sizes, n, 2) positions from ``base``; ``inv`` rotates into it."""
    return np.einsum("ij,snj->nsi", inv, pts_stack - base[None])


def _rule_points(piece: Piece, every_vertex: bool) -> tuple[list, list[bool]]:
    """The piece's rule ids and which vertices are rule points.

    Every vertex with ``every_vertex``; else the vertices with a rule id, or,
    on a piece without any, its turn points (every vertex when it has none)
    with fresh ids.
    """
    rules = list(piece.rules)
    has_rule = [r is not None for r in rules]
    if every_vertex:
        has_rule = [True] * piece.n_vertices
    elif not any(has_rule):
        turn = [k == VertexKind.TURN for k in piece.kinds]
        has_rule = turn if any(turn) else [True] * piece.n_vertices
        rules = [None] * piece.n_vertices
    return rules, has_rule


def _nest_piece(
    piece: Piece, per_size: list, sizes: Sequence[str], sample_size: str, book: _RuleBook, every_vertex: bool
) -> Piece:
    """The sample piece with rule ids whose deltas (stored in ``book``) reproduce ``per_size``.

    When every size is a full Piece, its internal lines, cutouts, sew lines,
    grain/grade-reference/mirror lines and drill holes get rules too.
    """
    stack = _outline_stack(piece, per_size, sizes)
    local = functools.partial(_in_rule_frame, _rotation(-frame_angle(piece)))
    d = local(stack, piece.outline)
    rules, has_rule = _rule_points(piece, every_vertex)
    new_rules = [
        book.assign(rules[i], d[i], _key(piece.name, piece.outline[i])) if has_rule[i] else None
        for i in range(piece.n_vertices)
    ]
    changes: dict = {"rules": tuple(new_rules)}
    full = [v if isinstance(v, Piece) else None for v in per_size]
    if all(v is not None or s == sample_size for v, s in zip(full, sizes, strict=True)) and any(full):
        changes.update(_derive_elements(piece, full, sizes, book, local))
    return dataclasses.replace(piece, **changes)


def rules_from_nest(
    sample: Pattern,
    nest: Mapping[str, Mapping[str, np.ndarray | Piece]],
    *,
    atol_cm: float = _SAME_RULE_CM,
    every_vertex: bool = False,
) -> Pattern:
    """Derive grade rules from a graded nest and return the sample with them.

    Parameters
    ----------
    sample : Pattern
        Pieces in the sample size; boundary vertices that carry a rule id are
        the rule points. A piece with no rule point gets fresh rules on its turn
        points (every vertex when it has none).
    nest : {size: {piece name: (n, 2) outline in cm, or a Piece}}
        Every size of every piece, vertex ``i`` corresponding to vertex ``i``
        of the sample. When the values are :class:`Piece` objects, internal
        lines, cutouts, sew lines, grain / grade-reference / mirror lines and
        drill holes are derived too (matched by order, skipped where counts
        differ); their points without a rule id get fresh ids.
    atol_cm : points sharing a rule id whose displacements differ by more
        than this get split into separate ids.
    every_vertex : make every boundary vertex a rule point (fresh ids where
        the sample has none), so grading reproduces the nest's own curves
        instead of following them by arc length between the rule points.

    Returns
    -------
    Pattern
        ``sample`` with ``sizes``, ``rules`` and re-labelled per-vertex rule ids.
        Grading it back to any nest size reproduces the nest at every rule
        point (to ``atol_cm``).

    Raises
    ------
    ValueError
        When a piece is missing from a size or its vertex count differs.
    """
    sizes = _nest_sizes(sample, nest)
    nest = {str(s): v for s, v in nest.items()}
    book = _RuleBook(_used_rule_ids(sample), atol_cm)
    pieces = [
        _nest_piece(
            piece, _nest_entries(piece, nest, sizes, sample.sample_size), sizes, sample.sample_size, book, every_vertex
        )
        for piece in sample.pieces
    ]
    table = GradeRuleTable(
        name=sample.rules.name or sample.style,
        sizes=sizes,
        sample_size=sample.sample_size,
        deltas=book.deltas,
    )
    return dataclasses.replace(sample, pieces=tuple(pieces), sizes=sizes, rules=table)


def _derive_elements(piece: Piece, full: list, sizes, book: _RuleBook, local) -> dict:
    changes: dict = {}

    def others(attr):
        return [None if v is None else getattr(v, attr) for v in full]

    for attr in ("internal_lines", "cutouts", "sew_lines"):
        items = getattr(piece, attr)
        per = others(attr)
        if any(o is not None and len(o) != len(items) for o in per):
            continue
        new = []
        for j, pl in enumerate(items):
            stack = _stack(pl.points, [None if o is None else o[j].points for o in per])
            if stack is None:
                new.append(pl)
                continue
            d = local(stack, pl.points)
            new.append(
                dataclasses.replace(
                    pl,
                    rules=tuple(book.assign(r, d[i], _key(piece.name, pl.points[i])) for i, r in enumerate(pl.rules)),
                )
            )
        changes[attr] = tuple(new)
    for attr in ("grain_line", "grade_reference", "mirror_line"):
        line = getattr(piece, attr)
        per = others(attr)
        if line is None or any(o is None for o, s in zip(per, full, strict=True) if s is not None):
            continue
        stack = _stack(line.points, [None if o is None else o.points for o in per])
        if stack is not None:
            d = local(stack, line.points)
            changes[attr] = dataclasses.replace(
                line,
                rules=tuple(book.assign(r, d[i], _key(piece.name, line.points[i])) for i, r in enumerate(line.rules)),
            )
    if piece.drill_holes:
        per = others("drill_holes")
        if all(o is None or len(o) == len(piece.drill_holes) for o in per):
            base = np.array([h.position for h in piece.drill_holes])
            stack = _stack(base, [None if o is None else np.array([h.position for h in o]) for o in per])
            if stack is not None:
                d = local(stack, base)
                changes["drill_holes"] = tuple(
                    dataclasses.replace(h, rule=book.assign(h.rule, d[i], _key(piece.name, h.position)))
                    for i, h in enumerate(piece.drill_holes)
                )
    return changes


def derive_rules(
    sample: Pattern,
    nest: Mapping[str, Mapping[str, np.ndarray | Piece]],
    *,
    atol_cm: float = _SAME_RULE_CM,
    every_vertex: bool = False,
) -> GradeRuleTable:
    """The grade-rule table of a graded nest (see :func:`rules_from_nest`).

    When the sample shares one rule id between points that move differently
    in the nest, the table holds split-off ids the sample does not reference;
    use :func:`rules_from_nest` to get the re-labelled pattern with the table.
    """
    return rules_from_nest(sample, nest, atol_cm=atol_cm, every_vertex=every_vertex).rules


# --------------------------------------------------------------------------- a new size


def _insert_column(old: np.ndarray, new: np.ndarray, k: int) -> np.ndarray:
    """(n_sizes + 1, 2) ``old`` (n_sizes, 2) with the row ``new`` inserted at ``k``.

    Examples
    --------
    >>> _insert_column(np.zeros((2, 2)), np.ones(2), 1).tolist()
    [[0.0, 0.0], [1.0, 1.0], [0.0, 0.0]]
    """
    return np.insert(np.asarray(old), k, new, axis=0)


def _size_table(pattern: Pattern, size: str, outlines: Mapping[str, np.ndarray], position: int | None):
    """The rule table to extend (a one-size table when the pattern has none), its sizes and where ``size`` goes.

    Raises
    ------
    ValueError
        On a duplicate size name, a missing piece or a position out of range.
    """
    table = pattern.rules
    old_sizes = tuple(table.sizes) or (pattern.sample_size or "sample",)
    if size in old_sizes:
        raise ValueError(f"add_size: size {size!r} is already in the size list {list(old_sizes)}")
    if not table.sizes:
        table = GradeRuleTable(name=table.name or pattern.style, sizes=old_sizes, sample_size=old_sizes[0], deltas={})
    missing = [p.name for p in pattern.pieces if p.name not in outlines]
    if missing:
        raise ValueError(f"add_size: no outline for pieces {missing} in size {size!r}")
    k_new = len(old_sizes) if position is None else int(position)
    if not 0 <= k_new <= len(old_sizes):
        raise ValueError(f"add_size: position {position} outside 0..{len(old_sizes)}")
    return table, old_sizes, k_new


class _Widening:
    """The rule table of a pattern growing one size column at index ``k``.

    ``deltas`` collects the widened (n_sizes + 1, 2) deltas by rule id and
    ``new_col`` the new column of each id, across all pieces: a rule shared by
    pieces keeps one new displacement, or is split.
    """

    def __init__(self, table: GradeRuleTable, k: int, book: _RuleBook, atol_cm: float) -> None:
        self.table = table
        self.k = k
        self.book = book
        self.atol = atol_cm
        self.deltas: dict[str, np.ndarray] = {}
        self.new_col: dict[str, np.ndarray] = {}

    def boundary_rules(self, piece: Piece, new_local: np.ndarray, old_local: np.ndarray) -> tuple[str, ...]:
        """A rule id per boundary vertex that moves it by ``new_local[i]`` in the new size.

        A vertex keeps its rule when the rule's new column is still free or
        already holds this displacement; otherwise (and for a vertex without a
        rule) it gets a fresh id whose old columns are ``old_local[i]``.
        """
        rules = []
        for i, r in enumerate(piece.rules):
            if r is not None and r in self.table.deltas:
                if r not in self.new_col:
                    self.new_col[r] = new_local[i]
                    self.deltas[r] = _insert_column(self.table.deltas[r], new_local[i], self.k)
                    rules.append(r)
                    continue
                if np.max(np.abs(self.new_col[r] - new_local[i])) <= self.atol:
                    rules.append(r)
                    continue
            rid = self.book.fresh()
            self.deltas[rid] = _insert_column(old_local[i], new_local[i], self.k)
            self.new_col[rid] = new_local[i]
            rules.append(rid)
        return tuple(rules)

    def off_boundary(self, piece: Piece, moved: np.ndarray, inv: np.ndarray) -> None:
        """Rules used only off the boundary get the new-size displacement ``moved``
        of the nearest boundary vertex of the first point that uses them."""
        for pts, rls in _off_boundary_points(piece):
            for p, r in zip(pts, rls, strict=True):
                if r is None or r in self.deltas or r not in self.table.deltas:
                    continue
                near = int(_nearest_vertex(np.asarray(p, float)[None], piece.outline)[0])
                self.deltas[r] = _insert_column(self.table.deltas[r], moved[near] @ inv.T, self.k)

    def finished(self) -> dict[str, np.ndarray]:
        """The widened deltas; rules nothing references keep a zero column."""
        for r, d in self.table.deltas.items():
            if r not in self.deltas:
                self.deltas[r] = _insert_column(d, np.zeros(2), self.k)
        return self.deltas


def add_size(
    pattern: Pattern,
    size: str,
    outlines: Mapping[str, np.ndarray],
    position: int | None = None,
    *,
    atol_cm: float = _SAME_RULE_CM,
) -> Pattern:
    """Append a freely shaped size as one more column of the grade-rule table.

    Every boundary vertex becomes a rule point: vertices without a rule get a
    fresh id whose existing columns hold the displacement grading gave them
    before, and a shared id whose points need different displacements in the
    new size is split. Grading to any original size therefore still gives
    exactly what it gave before, and grading to ``size`` gives ``outlines``.

    Parameters
    ----------
    pattern : Pattern in its sample size
    size : name of the new size (must not be in the size list yet)
    outlines : {piece name: (n, 2) cm}, vertex ``i`` corresponding to vertex
        ``i`` of the sample piece; every piece must be given
    position : index in the size list for the new size (default: last)

    Returns
    -------
    Pattern
        With ``sizes``, ``rules`` and per-vertex rule ids extended.

    Raises
    ------
    ValueError
        On a duplicate size name, a missing piece or a vertex-count mismatch.
    """
    size = str(size)
    table, old_sizes, k_new = _size_table(pattern, size, outlines, position)
    new_sizes = (*old_sizes[:k_new], size, *old_sizes[k_new:])
    widening = _Widening(table, k_new, _RuleBook(_used_rule_ids(pattern), atol_cm), atol_cm)
    boundary = []
    for piece in pattern.pieces:
        target = np.asarray(outlines[piece.name], dtype=np.float64)
        if target.shape != piece.outline.shape:
            raise ValueError(
                f"add_size: piece {piece.name!r} has {piece.n_vertices} vertices, size {size!r} gives {target.shape}"
            )
        inv = _rotation(-frame_angle(piece))
        disp = piece_displacements(piece, table)
        old_local = np.einsum("ij,snj->nsi", inv, disp["outline"])  # (n, n_sizes, 2)
        new_local = (target - piece.outline) @ inv.T  # (n, 2)
        boundary.append((piece, widening.boundary_rules(piece, new_local, old_local), target, inv))
    out_pieces = []
    for piece, rules, target, inv in boundary:
        widening.off_boundary(piece, target - piece.outline, inv)
        out_pieces.append(dataclasses.replace(piece, rules=rules))
    new_table = GradeRuleTable(
        name=table.name, sizes=new_sizes, sample_size=table.sample_size, deltas=widening.finished()
    )
    return dataclasses.replace(pattern, pieces=tuple(out_pieces), sizes=new_sizes, rules=new_table)


def _off_boundary_points(piece: Piece):
    for attr in ("internal_lines", "cutouts", "sew_lines"):
        for pl in getattr(piece, attr):
            yield pl.points, pl.rules
    for attr in ("grain_line", "grade_reference", "mirror_line"):
        line = getattr(piece, attr)
        if line is not None:
            yield line.points, line.rules
    for h in piece.drill_holes:
        yield h.position[None], (h.rule,)
    for n in piece.notches:
        if n.rule is not None:
            yield piece.outline[n.vertex][None], (n.rule,)
