"""The canonical pattern model and pure functions over it (no file I/O here).

``model``: frozen dataclasses; ``json``: canonical dict form; ``geometry``:
polygon functions on (n, 2) arrays; ``grading``: sizes from grade rules.
"""

from __future__ import annotations

from .model import (
    Annotation,
    BodyPart,
    Copy,
    DrillHole,
    EdgeRange,
    Flavor,
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
    Side,
    Units,
    VertexKind,
)

__all__ = [
    "Annotation",
    "BodyPart",
    "Copy",
    "DrillHole",
    "EdgeRange",
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
    "Seam",
    "SeamKind",
    "Side",
    "Units",
    "VertexKind",
]
