"""Sew and drape the placed pieces: the garment as one cloth, run by the solver core of :mod:`.cloth`.

:func:`build_cloth` stacks the placed piece instances into a :class:`Cloth`
(positions, pattern coordinates, triangles, sewn pairs, stretch and bending
springs at their pattern lengths, seam-gathered lengths, masses from the
fabric's density). :func:`drape` runs it for a number of time steps: the
seam springs' target lengths shrink from their starting gaps to zero while
sewing (``sew_steps``) and gravity ramps in after. Body contact and
self-contact are constraints inside the solver's iterations
(:class:`~patternbridge.assemble.cloth.ClothSolver`); seams are closed by
the simulation, and welded at the end only by averaging each group of sewn
vertices.
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from .cloth import ClothSolver, DrapeSettings, edges_and_bends, gathered_lengths, seam_gaps, weld_groups
from .cloth.solver import GRAVITY_CM_S2

__all__ = ["Cloth", "DrapeSettings", "build_cloth", "drape", "gathered_lengths", "seam_gaps", "weld_groups"]

log = logging.getLogger(__name__)


@dataclass(eq=False)
class Cloth:
    """The garment being simulated (all instances stacked).

    x : (N, 3) positions, cm ; uv : (N, 2) pattern coordinates, cm ;
    group : (N,) instance id ; faces : (F, 3) ; seams : (S, 2) sewn vertex pairs ;
    edges, rest : stretch springs ; bends, bend_rest : bending springs ;
    mass : (N,) kg ; target : the stretch springs' lengths in the solver (``rest``, except
    along gathered seams, see :func:`gathered_lengths`)
    """

    x: np.ndarray
    uv: np.ndarray
    group: np.ndarray
    faces: np.ndarray
    seams: np.ndarray
    edges: np.ndarray
    rest: np.ndarray
    bends: np.ndarray
    bend_rest: np.ndarray
    mass: np.ndarray
    v: np.ndarray = field(default=None)  # type: ignore[assignment]
    target: np.ndarray = field(default=None)  # type: ignore[assignment]

    def __post_init__(self) -> None:
        if self.v is None:
            self.v = np.zeros_like(self.x)
        if self.target is None:
            self.target = self.rest.copy()


def build_cloth(
    positions: list[np.ndarray],
    points2d: list[np.ndarray],
    faces: list[np.ndarray],
    seams: list[tuple[int, int, np.ndarray, np.ndarray]],
    *,
    density_kg_cm2: float = 1.5e-5,
) -> Cloth:
    """Stack the placed instances into one cloth.

    Parameters
    ----------
    positions : per instance (n_i, 3) float64, cm
    points2d : per instance (n_i, 2) float64, cm — pattern coordinates
    faces : per instance (F_i, 3) int64, local ids
    seams : (instance a, instance b, local ids on a, local ids on b)
    """
    offsets = np.concatenate([[0], np.cumsum([len(p) for p in positions])])
    x = np.concatenate(positions)
    uv = np.concatenate(points2d)
    group = np.repeat(np.arange(len(positions)), np.diff(offsets))
    f = np.concatenate([fc + offsets[i] for i, fc in enumerate(faces)])
    sewn = [(va + offsets[a], vb + offsets[b]) for a, b, va, vb in seams]  # global ids of both sides
    pairs = np.concatenate([np.stack(s, axis=1) for s in sewn]) if sewn else np.zeros((0, 2), np.int64)
    pairs = pairs[pairs[:, 0] != pairs[:, 1]]
    edges, bends = edges_and_bends(f)
    rest = np.linalg.norm(uv[edges[:, 0]] - uv[edges[:, 1]], axis=1)
    bend_rest = np.linalg.norm(uv[bends[:, 0]] - uv[bends[:, 1]], axis=1)
    u, w = uv[f[:, 1]] - uv[f[:, 0]], uv[f[:, 2]] - uv[f[:, 0]]
    a2 = np.abs(u[:, 0] * w[:, 1] - u[:, 1] * w[:, 0]) / 2
    mass = np.bincount(f.ravel(), weights=np.repeat(a2 / 3, 3), minlength=len(x)) * density_kg_cm2
    mass = np.maximum(mass, 1e-3 * mass.mean())
    target = gathered_lengths(edges, rest, sewn)
    return Cloth(
        x=x,
        uv=uv,
        group=group,
        faces=f,
        seams=pairs.astype(np.int64),
        edges=edges,
        rest=rest,
        bends=bends,
        bend_rest=bend_rest,
        mass=mass,
        target=target,
    )


def drape(
    cloth: Cloth,
    collider,
    *,
    steps: int = 150,
    sew_steps: int = 80,
    settings: DrapeSettings | None = None,
    gravity_scale: float = 1.0,
    progress: Callable[[str, int, int], None] | None = None,
    stage: str = "drape",
    solver: ClothSolver | None = None,
    anchors: tuple[np.ndarray, np.ndarray] | None = None,
    hold: np.ndarray | None = None,
    loose: np.ndarray | None = None,
    sew_ramp: tuple[float, float] | None = None,
    inertia: np.ndarray | None = None,
    on_step: Callable[[int], None] | None = None,
    untangle_steps: tuple[int, int] | None = None,
    body: Callable[[int], object] | None = None,
) -> ClothSolver:
    """Run the cloth for ``steps`` time steps against ``collider`` (in place).

    The seam springs' target length shrinks linearly to zero over the first
    ``sew_steps`` steps; gravity ramps up over the 20 steps after. Returns
    the solver, which can be passed back to continue with another collider
    (the constant part of its system is kept). ``anchors`` = (weights (N,)
    in units of the vertex's mass / h², positions (N, 3)) pins vertices
    softly while sewing; ``hold`` (N,) weights pin vertices where the sewing
    left them for the rest of the run (a waistband buttoned at the waist).
    ``loose`` (S,) bool leaves those seam pairs unsewn for this call (held
    at their gaps, see :meth:`~patternbridge.assemble.cloth.ClothSolver.loosen`).
    With ``sew_steps`` 0, ``sew_ramp`` = (from, to) keeps sewing during the
    call: the gaps shrink from ``from`` to ``to`` of the way between their
    lengths at the solver's last ``restart_seams`` and zero. ``inertia`` (N,)
    scales the vertices' masses in the solver for this call. ``on_step(k)``
    is called after step ``k`` (1-based), for measuring between phases.
    ``untangle_steps`` = (first, stop): the untangling (:mod:`.cloth.untangle`)
    acts in the steps first <= k < stop (0-based) of this call; None: in
    every step when ``settings.untangle``. ``body(k)``, called before step
    ``k`` (0-based), returns the collider of that step: a body that moves
    while the cloth runs (:class:`~patternbridge.assemble.phases.PoseKeyframe`).
    """
    settings = settings or DrapeSettings()
    solver = solver or ClothSolver(cloth, settings)
    solver.loosen(loose)
    solver.weigh(inertia)
    if sew_steps and anchors is not None:
        solver.pin(*anchors)
    else:
        solver.pin(hold, cloth.x)  # hold None releases
    for k in range(steps):
        if sew_steps:
            sew = (k + 1) / sew_steps
        elif sew_ramp is not None:
            sew = sew_ramp[0] + (sew_ramp[1] - sew_ramp[0]) * (k + 1) / max(steps, 1)
        else:
            sew = 1.0
        # no gravity while sewing (the pieces would fall before the seams hold them), then ramp it up
        g = (
            GRAVITY_CM_S2 * gravity_scale * float(np.clip((k - sew_steps) / 20.0, 0.0, 1.0))
            if sew_steps
            else GRAVITY_CM_S2 * gravity_scale
        )
        if body is not None:
            collider = body(k)
        solver.untangling = settings.untangle if untangle_steps is None else untangle_steps[0] <= k < untangle_steps[1]
        solver.step(collider, g, min(sew, 1.0))
        if k + 1 == sew_steps:
            solver.pin(hold, cloth.x)
        if on_step is not None:
            on_step(k + 1)
        if progress is not None and (k % 10 == 0 or k == steps - 1):
            progress(stage, k + 1, steps)
    return solver
