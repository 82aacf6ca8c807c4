"""Body contact as constraints of the cloth solver: closest-point planes with a thickness, and Coulomb friction.

A vertex is in contact in a time step when the step's unconstrained
solution brings it within ``offset_cm`` of the skin (or inside, by ray
parity) or when its move from the step's start crosses the skin (a swept
ray: nothing tunnels through a thin limb). While in contact its target is
the closest skin point moved ``offset_cm`` out along the distance gradient
(re-evaluated every iteration, so the plane follows a curved skin), and its
slide along the skin is bounded by Coulomb friction: the skin's push out
(``push``) takes ``friction * push`` off the slide the step's
unconstrained solution made (:func:`slide_budgets`).
The solver weighs these targets like any other projective-dynamics
constraint; nothing moves the cloth after the solve.
"""

from __future__ import annotations

import numpy as np

__all__ = ["contact_targets", "push_direction", "signed_distances", "slide_budgets", "swept_hits"]


def push_direction(x: np.ndarray, q: np.ndarray, n: np.ndarray, inside: np.ndarray) -> np.ndarray:
    """(n, 3) unit directions from the closest skin points ``q`` outward (the distance gradient).

    Away from the skin the direction from ``q`` to ``x`` (reversed inside) is
    exact even in hollows, where the face normal ``n`` points into the next
    face; on the skin itself the face normal is used, and never a direction
    against it.
    """
    d = (x - q) * np.where(inside, -1.0, 1.0)[:, None]
    ln = np.linalg.norm(d, axis=1, keepdims=True)
    use = ln[:, 0] > 1e-3
    out = np.array(n, dtype=np.float64)
    out[use] = d[use] / ln[use]
    flip = np.einsum("ij,ij->i", out, n) < 0
    out[flip] = n[flip]
    return out


def signed_distances(collider, x: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Closest skin points (n, 3), outward directions (n, 3) and signed distances (n,) cm (ray parity inside)."""
    q, nrm, _, _, _ = collider.closest(x)
    inside = collider.inside(x)
    dist = np.linalg.norm(x - q, axis=1)
    return q, push_direction(x, q, nrm, inside), np.where(inside, -dist, dist)


def slide_budgets(
    collider, x: np.ndarray, x0: np.ndarray, y: np.ndarray, offset_cm: float, friction: float
) -> np.ndarray:
    """(k,) float64, cm: how far each vertex in contact may slide along the skin in this step (Coulomb).

    ``x`` (k, 3) is the step's unconstrained solution, ``x0`` the start and
    ``y`` the inertial prediction. The skin pushes the vertex out by
    ``push`` (its offset-surface point against the deeper of the two, along
    the normal); friction takes ``friction * push`` off the tangential move
    the vertex would make without it. Cloth pressed hard sticks; cloth on a
    slope steeper than ``atan(friction)`` slides with the kinetic remainder.
    """
    q, out, _ = signed_distances(collider, x)
    p = q + offset_cm * out
    dx = x - x0
    slide = np.linalg.norm(dx - np.einsum("ij,ij->i", dx, out)[:, None] * out, axis=1)
    # the skin's push: against the free solution (the cloth's tension presses it in) or the inertial
    # prediction (its weight), whichever is deeper
    push = np.maximum(np.einsum("ij,ij->i", p - np.where(_deeper(x, y, out), x, y), out), 0.0)
    return np.maximum(slide - friction * push, 0.0)


def _deeper(x: np.ndarray, y: np.ndarray, out: np.ndarray) -> np.ndarray:
    """(k, 1) bool: ``x`` lies deeper than ``y`` along the outward directions ``out``."""
    return (np.einsum("ij,ij->i", x - y, out) < 0)[:, None]


def contact_targets(
    collider, x: np.ndarray, x0: np.ndarray, budget: np.ndarray, offset_cm: float
) -> tuple[np.ndarray, np.ndarray]:
    """Targets of the vertices in contact: on the offset surface, their slide within the friction budget.

    Parameters
    ----------
    collider : the body (``closest``, ``inside``)
    x : (k, 3) float64, cm — the vertices in contact, current iterate
    x0 : (k, 3) float64, cm — where they were at the step's start
    budget : (k,) float64, cm — :func:`slide_budgets`
    offset_cm : distance kept from the skin

    Returns
    -------
    targets : (k, 3) float64, cm ; normals : (k, 3) float64 unit outward directions
    """
    q, out, sd = signed_distances(collider, x)
    p = q + offset_cm * out
    dx = p - x0
    dn = np.einsum("ij,ij->i", dx, out)[:, None] * out
    dt = dx - dn
    slide = np.linalg.norm(dt, axis=1)
    keep = np.minimum(1.0, budget / np.maximum(slide, 1e-12))
    # a unilateral constraint: a vertex farther out than the offset (an outer layer lying on an inner one)
    # is where it is, not drawn onto the skin
    free = (sd >= offset_cm)[:, None]
    return np.where(free, x, x0 + dn + keep[:, None] * dt), out


def swept_hits(collider, x0: np.ndarray, x: np.ndarray, offset_cm: float) -> tuple[np.ndarray, np.ndarray]:
    """Where moves from ``x0`` (outside) to ``x`` (n, 3) first enter the skin (``collider.sweep``, any length).

    Returns
    -------
    hit : (n,) bool ; at : (n, 3) float64, cm — the entry point ``offset_cm`` out along the face normal
    """
    at, hit = collider.sweep(x0, x, offset_cm, min_move_cm=1e-6)
    return hit, at
