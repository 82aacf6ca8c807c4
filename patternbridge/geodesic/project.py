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
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def _inside(loc: _Local, f: int, q, tol: float = 1e-9) -> bool:
    a, b, c = (loc.pos(v) for v in loc.face(f))
    n = _crs(_sub(b, a), _sub(c, a))
    return (_dot(_crs(_sub(b, a), _sub(q, a)), n) >= -tol * _dot(n, n)
            and _dot(_crs(_sub(c, b), _sub(q, b)), n) >= -tol * _dot(n, n)
            and _dot(_crs(_sub(a, c), _sub(q, c)), n) >= -tol * _dot(n, n))


def _onto_face(loc: _Local, f: int, q):
    a, b, c = (loc.pos(v) for v in loc.face(f))
    n = _crs(_sub(b, a), _sub(c, a))
    nn = _dot(n, n)
    d = _dot(_sub(q, a), n) / nn
    return (q[0] - d * n[0], q[1] - d * n[1], q[2] - d * n[2])


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


def project_walk(mesh: SurfaceMesh, samples: np.ndarray, start: Endpoint, end: Endpoint,
                 *, local: _Local | None = None, max_steps: int | None = None
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
    loc = local or _Local(mesh)
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
    limit = max_steps or 40 * len(Q) + 2000

    def arrived(face):
        if end.vertex is not None:
            return end.vertex in loc.face(face)
        return face == end.face

    for _ in range(limit):
        if i >= len(Q) - 1 and arrived(f):
            pts.append(end.xyz)
            fcs.append(f)
            eds.append((-1, -1))
            return Walk(points=np.array(pts), faces=np.array(fcs, dtype=np.int64),
                        edges=np.array(eds, dtype=np.int64),
                        strip=np.array(strip, dtype=np.int64))
        q = Q[min(i, len(Q) - 1)]
        if i < len(Q) - 1 and _inside(loc, f, _onto_face(loc, f, q)):
            x = _onto_face(loc, f, q)
            pts.append(x)
            fcs.append(f)
            eds.append((-1, -1))
            entry = None
            i += 1
            continue
        fv = loc.face(f)
        a, b, c = (loc.pos(v) for v in fv)
        nf = _crs(_sub(b, a), _sub(c, a))
        d = _sub(q, x)
        N = _crs(d, nf)
        if _dot(N, N) == 0.0:
            return None
        best = None
        for u, w in ((fv[0], fv[1]), (fv[1], fv[2]), (fv[2], fv[0])):
            if entry is not None and {u, w} == entry:
                continue
            pu, pw = loc.pos(u), loc.pos(w)
            su, sw = _dot(N, _sub(pu, x)), _dot(N, _sub(pw, x))
            if su == sw or su * sw > 0:
                continue
            t = su / (su - sw)
            t = min(max(t, 1e-9), 1 - 1e-9)
            cpt = (pu[0] + t * (pw[0] - pu[0]), pu[1] + t * (pw[1] - pu[1]),
                   pu[2] + t * (pw[2] - pu[2]))
            ahead = _dot(_sub(cpt, x), d)
            if ahead <= 0:
                continue
            if best is None or ahead > best[0]:
                best = (ahead, u, w, cpt)
        if best is None:
            return None
        _, u, w, cpt = best
        g = loc.across(u, w, f)
        if g is None:
            return None
        pts.append(cpt)
        fcs.append(g)
        eds.append((u, w))
        strip.append(g)
        entry = {u, w}
        x = cpt
        f = g
    return None
