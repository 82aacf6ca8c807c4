"""Read and write canonical pattern JSON files (``*.json``)."""

from __future__ import annotations

import json
import os
from pathlib import Path

from ..atomic import write_text
from ..errors import InputError
from ..pattern.json import pattern_from_dict, pattern_to_dict
from ..pattern.model import Pattern
from .json_file import read_json

__all__ = ["dumps_pattern", "load_pattern_json", "save_pattern_json"]


def dumps_pattern(pattern: Pattern) -> str:
    """Return the canonical JSON text of ``pattern``."""
    return json.dumps(pattern_to_dict(pattern), indent=1, ensure_ascii=False) + "\n"


def save_pattern_json(pattern: Pattern, path: str | os.PathLike) -> Path:
    """Write ``pattern`` to ``path`` atomically as canonical JSON."""
    return write_text(path, dumps_pattern(pattern))


def load_pattern_json(path: str | os.PathLike) -> Pattern:
    """Read a canonical pattern JSON file.

    Raises
    ------
    InputError
        When the file is missing, is not JSON, or is not a PatternBridge pattern.
    """
    path = Path(path)
    hint = "give a pattern written by 'patternbridge import'"
    data = read_json(path, hint=hint, what="pattern file")
    try:
        return pattern_from_dict(data)
    except (KeyError, TypeError, ValueError) as exc:
        raise InputError(f"{path}: not a valid PatternBridge pattern ({str(exc)[:300]}); {hint}") from None
