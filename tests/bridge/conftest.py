"""Fixtures for the bridge-inference tests: the hand labels and their inferences."""

from __future__ import annotations

import pytest

from patternbridge.bridge import infer_bridge
from patternbridge.bridge.evaluate import LABELS_DIR, load_labelled

LABEL_FILES = sorted(LABELS_DIR.glob("*.json"))


@pytest.fixture(scope="session", params=LABEL_FILES, ids=[p.stem for p in LABEL_FILES])
def labelled(request, shared_dir):
    """``(pattern, label, pairs, inference)`` for every labelled file."""
    pattern, label, pairs = load_labelled(request.param, shared_dir)
    return pattern, label, pairs, infer_bridge(pattern)
