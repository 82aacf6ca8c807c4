"""Measurement results and their JSON form (``formats/measurements.md``)."""

from __future__ import annotations

import json
import os
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from types import MappingProxyType
from typing import Any

import numpy as np

from .._arrays import as_float_array, frozen
from ..atomic import write_text
from ..errors import InputError
from ..mesh.character import Landmark, LandmarkEvidence

__all__ = [
    "FORMAT_VERSION",
    "Measurement",
    "Measurements",
    "load_measurements",
    "measurements_from_dict",
    "measurements_to_dict",
    "write_measurements",
]

FORMAT_VERSION = 1


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class Measurement:
    """One measured value.

    id : measurement id (``formats/measurements.md``)
    value_cm : float, cm
    kind : ``"girth"`` or ``"length"``
    method : ``"hull"``, ``"geodesic"`` or ``"vertical"``
    polyline : (k, 3) float64, cm: the hull (closed: first point repeated) or the path
    landmarks : names of the datum points used
    details : extra facts (plane origin/normal, level, straight-line distance...)
    """

    id: str
    value_cm: float
    kind: str
    method: str
    polyline: np.ndarray
    landmarks: tuple[str, ...] = ()
    details: Mapping[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        object.__setattr__(self, "value_cm", float(self.value_cm))
        object.__setattr__(
            self, "polyline", frozen(as_float_array(self.polyline, (None, 3), self.id))
        )
        object.__setattr__(self, "landmarks", tuple(self.landmarks))
        object.__setattr__(self, "details", MappingProxyType(dict(self.details)))


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class Measurements:
    """All measurements of one character.

    character : name of the character
    measurements : id -> :class:`Measurement`
    landmarks : name -> :class:`~patternbridge.mesh.character.Landmark` (with its source)
    assumed : what the loader assumed (units, up axis, component, source file)
    missing : id -> reason, for measurements that could not be taken (partial runs)
    """

    character: str
    measurements: Mapping[str, Measurement]
    landmarks: Mapping[str, Landmark] = field(default_factory=dict)
    assumed: Mapping[str, str] = field(default_factory=dict)
    missing: Mapping[str, str] = field(default_factory=dict)

    def __post_init__(self) -> None:
        for name in ("measurements", "landmarks", "assumed", "missing"):
            object.__setattr__(self, name, MappingProxyType(dict(getattr(self, name))))

    def values_cm(self) -> dict[str, float]:
        """``{id: value_cm}`` for every measured id."""
        return {k: m.value_cm for k, m in self.measurements.items()}

    def __getitem__(self, key: str) -> Measurement:
        return self.measurements[key]

    def __contains__(self, key: object) -> bool:
        return key in self.measurements


def _round(a: np.ndarray, digits: int = 3) -> list:
    return np.round(np.asarray(a, dtype=np.float64), digits).tolist()


def _jsonable(value: Any) -> Any:
    if isinstance(value, np.ndarray):
        return _round(value)
    if isinstance(value, (np.floating, float)):
        return round(float(value), 4)
    if isinstance(value, (np.integer,)):
        return int(value)
    if isinstance(value, Mapping):
        return {str(k): _jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_jsonable(v) for v in value]
    return value


def measurements_to_dict(result: Measurements) -> dict[str, Any]:
    """The JSON object of ``formats/measurements.md``."""
    return {
        "format": "patternbridge-measurements",
        "version": FORMAT_VERSION,
        "character": result.character,
        "units": "cm",
        "assumed": dict(result.assumed),
        "landmarks": {
            name: {
                "position": _round(lm.position),
                "vertex": lm.vertex,
                "source": str(lm.source),
                "confidence": round(lm.confidence, 3),
                "evidence": {"rule": lm.evidence.rule, "checks": list(lm.evidence.checks)},
            }
            for name, lm in sorted(result.landmarks.items())
        },
        "measurements": {
            mid: {
                "value_cm": round(m.value_cm, 3),
                "kind": m.kind,
                "method": m.method,
                "landmarks": list(m.landmarks),
                "polyline": _round(m.polyline),
                **({"details": _jsonable(m.details)} if m.details else {}),
            }
            for mid, m in result.measurements.items()
        },
        "missing": dict(result.missing),
    }


MAX_VALUE_CM = 1e4
"""Largest measurement value read from a file (100 m); anything larger is a broken file."""


def _confidence(value: Any, name: str) -> float | None:
    """A landmark's confidence: absent, or a number in [0, 1]."""
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, int | float) or not 0.0 <= float(value) <= 1.0:
        raise ValueError(f"landmark {name} confidence {value!r} is not a number in [0, 1]")
    return float(value)


def _evidence(value: Any, name: str) -> LandmarkEvidence:
    """A landmark's evidence: absent, or an object with a rule and a list of checks."""
    value = {} if value is None else value
    if not isinstance(value, dict) or not isinstance(value.get("checks", []), list):
        raise TypeError(f"landmark {name} evidence must be an object with a list of checks")
    return LandmarkEvidence(rule=str(value.get("rule", "")), checks=tuple(str(c) for c in value.get("checks", [])))


def _value_cm(entry: Any, mid: str) -> float:
    """The ``value_cm`` of one entry: a finite number in (0, MAX_VALUE_CM]."""
    if not isinstance(entry, Mapping):
        raise TypeError(f"{mid}: expected an object with value_cm, got {type(entry).__name__}")
    value = entry["value_cm"]
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise TypeError(f"{mid}: value_cm must be a number, got {str(value)[:40]!r}")
    if not 0 < value <= MAX_VALUE_CM:  # also false for NaN
        raise ValueError(f"{mid}: value_cm {value:.6g} is outside (0, {MAX_VALUE_CM:g}] cm")
    return float(value)


def _points(value: Any, what: str) -> np.ndarray:
    """(k, 3) float64 points read from a file, each coordinate within ±MAX_VALUE_CM."""
    pts = np.asarray(value, dtype=np.float64).reshape(-1, 3)
    if not np.all(np.abs(pts) <= MAX_VALUE_CM):  # also false for NaN
        raise ValueError(f"{what}: coordinates beyond ±{MAX_VALUE_CM:g} cm or not finite")
    return pts


def measurements_from_dict(
    data: Mapping[str, Any], where: str = "measurements"
) -> Measurements:
    """Inverse of :func:`measurements_to_dict`.

    Raises
    ------
    InputError
        The object is not a measurements document or has wrong fields.
    """
    if not isinstance(data, Mapping) or not isinstance(
        data.get("measurements"), Mapping
    ):
        raise InputError(
            f"{where}: not a measurements file (no 'measurements' object); run patternbridge measure"
        )
    if data.get("units", "cm") != "cm":
        raise InputError(
            f"{where}: units {data.get('units')!r} are not 'cm'; write values in centimetres"
        )
    for key in ("assumed", "missing", "landmarks"):
        if not isinstance(data.get(key, {}), Mapping):
            raise InputError(f"{where}: {key!r} is not a JSON object; regenerate the file with patternbridge measure")
    out = {}
    try:
        for mid, m in data["measurements"].items():
            out[mid] = Measurement(
                id=mid,
                value_cm=_value_cm(m, mid),
                kind=str(m.get("kind", "length")),
                method=str(m.get("method", "")),
                polyline=_points(m.get("polyline", []), f"{mid} polyline"),
                landmarks=tuple(m.get("landmarks", ())),
                details=m.get("details", {}),
            )
        marks = {
            name: Landmark(
                name=name,
                position=_points(lm["position"], f"landmark {name}")[0],
                vertex=lm.get("vertex"),
                source=lm.get("source", "file"),
                confidence=_confidence(lm.get("confidence"), name),
                evidence=_evidence(lm.get("evidence"), name),
            )
            for name, lm in data.get("landmarks", {}).items()
        }
    except (KeyError, TypeError, ValueError) as exc:
        raise InputError(
            f"{where}: malformed measurement entry ({type(exc).__name__}: {exc}); regenerate the file"
        ) from None
    return Measurements(
        character=str(data.get("character", "character")),
        measurements=out,
        landmarks=marks,
        assumed=data.get("assumed", {}),
        missing=data.get("missing", {}),
    )


def write_measurements(path: str | os.PathLike, result: Measurements) -> Path:
    """Write the measurements JSON atomically."""
    return write_text(path, json.dumps(measurements_to_dict(result), indent=1) + "\n")


def load_measurements(path: str | os.PathLike) -> Measurements:
    """Read a measurements JSON file written by :func:`write_measurements`.

    A plain ``{id: value_cm}`` object is accepted too (no polylines).
    """
    from ..io.json_file import read_json

    path = Path(path)
    data = read_json(path, hint="regenerate it with patternbridge measure", what="measurements file")
    if (
        isinstance(data, dict)
        and "measurements" not in data
        and data
        and all(isinstance(v, (int, float)) for v in data.values())
    ):
        data = {"measurements": {k: {"value_cm": v} for k, v in data.items()}}
    return measurements_from_dict(data, str(path))
