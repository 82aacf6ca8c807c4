"""Self-contact of the cloth: vertex-triangle and edge-edge pairs that keep their sides, as solver constraints.

At every time step the pairs of a vertex and a cloth triangle closer than
``thickness_cm`` plus a margin are found from the step's start (a k-d tree of
the vertices against the triangle centres), by the **true** distance from the
vertex to the triangle's closest point (inside, on an edge or at a corner).
Each pair remembers the direction from that closest point to the vertex: the
side of the triangle it is on, or the way it lies beside an edge. While the
solver iterates, a pair whose vertex has come closer than ``thickness_cm``
along that direction (or gone through) gives the vertex and the triangle's
corners targets that restore the distance (shared by the closest point's
barycentric weights, as a point-triangle constraint of position-based
dynamics); a vertex in several pairs takes the mean. Edge-edge pairs do the
same along the direction that joined their closest points at the step's
start (two edges crossing like the threads of a weave, which no
vertex-triangle pair sees).

A pair is never formed between parts of the cloth that are close **in the
rest state of the sewn cloth** (:func:`rest_near_keys`: the shortest path
over the mesh edges at their pattern lengths, seam links counting 0, below a
radius): a vertex and a triangle it is a corner of, or whose corner it is
sewn to, touch by construction, while a vertex one edge away from a triangle
lies a triangle's height from it at rest and is held off it when the cloth
folds. Because the distance is the true one, a neighbour in the same flat
sheet is never within the thickness and the sheet is not pushed out of its
plane.

Given the step's expected motion, a pair is kept only when closer than
the thickness (and a margin) plus how far its two sides move against each
other: a vertex moving with its own layer needs no pair.

Side memory (:func:`keep_sides`): a pair found again at the next step keeps
the direction it had when its direction turns round in one step (the vertex
or edge went through during the step), so a crossing a soft constraint let
through is pulled back instead of being held on the wrong side.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...mesh.surface_point import closest_on_triangles

__all__ = [
    "EdgePairs",
    "SelfPairs",
    "closest_on_triangles",
    "find_edge_pairs",
    "find_pairs",
    "keep_sides",
    "resolve_pairs",
    "rest_near_keys",
]


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class SelfPairs:
    """Vertex-triangle pairs of one step.

    vertex : (k,) int64 ; triangle : (k,) int64 face id ; direction : (k, 3) float64 —
    the unit direction from the triangle's closest point to the vertex at the step's start
    (± the normal for a vertex over the triangle's inside)
    """

    vertex: np.ndarray
    triangle: np.ndarray
    direction: np.ndarray

    def __len__(self) -> int:
        return len(self.vertex)

    def keys(self, n_faces: int) -> np.ndarray:
        """(k,) int64 key ``vertex * n_faces + triangle`` of every pair."""
        return self.vertex * n_faces + self.triangle


def rest_near_keys(n: int, edges: np.ndarray, lengths: np.ndarray, seams: np.ndarray, radius_cm: float) -> np.ndarray:
    """Sorted int64 keys ``i * n + j`` of the vertex pairs closer than ``radius_cm`` on the sewn cloth at rest.

    The distance is the shortest path over ``edges`` (E, 2) at their rest
    ``lengths`` (E,) cm, the sewn pairs ``seams`` (S, 2) counting 0 (every
    vertex is near itself and the vertices sewn to it).
    """
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import dijkstra

    lengths = np.asarray(lengths, dtype=np.float64)
    short = np.asarray(edges, np.int64).reshape(-1, 2)[lengths < radius_cm]  # a path shorter than the radius
    tiny = 1e-9 * max(radius_cm, 1.0)  # has only such edges; a seam link: a stored (not dropped) zero
    w = np.concatenate([np.maximum(lengths[lengths < radius_cm], tiny), np.full(len(seams), tiny)])
    ends = np.concatenate([short, np.asarray(seams, np.int64).reshape(-1, 2)])
    own = np.arange(n, dtype=np.int64) * (n + 1)
    if len(ends) == 0:
        return own
    ids, local = np.unique(ends, return_inverse=True)
    local = local.reshape(-1, 2)
    g = coo_matrix((w, (local[:, 0], local[:, 1])), shape=(len(ids), len(ids))).tocsr()
    keys = [own]
    for lo in range(0, len(ids), 512):
        rows = np.arange(lo, min(len(ids), lo + 512))
        r, c = np.nonzero(dijkstra(g, directed=False, indices=rows, limit=radius_cm) < radius_cm)
        keys.append(ids[rows[r]] * n + ids[c])
    return np.unique(np.concatenate(keys))


def _is_in(keys: np.ndarray, sorted_keys: np.ndarray) -> np.ndarray:
    pos = np.clip(np.searchsorted(sorted_keys, keys), 0, max(len(sorted_keys) - 1, 0))
    return sorted_keys[pos] == keys if len(sorted_keys) else np.zeros(len(keys), dtype=bool)


def keep_sides(keys: np.ndarray, direction: np.ndarray, old_keys: np.ndarray, old_direction: np.ndarray) -> np.ndarray:
    """``direction`` (k, 3) with the pairs found at the last step whose direction turned round there keeping theirs.

    ``keys`` (k,) and ``old_keys`` (m,) identify the pairs (``old_keys``
    sorted); a pair whose new direction points against its old one went
    through within the step (a continuous slide round an edge turns the
    direction a little at every step) and is held to the old side.
    """
    if len(keys) == 0 or len(old_keys) == 0:
        return direction
    pos = np.clip(np.searchsorted(old_keys, keys), 0, len(old_keys) - 1)
    hit = old_keys[pos] == keys
    turned = hit & (np.einsum("ij,ij->i", direction, old_direction[pos]) < 0.0)
    if not turned.any():
        return direction
    out = direction.copy()
    out[turned] = old_direction[pos[turned]]
    return out


def find_pairs(
    x: np.ndarray,
    faces: np.ndarray,
    near: np.ndarray,
    reach_cm: float,
    moved: np.ndarray | None = None,
    gap_cm: float | None = None,
) -> SelfPairs:
    """The vertex-triangle pairs of the cloth ``x`` (N, 3) / ``faces`` (F, 3) closer than ``reach_cm``.

    The distance is to the triangle's closest point; pairs whose vertex is
    near a corner at rest (``near``, see :func:`rest_near_keys`) are left out.
    With the step's expected motion ``moved`` (N, 3), a pair is kept only when
    closer than ``gap_cm`` plus how far its vertex moves against the closest
    point (a vertex moving with its own layer needs no pair).
    """
    from scipy.spatial import cKDTree

    n = len(x)
    tri = x[faces]
    centre = tri.mean(axis=1)
    radius = np.sqrt(np.max(np.sum((tri - centre[:, None]) ** 2, axis=2), axis=1))
    r_max = float(radius.max(initial=0.0)) + reach_cm
    found = cKDTree(x).sparse_distance_matrix(cKDTree(centre), r_max, output_type="ndarray")
    v, t = found["i"].astype(np.int64), found["j"].astype(np.int64)
    keep = found["v"] <= radius[t] + reach_cm
    v, t = v[keep], t[keep]
    keep = ~(_is_in(v[:, None] * n + faces[t], near).any(axis=1))
    v, t = v[keep], t[keep]
    bary = closest_on_triangles(x[v], tri[t])
    d = x[v] - np.einsum("ij,ijk->ik", bary, tri[t])
    dist = np.linalg.norm(d, axis=1)
    close = dist < reach_cm
    if moved is not None and gap_cm is not None:
        rel = np.linalg.norm(moved[v] - np.einsum("ij,ijk->ik", bary, moved[faces[t]]), axis=1)
        close &= dist < gap_cm + rel
    keep = np.flatnonzero(close & (dist > 1e-9))
    keep = keep[_one_per_feature(v[keep], t[keep], faces, bary[keep])]
    return SelfPairs(vertex=v[keep], triangle=t[keep], direction=d[keep] / dist[keep, None])


def _one_per_feature(v: np.ndarray, t: np.ndarray, faces: np.ndarray, bary: np.ndarray) -> np.ndarray:
    """Indices of the pairs left when a vertex keeps one pair per closest feature (inside, edge or corner).

    The triangles round a corner (or the two beside an edge) that a vertex is
    closest to there give the same constraint: one of them is kept.
    """
    on = bary > 0.0
    corners = np.where(on, faces[t], -1)
    kind = on.sum(axis=1)
    lo, hi = np.sort(corners, axis=1)[:, 1:].T  # an edge's two corners, a corner's one (after -1s)
    feature = np.stack([v, kind, np.where(kind == 3, t, hi), np.where(kind == 2, lo, -1)], axis=1)
    return np.unique(feature, axis=0, return_index=True)[1]


def _accumulate(
    x: np.ndarray, faces: np.ndarray, pairs: SelfPairs, thickness_cm: float, delta: np.ndarray, count: np.ndarray
) -> None:
    """Add the corrections of the violated vertex-triangle pairs to ``delta`` (N, 3) and ``count`` (N,).

    A pair is violated when its vertex is closer than ``thickness_cm`` to the
    triangle's closest point along the pair's direction while lying within
    ``thickness_cm`` of that line (a vertex gone round the triangle's border
    is free).
    """
    if len(pairs) == 0:
        return
    f = faces[pairs.triangle]
    tri = x[f]
    p = x[pairs.vertex]
    bary = closest_on_triangles(p, tri)
    d = p - np.einsum("ij,ijk->ik", bary, tri)
    sep = np.einsum("ij,ij->i", d, pairs.direction)
    aside = np.linalg.norm(d - sep[:, None] * pairs.direction, axis=1)
    depth = thickness_cm - sep
    bad = (depth > 0) & (aside < thickness_cm)
    if not bad.any():
        return
    v, f, depth, bary, u = pairs.vertex[bad], f[bad], depth[bad], bary[bad], pairs.direction[bad]
    push = (depth / (1.0 + np.sum(bary**2, axis=1)))[:, None] * u
    np.add.at(delta, v, push)
    np.add.at(count, v, 1.0)
    for k in range(3):
        np.add.at(delta, f[:, k], -bary[:, k, None] * push)
        np.add.at(count, f[:, k], 1.0)


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class EdgePairs:
    """Edge-edge pairs of one step.

    edges : (k, 2, 2) int64 — the two edges of every pair ; direction : (k, 3) float64 —
    the unit direction from the second edge's closest point to the first's at the step's start ;
    key : (k,) int64 — ``i * E + j`` of the pair's edge ids ``i < j`` among the cloth's ``E`` edges
    """

    edges: np.ndarray
    direction: np.ndarray
    key: np.ndarray

    def __len__(self) -> int:
        return len(self.edges)


def _segment_params(p1, p2, q1, q2) -> tuple[np.ndarray, np.ndarray]:
    """Parameters (s, t) in [0, 1] of the closest points of the segments p1p2 and q1q2 (each (k, 3))."""
    d1, d2, r = p2 - p1, q2 - q1, p1 - q1
    a = np.einsum("ij,ij->i", d1, d1)
    e = np.einsum("ij,ij->i", d2, d2)
    f = np.einsum("ij,ij->i", d2, r)
    c = np.einsum("ij,ij->i", d1, r)
    b = np.einsum("ij,ij->i", d1, d2)
    den = np.maximum(a * e - b * b, 1e-12)
    s = np.clip((b * f - c * e) / den, 0.0, 1.0)
    t = np.clip((b * s + f) / np.maximum(e, 1e-12), 0.0, 1.0)
    s = np.clip((b * t - c) / np.maximum(a, 1e-12), 0.0, 1.0)
    return s, t


def find_edge_pairs(
    x: np.ndarray,
    edges: np.ndarray,
    near: np.ndarray,
    reach_cm: float,
    moved: np.ndarray | None = None,
    gap_cm: float | None = None,
) -> EdgePairs:
    """The pairs of cloth edges (E, 2) closer than ``reach_cm`` at ``x`` (N, 3) whose ends are not ``near`` at rest.

    ``moved`` and ``gap_cm`` as in :func:`find_pairs`, for the closest points of the two edges.
    """
    from scipy.spatial import cKDTree

    n = len(x)
    mid = 0.5 * (x[edges[:, 0]] + x[edges[:, 1]])
    half = 0.5 * np.linalg.norm(x[edges[:, 0]] - x[edges[:, 1]], axis=1)
    # (an edge stretched past the 99th percentile is reached from near its middle only)
    r = 2 * float(np.percentile(half, 99)) + reach_cm if len(half) else reach_cm
    found = cKDTree(mid).query_pairs(r, output_type="ndarray")
    if len(found) == 0:
        return EdgePairs(edges=np.zeros((0, 2, 2), np.int64), direction=np.zeros((0, 3)), key=np.zeros(0, np.int64))
    # the cheap tests first, the rest on what they leave (the same pairs, in the same order): two edges whose
    # midpoints lie farther apart than their half lengths and the reach are farther apart than the reach
    a, b = found[:, 0], found[:, 1]
    apart = mid[a] - mid[b]
    within = half[a] + half[b] + (reach_cm + 1e-3)
    keep = np.flatnonzero(np.einsum("ij,ij->i", apart, apart) < within * within)
    a, b = a[keep].astype(np.int64), b[keep].astype(np.int64)
    i, j = np.minimum(a, b), np.maximum(a, b)
    ei, ej = edges[i], edges[j]
    p1, p2, q1, q2 = x[ei[:, 0]], x[ei[:, 1]], x[ej[:, 0]], x[ej[:, 1]]
    s, t = _segment_params(p1, p2, q1, q2)
    d = (p1 + s[:, None] * (p2 - p1)) - (q1 + t[:, None] * (q2 - q1))
    dist = np.linalg.norm(d, axis=1)
    keep = np.flatnonzero((dist < reach_cm) & (dist > 1e-6) & (s > 0.0) & (s < 1.0) & (t > 0.0) & (t < 1.0))
    i, j, ei, ej, s, t, d, dist = i[keep], j[keep], ei[keep], ej[keep], s[keep], t[keep], d[keep], dist[keep]
    keys = ei[:, :, None] * n + ej[:, None, :]
    keep = ~_is_in(keys.reshape(-1), near).reshape(-1, 4).any(axis=1)
    if moved is not None and gap_cm is not None:
        m1, m2, n1, n2 = moved[ei[:, 0]], moved[ei[:, 1]], moved[ej[:, 0]], moved[ej[:, 1]]
        rel = (m1 + s[:, None] * (m2 - m1)) - (n1 + t[:, None] * (n2 - n1))
        keep &= dist < gap_cm + np.linalg.norm(rel, axis=1)
    return EdgePairs(
        edges=np.stack([ei[keep], ej[keep]], axis=1),
        direction=d[keep] / dist[keep, None],
        key=i[keep] * len(edges) + j[keep],
    )


def _accumulate_edges(
    x: np.ndarray, pairs: EdgePairs, thickness_cm: float, delta: np.ndarray, count: np.ndarray
) -> None:
    """Add the corrections of the edge pairs closer than ``thickness_cm`` along their starting direction."""
    if len(pairs) == 0:
        return
    e = pairs.edges
    p1, p2, q1, q2 = x[e[:, 0, 0]], x[e[:, 0, 1]], x[e[:, 1, 0]], x[e[:, 1, 1]]
    s, t = _segment_params(p1, p2, q1, q2)
    d = (p1 + s[:, None] * (p2 - p1)) - (q1 + t[:, None] * (q2 - q1))
    sep = np.einsum("ij,ij->i", d, pairs.direction)
    depth = thickness_cm - sep
    bad = (depth > 0) & (s > 0.0) & (s < 1.0) & (t > 0.0) & (t < 1.0)
    if not bad.any():
        return
    e, s, t, depth, u = e[bad], s[bad], t[bad], depth[bad], pairs.direction[bad]
    w = [1.0 - s, s, -(1.0 - t), -t]
    norm = sum(c * c for c in w)
    push = (depth / norm)[:, None] * u
    for c, ids in zip(w, (e[:, 0, 0], e[:, 0, 1], e[:, 1, 0], e[:, 1, 1]), strict=True):
        np.add.at(delta, ids, c[:, None] * push)
        np.add.at(count, ids, 1.0)


def resolve_pairs(
    x: np.ndarray, faces: np.ndarray, pairs: SelfPairs, thickness_cm: float, edge_pairs: EdgePairs | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """Per-vertex targets that put every violated pair back ``thickness_cm`` apart on its side.

    Returns
    -------
    ids : (k,) int64 vertices in a violated pair ; targets : (k, 3) float64, cm
    """
    delta = np.zeros_like(x)
    count = np.zeros(len(x))
    _accumulate(x, faces, pairs, thickness_cm, delta, count)
    if edge_pairs is not None:
        _accumulate_edges(x, edge_pairs, thickness_cm, delta, count)
    ids = np.flatnonzero(count)
    return ids, x[ids] + delta[ids] / count[ids, None]
