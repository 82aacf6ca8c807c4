"""Redraw the picture committed beside every label: ``python tests/bridge/labels/draw.py``.

Each picture shows the pieces upright, coloured by their labelled role, and
every labelled seam as one colour and number on both of its edges.
"""

from __future__ import annotations

from pathlib import Path

from patternbridge.bridge.evaluate import LABELS_DIR, label_inference, load_labelled
from patternbridge.bridge.picture import review_png

SHARED = Path(__file__).resolve().parents[4] / "shared"

if __name__ == "__main__":
    for path in sorted(LABELS_DIR.glob("*.json")):
        pattern, label, pairs = load_labelled(path, SHARED)
        png = review_png(
            pattern,
            label_inference(pattern, label, pairs),
            px_per_cm=4.0,
            title=f"label: {label['file']} ({len(pairs)} seams and folds)",
        )
        path.with_suffix(".png").write_bytes(png)
