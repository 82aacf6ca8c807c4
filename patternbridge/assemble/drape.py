"""Sew and drape the placed pieces: a projective-dynamics cloth solver in numpy/scipy.

Every constraint is a spring between two vertices that wants a target length:
the mesh edges (stretch, rest length from the 2D pattern), the far corners of
every pair of adjacent triangles (bending, rest length from the flat pattern)
and the seam pairs (target length shrinking from the initial gap to zero while
sewing, then zero; much stiffer than the cloth, so that the simulation, not the
final weld, closes the seams). Along a seam whose sides differ in length (a
gathered or eased edge) the longer side's springs take the shorter side's
lengths. Projective dynamics (Bouaziz et al. 2014) alternates a
local step (each spring's target vector) with a global step whose matrix
``M/h² + Σ w SᵀS`` is constant, so it is factorised once. Collisions with the
body are half-space projections rebuilt every step from the closest skin
point; Coulomb friction bounds how far a vertex in contact slides by how far
the skin pushed it out in that step; vertices of different layers are
pushed apart, and every vertex stays on its side of the cloth's nearby
triangles (:func:`~patternbridge.assemble.selfcross.keep_sides`). Seams
are welded at the end by averaging each group of sewn vertices.
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from .collision import BodyCollider, separate_layers
from .selfcross import keep_sides, keep_uncrossed, self_crossing

__all__ = ["Cloth", "DrapeSettings", "build_cloth", "drape", "gathered_lengths", "seam_gaps", "weld_groups"]

log = logging.getLogger(__name__)

GRAVITY_CM_S2 = 981.0


@dataclass(frozen=True, slots=True, kw_only=True)
class DrapeSettings:
    """Solver settings (SI-like units with lengths in cm)."""

    time_step_s: float = 1.0 / 60.0
    iterations: int = 6
    stretch_weight: float = 400.0  # in units of the mean vertex mass / h²
    bend_weight: float = 0.8
    seam_weight: float = 5000.0
    damping: float = 0.985  # velocity kept per step
    friction: float = 0.6  # Coulomb coefficient of the skin against the cloth
    offset_cm: float = 0.6  # distance kept from the skin
    thickness_cm: float = 0.35  # distance kept between layers
    density_kg_cm2: float = 1.5e-5  # 150 g/m²
    max_speed_cm_s: float = 150.0
    max_step_cm: float = 1.0
    # seams left unsewn for now (``loose``) hold their starting gaps with this share of the seam weight
    loose_share: float = 0.1
    keep_sides: bool = True  # a vertex stays on its side of the cloth's triangles (see selfcross.keep_sides)


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


def _edges_and_bends(faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Unique edges (E, 2) and bending pairs (B, 2) (opposite corners of adjacent triangles)."""
    he = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    opp = np.concatenate([faces[:, 2], faces[:, 0], faces[:, 1]])
    key = np.sort(he, axis=1)
    order = np.lexsort((key[:, 1], key[:, 0]))
    key, opp = key[order], opp[order]
    same = np.all(key[1:] == key[:-1], axis=1)
    edges = np.unique(key, axis=0)
    bends = np.stack([opp[:-1][same], opp[1:][same]], axis=1)
    return edges, bends


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
    edges, bends = _edges_and_bends(f)
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


def gathered_lengths(edges: np.ndarray, rest: np.ndarray, seams: list[tuple[np.ndarray, np.ndarray]]) -> np.ndarray:
    """(E,) stretch-spring lengths with the longer side of every sewn edge pair gathered to the shorter.

    A seam joins two edges of different lengths where one side is eased or
    gathered into the other (a sleeve hem into a narrower cuff, a sleeve
    cap into its armhole). The mesh matches their vertices one to one, so
    each segment of the longer side faces a shorter one: sewn flat, the
    longer side's segment takes the shorter one's length and the cloth
    beside it folds (the gathers). Springs at the pattern lengths on both
    sides would fight the seam springs, and the seam would stay open by the
    difference (a 4 cm ease spread along a cuff left its ends 1-3 cm off
    the hem).

    Parameters
    ----------
    edges : (E, 2) int64 sorted vertex pairs ; rest : (E,) float64, cm
    seams : per seam the sewn vertices of its two sides, in order (global ids)
    """
    out = np.array(rest, dtype=np.float64)
    if len(edges) == 0:
        return out
    n = int(edges.max()) + 1
    keys = edges[:, 0] * n + edges[:, 1]
    order = np.argsort(keys)
    sorted_keys = keys[order]

    def find(p: np.ndarray, q: np.ndarray) -> np.ndarray:
        k = np.minimum(p, q) * n + np.maximum(p, q)
        pos = np.clip(np.searchsorted(sorted_keys, k), 0, len(keys) - 1)
        return np.where(sorted_keys[pos] == k, order[pos], -1)

    for va, vb in seams:
        if len(va) < 2:
            continue
        ea, eb = find(va[:-1], va[1:]), find(vb[:-1], vb[1:])
        ok = (ea >= 0) & (eb >= 0) & (ea != eb)
        ea, eb = ea[ok], eb[ok]
        short = np.minimum(out[ea], out[eb])
        out[ea] = short
        out[eb] = short
    return out


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


def _push_direction(x: np.ndarray, q: np.ndarray, n: np.ndarray, inside: np.ndarray) -> np.ndarray:
    """Unit directions from the closest skin points outward (the distance gradient).

    Away from the skin the direction from ``q`` to ``x`` (reversed inside) is
    exact even in hollows, where the face normal points into the next face;
    on the skin itself the face normal is used.
    """
    d = (x - q) * np.where(inside, -1.0, 1.0)[:, None]
    ln = np.linalg.norm(d, axis=1, keepdims=True)
    use = ln[:, 0] > 1e-3
    out = n.copy()
    out[use] = d[use] / ln[use]
    # never push against the face normal (a point exactly on an edge can be ambiguous)
    flip = np.einsum("ij,ij->i", out, n) < 0
    out[flip] = n[flip]
    return out


class _Solver:
    def __init__(self, cloth: Cloth, settings: DrapeSettings) -> None:
        from scipy.sparse import coo_matrix

        self.c = cloth
        self.s = settings
        h = settings.time_step_s
        n = len(cloth.x)
        unit = float(cloth.mass.mean()) / h**2
        springs = np.concatenate([cloth.edges, cloth.bends, cloth.seams])
        w = np.concatenate(
            [
                np.full(len(cloth.edges), settings.stretch_weight * unit),
                np.full(len(cloth.bends), settings.bend_weight * unit),
                np.full(len(cloth.seams), settings.seam_weight * unit),
            ]
        )
        m = len(springs)
        rows = np.repeat(np.arange(m), 2)
        S = coo_matrix((np.tile([1.0, -1.0], m), (rows, springs.ravel())), shape=(m, n)).tocsr()
        self.S, self.St = S, S.T.tocsr()
        self.w = w
        self.n_stretch, self.n_bend = len(cloth.edges), len(cloth.bends)
        self.mass_h2 = cloth.mass / h**2
        self.m_h2 = self.mass_h2  # the inertia in the system: the masses, or scaled (``weigh``)
        self.pin_w = np.zeros(n)
        self.pin_x = np.zeros((n, 3))
        self._pins: np.ndarray | None = None  # the weights the factorisation ``lu`` was made with
        self.loose: np.ndarray | None = None  # seam pairs not sewn yet (held at their gaps, see ``loosen``)
        self._factorise()
        self.seam_start = seam_gaps(cloth.x, cloth.seams)
        self.weld = weld_groups(n, cloth.seams)
        self.guard_crossings = False  # see drape(guard_crossings=)
        self._crossed: tuple | None = None  # (collider, (E,) bool edges across its skin at the last step's end)
        self.face_group = cloth.group[cloth.faces[:, 0]]
        self._folded: np.ndarray | None = None  # (F,) bool triangles through their piece at the last step's end

    def _factorise(self) -> None:
        from scipy.sparse import diags
        from scipy.sparse.linalg import splu

        w = self.w
        if self.loose is not None:
            w = w.copy()
            w[self.n_stretch + self.n_bend :][self.loose] *= self.s.loose_share
        self.w_now = w
        self.A = (diags(self.m_h2) + self.St @ diags(w) @ self.S).tocsc()
        self.lu_free = splu(self.A)
        self.lu = splu((self.A + diags(self.pin_w)).tocsc()) if self._pins is not None else self.lu_free

    def loosen(self, seams: np.ndarray | None) -> None:
        """Leave the seam pairs ``seams`` (S,) bool unsewn until called with None.

        They keep a spring at ``loose_share`` of the seam weight holding them
        at their gaps of the last :meth:`restart_seams` (or the start): the two
        sides move together without closing. With no spring at all a cuff left
        free on a raised arm turned 60-80° round the wrist and slid up the
        forearm ahead of its sleeve, and closing it later twisted the hem
        round the thumb.
        """
        new = None if seams is None or not np.any(seams) else np.asarray(seams, dtype=bool).copy()
        if (new is None) != (self.loose is None) or (new is not None and not np.array_equal(new, self.loose)):
            self.loose = new
            self._factorise()

    def weigh(self, scale: np.ndarray | None) -> None:
        """Scale every vertex's inertia by ``scale`` (N,) (None: the plain masses) and refactorise if it changed.

        Without gravity a vertex's mass only decides how much of a seam's
        closing it takes: heavier cloth stays, lighter cloth comes to it.
        """
        m_h2 = self.mass_h2 if scale is None else self.mass_h2 * np.asarray(scale, dtype=np.float64)
        if not np.array_equal(m_h2, self.m_h2):
            self.m_h2 = m_h2
            self._factorise()

    def restart_seams(self) -> None:
        """Sew on from where the seams are now: the gaps shrink from their present lengths (see ``sew_ramp``)."""
        self.seam_start = seam_gaps(self.c.x, self.c.seams)

    def pin(self, weights: np.ndarray | None, targets: np.ndarray | None = None) -> None:
        """Hold vertices softly on ``targets`` (N, 3) with ``weights`` (N,) in units of their mass / h²; None releases.

        The pins enter the constant system matrix, which is refactorised
        (once per distinct set of pins).
        """
        from scipy.sparse import diags
        from scipy.sparse.linalg import splu

        if weights is None or not np.any(weights > 0):
            self.lu, self.pin_w, self._pins = self.lu_free, np.zeros(len(self.m_h2)), None
            return
        self.pin_w = np.asarray(weights, dtype=np.float64) * self.mass_h2
        self.pin_x = np.asarray(targets, dtype=np.float64).copy()
        if self._pins is not weights:  # (the array is kept, so its identity is not reused)
            self.lu = splu((self.A + diags(self.pin_w)).tocsc())
            self._pins = weights

    def _push_edges(self, collider: BodyCollider, x: np.ndarray, ni: np.ndarray) -> np.ndarray:
        """Push edge midpoints and triangle centroids near ``ni`` to ``offset_cm`` outside the skin.

        The vertices alone do not keep a long edge or a triangle out of a thin
        limb; a sample point that is too close moves all the vertices it is
        made of by its correction (averaged over the samples sharing a vertex).
        """
        s = self.s
        if len(ni) == 0:
            return x
        touch = np.zeros(len(x), dtype=bool)
        touch[ni] = True
        e = self.c.edges[touch[self.c.edges[:, 0]] | touch[self.c.edges[:, 1]]]
        f = self.c.faces[touch[self.c.faces].any(axis=1)]
        samples = [(e, 0.5 * (x[e[:, 0]] + x[e[:, 1]])), (f, x[f].mean(axis=1))]
        delta = np.zeros_like(x)
        cnt = np.zeros(len(x))
        for idx, m in samples:
            if len(idx) == 0:
                continue
            q, n, si, _, _ = collider.closest(m)
            close = si < s.offset_cm + 0.5
            if not close.any():
                continue
            idx, m, q, n, si = idx[close], m[close], q[close], n[close], si[close]
            si = np.where(collider.inside(m), -np.abs(si), np.abs(si))
            fix = si < s.offset_cm
            if not fix.any():
                continue
            idx, m, q, n, si = idx[fix], m[fix], q[fix], n[fix], si[fix]
            corr = q + s.offset_cm * _push_direction(m, q, n, si < 0) - m
            for k in range(idx.shape[1]):
                np.add.at(delta, idx[:, k], corr)
                np.add.at(cnt, idx[:, k], 1.0)
        return x + delta / np.maximum(cnt, 1.0)[:, None]

    def step(
        self,
        collider: BodyCollider,
        gravity: float,
        sew: float,
        *,
        layers: np.ndarray | None,
    ) -> None:
        c, s = self.c, self.s
        lu = self.lu
        h = s.time_step_s
        x0 = c.x.copy()
        y = c.x + h * c.v
        y[:, 1] -= h * h * gravity
        _, nrm, signed, _, _ = collider.closest(y)
        # ray parity decides inside/outside; the face normal alone misjudges deep points
        inside = collider.inside(y)
        signed = np.where(inside, -np.abs(signed), np.abs(signed))
        near = inside | (signed < s.offset_cm + s.max_speed_cm_s * h * 1.5)
        closing = np.full(len(c.seams), max(0.0, 1.0 - sew))
        if self.loose is not None:
            closing[self.loose] = 1.0  # held at their starting gaps, not sewn
        targets = np.concatenate([c.target, c.bend_rest, self.seam_start * closing])
        rhs0 = self.m_h2[:, None] * y
        if self._pins is not None:
            rhs0 = rhs0 + self.pin_w[:, None] * self.pin_x
        x = y.copy()
        ni = np.flatnonzero(near)
        contact = np.zeros(len(x), dtype=bool)
        for it in range(s.iterations):
            d = self.S @ x
            ln = np.linalg.norm(d, axis=1, keepdims=True)
            p = d * (targets[:, None] / np.maximum(ln, 1e-9))
            x = lu.solve(rhs0 + self.St @ (self.w_now[:, None] * p))
            # no vertex may jump through a limb in one step: when the fastest one
            # would move more than max_step_cm, the whole step is scaled down
            # (uniformly, so the cloth's shape is not torn)
            dx = x - x0
            fastest = float(np.sqrt(np.max(np.einsum("ij,ij->i", dx, dx))))
            if fastest > s.max_step_cm:
                x = x0 + dx * (s.max_step_cm / fastest)
            if layers is not None and it == s.iterations - 1:
                x = separate_layers(x, c.group, c.uv, s.thickness_cm, weld=layers)
            if it == s.iterations - 1:
                ni = np.arange(len(x))  # the last pass checks every vertex
            if len(ni):
                # closest points of the current positions: the skin is curved, a
                # tangent plane from the step start does not hold in its hollows
                qi, ni_n, si, _, _ = collider.closest(x[ni])
                if it == s.iterations - 1 or it % 2 == 0:
                    ins = collider.inside(x[ni])
                    si = np.where(ins, -np.abs(si), np.abs(si))
                else:
                    si = np.where(
                        np.einsum("ij,ij->i", x[ni] - qi, ni_n) < 0,
                        -np.abs(si),
                        np.abs(si),
                    )
                fix = si < s.offset_cm
                x[ni[fix]] = qi[fix] + s.offset_cm * _push_direction(x[ni[fix]], qi[fix], ni_n[fix], si[fix] < 0)
                if it == s.iterations - 1:
                    contact[ni[si < s.offset_cm + 0.05]] = True
                    nrm[ni] = ni_n
                if it % 2 == 1 or it == s.iterations - 1:
                    x = self._push_edges(collider, x, ni)
        if contact.any():
            # Coulomb friction, on the step's motion: how far the skin pushed a
            # vertex out this step (against the inertial prediction) bounds how
            # far it may slide along the skin; cloth pressed hard sticks, cloth
            # lying lightly on a slope gentler than atan(friction) stays put and
            # on a steeper one slides
            nn = nrm[contact]
            dx = x[contact] - x0[contact]
            dn = np.einsum("ij,ij->i", dx, nn)[:, None] * nn
            dt = dx - dn
            push = np.maximum(np.einsum("ij,ij->i", x[contact] - y[contact], nn), 0.0)
            slide = np.linalg.norm(dt, axis=1)
            keep = np.maximum(0.0, 1.0 - s.friction * push / np.maximum(slide, 1e-12))
            x[contact] = x0[contact] + dn + keep[:, None] * dt
        if s.keep_sides:  # last, after the skin's pushes: they must not drive one layer through another
            x = keep_sides(x, x0, c.faces, self.weld, s.thickness_cm)
        if self.guard_crossings:  # what crosses goes back to the step's start
            if self._folded is None:
                self._folded = self_crossing(x0, c.faces, self.face_group, self.weld)
            x, self._folded = keep_uncrossed(x, x0, c.faces, self.face_group, self.weld, self._folded)
            if self._crossed is None or self._crossed[0] is not collider:
                self._crossed = (collider, collider.crossing_edges(x0[c.edges[:, 0]], x0[c.edges[:, 1]]))
            x, crossed = collider.keep_edges_out(x, x0, c.edges, self._crossed[1])
            self._crossed = (collider, crossed)
        v = (x - x0) / h
        if contact.any():  # inelastic contact: no bounce off the skin
            vn = np.einsum("ij,ij->i", v[contact], nn)
            v[contact] -= np.maximum(vn, 0.0)[:, None] * nn
        speed = np.linalg.norm(v, axis=1, keepdims=True)
        v *= np.minimum(1.0, s.max_speed_cm_s / np.maximum(speed, 1e-9))
        c.v = v * s.damping
        c.x = x


def drape(
    cloth: Cloth,
    collider: BodyCollider,
    *,
    steps: int = 150,
    sew_steps: int = 80,
    settings: DrapeSettings | None = None,
    gravity_scale: float = 1.0,
    progress: Callable[[str, int, int], None] | None = None,
    stage: str = "drape",
    solver: _Solver | None = None,
    layer_every: int = 2,
    anchors: tuple[np.ndarray, np.ndarray] | None = None,
    hold: np.ndarray | None = None,
    loose: np.ndarray | None = None,
    sew_ramp: tuple[float, float] | None = None,
    inertia: np.ndarray | None = None,
    guard_crossings: bool = False,
) -> _Solver:
    """Run the cloth for ``steps`` time steps against ``collider`` (in place).

    The seam springs' target length shrinks linearly to zero over the first
    ``sew_steps`` steps; gravity ramps up over the same time. Returns the
    solver, which can be passed back to continue with another collider (the
    factorisation is reused). ``anchors`` = (weights (N,) in units of the
    vertex's mass / h², positions (N, 3)) pins vertices softly while sewing;
    ``hold`` (N,) weights pin vertices where the sewing left them for the
    rest of the run (a waistband buttoned at the waist). ``loose`` (S,) bool
    leaves those seam pairs unsewn for this call (held at their gaps, see
    :meth:`~_Solver.loosen`). With ``sew_steps`` 0,
    ``sew_ramp`` = (from, to) keeps sewing during the call: the gaps shrink
    from ``from`` to ``to`` of the way between their lengths at the
    solver's last :meth:`~_Solver.restart_seams` and zero. ``inertia`` (N,)
    scales the vertices' masses in the solver for this call (see
    :meth:`~_Solver.weigh`). ``guard_crossings`` keeps what is clear at
    the start of a step clear at its end: every triangle of the cloth
    clear of its own piece (:func:`~patternbridge.assemble.selfcross.keep_uncrossed`)
    and every edge clear of the skin
    (:meth:`~patternbridge.assemble.collision.BodyCollider.keep_edges_out`);
    the vertices that would cross go back. Not while sewing: pieces held
    back there keep their seams open.
    """
    settings = settings or DrapeSettings()
    solver = solver or _Solver(cloth, settings)
    solver.loosen(loose)
    solver.weigh(inertia)
    solver.guard_crossings = guard_crossings
    solver._folded = None  # the cloth may have been moved since the last call
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
        solver.step(
            collider,
            g,
            min(sew, 1.0),
            layers=solver.weld if k % layer_every == 0 else None,
        )
        if k + 1 == sew_steps:
            solver.pin(hold, cloth.x)
        if progress is not None and (k % 10 == 0 or k == steps - 1):
            progress(stage, k + 1, steps)
    return solver
