"""``OUT/batch.json``: the inputs, seed, versions and per-case results of a batch."""

from __future__ import annotations

import dataclasses
import json
import math
import platform
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from importlib import metadata
from pathlib import Path
from typing import Any

from ..workflow.model import FitOptions
from .cases import CaseOutcome

__all__ = ["FORMAT_VERSION", "BatchInputs", "manifest_dict", "outcome_dict", "versions", "write_manifest"]

FORMAT_VERSION = 1
_PACKAGES = ("patternbridge", "numpy", "scipy", "pymoo", "shapely", "ezdxf", "open3d-cpu", "dask", "distributed")


@dataclass(frozen=True, slots=True, kw_only=True)
class BatchInputs:
    """What a batch was asked: characters (name → file), garments (name → spec), seed, options, cluster."""

    characters: Mapping[str, str]
    garments: Mapping[str, str]
    seed: int
    options: FitOptions
    scheduler: str = ""
    dashboard: str = ""
    n_workers: int = 0


def versions() -> dict[str, str]:
    """Python and the installed versions of the packages that decide the results."""
    out = {"python": platform.python_version()}
    for name in _PACKAGES:
        try:
            out[name] = metadata.version(name)
        except metadata.PackageNotFoundError:
            continue
    return out


def _clean(value: Any) -> Any:
    if isinstance(value, float):
        return None if math.isnan(value) else round(value, 4)
    if hasattr(value, "value") and isinstance(value.value, str):  # enums
        return value.value
    return value


def outcome_dict(outcome: CaseOutcome, seed: int) -> dict[str, Any]:
    """One case of the manifest (and of the report page)."""
    case = outcome.case
    figures = None
    if outcome.figures is not None:
        figures = {k: _clean(v) for k, v in dataclasses.asdict(outcome.figures).items()}
    return {
        "character": case.character,
        "garment": case.garment,
        "folder": case.key,
        "seed": seed,
        "status": outcome.status.value,
        "reused": outcome.reused,
        "seconds": round(outcome.seconds, 2),
        "cpu_seconds": round(outcome.cpu_seconds, 2),
        "peak_rss_mb": round(outcome.peak_rss_mb, 1),
        "worker": outcome.worker,
        "error": outcome.error,
        "verdict": _clean(outcome.verdict),
        "figures": figures,
        "files": list(outcome.files),
    }


def manifest_dict(inputs: BatchInputs, outcomes: Sequence[CaseOutcome], *, seconds: float) -> dict[str, Any]:
    """The ``batch.json`` object."""
    counts: dict[str, int] = {}
    for o in outcomes:
        counts[o.status.value] = counts.get(o.status.value, 0) + 1
    return {
        "format": "patternbridge-batch",
        "version": FORMAT_VERSION,
        "written": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
        "seed": inputs.seed,
        "options": {k: _clean(v) for k, v in dataclasses.asdict(inputs.options).items()},
        "inputs": {
            "characters": [{"name": k, "path": v} for k, v in inputs.characters.items()],
            "garments": [{"name": k, "spec": v} for k, v in inputs.garments.items()],
        },
        "versions": versions(),
        "cluster": {"scheduler": inputs.scheduler, "dashboard": inputs.dashboard, "workers": inputs.n_workers},
        "seconds": round(seconds, 2),
        "counts": counts,
        "cases": [outcome_dict(o, inputs.seed) for o in outcomes],
    }


def write_manifest(out_dir: Path, manifest: Mapping[str, Any]) -> Path:
    """Write ``OUT/batch.json`` atomically."""
    from ..atomic import write_text

    return write_text(Path(out_dir) / "batch.json", json.dumps(manifest, indent=1) + "\n")
