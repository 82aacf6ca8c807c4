"""Test helpers: compare two patterns field by field with a length tolerance.

Like ``shapely.testing``: :func:`assert_patterns_equal` raises an
``AssertionError`` that lists *every* difference (piece, field, values), so a
failing round trip says what was lost.
"""

from __future__ import annotations

import math
from collections.abc import Iterable

import numpy as np

from .pattern.model import (
    Annotation,
    DrillHole,
    GradeRuleTable,
    Line,
    Notch,
    Pattern,
    Piece,
    Polyline,
)

__all__ = ["assert_patterns_equal", "pattern_differences"]


class _Diff:
    __slots__ = ("atol_cm", "atol_rad", "ignore", "out")

    def __init__(self, atol_cm: float, atol_rad: float, ignore: set[str]) -> None:
        self.atol_cm = atol_cm
        self.atol_rad = atol_rad
        self.ignore = ignore
        self.out: list[str] = []

    def skip(self, name: str) -> bool:
        return name in self.ignore

    def eq(self, where: str, name: str, a, b) -> None:
        if self.skip(name):
            return
        if a != b:
            self.out.append(f"{where}.{name}: {a!r} != {b!r}")

    def close(self, where: str, name: str, a, b, atol: float | None = None) -> None:
        if self.skip(name):
            return
        atol = self.atol_cm if atol is None else atol
        if a is None or b is None:
            if (a is None) != (b is None):
                self.out.append(f"{where}.{name}: {a!r} != {b!r}")
            return
        a = np.asarray(a, dtype=np.float64)
        b = np.asarray(b, dtype=np.float64)
        if a.shape != b.shape:
            self.out.append(f"{where}.{name}: shape {a.shape} != {b.shape}")
            return
        if a.size == 0:
            return
        err = np.abs(a - b)
        if not np.all(err <= atol):
            i = np.unravel_index(int(np.argmax(err)), err.shape)
            self.out.append(
                f"{where}.{name}: max difference {float(err[i]):.3g} > {atol:g} at index "
                f"{tuple(int(k) for k in i)} ({float(a[i])!r} vs {float(b[i])!r})"
            )

    def angle(self, where: str, name: str, a: float, b: float) -> None:
        if self.skip(name):
            return
        d = (a - b + math.pi) % (2 * math.pi) - math.pi
        if abs(d) > self.atol_rad:
            self.out.append(f"{where}.{name}: {a!r} != {b!r} (difference {d:.3g} rad)")

    def seq(self, where: str, name: str, a, b, item) -> None:
        if self.skip(name):
            return
        if len(a) != len(b):
            self.out.append(f"{where}.{name}: {len(a)} items != {len(b)} items")
            return
        for i, (x, y) in enumerate(zip(a, b)):
            item(f"{where}.{name}[{i}]", x, y)

    # -- elements -------------------------------------------------------------

    def line(self, where: str, name: str, a: Line | None, b: Line | None) -> None:
        if self.skip(name):
            return
        if a is None or b is None:
            if (a is None) != (b is None):
                self.out.append(f"{where}.{name}: {a!r} != {b!r}")
            return
        self.close(f"{where}.{name}", "points", a.points, b.points)
        self.eq(f"{where}.{name}", "rules", a.rules, b.rules)

    def polyline(self, where: str, a: Polyline, b: Polyline) -> None:
        self.close(where, "points", a.points, b.points)
        self.eq(where, "kinds", a.kinds, b.kinds)
        self.eq(where, "rules", a.rules, b.rules)
        self.eq(where, "closed", a.closed, b.closed)
        self.eq(where, "label", a.label, b.label)

    def notch(self, where: str, a: Notch, b: Notch) -> None:
        for f in ("vertex", "type", "rule"):
            self.eq(where, f, getattr(a, f), getattr(b, f))
        self.close(where, "depth_cm", a.depth_cm, b.depth_cm)
        self.close(where, "width_cm", a.width_cm, b.width_cm)
        self.angle(where, "angle", a.angle, b.angle)
        if not self.skip("source_angle_deg"):
            self.close(where, "source_angle_deg", a.source_angle_deg, b.source_angle_deg, atol=1e-3)

    def drill(self, where: str, a: DrillHole, b: DrillHole) -> None:
        self.close(where, "position", a.position, b.position)
        self.close(where, "diameter_cm", a.diameter_cm, b.diameter_cm)
        self.eq(where, "rule", a.rule, b.rule)
        self.eq(where, "label", a.label, b.label)

    def annotation(self, where: str, a: Annotation, b: Annotation) -> None:
        self.eq(where, "text", a.text, b.text)
        self.close(where, "position", a.position, b.position)
        self.close(where, "height_cm", a.height_cm, b.height_cm)
        self.angle(where, "angle", a.angle, b.angle)
        self.eq(where, "layer", a.layer, b.layer)

    def piece(self, where: str, a: Piece, b: Piece) -> None:
        for f in ("name", "size", "kinds", "rules", "quantity", "category", "annotation",
                  "fabric", "placement"):
            self.eq(where, f, getattr(a, f), getattr(b, f))
        for f in ("marks", "landmarks", "extra_text"):
            self.eq(where, f, dict(getattr(a, f)), dict(getattr(b, f)))
        self.close(where, "outline", a.outline, b.outline)
        self.seq(where, "notches", a.notches, b.notches, self.notch)
        for f in ("grain_line", "grade_reference", "mirror_line"):
            self.line(where, f, getattr(a, f), getattr(b, f))
        for f in ("internal_lines", "cutouts", "sew_lines"):
            self.seq(where, f, getattr(a, f), getattr(b, f), self.polyline)
        self.seq(where, "drill_holes", a.drill_holes, b.drill_holes, self.drill)
        self.seq(where, "annotations", a.annotations, b.annotations, self.annotation)

    def rules(self, where: str, a: GradeRuleTable, b: GradeRuleTable) -> None:
        if self.skip("rules"):
            return
        where = f"{where}.rules"
        for f in ("name", "sizes", "sample_size"):
            self.eq(where, f, getattr(a, f), getattr(b, f))
        if self.skip("deltas"):
            return
        ka, kb = set(a.deltas), set(b.deltas)
        if ka != kb:
            self.out.append(
                f"{where}.deltas: rule ids differ (only in first: {sorted(ka - kb)[:10]}, "
                f"only in second: {sorted(kb - ka)[:10]})"
            )
        for k in sorted(ka & kb):
            self.close(where, f"deltas[{k}]", a.deltas[k], b.deltas[k])

    def pattern(self, a: Pattern, b: Pattern) -> None:
        where = "pattern"
        for f in ("style", "units", "sample_size", "sizes", "description", "provenance",
                  "seams", "measurements"):
            self.eq(where, f, getattr(a, f), getattr(b, f))
        self.rules(where, a.rules, b.rules)
        if self.skip("pieces"):
            return
        names_a, names_b = a.piece_names, b.piece_names
        if names_a != names_b:
            self.out.append(f"{where}.pieces: names {list(names_a)} != {list(names_b)}")
        for pa in a.pieces:
            if pa.name in names_b:
                self.piece(f"{where}.pieces[{pa.name}]", pa, b.piece(pa.name))


def pattern_differences(
    a: Pattern,
    b: Pattern,
    *,
    atol_cm: float = 1e-4,
    atol_rad: float = 1e-6,
    ignore: Iterable[str] = (),
) -> list[str]:
    """List every difference between two patterns (empty when they match).

    Parameters
    ----------
    a, b : the patterns to compare
    atol_cm : absolute tolerance on every length and coordinate (cm)
    atol_rad : absolute tolerance on angles (radians, compared modulo 2π)
    ignore : field names to skip wherever they occur, e.g. ``{"provenance",
        "source_angle_deg"}`` (a file format that cannot carry them)
    """
    diff = _Diff(atol_cm, atol_rad, set(ignore))
    diff.pattern(a, b)
    return diff.out


def assert_patterns_equal(
    a: Pattern,
    b: Pattern,
    atol_cm: float = 1e-4,
    *,
    atol_rad: float = 1e-6,
    ignore: Iterable[str] = (),
) -> None:
    """Raise ``AssertionError`` listing every difference between ``a`` and ``b``.

    Every field of the pattern, its rule table and each piece (outline, vertex
    kinds and rules, notches, lines, polylines, drill holes, annotations,
    marks, bridge data) is compared; coordinates within ``atol_cm``.

    Examples
    --------
    >>> from patternbridge.pattern.model import Pattern, Piece
    >>> p = Pattern(style="S", pieces=(Piece(name="a", outline=[(0, 0), (1, 0), (0, 1)]),))
    >>> assert_patterns_equal(p, p)
    """
    out = pattern_differences(a, b, atol_cm=atol_cm, atol_rad=atol_rad, ignore=ignore)
    if out:
        shown = "\n  ".join(out[:40])
        more = f"\n  ... and {len(out) - 40} more" if len(out) > 40 else ""
        raise AssertionError(f"patterns differ in {len(out)} place(s):\n  {shown}{more}")
