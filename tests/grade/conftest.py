"""Fixtures shared by the grading tests."""

from __future__ import annotations

import pytest


@pytest.fixture(scope="module")
def measured(characters_dir):
    """``measured(name)``: the tape measurements (cm) of the shared character ``name``."""
    from patternbridge.measure.run import measure
    from patternbridge.mesh.load import load_character

    def values(name: str) -> dict[str, float]:
        character, _ = load_character(characters_dir / f"{name}.obj")
        return measure(character, partial=True).values_cm()

    return values
