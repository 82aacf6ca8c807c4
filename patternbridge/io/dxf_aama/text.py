"""Style and piece system text: ``Key: value`` lines, parsed the way real producers write them.

Keys are case-insensitive and split on the first colon (``Piece Name: X``,
``PIECE NAME: X``, ``Piece Name:X``). Size keys come as ``Size``, ``SIZE``,
``Size Name`` or Richpeace's ``SAMPLE SIZE`` inside a block; ``Quantity`` is a
total in AAMA (``2``) and a right,left pair in ASTM (``1,1``); ``Author`` is
either one vendor string (AAMA, with ``PRODUCT``/``VERSION`` lines) or
``vendor ; application ; release`` (ASTM).
"""

from __future__ import annotations

import re

from ...pattern.model import Quantity, Units

__all__ = [
    "ASTM_MARKER",
    "decode",
    "normal_key",
    "parse_author",
    "parse_quantity",
    "parse_rule_text",
    "parse_units",
    "split_key",
]

ASTM_MARKER = "ASTM/D13PROPOSAL 1 VERSION"
"""Normalised key of the ASTM version line (``ASTM/D13Proposal 1 Version: D 6673-04``)."""

_RULE_TEXT = re.compile(r"^\s*#\s*([^\s,]+)\s*(?:,\s*([^\s,]+)\s*)?$")
_KEY = re.compile(r"^\s*([^:]{1,60}?)\s*:(.*)$")


def decode(data: bytes) -> str:
    """Bytes of a DXF/RUL file as text: UTF-8, else cp1252, else latin-1.

    Examples
    --------
    >>> decode("Ärmel".encode("utf-8")), decode("Ärmel".encode("cp1252"))
    ('Ärmel', 'Ärmel')
    """
    for enc in ("utf-8", "cp1252"):
        try:
            return data.decode(enc)
        except UnicodeDecodeError:
            continue
    return data.decode("latin-1")


def normal_key(key: str) -> str:
    """Upper case, single spaces: ``"Piece  name"`` -> ``"PIECE NAME"``."""
    return " ".join(key.upper().split())


def split_key(text: str) -> tuple[str, str] | None:
    """``"Piece Name: BACK"`` -> ``("PIECE NAME", "BACK")``; ``None`` when there is no key.

    Examples
    --------
    >>> split_key("Piece Name:SLEEVE"), split_key("# 12")
    (('PIECE NAME', 'SLEEVE'), None)
    """
    m = _KEY.match(text)
    if not m:
        return None
    return normal_key(m.group(1)), m.group(2).strip()


def parse_rule_text(text: str) -> tuple[str, str | None] | None:
    """``"# 12"`` -> ``("12", None)``; ``"# 12, 40"`` -> ``("12", "40")``; else ``None``.

    Examples
    --------
    >>> parse_rule_text("# 509"), parse_rule_text("#3, 7"), parse_rule_text("B")
    (('509', None), ('3', '7'), None)
    """
    m = _RULE_TEXT.match(text)
    if not m:
        return None
    return m.group(1), m.group(2)


def parse_quantity(value: str) -> tuple[Quantity, bool] | None:
    """``Quantity:`` value -> ``(Quantity, is_pair)``; ``None`` when unreadable.

    ``"2"`` is a total (AAMA), ``"1,1"`` / ``"1, 0"`` a right,left pair (ASTM).

    Examples
    --------
    >>> parse_quantity("2")
    (Quantity(right=1, left=1), False)
    >>> parse_quantity("1,0")
    (Quantity(right=1, left=0), True)
    """
    nums = re.findall(r"\d+", value)
    if "," in value and len(nums) == 2:
        return Quantity(right=int(nums[0]), left=int(nums[1])), True
    if len(nums) == 1:
        return Quantity.from_total(int(nums[0])), False
    return None


def parse_units(value: str) -> Units | None:
    """``METRIC`` / ``ENGLISH`` (any case, also ``mm`` / ``in``); ``None`` when unknown."""
    v = value.strip().upper()
    if v in ("METRIC", "MM", "MILLIMETER", "MILLIMETERS", "MILLIMETRE", "MILLIMETRES"):
        return Units.METRIC
    if v in ("ENGLISH", "IN", "INCH", "INCHES", "IMPERIAL"):
        return Units.ENGLISH
    return None


def parse_author(value: str) -> tuple[str, str, str]:
    """``"GERBER TECHNOLOGY ; ACCUMARK ; 10.0.1"`` -> (producer, product, version).

    A plain AAMA author gives ``(value, "", "")``.
    """
    parts = [p.strip() for p in value.split(";")]
    if len(parts) >= 3:
        return parts[0], parts[1], ";".join(parts[2:]).strip()
    if len(parts) == 2:
        return parts[0], parts[1], ""
    return value.strip(), "", ""
