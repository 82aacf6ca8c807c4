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
repeats (``contact_rounds``).

Linear seams do not know which piece lies over which: two pieces pulled
together across a seam, or a piece bent round a corner, can end up through
each other, and the cloth simulation keeps whatever side each pair of layers
starts on. So the solve then separates the layers: the triangles through
other cloth (counted as :mod:`~patternbridge.assemble.selfcross` counts them,
the sides of a seam as one vertex) and their neighbours are held on an
offset surface of the skin, ``clearance_cm + layer * layer_cm`` out, where
``layer`` orders the pieces by the cloth they hold (:func:`layer_ranks`: a
collar over its neckline, a cuff over its sleeve, a sleeve cap over the
bodice); the sewn vertices stay free to meet between the layers. The solve
repeats (``layer_rounds``) and the round with the fewest crossing triangles
is kept. Every round ends with the body's clean-up: vertices inside pushed
out and triangles through the skin between their corners (a long edge over a
thin limb) cleared by the collider; what it moved is held there in the next
solve, and the crossings are counted after it.

Where two proxies meet (a leg's tube and the ring round the hips, blended
over the crotch; a sleeve's tube and the bodice) the wrapped shape itself
can fold through the cloth beside it, and the shape term keeps that fold
through any layering. So the crossing triangles and their neighbours also
lose their wrapped bend (their target Laplacian is set to zero: they lie
smooth between the cloth round them, the seams still pulling), round by
round (``flatten_rounds``), the round with the fewest crossing triangles
kept. The folds are smoothed before the layers are held apart and, in a
second try, after; the try with fewer crossing triangles is kept (a fold
held on a layer can no longer be smoothed, a smoothed one may still need
its layer).

Nothing here knows a piece, a garment or a body part: the seams, the wrap and
the body decide.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np

__all__ = ["SeamGraphSettings", "close_seam_graph", "layer_ranks"]

log = logging.getLogger(__name__)


@dataclass(frozen=True, slots=True, kw_only=True)
class SeamGraphSettings:
    """Weights of the seam-graph solve (relative; see the module docstring).

    clearance_cm : distance from the skin a vertex pushed out of the body keeps
    clear_move_cm : the farthest the skin clean-up may move a vertex
    layer_cm : distance between two layers of cloth held apart (see :func:`layer_ranks`)
    contact_rounds : solve / push out / add contacts rounds
    flatten_rounds : rounds that release the wrapped bend of cloth folded through cloth and solve again
    layer_rounds : rounds that hold crossing cloth on its layer and solve again
    """

    seam: float = 1.0
    shape: float = 0.5
    stay: float = 2e-3
    contact: float = 10.0
    clearance_cm: float = 1.0
    clear_move_cm: float = 2.0
    layer_cm: float = 0.6
    contact_rounds: int = 4
    flatten_rounds: int = 4
    layer_rounds: int = 6


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
    layers: np.ndarray | None = None,
) -> np.ndarray:
    """Positions (N, 3) near the wrapped layout ``x0`` with the sewn ``pairs`` brought together, outside the body.

    Parameters
    ----------
    x0 : (N, 3) float64, cm — every cut copy wrapped on its proxy, stacked
    faces : (F, 3) int64 — the triangles of all copies (global ids; copies share no vertex)
    pairs : (P, 2) int64 — sewn vertex pairs (global ids)
    scene : a :class:`~patternbridge.assemble.collision.BodyCollider`, or None (no obstacle)
    settings : the weights
    layers : (N,) int64 — the layer of every vertex's piece (0 nearest the body, :func:`layer_ranks`);
        with a ``scene``, cloth passing through cloth is held on its layer's offset from the skin

    Returns
    -------
    (N, 3) float64, cm

    Notes
    -----
    The matrix changes only where contacts are added, so each round is one
    sparse LU factorisation of an (N, N) matrix and three solves.
    """
    s = settings or SeamGraphSettings()
    x0 = np.asarray(x0, dtype=np.float64)
    n = len(x0)
    pairs = np.asarray(pairs, dtype=np.int64).reshape(-1, 2)
    pairs = pairs[pairs[:, 0] != pairs[:, 1]]
    if n == 0 or len(pairs) == 0:
        return x0.copy()
    faces = np.asarray(faces, dtype=np.int64)
    solve = _Solve(x0, faces, pairs, s)
    x = solve.contacts(scene)
    if scene is None:
        return x
    x = solve.clear_skin(scene, x, faces)
    layers = None if layers is None or s.layer_rounds <= 0 else np.asarray(layers, dtype=np.int64)
    steps = []
    if s.flatten_rounds > 0:
        steps.append(lambda trial, y, near: _flatten_folds(trial, scene, y, faces, near))
    if layers is not None:
        steps.append(lambda trial, y, near: _separate_layers(trial, scene, y, faces, pairs, layers, near))
    if not steps:
        return x
    near = _Near.of(len(x), faces, pairs)
    tries = []
    for order in (steps, steps[::-1]) if len(steps) == 2 else (steps,):
        trial, y, n_cross = solve.copy(), x, 0
        for step in order:
            y, n_cross = step(trial, y, near)
        tries.append((n_cross, y))
    # folds smoothed before or after the layers are held apart: the better is kept (the second on a tie)
    return min(tries[::-1], key=lambda t: t[0])[1]


@dataclass(frozen=True)
class _Near:
    """What the crossing searches of one garment share: the seam-welded labels and the vertex adjacency."""

    same: np.ndarray
    adjacency: object

    @classmethod
    def of(cls, n: int, faces: np.ndarray, pairs: np.ndarray) -> _Near:
        from ..cloth import vertex_adjacency, weld_groups

        edges = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
        return cls(weld_groups(n, pairs), vertex_adjacency(n, edges))

    def crossing(self, x: np.ndarray, faces: np.ndarray) -> np.ndarray:
        """(F,) bool: triangles of ``x`` through other cloth, the two sides of a seam one vertex."""
        from ..selfcross import self_crossing

        return self_crossing(x, faces, None, self.same)

    def crossings(self, x: np.ndarray, faces: np.ndarray) -> int:
        return int(np.count_nonzero(self.crossing(x, faces)))


class _Solve:
    """The seam-graph normal equations with contact terms that accumulate between solves."""

    def __init__(
        self,
        x0: np.ndarray,
        faces: np.ndarray,
        pairs: np.ndarray,
        s: SeamGraphSettings,
    ):
        from scipy.sparse import coo_matrix, diags

        n = len(x0)
        lap = _laplacian(faces, n)
        rows = np.repeat(np.arange(len(pairs)), 2)
        sew = coo_matrix((np.tile([1.0, -1.0], len(pairs)), (rows, pairs.ravel())), shape=(len(pairs), n)).tocsr()
        self.base = (s.seam * (sew.T @ sew) + s.shape * (lap.T @ lap) + s.stay * diags(np.ones(n))).tocsc()
        self.lap = lap
        self.shape_target = lap @ x0
        self.rhs0 = s.shape * (lap.T @ self.shape_target) + s.stay * x0
        self.w_contact = np.zeros(n)
        self.target = np.zeros((n, 3))
        self.settings = s
        self.x0 = x0

    def __call__(self) -> np.ndarray:
        from scipy.sparse import diags
        from scipy.sparse.linalg import splu

        lu = splu((self.base + diags(self.w_contact)).tocsc())
        rhs = self.rhs0 + self.w_contact[:, None] * self.target
        return np.stack([lu.solve(rhs[:, k]) for k in range(3)], axis=1)

    def copy(self) -> _Solve:
        """A solve with the same matrix and its own contacts and shape targets."""
        import copy

        out = copy.copy(self)
        out.w_contact, out.target = self.w_contact.copy(), self.target.copy()
        out.shape_target = self.shape_target.copy()
        return out

    def flatten(self, ids: np.ndarray) -> None:
        """Let vertices ``ids`` lie smooth between their neighbours from the next solve on (their wrapped bend
        released: the shape term's target Laplacian there is zero)."""
        s = self.settings
        self.shape_target[ids] = 0.0
        self.rhs0 = s.shape * (self.lap.T @ self.shape_target) + s.stay * self.x0

    def hold(self, ids: np.ndarray, target: np.ndarray) -> None:
        """Hold vertices ``ids`` on ``target`` (len(ids), 3) by contact terms from the next solve on."""
        self.w_contact[ids] = self.settings.contact
        self.target[ids] = target

    def contacts(self, scene) -> np.ndarray:
        """Solve, push what went inside the body out, hold it there, solve again (``contact_rounds``)."""
        s = self.settings
        x = self.x0.copy()
        for _ in range(max(1, s.contact_rounds)):
            x = self()
            if scene is None:
                return x
            pushed, moved = scene.push_out(x, s.clearance_cm, robust=True)
            if not moved.any():
                break
            self.hold(np.flatnonzero(moved), pushed[moved])
            log.debug("seam graph: %d vertices held outside the body", int(np.count_nonzero(self.w_contact)))
        return scene.push_out(x, s.clearance_cm, robust=True)[0]

    def clear_skin(self, scene, x: np.ndarray, faces: np.ndarray) -> np.ndarray:
        """``x`` pushed out of the body and with no triangle through the skin; what moved is held there."""
        s = self.settings
        pushed, moved = scene.push_out(x, s.clearance_cm, robust=True)
        cleared = scene.clear_triangles(pushed, faces, s.clearance_cm)
        # a corner the clean-up carries far (out between two body parts that
        # touch) opens its seams and folds the cloth: it stays
        far = np.linalg.norm(cleared - pushed, axis=1) > s.clear_move_cm
        cleared[far] = pushed[far]
        moved |= np.any(cleared != x, axis=1)
        self.hold(np.flatnonzero(moved), cleared[moved])
        return cleared


def _separate_layers(
    solve: _Solve, scene, x: np.ndarray, faces: np.ndarray, pairs: np.ndarray, layers: np.ndarray, near: _Near
) -> tuple[np.ndarray, int]:
    """``x`` with cloth passing through cloth moved onto its layer's offset surface, solved again, round by round.

    The triangles through other cloth (:func:`~patternbridge.assemble.selfcross.self_crossing`
    over the whole garment, the two sides of a seam counting as one vertex)
    and their neighbours within :data:`LAYER_RINGS` edges, except the sewn
    vertices (free to meet their partners between the layers), are held at the
    distance ``clearance_cm + layers * layer_cm`` outside the skin along the
    skin's normal: two pieces crossing at a seam lie one over the other, a
    piece folded through itself lies flat. The round with the fewest
    crossing triangles is kept.
    """
    sewn = np.zeros(len(x), dtype=bool)
    sewn[pairs.ravel()] = True
    s = solve.settings

    def hold_on_layers(ids: np.ndarray, x: np.ndarray) -> None:
        solve.hold(ids, _offset_points(scene, x[ids], s.clearance_cm + s.layer_cm * layers[ids]))

    # the two sides of a seam stay free to meet between their layers
    return _relieve_crossings(
        solve, scene, x, faces, near, rounds=s.layer_rounds, rings=LAYER_RINGS, relieve=hold_on_layers, free=sewn
    )


def _flatten_folds(solve: _Solve, scene, x: np.ndarray, faces: np.ndarray, near: _Near) -> tuple[np.ndarray, int]:
    """``x`` with the wrap's folds through other cloth smoothed out, round by round (``flatten_rounds``).

    Where two proxies meet (a leg's tube and the ring round the hips, blended
    over the crotch) the wrapped shape can fold through itself, and the shape
    term keeps that fold. The triangles through other cloth and their
    neighbours within :data:`FLATTEN_RINGS` edges lose their wrapped bend
    (:meth:`_Solve.flatten`): they lie smooth between the cloth round them,
    the seams still pulling. The round with the fewest crossing triangles is
    kept.
    """
    return _relieve_crossings(
        solve,
        scene,
        x,
        faces,
        near,
        rounds=solve.settings.flatten_rounds,
        rings=FLATTEN_RINGS,
        relieve=lambda ids, _x: solve.flatten(ids),
    )


def _relieve_crossings(
    solve: _Solve,
    scene,
    x: np.ndarray,
    faces: np.ndarray,
    near: _Near,
    *,
    rounds: int,
    rings: int,
    relieve,
    free: np.ndarray | None = None,
) -> tuple[np.ndarray, int]:
    """``x`` after up to ``rounds`` rounds of ``relieve``, each solved again: the best round and its crossings.

    Each round finds the triangles through other cloth (the whole garment,
    the two sides of a seam one vertex), takes their vertices and the
    neighbours within ``rings`` edges, less the ``free`` ones, calls
    ``relieve(ids, x)`` (it sets what the solve holds them to) and solves
    again with the skin cleared. It stops at a round without crossings.
    """
    best, best_n = x, None
    for _ in range(rounds + 1):
        crossing = near.crossing(x, faces)
        n_cross = int(np.count_nonzero(crossing))
        if best_n is None or n_cross < best_n:
            best, best_n = x, n_cross
        if n_cross == 0:
            break
        ids = np.zeros(len(x), dtype=bool)
        ids[faces[crossing].ravel()] = True
        for _ in range(rings):
            ids |= near.adjacency @ ids
        if free is not None:
            ids[free] = False
        ids = np.flatnonzero(ids)
        relieve(ids, x)
        x = solve.clear_skin(scene, solve(), faces)
        log.debug("seam graph: %d triangles through the cloth, %d vertices relieved", n_cross, len(ids))
    return best, best_n


FLATTEN_RINGS = 2  # neighbours (in edges) of the crossing triangles whose wrapped bend is released too
LAYER_RINGS = 2  # neighbours (in edges) of the crossing triangles held on their layer too


def _offset_points(scene, points: np.ndarray, offset_cm: np.ndarray) -> np.ndarray:
    """(n, 3): the closest skin points of ``points`` moved ``offset_cm`` (n,) out along the skin's normal."""
    q, normal, _, _, _ = scene.closest(points)
    inside = scene.inside(points)
    away = points - q
    length = np.linalg.norm(away, axis=1, keepdims=True)
    use_face = inside | (length[:, 0] < 1e-6)
    direction = np.where(use_face[:, None], normal, away / np.maximum(length, 1e-12))
    return q + np.asarray(offset_cm, dtype=np.float64)[:, None] * direction


def layer_ranks(sizes: np.ndarray) -> np.ndarray:
    """(k,) int64: the layer of each of ``k`` pieces from the cloth it holds, ``sizes`` (k,): 0 for the most.

    A piece with less cloth lies over the pieces it is sewn to: a collar over
    the neckline, a cuff over the sleeve, a band outside the body piece it
    binds, a sleeve cap over the bodice at the armhole. Of equal sizes (a
    piece and its mirror copy) the one listed first lies under the other: a
    centre seam laps one way all along.

    Examples
    --------
    >>> layer_ranks(np.array([900, 900, 300, 120, 300])).tolist()
    [0, 1, 2, 4, 3]
    """
    sizes = np.asarray(sizes)
    order = np.lexsort((np.arange(len(sizes)), -sizes))
    ranks = np.zeros(len(sizes), np.int64)
    ranks[order] = np.arange(len(sizes))
    return ranks
