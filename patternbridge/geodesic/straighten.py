"""Exact straightening of a path inside the strip of faces it crosses.

The strip (a sequence of faces, each sharing an edge with the next) is unfolded
into the plane and the shortest path through it is found with the funnel
algorithm. Where that path wraps around a strip vertex whose angle on the
*other* side is below pi, going around the other side is shorter: the strip is
re-routed through the faces on that side ("swung" over the vertex) and the
funnel is run again. When no such vertex is left the path is a locally
shortest geodesic of the polyhedral surface: straight in every unfolding, and
bending at vertices only where both sides measure at least pi.
"""

from __future__ import annotations

import logging
import math
import weakref
from dataclasses import dataclass

import numpy as np

from .surface import SurfaceMesh

__all__ = ["Endpoint", "StraightPath", "straighten", "strip_from_vertex_path"]

log = logging.getLogger(__name__)

_ANGLE_EPS = 1e-7


@dataclass(frozen=True, slots=True, kw_only=True)
class Endpoint:
    """An end of a path: a vertex (``vertex``) or a point inside ``face``."""

    vertex: int | None
    face: int | None
    xyz: tuple[float, float, float]


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class StraightPath:
    """Result of :func:`straighten`.

    points : (k, 3) float64, cm, on the surface
    faces : (k,) int64, a face holding each point
    edges : (k, 2) int64, edge of edge points, (-1, -1) otherwise
    length : float, cm
    strip : (n,) int64, the final face strip
    n_swings : int, how many times the strip was swung over a vertex
    """

    points: np.ndarray
    faces: np.ndarray
    edges: np.ndarray
    length: float
    strip: np.ndarray
    n_swings: int


#: a mesh's shared caches are dropped and started afresh past this many faces
_LOCAL_MAX_FACES = 200_000


class _Local:
    """Caches of face corners, vertex fans and unfolding steps (pure Python
    for speed). Everything in them depends on the mesh alone, so one instance
    serves every path on a mesh: see :meth:`of`."""

    @classmethod
    def of(cls, mesh: SurfaceMesh) -> _Local:
        """The caches kept with ``mesh`` (fresh ones once they grow large)."""
        loc = mesh._cache.get("local")
        if loc is None or len(loc.fv) > _LOCAL_MAX_FACES:
            # a weak reference: no cycle mesh -> cache -> mesh, so a mesh is
            # freed as soon as it is dropped
            loc = mesh._cache["local"] = cls(weakref.proxy(mesh))
        return loc

    def __init__(self, mesh: SurfaceMesh) -> None:
        self.mesh = mesh
        self.fv: dict[int, tuple[int, int, int]] = {}
        self.xyz: dict[int, tuple[float, float, float]] = {}
        self.fan: dict[int, dict[int, list[int]]] = {}
        # (previous face, face) -> unfolding step, see _hinge
        self.hinge: dict[tuple[int, int], tuple] = {}

    def face(self, f: int) -> tuple[int, int, int]:
        t = self.fv.get(f)
        if t is None:
            t = tuple(self.mesh.faces[f].tolist())
            self.fv[f] = t
        return t

    def pos(self, v: int) -> tuple[float, float, float]:
        p = self.xyz.get(v)
        if p is None:
            p = tuple(self.mesh.vertices[v].tolist())
            self.xyz[v] = p
        return p

    def around(self, v: int) -> dict[int, list[int]]:
        """Map neighbour vertex -> usable faces holding edge (v, neighbour)."""
        m = self.fan.get(v)
        if m is None:
            m = {}
            indptr, fl = self.mesh.vertex_faces
            fs = fl[indptr[v] : indptr[v + 1]]
            rows = self.mesh.faces[fs].tolist()
            fv = self.fv
            for f, (a, b, c) in zip(fs.tolist(), rows, strict=True):
                fv[f] = (a, b, c)
                if a == v:
                    x, y = b, c
                elif b == v:
                    x, y = c, a
                else:
                    x, y = a, b
                fx = m.get(x)
                if fx is None:
                    m[x] = [f]
                else:
                    fx.append(f)
                fy = m.get(y)
                if fy is None:
                    m[y] = [f]
                else:
                    fy.append(f)
            self.fan[v] = m
        return m

    def across(self, v: int, x: int, f: int) -> int | None:
        """The face across edge (v, x) from face ``f``; None on a boundary.

        Across a non-manifold edge the walk continues into the face whose plane
        is closest to that of ``f`` (the surface that carries on, not a fin).
        """
        fs = self.around(v).get(x, ())
        if len(fs) == 2:
            return fs[1] if fs[0] == f else fs[0]
        if len(fs) < 2 or f not in fs:
            return None
        # non-manifold edge: continue into the face closest to the same plane
        others = [g for g in fs if g != f]
        fn = self.mesh.normals_of([f, *others])  # no (F, 3) table for a few rows
        dots = np.abs(fn[1:] @ fn[0])
        return int(others[int(np.argmax(dots))])

    def walk(self, v: int, f: int, x: int, stop, limit: int = 64) -> list[int] | None:
        """Faces met turning around ``v`` from ``f`` across edge (v, x) until
        ``stop(face)``; None when blocked."""
        out = []
        for _ in range(limit):
            g = self.across(v, x, f)
            if g is None:
                return None
            out.append(g)
            if stop(g):
                return out
            a, b, c = self.face(g)
            x = a if a not in (v, x) else (b if b not in (v, x) else c)
            f = g
        return None


def _third(t: tuple[int, int, int], p: int, q: int) -> int:
    for x in t:
        if x != p and x != q:
            return x
    return -1


def strip_from_vertex_path(
    mesh: SurfaceMesh,
    vpath,
    start_face: int | None = None,
    end_face: int | None = None,
    local: _Local | None = None,
) -> list[int] | None:
    """Face strip around an edge path: turn around each path vertex.

    Parameters
    ----------
    vpath : (k,) int vertex path
    start_face, end_face : faces holding face-point ends (they contain the first /
        last path vertex), or None for vertex ends

    Returns
    -------
    list of face ids, consecutive ones sharing an edge, or None when a vertex
    cannot be turned around (boundary on both sides, non-manifold fan).
    """
    loc = local or _Local.of(mesh)
    vp = [int(x) for x in vpath]
    k = len(vp)
    if k == 1:
        v = vp[0]
        if start_face is None and end_face is None:
            fl = mesh.faces_of(v)
            return [int(fl[0])] if len(fl) else None
        cur = start_face if start_face is not None else end_face
        strip = [cur]
        tgt = end_face if end_face is not None else cur
    if k >= 2:
        if start_face is None:
            fs = loc.around(vp[0]).get(vp[1])
            if not fs:
                return None
            cur = fs[0]
        else:
            cur = start_face
        strip = [cur]
    for i in range(k):
        v = vp[i]
        if i + 1 < k:
            w = vp[i + 1]

            def stop(g, v=v, w=w):
                return w in loc.face(g)
        elif end_face is not None:
            tgt = end_face

            def stop(g, tgt=tgt):
                return g == tgt
        else:
            break
        if stop(cur):
            continue
        p, q = [x for x in loc.face(cur) if x != v]
        best = None
        for x in (p, q):
            fan = loc.walk(v, cur, x, stop)
            if fan is not None and (best is None or len(fan) < len(best)):
                best = fan
        if best is None:
            return None
        strip.extend(best)
        cur = best[-1]
    return strip


def _clean(strip: list[int], lo: int = 0, tail: int | None = None) -> list[int]:
    """Drop repeated faces and immediate back-tracks (a, b, a -> a).

    ``strip[:lo]`` and ``strip[tail:]`` may be given as already clean (the
    parts of a clean strip that an edit left alone): the scan starts at ``lo``
    and stops once it is two faces into the clean tail with nothing pending.
    """
    out: list[int] = strip[:lo]
    n = len(strip)
    stop = n if tail is None else max(tail + 2, lo + 2)
    for j in range(lo, n):
        f = strip[j]
        if (
            j >= stop
            and len(out) >= 2
            and out[-1] == strip[j - 1]
            and out[-2] == strip[j - 2]
        ):
            out.extend(strip[j:])
            break
        if out and out[-1] == f:
            continue
        if len(out) >= 2 and out[-2] == f:
            out.pop()
            continue
        out.append(f)
    return out


def _unfold(loc: _Local, strip, s: Endpoint, e: Endpoint, cache: dict | None = None):
    """Unfold the strip; return portals, 2D ends and per-face 2D corners.

    With ``cache`` (a dict kept between calls), the unfolding of the longest
    unchanged prefix of the previous strip is reused.
    """
    dist = math.dist
    sqrt = math.sqrt
    pos = loc.pos
    face = loc.face
    k0 = 0
    if cache and cache.get("strip"):
        k0 = _common_prefix(cache["strip"], strip)
    if k0 >= 1:
        face_xy = cache["face_xy"][:k0]
        portals = cache["portals"][: k0 - 1]
        coords = face_xy[-1]
    else:
        f0 = strip[0]
        a, b, c = face(f0)
        pa, pb, pc = pos(a), pos(b), pos(c)
        lab = dist(pa, pb)
        lac = dist(pa, pc)
        lbc = dist(pb, pc)
        x = (lac * lac - lbc * lbc + lab * lab) / (2 * lab)
        y = sqrt(max(lac * lac - x * x, 0.0))
        coords = {a: (0.0, 0.0), b: (lab, 0.0), c: (x, y)}
        face_xy = [coords]
        portals = []  # (left_id, right_id, left_xy, right_xy)
        k0 = 1
    hinge = loc.hinge
    add_portal = portals.append
    add_face = face_xy.append
    # each (previous face, face) step's corners and 3D lengths, and the new
    # corner's place along and off the hinge edge, are the same in every
    # round: only the 2D placement of the hinge changes
    for key in zip(strip[k0 - 1 : -1], strip[k0:], strict=True):
        step = hinge.get(key)
        if step is None:
            step = hinge[key] = _hinge(loc, *key)
        p, q, d, cprev, inv, t, h = step
        try:
            P = coords[p]
            Q = coords[q]
            cx, cy = coords[cprev]
        except KeyError:
            raise _StripError(f"faces {key[0]} and {key[1]} share no edge") from None
        px, py = P
        qx, qy = Q
        ex = qx - px
        ey = qy - py
        ux = ex * inv
        uy = ey * inv
        # (Q - P) x (C - P): which side of the hinge the previous face lies on
        if ex * (cy - py) - ey * (cx - px) > 0:
            D = (px + ux * t + uy * h, py + uy * t - ux * h)
            add_portal((q, p, Q, P))
        else:
            D = (px + ux * t - uy * h, py + uy * t + ux * h)
            add_portal((p, q, P, Q))
        coords = {p: P, q: Q, d: D}
        add_face(coords)
    if cache is not None:
        cache["strip"] = list(strip)
        cache["face_xy"] = face_xy
        cache["portals"] = portals
    s2 = _end_xy(loc, strip[0], face_xy[0], s)
    e2 = _end_xy(loc, strip[-1], face_xy[-1], e)
    return portals, s2, e2, face_xy


def _common_prefix(old: list, new: list) -> int:
    """Length of the common prefix of two lists (slice comparisons in C)."""
    lo, hi = 0, min(len(old), len(new))
    if old[:hi] == new[:hi]:
        return hi
    while hi - lo > 1:  # old[:lo] == new[:lo] and old[:hi] != new[:hi]
        mid = (lo + hi) // 2
        if old[lo:mid] == new[lo:mid]:
            lo = mid
        else:
            hi = mid
    return lo


def _hinge(loc: _Local, fa: int, fb: int) -> tuple:
    """Unfolding step from face ``fa`` to the edge-adjacent face ``fb``.

    Returns ``(p, q, d, c, 1 / |pq|, t, h)``: the shared edge (p, q), the new
    corner d of ``fb``, the third corner c of ``fa``, and d's place in the
    plane: ``t`` along p -> q from p and ``h`` off the edge, cm.
    """
    p0, p1, p2 = loc.face(fa)
    c0, c1, c2 = loc.face(fb)
    # the shared edge (p, q) in the order the corners of fb give it
    if c0 == p0 or c0 == p1 or c0 == p2:
        if c1 == p0 or c1 == p1 or c1 == p2:
            p, q, d = c0, c1, c2
        else:
            p, q, d = c0, c2, c1
    else:
        p, q, d = c1, c2, c0
    if (
        (p != p0 and p != p1 and p != p2)
        or (q != p0 and q != p1 and q != p2)
        or d == p0
        or d == p1
        or d == p2
    ):
        raise _StripError(f"faces {fa} and {fb} share no edge")
    cprev = p0 if p0 != p and p0 != q else (p1 if p1 != p and p1 != q else p2)
    pp, pq, pd = loc.pos(p), loc.pos(q), loc.pos(d)
    dist = math.dist
    lpq = dist(pp, pq)
    if lpq == 0.0:
        raise _StripError(f"edge ({p}, {q}) has zero length")
    lpd = dist(pp, pd)
    lqd = dist(pq, pd)
    t = (lpd * lpd - lqd * lqd + lpq * lpq) / (2 * lpq)
    h = math.sqrt(max(lpd * lpd - t * t, 0.0))
    return (p, q, d, cprev, 1.0 / lpq, t, h)


def _end_xy(loc: _Local, f: int, coords, end: Endpoint):
    if end.vertex is not None:
        return coords[end.vertex]
    # barycentric coordinates of the 3D point in face f, mapped to 2D
    a, b, c = loc.face(f)
    A, B, C = (np.array(loc.pos(v)) for v in (a, b, c))
    P = np.array(end.xyz)
    v0, v1, v2 = B - A, C - A, P - A
    d00, d01, d11 = v0 @ v0, v0 @ v1, v1 @ v1
    d20, d21 = v2 @ v0, v2 @ v1
    den = d00 * d11 - d01 * d01
    wb = (d11 * d20 - d01 * d21) / den
    wc = (d00 * d21 - d01 * d20) / den
    wa = 1.0 - wb - wc
    ca, cb, cc = coords[a], coords[b], coords[c]
    return (wa * ca[0] + wb * cb[0] + wc * cc[0], wa * ca[1] + wb * cb[1] + wc * cc[1])


class _StripError(Exception):
    pass


def _funnel(portals, s2, e2):
    """Simple funnel: returns apexes as (xy, portal_index, vertex_id or -1).

    Portal index 0 is the start and ``len(portals) + 1`` the end. The cross
    products are written out inline and the funnel sides are kept as vectors
    from the apex: this loop runs for every portal of every straightening
    round.
    """
    P = [(-1, -1, s2, s2), *portals, (-1, -1, e2, e2)]
    n = len(P)
    apex, apex_i, apex_v = s2, 0, -1
    ax, ay = apex
    # funnel sides: point, portal index, vertex id, vector from the apex, and
    # whether the side still sits on the apex
    left, left_i, left_v, lx0, ly0, l_at = s2, 0, -1, 0.0, 0.0, True
    right, right_i, right_v, rx0, ry0, r_at = s2, 0, -1, 0.0, 0.0, True
    out = [(s2, 0, -1)]
    i = 1
    guard = 0
    limit = 20 * n + 100
    while i < n:
        guard += 1
        if guard > limit:
            break
        lid, rid, pl, pr = P[i]
        # tighten the right side
        if rid != apex_v or rid < 0:
            rx, ry = pr[0] - ax, pr[1] - ay
            if r_at or rx0 * ry - ry0 * rx >= 0.0:
                if l_at or lx0 * ry - ly0 * rx < 0.0:
                    right, right_i, right_v, rx0, ry0, r_at = pr, i, rid, rx, ry, False
                else:
                    apex, apex_i, apex_v = left, left_i, left_v
                    ax, ay = apex
                    out.append((apex, apex_i, apex_v))
                    left = right = apex
                    left_i = right_i = apex_i
                    left_v = right_v = apex_v
                    lx0 = ly0 = rx0 = ry0 = 0.0
                    l_at = r_at = True
                    i = apex_i + 1
                    continue
        if lid != apex_v or lid < 0:
            lx, ly = pl[0] - ax, pl[1] - ay
            if l_at or lx0 * ly - ly0 * lx <= 0.0:
                if r_at or rx0 * ly - ry0 * lx > 0.0:
                    left, left_i, left_v, lx0, ly0, l_at = pl, i, lid, lx, ly, False
                else:
                    apex, apex_i, apex_v = right, right_i, right_v
                    ax, ay = apex
                    out.append((apex, apex_i, apex_v))
                    left = right = apex
                    left_i = right_i = apex_i
                    left_v = right_v = apex_v
                    lx0 = ly0 = rx0 = ry0 = 0.0
                    l_at = r_at = True
                    i = apex_i + 1
                    continue
        i += 1
    if out[-1][1] != n - 1:
        out.append((e2, n - 1, -1))
    return out


def _angle(u, w) -> float:
    return math.atan2(abs(u[0] * w[1] - u[1] * w[0]), u[0] * w[0] + u[1] * w[1])


def _corner(loc: _Local, f: int, v: int) -> float:
    o = [x for x in loc.face(f) if x != v]
    pv, p1, p2 = loc.pos(v), loc.pos(o[0]), loc.pos(o[1])
    u = (p1[0] - pv[0], p1[1] - pv[1], p1[2] - pv[2])
    w = (p2[0] - pv[0], p2[1] - pv[1], p2[2] - pv[2])
    cx = u[1] * w[2] - u[2] * w[1]
    cy = u[2] * w[0] - u[0] * w[2]
    cz = u[0] * w[1] - u[1] * w[0]
    return math.atan2(
        math.sqrt(cx * cx + cy * cy + cz * cz), u[0] * w[0] + u[1] * w[1] + u[2] * w[2]
    )


def _find_swings(
    loc: _Local, strip, portals, apexes, face_xy, s: Endpoint, e: Endpoint
):
    """Vertices the path wraps with less than pi on the other side; return
    (start, stop, replacement faces) edits of the strip."""
    edits = []
    n = len(portals)
    for k in range(1, len(apexes) - 1):
        _, pi_, v = apexes[k]
        if v < 0:
            continue
        side = 0 if portals[pi_ - 1][0] == v else 1
        i = j = pi_
        while i - 1 >= 1 and portals[i - 2][side] == v:
            i -= 1
        while j + 1 <= n and portals[j][side] == v:
            j += 1
        fa_i, fb_i = i - 1, j  # strip indices of the faces bounding the run
        fa, fb = strip[fa_i], strip[fb_i]
        other_i = portals[i - 1][1 - side]
        other_j = portals[j - 1][1 - side]
        xa = _third(loc.face(fa), v, other_i)
        xb = _third(loc.face(fb), v, other_j)
        if xa < 0 or xb < 0:
            continue
        prev_xy, next_xy = apexes[k - 1][0], apexes[k + 1][0]
        vx = face_xy[fa_i][v]
        u_in = (prev_xy[0] - vx[0], prev_xy[1] - vx[1])
        wa = (face_xy[fa_i][xa][0] - vx[0], face_xy[fa_i][xa][1] - vx[1])
        vy = face_xy[fb_i][v]
        u_out = (next_xy[0] - vy[0], next_xy[1] - vy[1])
        wb = (face_xy[fb_i][xb][0] - vy[0], face_xy[fb_i][xb][1] - vy[1])
        theta = _angle(u_in, wa) + _angle(u_out, wb)
        if theta >= math.pi:
            continue
        fan = loc.walk(v, fa, xa, lambda g, xb=xb, fb=fb: g != fb and xb in loc.face(g))
        if fan is None:
            continue
        theta += sum(_corner(loc, g, v) for g in fan)
        if theta >= math.pi - _ANGLE_EPS:
            continue
        lo, hi = fa_i, fb_i
        new = [*fan]
        new = ([] if (fa_i == 0 and s.vertex == xa) else [fa]) + new
        new = new + ([] if (fb_i == len(strip) - 1 and e.vertex == xb) else [fb])
        edits.append((lo, hi, new))
    return edits


def straighten(
    mesh: SurfaceMesh,
    strip,
    s: Endpoint,
    e: Endpoint,
    *,
    max_rounds: int = 400,
    local: _Local | None = None,
) -> StraightPath:
    """Shortest path through ``strip``, swinging it over vertices until it is a
    locally shortest geodesic.

    Parameters
    ----------
    mesh : SurfaceMesh
    strip : sequence of face ids; the first holds ``s``, the last holds ``e``
    s, e : Endpoint

    Returns
    -------
    StraightPath

    Raises
    ------
    ValueError
        When the strip is not a chain of edge-adjacent faces.
    """
    loc = local or _Local.of(mesh)
    strip = _clean([int(f) for f in strip])
    n_swings = 0
    cache: dict = {}
    for _ in range(max_rounds):
        try:
            portals, s2, e2, face_xy = _unfold(loc, strip, s, e, cache)
        except _StripError as exc:
            raise ValueError(str(exc)) from None
        apexes = _funnel(portals, s2, e2)
        edits = _find_swings(loc, strip, portals, apexes, face_xy, s, e)
        if not edits:
            break
        edits.sort(key=lambda t: t[0], reverse=True)
        floor = len(strip) + 1
        n_old = len(strip)
        top = -1
        for lo, hi, new in edits:
            if hi >= floor:
                continue
            strip[lo : hi + 1] = new
            floor = lo
            top = max(top, hi)
            n_swings += 1
        # only the edited stretch can hold repeats or back-tracks
        strip = _clean(strip, max(floor - 2, 0), len(strip) - (n_old - 1 - top))
    return _assemble(loc, strip, portals, apexes, s, e, n_swings)


def _assemble(
    loc: _Local, strip, portals, apexes, s: Endpoint, e: Endpoint, n_swings: int
) -> StraightPath:
    pts: list[tuple[float, float, float]] = [s.xyz]
    fcs: list[int] = [s.face if s.face is not None else strip[0]]
    eds: list[tuple[int, int]] = [(-1, -1)]
    length = 0.0
    for k in range(len(apexes) - 1):
        A, ia, va = apexes[k]
        B, ib, vb = apexes[k + 1]
        length += math.hypot(B[0] - A[0], B[1] - A[1])
        for m in range(ia + 1, ib):
            lid, rid, L, R = portals[m - 1]
            if lid == va or rid == va or lid == vb or rid == vb:
                continue
            dx, dy = B[0] - A[0], B[1] - A[1]
            ex, ey = L[0] - R[0], L[1] - R[1]
            den = dx * ey - dy * ex
            if den == 0.0:
                continue
            t = (dx * (A[1] - R[1]) - dy * (A[0] - R[0])) / den
            t = min(max(t, 0.0), 1.0)
            pr, pl = loc.pos(rid), loc.pos(lid)
            pts.append(tuple(pr[c] + t * (pl[c] - pr[c]) for c in range(3)))
            fcs.append(strip[m])
            eds.append((rid, lid))
        if k + 1 < len(apexes) - 1:
            pts.append(loc.pos(vb))
            fcs.append(strip[ib])
            eds.append((-1, -1))
    pts.append(e.xyz)
    fcs.append(e.face if e.face is not None else strip[-1])
    eds.append((-1, -1))
    # drop repeated points (a crossing exactly at a vertex the path runs through)
    keep = [0]
    for i in range(1, len(pts)):
        if math.dist(pts[i], pts[keep[-1]]) > 1e-12:
            keep.append(i)
        elif i == len(pts) - 1:
            keep[-1] = i
    if len(keep) < len(pts):
        pts = [pts[i] for i in keep]
        fcs = [fcs[i] for i in keep]
        eds = [eds[i] for i in keep]
    return StraightPath(
        points=np.array(pts, dtype=np.float64),
        faces=np.array(fcs, dtype=np.int64),
        edges=np.array(eds, dtype=np.int64),
        length=float(length),
        strip=np.array(strip, dtype=np.int64),
        n_swings=n_swings,
    )
