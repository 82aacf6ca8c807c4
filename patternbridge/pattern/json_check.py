"""Structural check of a pattern dict before the model is built from it.

:func:`check_pattern_dict` walks a parsed pattern JSON against a compact
description of ``formats/pattern.schema.json`` (types, required keys, finite
numbers within ``MAX_ABS``, text lengths within ``MAX_TEXT``) and raises one
``ValueError`` naming the JSON path of the first problem, e.g.
``pieces[0].outline[3][1]: 1e+308 is outside ±1e+06``. Unknown keys are left
alone so a newer writer's fields do not break an older reader; semantic
checks (marks inside the outline, duplicate names) stay in the model.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

__all__ = ["MAX_ABS", "MAX_TEXT", "check_pattern_dict", "check_sidecar_dict"]

MAX_ABS = 1e6
"""Largest magnitude of any number in a pattern (cm: 10 km; radians; counts)."""
MAX_TEXT = 65_536
"""Longest string in a pattern (names, labels, texts), in characters."""


class _Req:
    """A required key of an object spec."""

    __slots__ = ("spec",)

    def __init__(self, spec: Any) -> None:
        self.spec = spec


class _Opt:
    """A value that may also be ``null``."""

    __slots__ = ("spec",)

    def __init__(self, spec: Any) -> None:
        self.spec = spec


class _List:
    __slots__ = ("item", "length", "min_length")

    def __init__(self, item: Any, length: int | None = None, min_length: int = 0) -> None:
        self.item, self.length, self.min_length = item, length, min_length


class _Map:
    """An object with free keys, every value of one spec."""

    __slots__ = ("value",)

    def __init__(self, value: Any) -> None:
        self.value = value


class _Either:
    """A value matching the first spec or, failing that, the second (whose message is kept)."""

    __slots__ = ("first", "second")

    def __init__(self, first: Any, second: Any) -> None:
        self.first, self.second = first, second


STR, NUM, INT, BOOL = "string", "number", "integer", "boolean"

_POINT = _List(NUM, length=2)
_POINTS = _List(_POINT)
_RULES = _List(_Opt(STR))
_LINE = _Opt({"points": _Req(_List(_POINT, length=2)), "rules": _RULES})
_POLYLINE = {
    "points": _Req(_POINTS),
    "kinds": _Opt(_List(STR)),
    "rules": _Opt(_RULES),
    "closed": BOOL,
    "label": _Opt(STR),
}
_PIECE = {
    "name": _Req(STR),
    "size": STR,
    "quantity": {"right": _Req(INT), "left": _Req(INT)},
    "category": STR,
    "annotation": STR,
    "fabric": STR,
    "outline": _Req(_List(_POINT, min_length=3)),
    "kinds": _Opt(_List(STR)),
    "rules": _Opt(_RULES),
    "notches": _List(
        {
            "vertex": _Req(INT),
            "type": STR,
            "depth_cm": NUM,
            "width_cm": NUM,
            "angle": NUM,
            "source_angle_deg": _Opt(NUM),
            "rule": _Opt(STR),
        }
    ),
    "grain_line": _LINE,
    "grade_reference": _LINE,
    "mirror_line": _LINE,
    "internal_lines": _List(_POLYLINE),
    "cutouts": _List(_POLYLINE),
    "drill_holes": _List({"position": _Req(_POINT), "diameter_cm": NUM, "rule": _Opt(STR), "label": _Opt(STR)}),
    "sew_lines": _List(_POLYLINE),
    "annotations": _List({"text": _Req(STR), "position": _Req(_POINT), "height_cm": NUM, "angle": NUM, "layer": INT}),
    "marks": _Map(INT),
    "landmarks": _Map(STR),
    "placement": _Opt(
        {"body_part": _Req(STR), "side": _Req(STR), "anchor": _Req(STR), "anchor_mark": _Opt(STR), "drop_cm": NUM}
    ),
    "extra_text": _Map(STR),
    "fabric_class": STR,
}
_EDGE = {"piece": _Req(STR), "start": _Req(STR), "end": _Req(STR), "copy": STR}
_SEAM = {"id": _Req(STR), "a": _Req(_EDGE), "b": _Req(_EDGE), "kind": STR, "reverse": BOOL, "ease_cm": NUM}
_LINK = {
    "id": STR,
    "measurement": _Req(STR),
    "ease_cm": NUM,
    "at_least": BOOL,
    "legs": _Req(_List({"piece": _Req(STR), "start": _Req(STR), "end": _Req(STR), "along": STR, "factor": NUM})),
}
_PATTERN = {
    "format": _Req(STR),
    "format_version": STR,
    "length_unit": STR,
    "style": _Req(STR),
    "description": STR,
    "units": STR,
    "sample_size": STR,
    "sizes": _List(STR),
    "provenance": {
        "producer": STR,
        "product": STR,
        "version": STR,
        "author": STR,
        "created": STR,
        "flavor": _Opt(STR),
        "source_file": STR,
        "extra_text": _Map(STR),
    },
    "rules": {"name": STR, "sizes": _List(STR), "sample_size": STR, "deltas": _Map(_POINTS)},
    "pieces": _Req(_List(_PIECE, min_length=1)),
    "seams": _List(_SEAM),
    "measurements": _List(_LINK),
    "fabric_class": STR,
    "fabric_why": STR,
}
_SIDECAR = {
    "format": _Req(STR),
    "format_version": STR,
    "length_unit": STR,
    "style": STR,
    "description": _Opt(STR),
    "sample_size": STR,
    "size_chart": _Opt({"system": _Req(STR), "sample_size": STR, "why": STR, "body_cm": _Map(NUM)}),
    "pieces": _List(
        {
            "name": _Req(STR),
            "n_vertices": INT,
            "marks": _Map(_Either(INT, {"vertex": _Req(INT), "xy": _Opt(_POINT), "insert": BOOL})),
            "landmarks": _Map(STR),
            "placement": _PIECE["placement"],
            "fabric_class": STR,
        }
    ),
    "seams": _List({**_SEAM, "status": STR}),
    "measurements": _List(_LINK),
    "fabric_class": STR,
    "fabric_why": STR,
}


def _kind(value: Any) -> str:
    if value is None:
        return "null"
    if isinstance(value, bool):
        return "a boolean"
    if isinstance(value, (int, float)):
        return "a number"
    if isinstance(value, str):
        return "a string"
    if isinstance(value, list):
        return "an array"
    return "an object"


def _fail(where: str, want: str, value: Any) -> None:
    shown = "" if isinstance(value, (list, dict)) or value is None else f" {str(value)[:40]!r}"
    raise ValueError(f"{where or 'top level'}: expected {want}, got {_kind(value)}{shown}")


def _scalar(value: Any, spec: str, where: str) -> None:
    if spec == STR:
        if not isinstance(value, str):
            _fail(where, "a string", value)
        if len(value) > MAX_TEXT:
            raise ValueError(f"{where}: text of {len(value)} characters is longer than {MAX_TEXT}")
        return
    if spec == BOOL:
        if not isinstance(value, bool):
            _fail(where, "true or false", value)
        return
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        _fail(where, f"{'an integer' if spec == INT else 'a number'}", value)
    if spec == INT and isinstance(value, float) and not value.is_integer():
        _fail(where, "an integer", value)
    if not math.isfinite(value) or abs(value) > MAX_ABS:
        raise ValueError(f"{where}: {value:.6g} is outside ±{MAX_ABS:g}")


def _walk(value: Any, spec: Any, where: str) -> None:
    if isinstance(spec, _Either):
        try:
            _walk(value, spec.first, where)
        except ValueError:
            _walk(value, spec.second, where)
    elif isinstance(spec, _Opt):
        if value is not None:
            _walk(value, spec.spec, where)
    elif isinstance(spec, str):
        _scalar(value, spec, where)
    elif isinstance(spec, _List):
        if not isinstance(value, list):
            _fail(where, "an array", value)
        if spec.length is not None and len(value) != spec.length:
            raise ValueError(f"{where}: expected {spec.length} items, got {len(value)}")
        if len(value) < spec.min_length:
            raise ValueError(f"{where}: expected at least {spec.min_length} item(s), got {len(value)}")
        for i, item in enumerate(value):
            _walk(item, spec.item, f"{where}[{i}]")
    elif isinstance(spec, _Map):
        if not isinstance(value, Mapping):
            _fail(where, "an object", value)
        for key, item in value.items():
            _walk(item, spec.value, f"{where}.{key}"[:200])
    else:
        if not isinstance(value, Mapping):
            _fail(where, "an object", value)
        for key, sub in spec.items():
            required = isinstance(sub, _Req)
            if key not in value:
                if required:
                    raise ValueError(f"{where + '.' if where else ''}{key}: required key is missing")
                continue
            _walk(value[key], sub.spec if required else sub, f"{where + '.' if where else ''}{key}")


def check_pattern_dict(data: Any) -> None:
    """Raise ``ValueError`` at the first part of ``data`` that is not a pattern dict.

    Raises
    ------
    ValueError
        With the JSON path and the expected versus actual type or value.

    Examples
    --------
    >>> check_pattern_dict([])
    Traceback (most recent call last):
    ...
    ValueError: top level: expected an object, got an array
    """
    _walk(data, _PATTERN, "")


def check_sidecar_dict(data: Any) -> None:
    """Raise ``ValueError`` at the first part of ``data`` that is not a bridge-data sidecar.

    The sidecar format is ``formats/bridge.md``: per-piece marks (a vertex id, or
    ``{"vertex", "xy"}``), landmarks and placement, seams with a ``status``, and
    measurement links.

    Raises
    ------
    ValueError
        With the JSON path and the expected versus actual type or value.
    """
    _walk(data, _SIDECAR, "")
