"""Close the seam graph of the wrapped pieces: one sparse least-squares solve, with the body as an obstacle.

The pieces come wrapped on their body parts' proxy surfaces
(:mod:`~patternbridge.assemble.place.wrap`); a cylinder has no top and no
crotch, so seams running over a shoulder or between two proxies start a
hand's width open. Every cut copy is then moved and bent at once so that its
sewn vertices meet their partners: the positions ``X`` (N, 3) minimise

``E(X) = w_seam Σ_pairs |x_a − x_b|² + w_shape |L (X − X₀)|² + w_stay |X − X₀|² + w_contact Σ_c |x_c − y_c|²``

where ``X₀`` is the wrapped layout, ``L`` each piece's graph Laplacian (it
keeps every piece's wrapped shape, so the pieces bend smoothly instead of
stretching locally), ``w_stay`` a weak pull toward the wrap (it fixes the
translation: a piece with more vertices, that is more cloth, moves less, so
a cuff goes to its sleeve and a collar to its neckline without being told
which is which), and the contact terms hold vertices that fell inside the
body on their pushed-out positions ``y_c``. The normal equations
``(w_seam SᵀS + w_shape LᵀL + w_stay I + W_c) X = …`` are solved, the body
pushes out what went inside, those vertices become contacts, and the solve
repeats (:data:`CONTACT_ROUNDS`).

Nothing here knows a piece, a garment or a body part: the seams, the wrap and
the body decide.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np

__all__ = ["SeamGraphSettings", "close_seam_graph"]

log = logging.getLogger(__name__)


@dataclass(frozen=True, slots=True, kw_only=True)
class SeamGraphSettings:
    """Weights of the seam-graph solve (relative; see the module docstring).

    clearance_cm : distance from the skin a vertex pushed out of the body keeps
    contact_rounds : solve / push out / add contacts rounds
    """

    seam: float = 1.0
    shape: float = 0.5
    stay: float = 2e-3
    contact: float = 10.0
    clearance_cm: float = 1.0
    contact_rounds: int = 4


def _laplacian(faces: np.ndarray, n: int):
    """(n, n) sparse uniform graph Laplacian of a triangle mesh (degree on the diagonal, -1 per edge)."""
    from scipy.sparse import coo_matrix, diags

    e = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    e = np.unique(np.sort(e, axis=1), axis=0)
    adj = coo_matrix((np.ones(2 * len(e)), (e.ravel(), e[:, ::-1].ravel())), shape=(n, n)).tocsr()
    return (diags(np.asarray(adj.sum(axis=1)).ravel()) - adj).tocsr()


def close_seam_graph(
    x0: np.ndarray,
    faces: np.ndarray,
    pairs: np.ndarray,
    *,
    scene=None,
    settings: SeamGraphSettings | None = None,
) -> np.ndarray:
    """Positions (N, 3) near the wrapped layout ``x0`` with the sewn ``pairs`` brought together, outside the body.

    Parameters
    ----------
    x0 : (N, 3) float64, cm — every cut copy wrapped on its proxy, stacked
    faces : (F, 3) int64 — the triangles of all copies (global ids; copies share no vertex)
    pairs : (P, 2) int64 — sewn vertex pairs (global ids)
    scene : a :class:`~patternbridge.assemble.collision.BodyCollider`, or None (no obstacle)
    settings : the weights

    Returns
    -------
    (N, 3) float64, cm

    Notes
    -----
    The matrix changes only where contacts are added, so each round is one
    sparse LU factorisation of an (N, N) matrix and three solves.
    """
    from scipy.sparse import coo_matrix, diags
    from scipy.sparse.linalg import splu

    s = settings or SeamGraphSettings()
    x0 = np.asarray(x0, dtype=np.float64)
    n = len(x0)
    pairs = np.asarray(pairs, dtype=np.int64).reshape(-1, 2)
    pairs = pairs[pairs[:, 0] != pairs[:, 1]]
    if n == 0 or len(pairs) == 0:
        return x0.copy()
    lap = _laplacian(np.asarray(faces, dtype=np.int64), n)
    rows = np.repeat(np.arange(len(pairs)), 2)
    sew = coo_matrix((np.tile([1.0, -1.0], len(pairs)), (rows, pairs.ravel())), shape=(len(pairs), n)).tocsr()
    base = (s.seam * (sew.T @ sew) + s.shape * (lap.T @ lap) + s.stay * diags(np.ones(n))).tocsc()
    rhs0 = s.shape * (lap.T @ (lap @ x0)) + s.stay * x0
    w_contact = np.zeros(n)
    target = np.zeros((n, 3))
    x = x0.copy()
    for _ in range(max(1, s.contact_rounds)):
        lu = splu((base + diags(w_contact)).tocsc())
        rhs = rhs0 + w_contact[:, None] * target
        x = np.stack([lu.solve(rhs[:, k]) for k in range(3)], axis=1)
        if scene is None:
            break
        pushed, moved = scene.push_out(x, s.clearance_cm, robust=True)
        if not moved.any():
            break
        w_contact[moved] = s.contact
        target[moved] = pushed[moved]
        log.debug("seam graph: %d vertices held outside the body", int(np.count_nonzero(w_contact)))
    if scene is not None:
        x, _ = scene.push_out(x, s.clearance_cm, robust=True)
    return x
