"""The review picture (``bridge.picture``): seams coloured on both edges, a canvas fitted to the pieces."""

from __future__ import annotations

import io
from pathlib import Path

import numpy as np
from PIL import Image

from patternbridge.bridge import infer_bridge
from patternbridge.bridge.picture import review_png, seam_colour, seam_numbers
from patternbridge.io.dxf_aama import read_dxf


def test_review_picture_draws_every_seam_in_its_own_colour_on_a_fitted_canvas():
    """Library shirt read without its sidecar: each seam's colour shows on both edges; no empty canvas band."""
    dxf = Path(__file__).resolve().parents[2] / "garment_library" / "shirt" / "shirt_aama.dxf"
    pattern, _ = read_dxf(dxf)
    inference = infer_bridge(pattern)
    img = Image.open(io.BytesIO(review_png(pattern, inference))).convert("RGB")
    pixels = np.asarray(img).reshape(-1, 3)
    numbers = seam_numbers(inference)
    assert sorted(numbers.values()) == list(range(1, len(numbers) + 1))
    colours = {seam_colour(n) for n in numbers.values()}
    assert len(colours) == len(numbers)  # one colour per seam
    for j in inference.joins:
        if j.kind == "fold":
            continue
        # a 4 px line along both edges (and the list line): far more pixels than the number alone
        drawn = int(np.all(pixels == seam_colour(numbers[j.id]), axis=1).sum())
        assert drawn > 4 * 4 * min(j.a.length_cm, j.b.length_cm), j.id
    # the pieces fill the width: no column of the picture's right third is blank
    grey = np.asarray(img.convert("L"))
    blank = np.all(grey > 250, axis=0)
    assert not blank[int(0.66 * grey.shape[1]) : int(0.9 * grey.shape[1])].all()
    assert img.width < 2.5 * img.height
