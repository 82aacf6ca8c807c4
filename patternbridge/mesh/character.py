"""The character model shared by measuring, grading and assembling.

A :class:`Character` is a body mesh in centimetres, +Y up, with its optional
skeleton, skin weights and datum points (landmarks). Loaders in
``patternbridge.mesh.load`` build it and say what they assumed.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from enum import StrEnum
from types import MappingProxyType

import numpy as np

from .._arrays import as_float_array, as_index_array, frozen

__all__ = [
    "LOW_CONFIDENCE",
    "Character",
    "Landmark",
    "LandmarkEvidence",
    "LandmarkSource",
    "Skeleton",
    "Skin",
]

#: landmarks below this confidence are flagged (``measure --png`` marks them)
LOW_CONFIDENCE = 0.5


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class Skeleton:
    """Bones in rest pose.

    names : tuple of str, one per bone
    parents : (B,) int64, index of the parent bone, -1 for a root
    heads, tails : (B, 3) float64, cm, same frame as the mesh
    """

    names: tuple[str, ...]
    parents: np.ndarray
    heads: np.ndarray
    tails: np.ndarray

    def __post_init__(self) -> None:
        n = len(self.names)
        object.__setattr__(self, "names", tuple(self.names))
        object.__setattr__(self, "parents", frozen(as_index_array(self.parents, (n,), "parents")))
        object.__setattr__(self, "heads", frozen(as_float_array(self.heads, (n, 3), "heads")))
        object.__setattr__(self, "tails", frozen(as_float_array(self.tails, (n, 3), "tails")))

    def index(self, name: str) -> int:
        return self.names.index(name)


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class Skin:
    """Linear-blend-skinning weights.

    bone_indices : (V, K) int64 into ``Skeleton.names``; -1 marks an unused slot
    weights : (V, K) float64, rows sum to 1
    """

    bone_indices: np.ndarray
    weights: np.ndarray

    def __post_init__(self) -> None:
        idx = as_index_array(self.bone_indices, (None, None), "bone_indices")
        w = as_float_array(self.weights, idx.shape, "weights")
        object.__setattr__(self, "bone_indices", frozen(idx))
        object.__setattr__(self, "weights", frozen(w))


class LandmarkSource(StrEnum):
    """Where a landmark came from (compares equal to its string)."""

    FILE = "file"
    SKELETON = "skeleton"
    DETECTED = "detected"


#: confidence of a landmark before any check, by source
BASE_CONFIDENCE = {
    LandmarkSource.FILE: 1.0,
    LandmarkSource.SKELETON: 0.8,
    LandmarkSource.DETECTED: 0.7,
}


@dataclass(frozen=True, slots=True, kw_only=True)
class LandmarkEvidence:
    """Why a landmark is where it is.

    rule : how it was placed (the file and vertex, the joint and direction, the
        detection rule and the level it found)
    checks : plausibility checks that changed it or its confidence, one line each
        (``"mirrored from the right side: left/right 4.2 cm apart"``)
    """

    rule: str = ""
    checks: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        object.__setattr__(self, "checks", tuple(self.checks))

    def with_check(self, text: str) -> LandmarkEvidence:
        return LandmarkEvidence(rule=self.rule, checks=(*self.checks, text))


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class Landmark:
    """A datum point on the body surface.

    position : (3,) float64, cm, on the surface: a vertex, or a point inside a
        face where a rule defines a level or a point between vertices
    vertex : the nearest mesh vertex id (for code that needs an id), or None
        when unknown (a position given for a mesh without ids)
    face, bary : the face holding ``position`` and its barycentric weights of
        ``faces[face]``, when the point lies between vertices; None when it
        is the vertex itself. They carry the point to another pose of the same
        mesh (:meth:`at`) and start geodesics there.
    source : :class:`LandmarkSource` (or its string): ``"file"``, ``"skeleton"``
        or ``"detected"``
    confidence : 0..1; 1 for a point given in a file, lower for projected or
        detected points, lowered further by failed plausibility checks
        (:data:`LOW_CONFIDENCE` and below is flagged); ``None`` takes the
        source's base confidence
    evidence : :class:`LandmarkEvidence`
    """

    name: str
    position: np.ndarray
    vertex: int | None = None
    face: int | None = None
    bary: tuple[float, float, float] | None = None
    source: LandmarkSource = LandmarkSource.FILE
    confidence: float | None = None
    evidence: LandmarkEvidence = LandmarkEvidence()

    def __post_init__(self) -> None:
        object.__setattr__(self, "position", frozen(as_float_array(self.position, (3,), self.name)))
        if (self.face is None) != (self.bary is None):
            raise ValueError(f"landmark {self.name}: give both face and bary, or neither")
        if self.face is not None:
            b = tuple(float(x) for x in self.bary)
            if len(b) != 3 or not np.all(np.isfinite(b)) or abs(sum(b) - 1.0) > 1e-6:
                raise ValueError(f"landmark {self.name}: bary {self.bary!r} is not three weights summing to 1")
            object.__setattr__(self, "face", int(self.face))
            object.__setattr__(self, "bary", b)
        src = LandmarkSource(self.source)
        object.__setattr__(self, "source", src)
        conf = BASE_CONFIDENCE[src] if self.confidence is None else float(self.confidence)
        if not 0.0 <= conf <= 1.0:
            raise ValueError(f"landmark {self.name}: confidence {conf} outside 0..1")
        object.__setattr__(self, "confidence", conf)

    @property
    def is_low_confidence(self) -> bool:
        return self.confidence < LOW_CONFIDENCE

    def at(self, vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
        """(3,) this surface point on ``vertices``: the same mesh (same ids) in another pose.

        A point inside a face keeps its barycentric weights, a vertex its id;
        a point with neither is returned as it is.
        """
        if self.face is not None:
            return np.asarray(self.bary) @ np.asarray(vertices, dtype=np.float64)[faces[self.face]]
        if self.vertex is not None:
            return np.array(vertices[self.vertex], dtype=np.float64)
        return np.array(self.position)

    def moved_to(self, vertices: np.ndarray, faces: np.ndarray) -> Landmark:
        """This landmark carried to ``vertices`` (:meth:`at`), face and weights kept."""
        return replace(self, position=self.at(vertices, faces))


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class Character:
    """A body mesh ready for measuring and dressing.

    vertices : (V, 3) float64, cm, +Y up, feet near y = 0
    faces : (F, 3) int64
    name : short identifier (file stem)
    skeleton, skin : present when the source file is rigged
    landmarks : name -> :class:`Landmark`
    assumed : what the loader assumed, e.g. ``{"units": "cm", "up": "+Y",
        "component": "0 of 1 (13380 vertices)", "source": "A_superhero.obj"}``
    """

    vertices: np.ndarray
    faces: np.ndarray
    name: str = "character"
    skeleton: Skeleton | None = None
    skin: Skin | None = None
    landmarks: Mapping[str, Landmark] = field(default_factory=dict)
    assumed: Mapping[str, str] = field(default_factory=dict)

    def __post_init__(self) -> None:
        v = as_float_array(self.vertices, (None, 3), "vertices")
        f = as_index_array(self.faces, (None, 3), "faces")
        object.__setattr__(self, "vertices", frozen(v))
        object.__setattr__(self, "faces", frozen(f))
        object.__setattr__(self, "landmarks", MappingProxyType(dict(self.landmarks)))
        object.__setattr__(self, "assumed", MappingProxyType(dict(self.assumed)))

    @property
    def stature_cm(self) -> float:
        return float(np.ptp(self.vertices[:, 1]))

    def landmark_position(self, name: str) -> np.ndarray:
        from ..errors import LandmarkError

        try:
            return self.landmarks[name].position
        except KeyError:
            raise LandmarkError(
                f"{self.name}: landmark {name!r} is missing; give it with --landmarks FILE"
            ) from None
