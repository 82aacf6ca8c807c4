"""Projection of a floating polyline onto the mesh by a face-to-face walk.

From the current surface point the walk intersects the plane through the
point, the next sample and the face normal (the approximate osculating plane
of the projected curve) with the current face, leaves the face through the
edge it meets ahead, and enters the face across that edge. When the next
sample projects into the current face, the walk moves on to the sample after
it. The result lies exactly on the surface, its inner points on edges, and the
faces it visits form the strip used by the exact straightening.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass

import numpy as np

from .straighten import Endpoint, _Local
from .surface import SurfaceMesh

__all__ = ["Walk", "project_walk"]

log = logging.getLogger(__name__)


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class Walk:
    """A projected path: (k, 3) ``points`` on the surface, their ``faces`` and
    ``edges`` ((-1, -1) off edges), and the (n,) face ``strip`` it crossed."""

    points: np.ndarray
    faces: np.ndarray
    edges: np.ndarray
    strip: np.ndarray


def _sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def _dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def _crs(a, b):
    return (
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    )


def _plane(loc: _Local, f: int) -> tuple:
    """Corners a, b, c of face ``f``, its edges b - a, c - b, a - c, its
    (unnormalised) normal n = (b - a) x (c - a) and n . n."""
    a, b, c = (loc.pos(v) for v in loc.face(f))
    n = _crs(_sub(b, a), _sub(c, a))
    return (a, b, c, _sub(b, a), _sub(c, b), _sub(a, c), n, _dot(n, n))


def _project_into(loc: _Local, f: int, q, cache: dict, tol: float = 1e-9):
    """``q`` projected onto the plane of face ``f`` if it falls inside the face,
    else None (the normal offset of ``q`` does not change the inside test)."""
    g = cache.get(f)
    if g is None:
        g = cache[f] = _plane(loc, f)
    a, b, c, eab, ebc, eca, n, nn = g
    lim = -tol * nn
    n0, n1, n2 = n
    q0, q1, q2 = q
    # the three edge tests written out (same operations as _dot(_crs(e, q - p), n))
    for e, p in ((eab, a), (ebc, b), (eca, c)):
        s0, s1, s2 = q0 - p[0], q1 - p[1], q2 - p[2]
        e0, e1, e2 = e
        if (e1 * s2 - e2 * s1) * n0 + (e2 * s0 - e0 * s2) * n1 + (e0 * s1 - e1 * s0) * n2 < lim:
            return None
    d = ((q0 - a[0]) * n0 + (q1 - a[1]) * n1 + (q2 - a[2]) * n2) / nn
    return (q0 - d * n0, q1 - d * n1, q2 - d * n2)


def _start_face(loc: _Local, v: int, toward) -> int | None:
    best, best_score = None, -math.inf
    pv = loc.pos(v)
    d = _sub(toward, pv)
    for f in loc.mesh.faces_of(v).tolist():
        u, w = (x for x in loc.face(f) if x != v)
        eu, ew = _sub(loc.pos(u), pv), _sub(loc.pos(w), pv)
        n = _crs(eu, ew)
        if _dot(n, n) == 0.0:
            continue
        s1 = _dot(_crs(eu, d), n)
        s2 = _dot(_crs(d, ew), n)
        score = min(s1, s2) / math.sqrt(_dot(n, n))
        if score > best_score:
            best, best_score = f, score
    return best


def _face_plane(loc: _Local, f: int, planes: dict) -> tuple:
    """:func:`_plane` of face ``f``, cached in ``planes``."""
    g = planes.get(f)
    if g is None:
        g = planes[f] = _plane(loc, f)
    return g


def _ahead(p, x, d) -> float:
    """(p - x) . d"""
    return (p[0] - x[0]) * d[0] + (p[1] - x[1]) * d[1] + (p[2] - x[2]) * d[2]


def _cutting_plane(g: tuple, x, q) -> tuple | None:
    """The plane through ``x`` and ``q`` that holds the normal of face ``g`` (a :func:`_plane`).

    Returns the signed distances of the face's corners from it, the tolerance
    below which a corner lies on it, and the direction d = q - x; None when
    d is along the face normal.
    """
    n0, n1, n2 = g[6]
    x0, x1, x2 = x
    d0, d1, d2 = q[0] - x0, q[1] - x1, q[2] - x2
    N0 = d1 * n2 - d2 * n1
    N1 = d2 * n0 - d0 * n2
    N2 = d0 * n1 - d1 * n0
    nn = math.sqrt(N0 * N0 + N1 * N1 + N2 * N2)
    if nn == 0.0:
        return None
    N0, N1, N2 = N0 / nn, N1 / nn, N2 / nn
    sd = [N0 * (pv[0] - x0) + N1 * (pv[1] - x1) + N2 * (pv[2] - x2) for pv in (g[0], g[1], g[2])]
    tol = 1e-9 * math.sqrt(d0 * d0 + d1 * d1 + d2 * d2) + 1e-12
    return sd, tol, (d0, d1, d2)


def _exit(corners: tuple, fv, cut: tuple, x, entry: set | None, at_vertex: int | None) -> tuple | None:
    """Where the cutting plane ``cut`` leaves the face farthest ahead of ``x``.

    Returns ``(ahead, u, w, point)``: through corner ``u == w`` (not the one
    the walk stands on), or across edge (u, w) (not the entry edge); None when
    nothing lies ahead.
    """
    sd, tol, d = cut
    best = None
    for k in range(3):  # the plane through a vertex ahead
        v = fv[k]
        if v != at_vertex and abs(sd[k]) <= tol:
            pv = corners[k]
            ahead = _ahead(pv, x, d)
            if ahead > 0 and (best is None or ahead > best[0]):
                best = (ahead, v, v, pv)
    for ku, kw in ((0, 1), (1, 2), (2, 0)):
        u, w = fv[ku], fv[kw]
        if entry is not None and {u, w} == entry:
            continue
        su, sw = sd[ku], sd[kw]
        if abs(su) <= tol or abs(sw) <= tol or su * sw > 0:
            continue
        t = su / (su - sw)
        pu, pw = corners[ku], corners[kw]
        cpt = (
            pu[0] + t * (pw[0] - pu[0]),
            pu[1] + t * (pw[1] - pu[1]),
            pu[2] + t * (pw[2] - pu[2]),
        )
        ahead = _ahead(cpt, x, d)
        if ahead > 0 and (best is None or ahead > best[0]):
            best = (ahead, u, w, cpt)
    return best


def _fan(loc: _Local, f: int, fv, u: int, g: int) -> list | None:
    """The shortest run of faces around vertex ``u`` from face ``f`` to face ``g``, or None."""
    fan = None
    for xo in (x_ for x_ in fv if x_ != u):
        cand = loc.walk(u, f, xo, lambda h, g=g: h == g)
        if cand is not None and (fan is None or len(cand) < len(fan)):
            fan = cand
    return fan


def _turn(loc: _Local, f: int, fv, u: int, toward) -> tuple[int, list] | None:
    """The face around vertex ``u`` that leads toward ``toward``, and the faces
    passed from face ``f`` to reach it; None when there is no way."""
    g = _start_face(loc, u, toward)
    if g is None:
        return None
    if g == f:
        return g, []
    fan = _fan(loc, f, fv, u, g)
    return None if fan is None else (g, fan)


@dataclass(frozen=True, slots=True, kw_only=True)
class _Step:
    """The walk's move out of a face: the face it enters, the faces it passes
    on the way (for the strip), the edge it crosses ((-1, -1) through a
    vertex), the edge it then came in through and the vertex it stands on."""

    face: int
    passed: list
    edge: tuple[int, int]
    entry: set | None
    at_vertex: int | None


def _step_across(loc: _Local, f: int, fv, best: tuple, toward) -> _Step | None:
    """The move out of face ``f`` through the exit ``best`` of :func:`_exit`; None at a boundary.

    Through a vertex the walk turns around it to the face that leads toward
    ``toward``; across an edge it enters the face on the other side.
    """
    _, u, w, _point = best
    if u == w:
        turn = _turn(loc, f, fv, u, toward)
        if turn is None:
            return None
        g, fan = turn
        return _Step(face=g, passed=fan, edge=(-1, -1), entry=None, at_vertex=u)
    g = loc.across(u, w, f)
    if g is None:
        return None
    return _Step(face=g, passed=[g], edge=(u, w), entry={u, w}, at_vertex=None)


def _walk(pts: list, fcs: list, eds: list, strip: list) -> Walk:
    return Walk(
        points=np.array(pts),
        faces=np.array(fcs, dtype=np.int64),
        edges=np.array(eds, dtype=np.int64),
        strip=np.array(strip, dtype=np.int64),
    )


def _arrived(loc: _Local, end: Endpoint, face: int) -> bool:
    if end.vertex is not None:
        return end.vertex in loc.face(face)
    return face == end.face


def project_walk(
    mesh: SurfaceMesh,
    samples: np.ndarray,
    start: Endpoint,
    end: Endpoint,
    *,
    local: _Local | None = None,
    max_steps: int | None = None,
) -> Walk | None:
    """Walk the samples onto the surface.

    Parameters
    ----------
    samples : (m, 3) float64, cm, floating polyline from the flow, ends included
    start, end : Endpoint

    Returns
    -------
    Walk, or None when the walk leaves through a boundary or does not arrive.
    """
    loc = local or _Local.of(mesh)
    Q = [tuple(p) for p in np.asarray(samples, dtype=np.float64).tolist()]
    if len(Q) < 2:
        return None
    x = start.xyz
    if start.vertex is not None:
        f = _start_face(loc, start.vertex, Q[1])
        if f is None:
            return None
    else:
        f = start.face
    pts, fcs, eds, strip = [x], [f], [(-1, -1)], [f]
    i = 1
    entry = None  # edge we came in through
    at_vertex = start.vertex  # vertex the walk stands on, if any
    planes: dict = {}  # per-face corners, edges and normal
    for _ in range(max_steps or 40 * len(Q) + 2000):
        last = i >= len(Q) - 1
        if last and _arrived(loc, end, f):
            pts.append(end.xyz)
            fcs.append(f)
            eds.append((-1, -1))
            return _walk(pts, fcs, eds, strip)
        q = Q[min(i, len(Q) - 1)]
        inside = None if last else _project_into(loc, f, q, planes)
        if inside is not None:  # the sample lies over this face: step to it
            x, entry, at_vertex = inside, None, None
            pts.append(x)
            fcs.append(f)
            eds.append((-1, -1))
            i += 1
            continue
        g = _face_plane(loc, f, planes)
        cut = _cutting_plane(g, x, q)
        if cut is None:
            return None
        fv = loc.face(f)
        best = _exit((g[0], g[1], g[2]), fv, cut, x, entry, at_vertex)
        if best is None:
            if not last:  # the sample is behind us: aim at the next one
                i += 1
                continue
            return None
        step = _step_across(loc, f, fv, best, end.xyz if last else q)
        if step is None:
            return None
        strip.extend(step.passed)
        x, f, entry, at_vertex = best[3], step.face, step.entry, step.at_vertex
        pts.append(x)
        fcs.append(f)
        eds.append(step.edge)
    return None
