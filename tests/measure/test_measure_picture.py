"""The measurement picture marks low-confidence landmarks (orange ring and label), and only those."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from patternbridge.measure import measure
from patternbridge.measure.picture import _LOW, measurement_picture
from patternbridge.mesh.load import load_character

pytestmark = pytest.mark.shared


def _orange_pixels(image: np.ndarray) -> int:
    return int(np.count_nonzero(np.all(np.abs(image.astype(int) - np.array(_LOW)) < 40, axis=-1)))


def test_picture_rings_low_confidence_landmarks(characters_dir):
    character, _ = load_character(characters_dir / "D_cartoon_child.obj")
    result = measure(character)  # sidecar landmarks: confidence 1, nothing flagged
    assert not any(lm.is_low_confidence for lm in result.landmarks.values())
    plain = measurement_picture(character, result, size=(200, 320))
    doubtful = dict(result.landmarks)
    doubtful["elbow_point_left"] = dataclasses.replace(doubtful["elbow_point_left"], confidence=0.3)
    flagged = measurement_picture(character, dataclasses.replace(result, landmarks=doubtful), size=(200, 320))
    assert _orange_pixels(plain) == 0
    assert _orange_pixels(flagged) > 20
