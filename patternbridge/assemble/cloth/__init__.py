"""The cloth solver core: constraint data, body contact, self-contact and the projective-dynamics loop."""

from .constraints import SpringKind, Springs, edges_and_bends, gathered_lengths
from .solver import ClothSolver, DrapeSettings, seam_gaps, vertex_adjacency, weld_groups

__all__ = [
    "ClothSolver",
    "DrapeSettings",
    "SpringKind",
    "Springs",
    "edges_and_bends",
    "gathered_lengths",
    "seam_gaps",
    "vertex_adjacency",
    "weld_groups",
]
