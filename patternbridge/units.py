"""Length units: the only place conversion factors live.

Internal lengths are centimetres and angles radians. DXF METRIC files are in
millimetres, ENGLISH files in inches; meshes may arrive in m, cm, mm or inches.
"""

from __future__ import annotations

from typing import Final

from .errors import UnitsError

__all__ = ["CM_PER_UNIT", "from_cm", "to_cm", "unit_factor"]

CM_PER_UNIT: Final[dict[str, float]] = {
    "mm": 0.1,
    "cm": 1.0,
    "dm": 10.0,
    "m": 100.0,
    "in": 2.54,
    "inch": 2.54,
    "ft": 30.48,
    # DXF-AAMA/ASTM `Units:` keywords
    "METRIC": 0.1,
    "ENGLISH": 2.54,
}


def unit_factor(unit: str) -> float:
    """Return how many centimetres one ``unit`` is.

    Examples
    --------
    >>> unit_factor("mm")
    0.1
    >>> unit_factor("ENGLISH")
    2.54
    """
    try:
        return CM_PER_UNIT[unit]
    except KeyError:
        key = unit.strip()
        for candidate in (key, key.lower(), key.upper()):
            if candidate in CM_PER_UNIT:
                return CM_PER_UNIT[candidate]
        known = ", ".join(sorted(CM_PER_UNIT))
        raise UnitsError(f"unknown length unit {unit!r} (known: {known})") from None


def to_cm(value, unit: str):
    """Convert ``value`` (scalar or array) from ``unit`` to centimetres."""
    return value * unit_factor(unit)


def from_cm(value, unit: str):
    """Convert ``value`` (scalar or array) from centimetres to ``unit``."""
    return value / unit_factor(unit)
