"""Read a JSON input file once, at the boundary, with limits a hostile file cannot pass.

Every JSON file PatternBridge reads (patterns, measurements, landmarks, mesh and
bridge-data sidecars, the JSON chunk of a GLB) goes through :func:`loads_json`:

- the text is UTF-8 and at most ``MAX_JSON_BYTES`` long;
- arrays and objects nest at most ``MAX_DEPTH`` deep, checked by a linear scan
  before parsing (a 100 000-deep ``[[[...]]]`` would otherwise end in a
  ``RecursionError`` in the parser or in any code walking the result);
- numbers are finite: the non-standard ``NaN``/``Infinity`` literals and
  overflowing literals such as ``1e400`` (which Python reads as ``inf``) are
  refused.

Magnitudes and types that depend on the meaning of a field are checked by the
reader of that format (``patternbridge.pattern.json_check`` for patterns).
"""

from __future__ import annotations

import json
import math
import os
import re
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import InputError

__all__ = ["MAX_DEPTH", "MAX_JSON_BYTES", "json_depth", "loads_json", "read_json"]

MAX_DEPTH = 64
MAX_JSON_BYTES = 512 * 2**20

# a JSON string literal (escapes included); removed before brackets are counted
_STRING = re.compile(rb'"(?:[^"\\]|\\.)*"', re.DOTALL)


class _BadNumber(ValueError):
    pass


def json_depth(raw: bytes) -> int:
    """Deepest nesting of arrays and objects in the JSON text ``raw`` (0 for a scalar).

    Examples
    --------
    >>> json_depth(b'{"a": [1, [2, "]]]"]]}')
    3
    """
    code = np.frombuffer(_STRING.sub(b'""', raw), dtype=np.uint8)
    step = np.isin(code, (ord("["), ord("{"))).astype(np.int64) - np.isin(code, (ord("]"), ord("}")))
    return int(np.cumsum(step).max(initial=0))


def _constant(name: str) -> Any:
    raise _BadNumber(f"{name} is not a JSON number")


def _float(text: str) -> float:
    value = float(text)
    if not math.isfinite(value):
        raise _BadNumber(f"number {text[:40]} overflows a double")
    return value


def loads_json(raw: bytes, where: str, *, error: type[InputError] = InputError, hint: str = "fix the file") -> Any:
    """Parse JSON bytes under the limits of the module docstring.

    Parameters
    ----------
    raw : the file content.
    where : the file name used in messages.
    error : the :class:`InputError` subclass to raise.
    hint : what the user should do, ending the one-line message.

    Raises
    ------
    InputError (``error``)
        Not UTF-8, not JSON, too deep, too large, or a non-finite number.
    """
    if len(raw) > MAX_JSON_BYTES:
        raise error(f"{where}: JSON file of {len(raw)} bytes is larger than {MAX_JSON_BYTES} bytes; {hint}")
    depth = json_depth(raw)
    if depth > MAX_DEPTH:
        raise error(f"{where}: JSON nests {depth} levels deep (at most {MAX_DEPTH}); {hint}")
    try:
        text = raw.decode("utf-8-sig")
        return json.loads(text, parse_constant=_constant, parse_float=_float)
    except _BadNumber as exc:
        raise error(f"{where}: not valid JSON ({exc}); {hint}") from None
    except UnicodeDecodeError as exc:
        raise error(f"{where}: not UTF-8 text ({exc.reason} at byte {exc.start}); {hint}") from None
    except (ValueError, RecursionError) as exc:
        raise error(f"{where}: not valid JSON ({str(exc)[:200]}); {hint}") from None


def read_json(
    path: str | os.PathLike, *, error: type[InputError] = InputError, hint: str = "fix the file", what: str = "file"
) -> Any:
    """Read and parse the JSON file ``path`` (see :func:`loads_json`).

    Raises
    ------
    InputError (``error``)
        The file is missing or unreadable, or its content fails :func:`loads_json`.
    """
    path = Path(path)
    try:
        raw = path.read_bytes()
    except FileNotFoundError:
        raise error(f"{path}: no such {what}") from None
    except IsADirectoryError:
        raise error(f"{path}: is a folder, not a JSON {what}; {hint}") from None
    except OSError as exc:
        raise error(f"{path}: cannot read the {what} ({exc.strerror}); {hint}") from None
    return loads_json(raw, str(path), error=error, hint=hint)
