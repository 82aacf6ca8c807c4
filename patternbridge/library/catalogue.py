"""The garment library on disk: names, folders, loading and regenerating garments.

Each garment lives in ``garment_library/<name>/``: ``draft.py`` (the drafting
code), the canonical ``<name>.json``, ``<name>_aama.dxf``, ``<name>_astm.dxf``,
``<name>.rul`` and the bridge-data sidecar ``<name>.seams.json``.
"""

from __future__ import annotations

import functools
import logging
import os
from pathlib import Path

from ..pattern.model import Pattern

__all__ = [
    "GARMENTS",
    "LIBRARY_DIR",
    "garment_dir",
    "garment_names",
    "load_garment",
    "write_garment",
]

log = logging.getLogger(__name__)

LIBRARY_DIR = Path(__file__).resolve().parents[2] / "garment_library"
DOCS_DIR = Path(__file__).resolve().parents[2] / "docs" / "library"

#: library garments in the order they are listed
GARMENTS = ("shirt", "trousers", "skirt", "dress", "tshirt", "shorts")


def garment_names() -> tuple[str, ...]:
    """Names of the garments present in ``garment_library/``."""
    return tuple(n for n in GARMENTS if (LIBRARY_DIR / n / f"{n}.json").is_file())


def garment_dir(name: str) -> Path:
    """Folder of garment ``name``.

    Raises
    ------
    KeyError
        When ``name`` is not a library garment.
    """
    if name not in garment_names():
        raise KeyError(
            f"no library garment {name!r} (library: {', '.join(garment_names())})"
        )
    return LIBRARY_DIR / name


@functools.lru_cache(maxsize=16)
def load_garment(name: str) -> Pattern:
    """Load library garment ``name`` from its canonical JSON (cached; patterns are immutable).

    Raises
    ------
    KeyError
        When ``name`` is not a library garment.
    """
    from ..io.pattern_json import load_pattern_json

    return load_pattern_json(garment_dir(name) / f"{name}.json")


def write_garment(
    pattern: Pattern, directory: str | os.PathLike, *, picture: bool = True
) -> list[Path]:
    """Write a drafted garment's files into ``directory`` (and its picture into ``docs/library``).

    Writes ``<style>.json``, ``<style>.seams.json`` and, when the DXF writer
    is available, ``<style>_aama.dxf`` + ``<style>.rul`` and ``<style>_astm.dxf``.

    Returns
    -------
    The paths written.
    """
    from ..io.pattern_json import save_pattern_json
    from .sidecar import write_sidecar

    directory = Path(directory)
    name = pattern.style
    written = [save_pattern_json(pattern, directory / f"{name}.json")]
    written.append(write_sidecar(pattern, directory / f"{name}.seams.json"))
    try:
        from ..io.dxf_aama import write_dxf
    except ImportError:  # pragma: no cover - writer absent
        log.warning("DXF writer not available; %s DXF/RUL not written", name)
    else:
        written.append(
            write_dxf(
                pattern,
                directory / f"{name}_aama.dxf",
                flavor="aama",
                rul_path=directory / f"{name}.rul",
            )
        )
        written.append(directory / f"{name}.rul")
        written.append(
            write_dxf(pattern, directory / f"{name}_astm.dxf", flavor="astm")
        )
    if picture:
        from ..io.plot_library import plot_library_garment

        written.append(plot_library_garment(pattern, DOCS_DIR / f"{name}.png"))
    load_garment.cache_clear()
    return written
