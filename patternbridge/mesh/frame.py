"""The body's frame from its own geometry: main component, up axis, units and facing.

A file may carry stray geometry (a lost triangle metres above the head, props,
eyes) and may say nothing about its units, up axis or which way the character
faces. Everything here is read from the **main component** (the largest
connected piece by area), never from the whole file, so one stray triangle does
not change the units.

* **Up**: +Y or +Z (and their negatives for a rigged file), the axis along
  which the head joints lie above the root, else the longest extent of the body.
* **Units**: the unit that makes the body's height a plausible stature
  (:data:`STATURE_RANGE_CM`), metres first for glTF (its unit by definition).
* **Facing**: the feet point forward. The horizontal offset from the ankles
  (sections at 6–10 % of the height) to the soles (the lowest 3 %) gives the
  facing direction; the body is turned about the up axis so that it faces +Z
  (the character's left is then +X).

Each choice comes with its evidence, so the loader can report it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = [
    "FACING_TURNS",
    "STATURE_RANGE_CM",
    "Facing",
    "detect_facing",
    "facing_matrix",
    "main_component",
]

STATURE_RANGE_CM = (20.0, 300.0)

#: facing direction in the +Y-up frame -> rotation about +Y taking it to +Z (row vectors: v @ R.T)
FACING_TURNS: dict[str, np.ndarray] = {
    "+Z": np.eye(3),
    "-Z": np.array([[-1.0, 0, 0], [0, 1, 0], [0, 0, -1]]),
    "+X": np.array([[0.0, 0, -1], [0, 1, 0], [1, 0, 0]]),
    "-X": np.array([[0.0, 0, 1], [0, 1, 0], [-1, 0, 0]]),
}


@dataclass(frozen=True, slots=True, kw_only=True)
class Facing:
    """Which way a standing body faces, with the evidence.

    direction : ``"+Z"``, ``"-Z"``, ``"+X"`` or ``"-X"`` in the +Y-up frame
    offset_cm : horizontal distance from the ankles' centre to the soles' centre
    confidence : 0..1; the toe offset relative to 3 % of the height (a foot
        points forward by 3–5 % of the stature), capped at 1
    """

    direction: str
    offset_cm: float
    confidence: float

    @property
    def evidence(self) -> str:
        return (
            f"the soles lie {self.offset_cm:.3g} cm towards {self.direction} of the ankles "
            f"(confidence {self.confidence:.2f})"
        )


def main_component(labels: np.ndarray, faces: np.ndarray, areas: np.ndarray) -> int:
    """The label of the component with the largest surface area.

    labels : (V,) int64 component of each vertex (-1: unused)
    faces : (F, 3) int64
    areas : (F,) float64 triangle areas
    """
    n = int(labels.max()) + 1
    per = np.bincount(labels[faces[:, 0]], weights=areas, minlength=n)
    return int(np.argmax(per))


def detect_facing(vertices: np.ndarray) -> Facing:
    """Which way a body standing on y = min(y), +Y up, faces (see the module notes).

    vertices : (V, 3) float64, any unit, +Y up
    """
    v = np.asarray(vertices, dtype=np.float64)
    floor = float(v[:, 1].min())
    height = float(np.ptp(v[:, 1]))
    rel = (v[:, 1] - floor) / max(height, 1e-12)
    soles = v[rel < 0.03]
    ankles = v[(rel > 0.06) & (rel < 0.10)]
    if not len(soles) or not len(ankles):
        return Facing(direction="+Z", offset_cm=0.0, confidence=0.0)
    d = soles[:, [0, 2]].mean(axis=0) - ankles[:, [0, 2]].mean(axis=0)
    axis = 1 if abs(d[1]) >= abs(d[0]) else 0
    sign = "+" if d[axis] >= 0 else "-"
    off = float(np.hypot(*d))
    conf = float(min(1.0, abs(d[axis]) / (0.03 * height)))
    return Facing(direction=f"{sign}{'XZ'[axis]}", offset_cm=off, confidence=conf)


def facing_matrix(direction: str) -> np.ndarray:
    """The turn about +Y that makes a body facing ``direction`` face +Z."""
    return FACING_TURNS[direction]
