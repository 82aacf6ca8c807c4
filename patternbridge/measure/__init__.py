"""Tailoring measurements of a character: convex-hull girths and tape-corrected geodesic lengths."""

from __future__ import annotations

from .definitions import DEFINITIONS, GIRTH_IDS, LENGTH_IDS, MEASUREMENT_IDS, Definition
from .model import (
    Measurement,
    Measurements,
    load_measurements,
    measurements_from_dict,
    measurements_to_dict,
    write_measurements,
)
from .run import measure

__all__ = [
    "DEFINITIONS",
    "GIRTH_IDS",
    "LENGTH_IDS",
    "MEASUREMENT_IDS",
    "Definition",
    "Measurement",
    "Measurements",
    "load_measurements",
    "measure",
    "measurements_from_dict",
    "measurements_to_dict",
    "write_measurements",
]
