"""Test helpers: compare two patterns field by field with a length tolerance.

Like ``shapely.testing``: :func:`assert_patterns_equal` raises an
``AssertionError`` that lists *every* difference (piece, field, values), so a
failing round trip says what was lost.
"""

from __future__ import annotations

import math
import re
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

__all__ = [
    "NOT_IN_DXF",
    "assert_patterns_equal",
    "example_pattern",
    "pattern_differences",
    "timeless",
    "without_stamps",
]

#: fields a DXF cannot carry (bridge data, provenance details, the source's
#: notch angle): pass as ``ignore`` when comparing a pattern with its DXF round trip
NOT_IN_DXF = (
    "provenance",
    "description",
    "seams",
    "measurements",
    "marks",
    "landmarks",
    "placement",
    "source_angle_deg",
)


class _Diff:
    __slots__ = ("atol_cm", "atol_rad", "ignore", "out")

    def __init__(self, atol_cm: float, atol_rad: float, ignore: set[str]) -> None:
        self.atol_cm = atol_cm
        self.atol_rad = atol_rad
        self.ignore = ignore
        self.out: list[str] = []

    def skip(self, name: str, kind: str = "") -> bool:
        return name in self.ignore or (bool(kind) and f"{kind}.{name}" in self.ignore)

    def eq(self, where: str, name: str, a, b, kind: str = "") -> None:
        if self.skip(name, kind):
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
        for i, (x, y) in enumerate(zip(a, b, strict=True)):
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
        self.eq(f"{where}.{name}", "rules", a.rules, b.rules, "line")

    def polyline(self, where: str, a: Polyline, b: Polyline) -> None:
        self.close(where, "points", a.points, b.points)
        self.eq(where, "kinds", a.kinds, b.kinds)
        self.eq(where, "rules", a.rules, b.rules, "polyline")
        self.eq(where, "closed", a.closed, b.closed)
        self.eq(where, "label", a.label, b.label)

    def notch(self, where: str, a: Notch, b: Notch) -> None:
        for f in ("vertex", "type", "rule"):
            self.eq(where, f, getattr(a, f), getattr(b, f), "notch")
        self.close(where, "depth_cm", a.depth_cm, b.depth_cm)
        self.close(where, "width_cm", a.width_cm, b.width_cm)
        self.angle(where, "angle", a.angle, b.angle)
        if not self.skip("source_angle_deg"):
            self.close(
                where,
                "source_angle_deg",
                a.source_angle_deg,
                b.source_angle_deg,
                atol=1e-3,
            )

    def drill(self, where: str, a: DrillHole, b: DrillHole) -> None:
        self.close(where, "position", a.position, b.position)
        self.close(where, "diameter_cm", a.diameter_cm, b.diameter_cm)
        self.eq(where, "rule", a.rule, b.rule, "drill")
        self.eq(where, "label", a.label, b.label)

    def annotation(self, where: str, a: Annotation, b: Annotation) -> None:
        self.eq(where, "text", a.text, b.text)
        self.close(where, "position", a.position, b.position)
        self.close(where, "height_cm", a.height_cm, b.height_cm)
        self.angle(where, "angle", a.angle, b.angle)
        self.eq(where, "layer", a.layer, b.layer)

    def piece(self, where: str, a: Piece, b: Piece) -> None:
        for f in (
            "name",
            "size",
            "kinds",
            "rules",
            "quantity",
            "category",
            "annotation",
            "fabric",
            "placement",
            "fabric_class",
        ):
            self.eq(where, f, getattr(a, f), getattr(b, f), "piece")
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
        if self.skip("rules") or self.skip("table"):
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
        for f in (
            "style",
            "units",
            "sample_size",
            "sizes",
            "description",
            "provenance",
            "seams",
            "measurements",
            "fabric_class",
            "fabric_why",
        ):
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
        "source_angle_deg"}`` (a file format that cannot carry them), or
        qualified by element: ``"piece.rules"``, ``"polyline.rules"``,
        ``"line.rules"``, ``"notch.rule"``, ``"drill.rule"``; ``"table"`` skips
        the grade-rule table, ``"deltas"`` only its values
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


def _bezier(a, c, b, n: int) -> np.ndarray:
    t = np.linspace(0.0, 1.0, n)[:, None]
    return (1 - t) ** 2 * np.asarray(a, float) + 2 * t * (1 - t) * np.asarray(c, float) + t**2 * np.asarray(b, float)


def example_pattern() -> Pattern:
    """A small three-piece tee in size M of S to XL with every element the model has.

    Front (curved armhole and neck, two notches, dart, sew line, drill hole),
    back (cut on fold, T notch) and sleeve (cap curve, cutout); grade rules on
    the front and back turn points, marks, a seam and a measurement link. Used
    by tests and examples; notch angles point into the piece, and a notch or
    line end on a graded vertex carries that vertex's rule (as in a DXF, where
    rule texts attach by position).
    """
    from .pattern.model import EdgeRange, Leg, MeasurementLink, Seam

    front, back, sleeve = _example_front(), _example_back(), _example_sleeve()
    sizes = ("S", "M", "L", "XL")
    return Pattern(
        style="EXAMPLE TEE",
        pieces=(front, back, sleeve),
        sample_size="M",
        sizes=sizes,
        rules=GradeRuleTable(name="EXAMPLE", sizes=sizes, sample_size="M", deltas=_example_deltas((front, back))),
        seams=(
            Seam(
                id="side",
                a=EdgeRange(piece="FRONT", start="hem_side", end="underarm"),
                b=EdgeRange(piece="BACK", start="hem_side", end="underarm"),
            ),
        ),
        measurements=(
            MeasurementLink(
                measurement="hip_girth",
                ease_cm=8.0,
                legs=(
                    Leg(piece="FRONT", start="hem_cf", end="hem_side", factor=2),
                    Leg(piece="BACK", start="hem_cb", end="hem_side", factor=2),
                ),
            ),
        ),
    )


def _example_front() -> Piece:
    """The example's front: curved armhole and neck, a slit and a V notch, a dart, sew line, drill hole, marks."""
    from .pattern.grading import inward_angles
    from .pattern.model import Placement, Quantity

    front_pts = np.vstack(
        [
            [[0.0, 0.0], [25.0, 0.0]],
            _bezier([26, 40], [18, 44], [18, 62], 8)[:-1],
            [[18.0, 62.0]],
            _bezier([8, 60], [8, 52], [0, 52], 7)[:-1],
            [[0.0, 52.0]],
        ]
    )
    n = len(front_pts)
    turn = {0, 1, 2, 9, 10, n - 1}
    kinds = ["turn" if i in turn else "curve" for i in range(n)]
    rules = [str(i + 1) if i in turn else None for i in range(n)]
    f_angles = inward_angles(front_pts, [2, 5])
    return Piece(
        name="FRONT",
        size="M",
        outline=front_pts,
        kinds=kinds,
        rules=rules,
        quantity=Quantity(right=1, left=1),
        category="SHELL",
        fabric="1",
        notches=(
            Notch(
                vertex=2,
                type="slit",
                depth_cm=0.6,
                angle=float(f_angles[0]),
                rule=rules[2],
            ),
            Notch(vertex=5, type="V", depth_cm=0.6, width_cm=0.4, angle=float(f_angles[1])),
        ),
        grain_line=Line(points=[[10, 10], [10, 45]]),
        internal_lines=(Polyline(points=[[6, 20], [9, 35], [12, 20]], kinds=["turn"] * 3, label="B"),),
        sew_lines=(Polyline(points=front_pts * 0.96 + 0.5, closed=True),),
        drill_holes=(DrillHole(position=[9, 33], diameter_cm=0.3, label="D"),),
        annotations=(Annotation(text="TEE FRONT", position=[4.0, 5.0], height_cm=1.0),),
        marks={
            "hem_cf": 0,
            "hem_side": 1,
            "underarm": 2,
            "shoulder": 9,
            "neck_cf": n - 1,
        },
        landmarks={"waist_side_right": "hem_side"},
        placement=Placement(
            body_part="torso",
            side="front",
            anchor="waist_side_right",
            anchor_mark="hem_side",
        ),
    )


def _example_back() -> Piece:
    """The example's back: cut on the fold, a T notch, graded turn points."""
    from .pattern.grading import inward_angles
    from .pattern.model import Quantity

    back_pts = np.array([[0, 0], [24, 0], [25, 40], [17, 60], [6, 62], [0, 61]], float)
    return Piece(
        name="BACK",
        size="M",
        outline=back_pts,
        kinds=["turn"] * 6,
        rules=[str(i + 20) for i in range(6)],
        quantity=Quantity(right=1, left=0),
        mirror_line=Line(points=[[0, 61], [0, 0]], rules=("25", "20")),
        grain_line=Line(points=[[8, 8], [8, 50]]),
        notches=(
            Notch(
                vertex=2,
                type="T",
                depth_cm=0.5,
                width_cm=0.3,
                angle=float(inward_angles(back_pts, [2])[0]),
                rule="22",
            ),
        ),
        marks={"hem_cb": 0, "hem_side": 1, "underarm": 2},
    )


def _example_sleeve() -> Piece:
    """The example's sleeve: a cap curve and a cutout, ungraded."""
    from .pattern.model import Quantity

    cap = _bezier([34, 35], [17, 62], [0, 35], 12)[1:-1]
    sleeve_pts = np.vstack([[[4, 0], [30, 0], [34, 35]], cap, [[0, 35]]])
    return Piece(
        name="SLEEVE",
        size="M",
        outline=sleeve_pts,
        kinds=["turn", "turn", "turn"] + ["curve"] * len(cap) + ["turn"],
        quantity=Quantity(right=1, left=1),
        grain_line=Line(points=[[17, 5], [17, 45]]),
        cutouts=(
            Polyline(
                points=[[14, 15], [20, 15], [20, 18], [14, 18]],
                kinds=["turn"] * 4,
                closed=True,
            ),
        ),
    )


def _example_deltas(pieces: Iterable[Piece]) -> dict[str, np.ndarray]:
    """Rule -> (4, 2) deltas of sizes S to XL: 4 % of x and 2 % of y of the ruled vertex per size step."""
    steps = np.array([-1.0, 0.0, 1.0, 2.0])[:, None]
    deltas = {}
    for piece in pieces:
        for i, rule in enumerate(piece.rules):
            if rule is not None:
                v = piece.outline[i]
                deltas[rule] = steps * np.array([0.04 * v[0], 0.02 * v[1]])
    return deltas


# the DXF/RUL writer stamps the wall-clock creation date and time
_STAMP = re.compile(rb"(?im)^creation (date|time):.*$")


def timeless(obj):
    """A fit report (parsed JSON) without its timings: the only thing two runs of one fit may differ in."""
    if isinstance(obj, dict):
        return {k: timeless(v) for k, v in obj.items() if k != "seconds"}
    if isinstance(obj, list):
        return [timeless(v) for v in obj]
    return obj


def without_stamps(data: bytes) -> bytes:
    """DXF/RUL bytes without the writer's creation date and time (the wall clock, not the fit)."""
    return _STAMP.sub(b"", data)
