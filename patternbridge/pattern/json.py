"""Canonical JSON form of a :class:`~patternbridge.pattern.model.Pattern`.

Pure conversion between the model and plain JSON-ready dicts; the schema is
``formats/pattern.schema.json`` and the round trip is lossless (floats are
written with ``repr`` precision by :mod:`json`). File reading and writing live in
``patternbridge.io.pattern_json``.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .json_check import check_pattern_dict
from .model import (
    Annotation,
    DrillHole,
    EdgeRange,
    FabricClass,
    GradeRuleTable,
    Leg,
    Line,
    MeasurementLink,
    Notch,
    Pattern,
    Piece,
    Placement,
    Polyline,
    Provenance,
    Quantity,
    Seam,
)

__all__ = [
    "FORMAT_VERSION",
    "fabric_to_dict",
    "measurement_link_from_dict",
    "measurement_link_to_dict",
    "pattern_from_dict",
    "pattern_to_dict",
    "placement_to_dict",
    "seam_from_dict",
    "seam_to_dict",
]

FORMAT_VERSION = "1.0"
_FORMAT_ID = "patternbridge.pattern"


def _xy(a: np.ndarray) -> list:
    return np.asarray(a, dtype=np.float64).tolist()


def _kinds(kinds) -> list[str]:
    return [str(k) for k in kinds]


def _polyline_to_dict(p: Polyline) -> dict[str, Any]:
    out: dict[str, Any] = {"points": _xy(p.points), "kinds": _kinds(p.kinds), "rules": list(p.rules)}
    if p.closed:
        out["closed"] = True
    if p.label is not None:
        out["label"] = p.label
    return out


def _polyline_from_dict(d: dict[str, Any]) -> Polyline:
    return Polyline(
        points=d["points"],
        kinds=d.get("kinds"),
        rules=d.get("rules"),
        closed=bool(d.get("closed", False)),
        label=d.get("label"),
    )


def _line_to_dict(line: Line | None) -> dict[str, Any] | None:
    if line is None:
        return None
    return {"points": _xy(line.points), "rules": list(line.rules)}


def _line_from_dict(d: dict[str, Any] | None) -> Line | None:
    if d is None:
        return None
    return Line(points=d["points"], rules=tuple(d.get("rules", (None, None))))


def _notch_to_dict(n: Notch) -> dict[str, Any]:
    out: dict[str, Any] = {
        "vertex": n.vertex,
        "type": str(n.type),
        "depth_cm": n.depth_cm,
        "width_cm": n.width_cm,
        "angle": n.angle,
    }
    if n.source_angle_deg is not None:
        out["source_angle_deg"] = n.source_angle_deg
    if n.rule is not None:
        out["rule"] = n.rule
    return out


def _piece_to_dict(p: Piece) -> dict[str, Any]:
    out: dict[str, Any] = {
        "name": p.name,
        "size": p.size,
        "quantity": {"right": p.quantity.right, "left": p.quantity.left},
        "category": p.category,
        "annotation": p.annotation,
        "fabric": p.fabric,
        "outline": _xy(p.outline),
        "kinds": _kinds(p.kinds),
        "rules": list(p.rules),
        "notches": [_notch_to_dict(n) for n in p.notches],
        "grain_line": _line_to_dict(p.grain_line),
        "grade_reference": _line_to_dict(p.grade_reference),
        "mirror_line": _line_to_dict(p.mirror_line),
        "internal_lines": [_polyline_to_dict(x) for x in p.internal_lines],
        "cutouts": [_polyline_to_dict(x) for x in p.cutouts],
        "drill_holes": [
            {"position": _xy(h.position), "diameter_cm": h.diameter_cm, "rule": h.rule, "label": h.label}
            for h in p.drill_holes
        ],
        "sew_lines": [_polyline_to_dict(x) for x in p.sew_lines],
        "annotations": [
            {"text": a.text, "position": _xy(a.position), "height_cm": a.height_cm, "angle": a.angle, "layer": a.layer}
            for a in p.annotations
        ],
        "marks": dict(p.marks),
        "landmarks": dict(p.landmarks),
        "placement": placement_to_dict(p.placement),
        "extra_text": dict(p.extra_text),
    }
    if p.role is not None:
        out["role"] = str(p.role)
        if p.role_confidence is not None:
            out["role_confidence"] = p.role_confidence
    if p.fabric_class is not None:
        out["fabric_class"] = str(p.fabric_class)
    return out


def _piece_from_dict(d: dict[str, Any]) -> Piece:
    q = d.get("quantity", {"right": 1, "left": 0})
    pl = d.get("placement")
    return Piece(
        name=d["name"],
        size=d.get("size", ""),
        quantity=Quantity(right=int(q["right"]), left=int(q["left"])),
        category=d.get("category", ""),
        annotation=d.get("annotation", ""),
        fabric=d.get("fabric", ""),
        outline=d["outline"],
        kinds=d.get("kinds"),
        rules=d.get("rules"),
        notches=tuple(
            Notch(
                vertex=n["vertex"],
                type=n.get("type", "slit"),
                depth_cm=n.get("depth_cm", 0.5),
                width_cm=n.get("width_cm", 0.0),
                angle=n.get("angle", 0.0),
                source_angle_deg=n.get("source_angle_deg"),
                rule=n.get("rule"),
            )
            for n in d.get("notches", ())
        ),
        grain_line=_line_from_dict(d.get("grain_line")),
        grade_reference=_line_from_dict(d.get("grade_reference")),
        mirror_line=_line_from_dict(d.get("mirror_line")),
        internal_lines=tuple(_polyline_from_dict(x) for x in d.get("internal_lines", ())),
        cutouts=tuple(_polyline_from_dict(x) for x in d.get("cutouts", ())),
        drill_holes=tuple(
            DrillHole(
                position=h["position"], diameter_cm=h.get("diameter_cm", 0.0), rule=h.get("rule"), label=h.get("label")
            )
            for h in d.get("drill_holes", ())
        ),
        sew_lines=tuple(_polyline_from_dict(x) for x in d.get("sew_lines", ())),
        annotations=tuple(
            Annotation(
                text=a["text"],
                position=a["position"],
                height_cm=a.get("height_cm", 0.5),
                angle=a.get("angle", 0.0),
                layer=a.get("layer", 15),
            )
            for a in d.get("annotations", ())
        ),
        marks=d.get("marks", {}),
        landmarks=d.get("landmarks", {}),
        placement=None if pl is None else Placement(**pl),
        extra_text=d.get("extra_text", {}),
        role=d.get("role"),
        role_confidence=d.get("role_confidence"),
        fabric_class=d.get("fabric_class"),
    )


def _edge_to_dict(e: EdgeRange) -> dict[str, Any]:
    return {"piece": e.piece, "start": e.start, "end": e.end, "copy": str(e.copy)}


def placement_to_dict(placement: Placement | None) -> dict[str, Any] | None:
    """JSON form of a piece's placement hint (``None`` stays ``None``)."""
    if placement is None:
        return None
    out = {
        "body_part": str(placement.body_part),
        "side": str(placement.side),
        "anchor": placement.anchor,
        "anchor_mark": placement.anchor_mark,
    }
    return out | ({"drop_cm": placement.drop_cm} if placement.drop_cm else {})


def seam_to_dict(seam: Seam) -> dict[str, Any]:
    """JSON form of a seam (also used by the bridge-data sidecar)."""
    return {
        "id": seam.id,
        "a": _edge_to_dict(seam.a),
        "b": _edge_to_dict(seam.b),
        "kind": str(seam.kind),
        "reverse": seam.reverse,
        "ease_cm": seam.ease_cm,
    }


def seam_from_dict(d: dict[str, Any]) -> Seam:
    """Inverse of :func:`seam_to_dict` (``kind``, ``reverse``, ``ease_cm`` optional)."""
    return Seam(
        id=d["id"],
        a=EdgeRange(**d["a"]),
        b=EdgeRange(**d["b"]),
        kind=d.get("kind", "seam"),
        reverse=bool(d.get("reverse", True)),
        ease_cm=float(d.get("ease_cm", 0.0)),
    )


def measurement_link_to_dict(link: MeasurementLink) -> dict[str, Any]:
    """JSON form of a measurement link (also used by the bridge-data sidecar).

    ``at_least`` and ``proportional`` are written only when set, so plain
    links keep their form.
    """
    d: dict[str, Any] = {
        "id": link.id,
        "measurement": link.measurement,
        "ease_cm": link.ease_cm,
    }
    if link.at_least:
        d["at_least"] = True
    if link.proportional:
        d["proportional"] = True
    d["legs"] = [
        {"piece": g.piece, "start": g.start, "end": g.end, "along": g.along, "factor": g.factor} for g in link.legs
    ]
    return d


def measurement_link_from_dict(d: dict[str, Any]) -> MeasurementLink:
    """Inverse of :func:`measurement_link_to_dict`."""
    at_least = d.get("at_least", False)
    if not isinstance(at_least, bool):  # "yes" would read as true
        raise ValueError(f"measurement link at_least must be true or false, got {at_least!r}")
    proportional = d.get("proportional", False)
    if not isinstance(proportional, bool):
        raise ValueError(f"measurement link proportional must be true or false, got {proportional!r}")
    return MeasurementLink(
        id=d.get("id", ""),
        measurement=d["measurement"],
        ease_cm=d.get("ease_cm", 0.0),
        at_least=at_least,
        proportional=proportional,
        legs=tuple(Leg(**g) for g in d["legs"]),
    )


def pattern_to_dict(pattern: Pattern) -> dict[str, Any]:
    """Return the canonical JSON-ready dict of ``pattern`` (units: cm, radians)."""
    prov = pattern.provenance
    return {
        "format": _FORMAT_ID,
        "format_version": FORMAT_VERSION,
        "length_unit": "cm",
        "style": pattern.style,
        "description": pattern.description,
        "units": str(pattern.units),
        "sample_size": pattern.sample_size,
        "sizes": list(pattern.sizes),
        "provenance": {
            "producer": prov.producer,
            "product": prov.product,
            "version": prov.version,
            "author": prov.author,
            "created": prov.created,
            "flavor": None if prov.flavor is None else str(prov.flavor),
            "source_file": prov.source_file,
            "extra_text": dict(prov.extra_text),
        },
        "rules": {
            "name": pattern.rules.name,
            "sizes": list(pattern.rules.sizes),
            "sample_size": pattern.rules.sample_size,
            "deltas": {k: _xy(v) for k, v in pattern.rules.deltas.items()},
        },
        "pieces": [_piece_to_dict(p) for p in pattern.pieces],
        "seams": [seam_to_dict(s) for s in pattern.seams],
        "measurements": [measurement_link_to_dict(m) for m in pattern.measurements],
        **fabric_to_dict(pattern),
    }


def fabric_to_dict(pattern: Pattern) -> dict[str, Any]:
    """The garment's ``fabric_class`` and ``fabric_why`` (none for a woven garment whose fabric nothing stated)."""
    if pattern.fabric_class is FabricClass.WOVEN and not pattern.fabric_why:
        return {}
    return {"fabric_class": str(pattern.fabric_class), "fabric_why": pattern.fabric_why}


def pattern_from_dict(d: dict[str, Any]) -> Pattern:
    """Build a :class:`Pattern` from its canonical dict (see :func:`pattern_to_dict`).

    Raises
    ------
    ValueError
        When the dict is not a PatternBridge pattern or a field is malformed.
    """
    if not isinstance(d, dict):
        check_pattern_dict(d)  # names what the top level is instead
    if d.get("format") != _FORMAT_ID:
        raise ValueError(f"not a PatternBridge pattern (format={str(d.get('format'))[:80]!r}, expected {_FORMAT_ID!r})")
    check_pattern_dict(d)
    if d.get("length_unit", "cm") != "cm":
        raise ValueError(f"length_unit must be 'cm', got {d.get('length_unit')!r}")
    prov = d.get("provenance", {})
    rules = d.get("rules", {})
    return Pattern(
        style=d["style"],
        description=d.get("description", ""),
        units=d.get("units", "METRIC"),
        sample_size=d.get("sample_size", ""),
        sizes=tuple(d.get("sizes", ())),
        provenance=Provenance(
            producer=prov.get("producer", ""),
            product=prov.get("product", ""),
            version=prov.get("version", ""),
            author=prov.get("author", ""),
            created=prov.get("created", ""),
            flavor=prov.get("flavor"),
            source_file=prov.get("source_file", ""),
            extra_text=prov.get("extra_text", {}),
        ),
        rules=GradeRuleTable(
            name=rules.get("name", ""),
            sizes=tuple(rules.get("sizes", ())),
            sample_size=rules.get("sample_size", ""),
            deltas=rules.get("deltas", {}),
        ),
        pieces=tuple(_piece_from_dict(p) for p in d["pieces"]),
        seams=tuple(seam_from_dict(s) for s in d.get("seams", ())),
        measurements=tuple(measurement_link_from_dict(m) for m in d.get("measurements", ())),
        fabric_class=d.get("fabric_class", FabricClass.WOVEN),
        fabric_why=d.get("fabric_why", ""),
    )
