"""The draped garment: welded surface, pattern UVs, pieces and skin weights."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from ..mesh.character import Skeleton
from ..report import Report

if TYPE_CHECKING:
    from .drape_report import DrapeReport

__all__ = ["Garment"]


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class Garment:
    """A draped garment in the character's rest pose.

    vertices : (N, 3) float64, cm — one vertex per pattern vertex of every cut
        copy; sewn vertices sit at exactly the same position (welded)
    faces : (F, 3) int64, outward (counter-clockwise seen from outside)
    uv : (N, 2) float64, cm — pattern coordinates of each vertex
    instance : (N,) int64 index into ``instance_names`` (``"front"``,
        ``"sleeve~mirror"`` for the mirrored copy of ``sleeve``...)
    weld : (N,) int64 — vertices sewn together share an id
    joints, weights : (N, 4) int64 / float64 — skin weights on ``skeleton``
        (-1 / 0 for unused slots), rows summing to 1; empty without a rig
    skeleton : the character's skeleton, or None
    report : the ``drape`` report (:class:`~.drape_report.DrapeReport`), None before measuring
    flagged : (F,) bool — faces the verdict names (open seams, cloth through
        itself or the skin, torn stretch, cloth turned over), drawn red in the pictures
    findings : recoverable problems met on the way
    """

    vertices: np.ndarray
    faces: np.ndarray
    uv: np.ndarray
    instance: np.ndarray
    instance_names: tuple[str, ...]
    weld: np.ndarray
    joints: np.ndarray
    weights: np.ndarray
    skeleton: Skeleton | None
    report: DrapeReport | None = None
    flagged: np.ndarray | None = None
    findings: Report = field(default_factory=Report)

    def welded(self) -> tuple[np.ndarray, np.ndarray]:
        """Welded mesh: (M, 3) vertices and (F, 3) faces over the weld ids."""
        ids, inv = np.unique(self.weld, return_inverse=True)
        v = np.zeros((len(ids), 3))
        v[inv] = self.vertices
        return v, inv[self.faces]
