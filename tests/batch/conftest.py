"""Batch inputs: the hand-made skirt (with and without measurement links) and two measured bodies."""

from __future__ import annotations

import json
import re
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "grade"))
from grade_fixtures import BODY, skirt_pattern

from patternbridge.io.pattern_json import save_pattern_json

# the grader's budget of every batch test: tiny, the skirt still fits
BUDGET = ["--pop-size", "20", "--generations", "10"]


@pytest.fixture
def batch_inputs(tmp_path) -> dict[str, Path]:
    """``skirt`` (fits), ``bare`` (no measurement links: fails), ``hero`` and ``big`` (measurements JSONs)."""
    paths = {name: tmp_path / f"{name}.json" for name in ("skirt", "bare", "hero", "big")}
    save_pattern_json(skirt_pattern(), paths["skirt"])
    save_pattern_json(skirt_pattern(links=False), paths["bare"])
    paths["hero"].write_text(json.dumps(BODY))
    paths["big"].write_text(json.dumps({k: round(v * 1.08, 2) for k, v in BODY.items()}))
    return paths


def timeless(obj):
    """A fit report without its timings (the only thing two runs of one case may differ in)."""
    if isinstance(obj, dict):
        return {k: timeless(v) for k, v in obj.items() if k != "seconds"}
    if isinstance(obj, list):
        return [timeless(v) for v in obj]
    return obj


_STAMP = re.compile(rb"(?im)^creation (date|time):.*$")


def without_stamps(data: bytes) -> bytes:
    """DXF/RUL bytes without the writer's creation date and time (the wall clock, not the fit)."""
    return _STAMP.sub(b"", data)
