"""The cloth solver: projective dynamics over springs, pins, body contact and self-contact.

One time step minimises, by local-global iterations (Bouaziz et al. 2014),

    |M^(1/2) (x - y)|² / 2h²  +  Σ_springs w/2 |S x - p|²  +  Σ_pins w/2 |x - t|²
        +  Σ_contacts w/2 |x - c|²  +  Σ_self w/2 |x - s|²

where ``y`` is the inertial prediction. The springs (stretch, bending,
seams; :mod:`.constraints`) project onto their target lengths; a vertex in
body contact (:mod:`.contact`) onto the offset surface of the skin, its
slide bounded by friction; the vertices of a vertex-triangle pair closer
than the cloth's thickness (:mod:`.selfcontact`) onto the separated
configuration on the side the pair started on. The contacts of a step are
found from the unconstrained solution (and by a swept ray from the step's
start); the global matrix with their weights is factorised once per step,
and a second round (``contact_rounds``) adds the contacts the iterations
created: every self-contact pair they violate, by any depth, and every
vertex they bring near the skin. Nothing
moves the cloth after the solve: the positions at a step's end are the
last global solution.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .constraints import SpringKind, Springs, difference_operator, project_springs
from .contact import contact_targets, signed_distances, slide_budgets, swept_hits
from .selfcontact import EdgePairs, SelfPairs, find_edge_pairs, find_pairs, keep_sides, resolve_pairs, rest_near_keys
from .untangle import edge_faces, untangle_targets

__all__ = ["ClothSolver", "DrapeSettings", "seam_gaps", "vertex_adjacency", "weld_groups"]

GRAVITY_CM_S2 = 981.0


@dataclass(frozen=True, slots=True, kw_only=True)
class DrapeSettings:
    """Solver settings (SI-like units with lengths in cm; weights in units of the mean vertex mass / h²)."""

    time_step_s: float = 1.0 / 60.0
    iterations: int = 8
    # rounds of iterations per step: a round after the first adds the contacts the iterations made (every
    # self-contact pair violated at all, every vertex gone within half the offset of the skin) to the matrix;
    # more rounds (4) held A's skirt and T-shirt as well but left B's shorts 2.1 mm open before welding
    contact_rounds: int = 2
    stretch_weight: float = 400.0
    bend_weight: float = 0.8
    seam_weight: float = 5000.0
    contact_weight: float = 5000.0  # body contact
    self_weight: float = 2000.0  # self-contact
    edge_edge: bool = True  # self-contact also between edges (else vertex-triangle only)
    # shrink the intersection contours of crossings that exist (:mod:`.untangle`) in a drape call that does not
    # say in which steps; the planned phases say it (``phases.plan_phases``: the sewing and settling of a garment
    # in the rest pose, not a drape in the dressing pose, where it made more crossings than it undid)
    untangle: bool = False
    untangle_weight: float = 8000.0
    untangle_step_cm: float = 0.5  # relative motion of a crossing edge against its triangle per step
    untangle_rings: int = 2  # self-contact is off this many edges round a crossing (the layers must pass)
    untangle_open_cm: float = 1.0  # no untangling within untangle_rings + 1 edges of a seam this wide open
    damping: float = 0.985  # velocity kept per step
    friction: float = 0.6  # Coulomb coefficient of the skin against the cloth
    offset_cm: float = 0.6  # distance kept from the skin
    contact_margin_cm: float = 0.1  # a vertex this much beyond the offset after the free solve is in contact
    thickness_cm: float = 0.35  # distance kept between layers
    # no self-contact between parts of the cloth closer than this at rest (path over the pattern's edges,
    # seams counting 0): a vertex and the triangles it is, or is sewn to, a corner of, and the ends of slivers
    self_rest_cm: float = 0.35
    density_kg_cm2: float = 1.5e-5  # 150 g/m²
    max_speed_cm_s: float = 150.0
    # seams left unsewn for now (``loose``) hold their starting gaps with this share of the seam weight
    loose_share: float = 0.1


def weld_groups(n: int, pairs: np.ndarray) -> np.ndarray:
    """(n,) int64 group id of every vertex, sewn vertices sharing one (connected components)."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    g = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
    _, labels = connected_components(g, directed=False)
    return labels.astype(np.int64)


def seam_gaps(x: np.ndarray, pairs: np.ndarray) -> np.ndarray:
    """(S,) float64, cm — distance between sewn vertex pairs."""
    return np.linalg.norm(x[pairs[:, 0]] - x[pairs[:, 1]], axis=1) if len(pairs) else np.zeros(0)


class ClothSolver:
    """Projective dynamics on a :class:`~patternbridge.assemble.drape.Cloth` (moves ``cloth.x`` and ``cloth.v``).

    The seam springs' target is ``seam_start * closing`` (see :meth:`step`);
    :meth:`restart_seams` makes the present gaps the start. :meth:`loosen`,
    :meth:`weigh` and :meth:`pin` change the constant part of the system.
    """

    def __init__(self, cloth, settings: DrapeSettings) -> None:
        self.c = cloth
        self.s = settings
        h = settings.time_step_s
        n = len(cloth.x)
        self.unit = float(cloth.mass.mean()) / h**2
        kinds = [SpringKind.STRETCH, SpringKind.BEND, SpringKind.SEAM]
        groups = [cloth.edges, cloth.bends, cloth.seams]
        weights = [settings.stretch_weight, settings.bend_weight, settings.seam_weight]
        self.springs = Springs(
            pairs=np.concatenate(groups).reshape(-1, 2),
            kind=np.concatenate([np.full(len(g), int(k)) for g, k in zip(groups, kinds, strict=True)]),
            weight=np.concatenate([np.full(len(g), w) for g, w in zip(groups, weights, strict=True)]),
        )
        self.S = difference_operator(n, self.springs.pairs)
        self.St = self.S.T.tocsr()
        self.is_seam = self.springs.of(SpringKind.SEAM)
        self.mass_h2 = cloth.mass / h**2
        self.m_h2 = self.mass_h2
        self.pin_w = np.zeros(n)
        self.pin_x = np.zeros((n, 3))
        self.loose: np.ndarray | None = None
        self.seam_start = seam_gaps(cloth.x, cloth.seams)
        self.weld = weld_groups(n, cloth.seams)
        self.near = rest_near_keys(n, cloth.edges, cloth.rest, cloth.seams, settings.self_rest_cm)
        self._sides = (np.zeros(0, np.int64), np.zeros((0, 3)))  # the last step's vertex-triangle pairs
        self._edge_sides = (np.zeros(0, np.int64), np.zeros((0, 3)))  # and edge-edge pairs: key, direction
        self._last_x: np.ndarray | None = None  # the cloth at the last step's end
        self.beside = edge_faces(cloth.faces, cloth.edges)
        self.adjacency = vertex_adjacency(n, cloth.edges)
        self._base = None  # the constant part of the global matrix
        self._free = None  # its factorisation
        self.untangling = settings.untangle  # the untangling acts in this step (``drape`` sets it per phase)
        self.stats = {"factorisations": 0, "contacts": 0, "self_pairs": 0, "crossings": 0}

    # -- the constant part of the system ---------------------------------------------------------
    def _weights(self) -> np.ndarray:
        w = self.springs.weight * self.unit
        if self.loose is not None:
            w = w.copy()
            w[np.flatnonzero(self.is_seam)[self.loose]] *= self.s.loose_share
        return w

    def _system(self):
        from scipy.sparse import diags
        from scipy.sparse.linalg import splu

        if self._base is None:
            self.w_now = self._weights()
            self._base = (diags(self.m_h2 + self.pin_w) + self.St @ diags(self.w_now) @ self.S).tocsc()
            self._free = splu(self._base)
            self.stats["factorisations"] += 1
        return self._base, self._free

    def _factor(self, extra: np.ndarray):
        from scipy.sparse import diags
        from scipy.sparse.linalg import splu

        base, free = self._system()
        if not extra.any():
            return free
        self.stats["factorisations"] += 1
        return splu((base + diags(extra)).tocsc())

    def loosen(self, seams: np.ndarray | None) -> None:
        """Leave the seam pairs ``seams`` (S,) bool unsewn until called with None.

        They keep a spring at ``loose_share`` of the seam weight holding them
        at their gaps of the last :meth:`restart_seams` (or the start): the
        two sides move together without closing.
        """
        new = None if seams is None or not np.any(seams) else np.asarray(seams, dtype=bool).copy()
        if (new is None) != (self.loose is None) or (new is not None and not np.array_equal(new, self.loose)):
            self.loose = new
            self._base = None

    def weigh(self, scale: np.ndarray | None) -> None:
        """Scale every vertex's inertia by ``scale`` (N,) (None: the plain masses)."""
        m_h2 = self.mass_h2 if scale is None else self.mass_h2 * np.asarray(scale, dtype=np.float64)
        if not np.array_equal(m_h2, self.m_h2):
            self.m_h2 = m_h2
            self._base = None

    def restart_seams(self) -> None:
        """Sew on from where the seams are now: the gaps shrink from their present lengths."""
        self.seam_start = seam_gaps(self.c.x, self.c.seams)

    def pin(self, weights: np.ndarray | None, targets: np.ndarray | None = None) -> None:
        """Hold vertices softly on ``targets`` (N, 3), ``weights`` (N,) in units of their mass / h²; None releases."""
        if weights is None or not np.any(np.asarray(weights) > 0):
            pin_w = np.zeros(len(self.mass_h2))
        else:
            pin_w = np.asarray(weights, dtype=np.float64) * self.mass_h2
            self.pin_x = np.asarray(targets, dtype=np.float64).copy()
        if not np.array_equal(pin_w, self.pin_w):
            self.pin_w = pin_w
            self._base = None

    # -- one time step ------------------------------------------------------------------------------
    def _untangle(self, x0: np.ndarray, x: np.ndarray, pairs: SelfPairs, epairs: EdgePairs | None):
        """The untangling of one step: crossing vertices, their targets, and the self-contact pairs left on.

        The crossings are found at the step's start ``x0``; their moves
        (:func:`.untangle.untangle_targets`) are added to the free solution
        ``x``. Self-contact pairs whose two sides lie round a crossing are
        left out (a crossed layer is not held on the side it is on: the
        contour's shrinking decides).
        """
        none = np.zeros(0, np.int64)
        if not self.untangling:
            return none, np.zeros((0, 3)), pairs, epairs
        c, s = self.c, self.s
        # the cloth round a seam still open is left to the seam: pulling it through the cloth there fights the
        # seam's spring, which drags it back (and opened seams)
        held = np.zeros(len(x), dtype=bool)
        held[c.seams[seam_gaps(x0, c.seams) > s.untangle_open_cm].ravel()] = True
        for _ in range(s.untangle_rings + 1):
            held |= self.adjacency @ held
        ids, moves, n = untangle_targets(x0, c.faces, c.edges, self.beside, self.weld, s.untangle_step_cm, held)
        self.stats["crossings"] += n
        if len(ids):
            around = np.zeros(len(x), dtype=bool)
            around[ids] = True
            for _ in range(s.untangle_rings):
                around |= self.adjacency @ around
            pairs, epairs = _without(pairs, epairs, c.faces, np.flatnonzero(around), len(x))
        # the sides of a seam are one point: they aim at their common position (their mean), so a gap is
        # closed and not held open by the untangling's weight, which exceeds the seam's
        count = np.bincount(self.weld, minlength=len(x)).astype(np.float64)
        mean = np.stack([np.bincount(self.weld, weights=x[:, k], minlength=len(x)) for k in range(3)], axis=1)
        return ids, mean[self.weld[ids]] / count[self.weld[ids], None] + moves, pairs, epairs

    def _remember(self, pairs: SelfPairs, epairs: EdgePairs | None) -> tuple[SelfPairs, EdgePairs | None]:
        """The step's pairs with the sides of the last step's kept where they turned round (:func:`keep_sides`).

        The cloth moved between two steps (a pose applied by skinning) starts
        without memory: a side turned round there was not turned by a step.
        """
        if self._last_x is None or not np.array_equal(self._last_x, self.c.x):  # moved between steps: forget
            self._sides = self._edge_sides = (np.zeros(0, np.int64), np.zeros((0, 3)))
        keys = pairs.keys(len(self.c.faces))
        direction = keep_sides(keys, pairs.direction, *self._sides)
        order = np.argsort(keys)
        self._sides = (keys[order], direction[order])
        pairs = SelfPairs(vertex=pairs.vertex, triangle=pairs.triangle, direction=direction)
        if epairs is not None:
            direction = keep_sides(epairs.key, epairs.direction, *self._edge_sides)
            order = np.argsort(epairs.key)
            self._edge_sides = (epairs.key[order], direction[order])
            epairs = EdgePairs(edges=epairs.edges, direction=direction, key=epairs.key)
        return pairs, epairs

    def _springs_rhs(self, x: np.ndarray, targets: np.ndarray) -> np.ndarray:
        return self.St @ (self.w_now[:, None] * project_springs(self.S @ x, targets))

    def step(self, collider, gravity: float, sew: float) -> None:
        """Advance one time step under ``gravity`` (cm/s²) with the seams ``sew`` (0..1) of the way closed."""
        c, s = self.c, self.s
        h = s.time_step_s
        x0 = c.x.copy()
        v = c.v * np.minimum(1.0, s.max_speed_cm_s / np.maximum(np.linalg.norm(c.v, axis=1), 1e-9))[:, None]
        y = x0 + h * v
        y[:, 1] -= h * h * gravity
        closing = np.full(len(c.seams), max(0.0, 1.0 - sew))
        if self.loose is not None:
            closing[self.loose] = 1.0
        targets = np.concatenate([c.target, c.bend_rest, self.seam_start * closing])
        _, free = self._system()
        rhs0 = self.m_h2[:, None] * y + self.pin_w[:, None] * self.pin_x
        # the free solution decides which contacts the step has
        x = free.solve(rhs0 + self._springs_rhs(y, targets))
        hit, at = swept_hits(collider, x0, x, s.offset_cm)
        x[hit] = at[hit]
        _, _, sd = signed_distances(collider, x)
        body = (sd < s.offset_cm + s.contact_margin_cm) | hit
        # pairs within reach of the step's motion: a layer moving fast toward another is caught before it passes
        motion = float(np.percentile(np.linalg.norm(x - x0, axis=1), 99)) if len(x) else 0.0
        reach = s.thickness_cm + 2 * s.contact_margin_cm + min(motion, s.max_speed_cm_s * h)
        # a pair whose two sides move together (one layer) is left out: only the motion against each other counts
        gap = s.thickness_cm + 2 * s.contact_margin_cm
        pairs = find_pairs(x0, c.faces, self.near, reach, x - x0, gap)
        epairs = find_edge_pairs(x0, c.edges, self.near, reach, x - x0, gap) if s.edge_edge else None
        tangled, tangle_x, pairs, epairs = self._untangle(x0, x, pairs, epairs)
        pairs, epairs = self._remember(pairs, epairs)
        tangle_w = np.zeros(len(x))
        tangle_w[tangled] = s.untangle_weight * self.unit
        selfv = np.zeros(len(x), dtype=bool)
        selfv[resolve_pairs(x, c.faces, pairs, s.thickness_cm, epairs)[0]] = True
        self.stats["self_pairs"] += len(pairs) + (len(epairs) if epairs is not None else 0)
        normals = np.zeros_like(x)
        budget = np.zeros(len(x))
        bi = np.flatnonzero(body)
        budget[bi] = slide_budgets(collider, x[bi], x0[bi], y[bi], s.offset_cm, s.friction)
        for rnd in range(s.contact_rounds):
            extra = self.unit * (s.contact_weight * body + s.self_weight * selfv) + tangle_w
            lu = self._factor(extra)
            for _ in range(s.iterations if rnd == 0 else max(2, s.iterations // 2)):
                rhs = rhs0 + self._springs_rhs(x, targets)
                if len(tangled):
                    rhs[tangled] += tangle_w[tangled, None] * tangle_x
                bi = np.flatnonzero(body)
                if len(bi):
                    p, normals[bi] = contact_targets(collider, x[bi], x0[bi], budget[bi], s.offset_cm)
                    rhs[bi] += (s.contact_weight * self.unit) * p
                si = np.flatnonzero(selfv)
                if len(si):
                    ids, q = resolve_pairs(x, c.faces, pairs, s.thickness_cm, epairs)
                    st = x.copy()
                    st[ids] = q
                    rhs[si] += (s.self_weight * self.unit) * st[si]
                x = lu.solve(rhs)
            # another round with the contacts the iterations made: a pair the iterations violate that is not
            # in the matrix yet is otherwise not held at all (its vertex is pushed through by the skin's
            # contact and the stretch, with the pair's correction in no equation)
            _, _, sd = signed_distances(collider, x)
            hit, at = swept_hits(collider, x0, x, s.offset_cm)
            new_body = ((sd < 0.5 * s.offset_cm) | hit) & ~body
            ids, _ = resolve_pairs(x, c.faces, pairs, s.thickness_cm, epairs)
            new_self = np.zeros(len(x), dtype=bool)
            new_self[ids] = True
            new_self &= ~selfv
            if rnd == s.contact_rounds - 1 or not (new_body.any() or new_self.any()):
                break
            x[hit & ~body] = at[hit & ~body]
            ni = np.flatnonzero(new_body)
            budget[ni] = slide_budgets(collider, x[ni], x0[ni], y[ni], s.offset_cm, s.friction)
            body |= new_body
            selfv |= new_self
        self.stats["contacts"] += int(np.count_nonzero(body))
        v = (x - x0) / h
        bi = np.flatnonzero(body)
        if len(bi):  # inelastic contact: no bounce off the skin
            vn = np.einsum("ij,ij->i", v[bi], normals[bi])
            v[bi] -= np.maximum(vn, 0.0)[:, None] * normals[bi]
        c.v = v * s.damping
        c.x = x
        self._last_x = x.copy()


def _without(
    pairs: SelfPairs, epairs: EdgePairs | None, faces: np.ndarray, vertices: np.ndarray, n: int
) -> tuple[SelfPairs, EdgePairs | None]:
    """The self-contact pairs that do not join two parts of the cloth round a crossing (``vertices``).

    A pair is left out when both its sides touch ``vertices``: the layers that
    cross may pass back through each other, while a third layer still holds
    them off.
    """
    out = np.zeros(n, dtype=bool)
    out[vertices] = True
    keep = ~(out[pairs.vertex] & out[faces[pairs.triangle]].any(axis=1))
    pairs = SelfPairs(vertex=pairs.vertex[keep], triangle=pairs.triangle[keep], direction=pairs.direction[keep])
    if epairs is not None:
        ends = out[epairs.edges.reshape(len(epairs), 4)]
        keep = ~(ends[:, :2].any(axis=1) & ends[:, 2:].any(axis=1))
        epairs = EdgePairs(edges=epairs.edges[keep], direction=epairs.direction[keep], key=epairs.key[keep])
    return pairs, epairs


def vertex_adjacency(n: int, edges: np.ndarray):
    """(n, n) boolean sparse matrix: True where an edge of ``edges`` (E, 2) joins two of ``n`` vertices.

    A boolean vector ``m`` grown by ``m |= adjacency @ m`` gains its ring of
    neighbours; repeated edges (a triangle mesh's shared edges) are harmless.
    """
    from scipy.sparse import coo_matrix

    e = np.asarray(edges, dtype=np.int64)
    return coo_matrix((np.ones(2 * len(e), dtype=bool), (e.ravel(), e[:, ::-1].ravel())), shape=(n, n)).tocsr()
