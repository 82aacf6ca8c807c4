"""Open whatever a user names as a pattern: a JSON file, a DXF file or a library garment."""

from __future__ import annotations

import os
from pathlib import Path

from ..errors import InputError
from ..pattern.model import Pattern
from ..report import Report

__all__ = ["load_pattern"]


def load_pattern(
    spec: str | os.PathLike,
    *,
    rul: str | os.PathLike | None = None,
    units: str | None = None,
) -> tuple[Pattern, Report]:
    """Load a pattern from ``spec``.

    ``spec`` is a canonical ``.json`` file, a DXF-AAMA/ASTM ``.dxf`` file (with
    an optional ``.RUL`` beside it or given as ``rul``), or the name of a garment
    in ``garment_library/`` (``"shirt"``).

    Raises
    ------
    InputError
        When ``spec`` is neither an existing file nor a library garment.
    """
    path = Path(spec)
    if path.is_file():
        suffix = path.suffix.lower()
        if suffix == ".json":
            from .pattern_json import load_pattern_json

            return load_pattern_json(path), _ignored(path.name, rul, units)
        if suffix == ".dxf":
            from .dxf_aama import read_dxf

            return read_dxf(path, rul=rul, units=units)
        raise InputError(f"{path}: unknown pattern file type {suffix!r}; give a .dxf or .json file")
    if path.is_dir():
        raise InputError(
            f"{path}: is a directory; give a pattern file (.json, .dxf) or a library name"
        )
    if path.suffix or os.sep in str(spec):
        raise InputError(f"{path}: no such file")
    from ..library import garment_names, load_garment

    try:
        return load_garment(str(spec)), _ignored(str(spec), rul, units)
    except KeyError:
        names = ", ".join(garment_names())
        raise InputError(f"{spec}: neither a file nor a library garment (library: {names})") from None


def _ignored(where: str, rul, units) -> Report:
    """Findings for DXF-only options given with a pattern that is not a DXF."""
    report = Report()
    for flag, value in (("--rul", rul), ("--units", units)):
        if value is not None:
            report.add(
                "option-ignored",
                f"{flag} {value} applies to a DXF only; this pattern already has its "
                "grade rules and is in centimetres",
                where=where,
            )
    return report
