"""The DXF-AAMA / ASTM D6673 layer table as data, shared by the reader and the writer.

Layer names in these files are decimal numbers written as strings (``"1"``,
``"84"``). :data:`LAYERS` maps each number to what it carries; the named
constants on :class:`Layer` are what code should use instead of bare numbers.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import IntEnum
from types import MappingProxyType

from ...pattern.model import NotchType

__all__ = [
    "LAYERS",
    "NOTCH_LAYERS",
    "NOTCH_LAYER_BY_TYPE",
    "NOTCH_TYPE_BY_LAYER",
    "RULE_POINT_LAYERS",
    "VALIDATION_LAYERS",
    "Layer",
    "LayerInfo",
    "layer_number",
]


class Layer(IntEnum):
    """Layer numbers of ASTM D6673 (and the AAMA-292 subset)."""

    BOUNDARY = 1  # cut line polyline(s) + style/piece system text
    TURN_POINTS = 2  # POINTs on turn (corner) vertices of 1, 8, 11, 14
    CURVE_POINTS = 3  # POINTs on curve vertices of 1, 8, 11, 14
    NOTCH = 4  # slit / V notch POINT (30 depth, 39 width, 50 angle)
    GRADE_REFERENCE = 5  # grade reference line (frame of the grade rules)
    MIRROR = 6  # mirror (fold) line
    GRAIN = 7  # grain line, tail -> head
    INTERNAL = 8  # internal lines drawn, not cut (+ TEXT labels)
    STRIPE = 9  # stripe reference line
    PLAID = 10  # plaid reference line
    CUTOUT = 11  # internal cutouts
    CUTTER = 12  # ASTM: blank; AAMA: cutter instruction
    DRILL = 13  # drill holes (POINT, Z = diameter)
    SEW = 14  # sew lines
    ANNOTATION = 15  # annotation text
    T_NOTCH = 80
    CASTLE_NOTCH = 81
    CHECK_NOTCH = 82
    U_NOTCH = 83
    VALIDATION_BOUNDARY = 84  # dense copy of 1 for the receiver's curve check
    VALIDATION_INTERNAL = 85  # ... of 8
    VALIDATION_CUTOUT = 86  # ... of 11
    VALIDATION_SEW = 87  # ... of 14


@dataclass(frozen=True, slots=True, kw_only=True)
class LayerInfo:
    """What one layer carries.

    entities : DXF entity types met on the layer in real exports
    kept : whether the reader keeps the content in the model
    model_field : the :class:`~patternbridge.pattern.model.Piece` field it feeds
    """

    number: int
    name: str
    meaning: str
    entities: tuple[str, ...]
    kept: bool
    model_field: str = ""


def _info(number, name, meaning, entities, kept, field=""):
    return LayerInfo(number=number, name=name, meaning=meaning, entities=entities, kept=kept, model_field=field)


LAYERS = MappingProxyType(
    {
        1: _info(1, "boundary", "piece boundary (cut line), style and piece system text",
                 ("POLYLINE", "LINE", "TEXT", "ATTDEF"), True, "outline"),
        2: _info(2, "turn points", "turn points of layers 1, 8, 11, 14 (+ AAMA '# n' rule texts)",
                 ("POINT", "TEXT"), True, "kinds"),
        3: _info(3, "curve points", "curve points of layers 1, 8, 11, 14 (+ AAMA '# n' rule texts)",
                 ("POINT", "TEXT"), True, "kinds"),
        4: _info(4, "notches", "slit / V notches", ("POINT", "LINE"), True, "notches"),
        5: _info(5, "grade reference", "grade reference line: +x of the grade rules", ("LINE",), True,
                 "grade_reference"),
        6: _info(6, "mirror line", "mirror (fold) line", ("LINE",), True, "mirror_line"),
        7: _info(7, "grain line", "grain line, tail to head", ("LINE",), True, "grain_line"),
        8: _info(8, "internal lines", "internal lines (drawn, not cut) and their labels",
                 ("LINE", "POLYLINE", "TEXT"), True, "internal_lines"),
        9: _info(9, "stripe reference", "stripe reference line", ("LINE",), False),
        10: _info(10, "plaid reference", "plaid reference line", ("LINE",), False),
        11: _info(11, "internal cutouts", "internal cutouts", ("POLYLINE",), True, "cutouts"),
        12: _info(12, "cutter instruction", "blank in ASTM, cutter instruction in AAMA", (), False),
        13: _info(13, "drill holes", "drill holes (Z = diameter)", ("POINT", "TEXT"), True, "drill_holes"),
        14: _info(14, "sew lines", "sew lines", ("POLYLINE",), True, "sew_lines"),
        15: _info(15, "annotation", "annotation text", ("TEXT",), True, "annotations"),
        80: _info(80, "T notches", "T notches", ("POINT",), True, "notches"),
        81: _info(81, "castle notches", "castle (box) notches", ("POINT",), True, "notches"),
        82: _info(82, "check notches", "check notches", ("POINT",), True, "notches"),
        83: _info(83, "U notches", "U notches", ("POINT",), True, "notches"),
        84: _info(84, "boundary validation", "quality-validation curve of layer 1", ("POLYLINE",), False),
        85: _info(85, "internal validation", "quality-validation curve of layer 8", ("POLYLINE", "TEXT"),
                  False),
        86: _info(86, "cutout validation", "quality-validation curve of layer 11", ("POLYLINE",), False),
        87: _info(87, "sew validation", "quality-validation curve of layer 14", ("POLYLINE",), False),
    }
)
"""Layer number -> :class:`LayerInfo` for every layer the reader recognises."""

NOTCH_TYPE_BY_LAYER = MappingProxyType(
    {4: NotchType.SLIT, 80: NotchType.T, 81: NotchType.CASTLE, 82: NotchType.CHECK, 83: NotchType.U}
)
"""Notch layer -> notch type; layer 4 is a V notch when its width (group 39) is > 0."""

NOTCH_LAYER_BY_TYPE = MappingProxyType(
    {
        NotchType.SLIT: 4,
        NotchType.V: 4,
        NotchType.T: 80,
        NotchType.CASTLE: 81,
        NotchType.CHECK: 82,
        NotchType.U: 83,
    }
)
"""Notch type -> layer the writer puts it on."""

NOTCH_LAYERS = frozenset(NOTCH_TYPE_BY_LAYER)
VALIDATION_LAYERS = frozenset({84, 85, 86, 87})
RULE_POINT_LAYERS = frozenset({2, 3})


def layer_number(name: str) -> int | None:
    """Layer name as written in the file -> number, or ``None`` for named layers.

    Examples
    --------
    >>> layer_number(" 84"), layer_number("0"), layer_number("CUT")
    (84, 0, None)
    """
    try:
        return int(str(name).strip())
    except ValueError:
        return None
