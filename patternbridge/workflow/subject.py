"""The character side of a fit: a mesh measured like a tailor's tape, or a measurements JSON."""

from __future__ import annotations

import dataclasses
import os
import re
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..errors import InputError
from ..report import Report

if TYPE_CHECKING:  # pragma: no cover
    from ..measure.model import Measurements
    from ..mesh.character import Character

__all__ = ["Subject", "is_measurements_json", "load_subject", "safe_name"]

Progress = Callable[[str, int, int], None] | None


def safe_name(text: str) -> str:
    """``text`` reduced to a file-name-safe token (letters, digits, ``_.-``); ``"fit"`` when empty.

    Examples
    --------
    >>> safe_name("Hero (v2)")
    'Hero_v2'
    """
    return re.sub(r"[^A-Za-z0-9_.-]+", "_", text).strip("_") or "fit"


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class Subject:
    """A character ready to be fitted.

    name : the character's name (size name in the graded pattern)
    source : the file it came from
    measurements : its measurements
    character : the body mesh, with the landmarks measuring found; None when
        only a measurements JSON was given (no drape then)
    """

    name: str
    source: str
    measurements: Measurements
    character: Character | None = None

    def __reduce__(self):
        # the model's read-only mappings (mappingproxy) do not pickle; a Subject
        # travels between processes (the batch measures once, fits elsewhere)
        # as the constructor arguments of its parts, rebuilt on arrival
        return _rebuild, (_state(self),)


class _Parts:
    """A frozen dataclass taken apart for pickling: its class and constructor arguments."""

    __slots__ = ("cls", "kwargs")

    def __init__(self, cls: type, kwargs: dict[str, Any]) -> None:
        self.cls, self.kwargs = cls, kwargs

    def __reduce__(self):
        return _Parts, (self.cls, self.kwargs)


def _state(obj: Any) -> Any:
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        return _Parts(type(obj), {f.name: _state(getattr(obj, f.name)) for f in dataclasses.fields(obj) if f.init})
    if isinstance(obj, Mapping):
        return {k: _state(v) for k, v in obj.items()}
    if type(obj) in (list, tuple):
        return type(obj)(_state(v) for v in obj)
    return obj


def _rebuild(state: Any) -> Any:
    if isinstance(state, _Parts):
        return state.cls(**{k: _rebuild(v) for k, v in state.kwargs.items()})
    if isinstance(state, dict):
        return {k: _rebuild(v) for k, v in state.items()}
    if type(state) in (list, tuple):
        return type(state)(_rebuild(v) for v in state)
    return state


def is_measurements_json(path: str | os.PathLike) -> bool:
    """True when ``path`` names a measurements JSON: meshes are never ``.json`` (glTF is ``.gltf``), so a
    ``.json`` character is read, and checked, as measurements (a broken one gets its own one-line error)."""
    return Path(path).suffix.lower() == ".json"


def load_subject(
    path: str | os.PathLike,
    *,
    units: str | None = None,
    up: str | None = None,
    landmarks: str | os.PathLike | Mapping[str, Any] | None = None,
    progress: Progress = None,
) -> tuple[Subject, Report]:
    """Load a character mesh and measure it, or read a measurements JSON.

    Parameters
    ----------
    path : mesh (OBJ/PLY/STL/glTF, with its ``.json`` sidecar if any) or a
        measurements JSON written by ``patternbridge measure``
    units, up, landmarks : see :func:`patternbridge.mesh.load.load_character`
    progress : ``progress(stage, done, total)`` callback of the measuring

    Returns
    -------
    subject : the measured character; its mesh carries the landmarks measuring
        found (from the rig or the geometry) beside its own, since they also
        place the pattern on a bare mesh
    report : the loader's findings

    Raises
    ------
    InputError
        The file is missing or unusable.
    """
    path = Path(path)
    if is_measurements_json(path):
        from ..measure.model import load_measurements

        meas = load_measurements(path)
        name = meas.character if meas.character and meas.character != "character" else path.stem
        return Subject(name=name, source=str(path), measurements=meas), Report()
    if not path.is_file():
        raise InputError(f"{path}: no such character file; give a mesh (OBJ/PLY/STL/glTF) or a measurements JSON")
    from ..measure.run import measure
    from ..mesh.load import load_character

    character, report = load_character(path, units=units, up=up, landmarks=landmarks)
    meas = measure(character, progress=progress, partial=True)
    name = getattr(character, "name", "") or path.stem
    character = dataclasses.replace(character, landmarks={**meas.landmarks, **character.landmarks})
    return Subject(name=name, source=str(path), measurements=meas, character=character), report
