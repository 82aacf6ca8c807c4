"""Fixtures for the garment-library tests."""

from __future__ import annotations

import runpy

import pytest

from patternbridge.library import garment_names, load_garment
from patternbridge.library.catalogue import LIBRARY_DIR


@pytest.fixture(scope="session", params=garment_names())
def garment(request):
    """Each library garment as loaded from its committed canonical JSON."""
    return load_garment(request.param)


@pytest.fixture(scope="session")
def draft_module():
    """``draft_module(name)``: the namespace of ``garment_library/<name>/draft.py``."""

    def load(name: str) -> dict:
        return runpy.run_path(str(LIBRARY_DIR / name / "draft.py"))

    return load
