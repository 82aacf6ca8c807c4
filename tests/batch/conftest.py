"""Batch inputs: the hand-made skirt (with and without measurement links) and two measured bodies."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "grade"))
from grade_fixtures import BODY, skirt_pattern

from patternbridge.io.pattern_json import save_pattern_json


@pytest.fixture
def batch_inputs(tmp_path) -> dict[str, Path]:
    """``skirt`` (fits), ``bare`` (no measurement links: fails), ``hero`` and ``big`` (measurements JSONs)."""
    paths = {name: tmp_path / f"{name}.json" for name in ("skirt", "bare", "hero", "big")}
    save_pattern_json(skirt_pattern(), paths["skirt"])
    save_pattern_json(skirt_pattern(links=False), paths["bare"])
    paths["hero"].write_text(json.dumps(BODY))
    paths["big"].write_text(json.dumps({k: round(v * 1.08, 2) for k, v in BODY.items()}))
    return paths
