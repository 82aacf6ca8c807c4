"""Geodesic paths and distances on triangle meshes (the measuring tape).

``SurfaceMesh`` prepares a mesh once; ``geodesic_path`` measures between two
surface points; ``geodesic_distances`` propagates from one source to every
vertex; ``tape_correct`` lifts a path off concave stretches like a real tape.
"""

from __future__ import annotations

from .path import METHODS, GeodesicPath, geodesic_path, geodesic_paths
from .surface import SurfaceMesh, SurfacePoint

__all__ = [
    "METHODS",
    "GeodesicPath",
    "SurfaceMesh",
    "SurfacePoint",
    "geodesic_distances",
    "geodesic_path",
    "geodesic_paths",
    "tape_correct",
]


def __getattr__(name):  # keep the import of the package light
    if name == "geodesic_distances":
        from .propagate import geodesic_distances

        return geodesic_distances
    if name == "tape_correct":
        from .tape import tape_correct

        return tape_correct
    raise AttributeError(name)
