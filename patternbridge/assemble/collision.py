"""The body as a collider (Open3D): closest points, inside tests, rays, and helper volumes.

The body is held in an Open3D ``RaycastingScene``. The cloth solver's body
contact (:mod:`patternbridge.assemble.cloth.contact`) asks it for closest
skin points and inside tests; the finishing step and the report use its
ray casts (edges and triangles through the skin, the skin through the cloth)
and its clean-up of welded cloth.
"""

from __future__ import annotations

from functools import cached_property

import numpy as np

__all__ = ["BodyCollider", "carry_layers", "hand_mitts", "mitt_hulls", "thigh_fill", "triangle_scene"]


def triangle_scene(vertices: np.ndarray, faces: np.ndarray):
    """An Open3D ``RaycastingScene`` of one triangle mesh (``vertices`` (V, 3) cm, ``faces`` (F, 3))."""
    import open3d as o3d

    scene = o3d.t.geometry.RaycastingScene()
    scene.add_triangles(
        o3d.core.Tensor(np.asarray(vertices, dtype=np.float32)),
        o3d.core.Tensor(np.asarray(faces, dtype=np.uint32)),
    )
    return scene


def carry_layers(
    before: np.ndarray,
    after: np.ndarray,
    faces: np.ndarray,
    gap_cm: float,
    *,
    rounds: int = 4,
    body: BodyCollider | None = None,
) -> np.ndarray:
    """The cloth moved from ``before`` to ``after`` (V, 3) with the layers over each moved vertex carried along.

    A clean-up push moves single vertices (out of the skin, along its
    normal); where the cloth lies folded over itself (hems piled on the
    feet), the pushed layer would pass through the layer above it. Each
    moving vertex casts a ray along its move against the cloth as it was
    (``before``, triangles not round the vertex); a triangle hit closer than
    the move plus ``gap_cm`` is carried: its corners move at least so far
    along that direction that they stay ``gap_cm`` beyond the pushed vertex.
    Carried corners push the layers above them in the next round (up to
    ``rounds`` layers). With a ``body``, a corner the carry would put inside
    it (the layer over an armpit is against the arm) stays.

    Returns
    -------
    (V, 3) float64, ``after`` with the carried corners moved
    """
    import open3d as o3d

    x0 = np.asarray(before, dtype=np.float64)
    out = np.array(after, dtype=np.float64)
    f = np.asarray(faces, dtype=np.int64)
    if len(f) == 0:
        return out
    scene = triangle_scene(x0, f)
    checked = np.zeros(len(x0))  # move length already cast per vertex
    for _ in range(rounds):
        d = out - x0
        ln = np.linalg.norm(d, axis=1)
        cast = np.flatnonzero((ln > 1e-4) & (ln > checked + 1e-4))
        if len(cast) == 0:
            break
        checked[cast] = ln[cast]
        u = d[cast] / ln[cast, None]
        rays = np.concatenate([x0[cast] + 1e-3 * u, u], axis=1).astype(np.float32)
        hit = scene.cast_rays(o3d.core.Tensor(rays))
        t = hit["t_hit"].numpy().astype(np.float64) + 1e-3
        prim = hit["primitive_ids"].numpy().astype(np.int64)
        reach = ln[cast] + gap_cm
        ok = np.isfinite(t) & (t < reach)
        ok[ok] &= ~(f[prim[ok]] == cast[ok, None]).any(axis=1)  # not a triangle round the vertex itself
        if not ok.any():
            break
        src, tri = np.flatnonzero(ok), prim[ok]
        corners = f[tri].ravel()
        target = np.repeat(x0[cast[src]] + reach[src, None] * u[src], 3, axis=0)  # (k*3, 3)
        uu = np.repeat(u[src], 3, axis=0)
        # how far each corner has to go along the push to lie at the target's level
        need = np.einsum("ij,ij->i", target - out[corners], uu)
        push = np.where(need > 0, need, 0.0)[:, None] * uu
        # a corner carried by several pushes takes the largest
        order = np.argsort(np.linalg.norm(push, axis=1), kind="stable")
        corners, push = corners[order], push[order]
        last = len(corners) - 1 - np.unique(corners[::-1], return_index=True)[1]
        moved = out[corners[last]] + push[last]
        if body is not None:
            free = ~body.inside(moved)
            last, moved = last[free], moved[free]
        out[corners[last]] = moved
    return out


class BodyCollider:
    """Signed distance and closest points to a closed body mesh.

    Parameters
    ----------
    vertices : (V, 3) float64, cm
    faces : (F, 3) int64
    """

    def __init__(
        self,
        vertices: np.ndarray,
        faces: np.ndarray,
        *,
        proxies: tuple[tuple[np.ndarray, np.ndarray], ...] = (),
    ) -> None:
        import open3d as o3d

        self._o3c = o3d.core
        self.vertices = np.asarray(vertices, dtype=np.float64)
        self.faces = np.asarray(faces, dtype=np.int64)
        self.scene = self._scene(self.vertices, self.faces)
        # closed helper volumes the cloth also stays out of (the space between
        # the thighs under a shirt); closest() and inside() see them, the
        # other queries see the body only
        self._add_proxies(proxies)

    _scene = staticmethod(triangle_scene)

    def _add_proxies(self, proxies) -> None:
        self._proxies = [self._scene(np.asarray(v), np.asarray(f)) for v, f in proxies]
        # their boxes: only points nearer a box than the skin need the proxy's queries
        self._boxes = [(np.min(v, axis=0), np.max(v, axis=0)) for v, _ in proxies]

    def with_proxies(self, proxies: tuple[tuple[np.ndarray, np.ndarray], ...]) -> BodyCollider:
        """This body with the helper volumes ``proxies`` (as in the constructor); the body's scene is shared."""
        out = object.__new__(BodyCollider)
        out._o3c, out.vertices, out.faces, out.scene = self._o3c, self.vertices, self.faces, self.scene
        out._add_proxies(proxies)
        return out

    def _t(self, a: np.ndarray):
        return self._o3c.Tensor(np.ascontiguousarray(a, dtype=np.float32))

    def closest(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Closest skin points.

        Returns
        -------
        closest : (n, 3) float64, cm
        normals : (n, 3) float64 outward face normals
        signed : (n,) float64, cm — distance along the normal (negative inside)
        triangle : (n,) int64 face id
        uv : (n, 2) float64 barycentric coordinates of the closest point
            (weights of the face's 2nd and 3rd corner)
        """
        res = self.scene.compute_closest_points(self._t(points))
        q = res["points"].numpy().astype(np.float64)
        n = res["primitive_normals"].numpy().astype(np.float64)
        tri = res["primitive_ids"].numpy().astype(np.int64)
        uv = res["primitive_uvs"].numpy().astype(np.float64)
        # the closest point of the boundary of the body and its helper volumes (triangle -1 on a helper): a
        # helper's surface buried in the skin (a mitt's end cutting through the wrist) is no boundary, nor is
        # skin buried in a helper (a palm inside its mitt); a nearer helper surface wins, and a helper surface
        # over buried skin wins at any distance
        for scene, (lo, hi) in zip(self._proxies, self._boxes, strict=True):
            d_box = np.linalg.norm(np.maximum(np.maximum(lo - points, points - hi), 0.0), axis=1)
            inbox = np.all((q >= lo) & (q <= hi), axis=1)  # the closest point so far may lie in the helper
            ask = np.flatnonzero((d_box * d_box <= np.einsum("ij,ij->i", points - q, points - q)) | inbox)
            if len(ask) == 0:
                continue
            r = scene.compute_closest_points(self._t(points[ask]))
            qp = r["points"].numpy().astype(np.float64)
            d = points[ask]
            nearer = np.einsum("ij,ij->i", d - qp, d - qp) < np.einsum("ij,ij->i", d - q[ask], d - q[ask])
            buried = scene.compute_occupancy(self._t(q[ask])).numpy() > 0.5
            bare = self.scene.compute_occupancy(self._t(qp)).numpy() < 0.5
            use = bare & (nearer | buried)
            win = ask[use]
            q[win] = qp[use]
            n[win] = r["primitive_normals"].numpy().astype(np.float64)[use]
            tri[win] = -1
            uv[win] = 0.0
        signed = np.einsum("ij,ij->i", points - q, n)
        return q, n, signed, tri, uv

    def sweep(
        self,
        start: np.ndarray,
        end: np.ndarray,
        offset_cm: float,
        *,
        min_move_cm: float = 3.0,
    ) -> tuple[np.ndarray, np.ndarray]:
        """Stop points moving from ``start`` (outside) to ``end`` where they first enter the skin.

        A ray is cast along each move; a move that crosses the skin ends at
        the crossing, ``offset_cm`` out along the face normal (continuous
        collision: no point can jump through a limb in one step). Moves
        shorter than ``min_move_cm`` are left to the closest-point projection:
        they cannot cross a limb, and a point sliding along the skin would
        otherwise stick at every grazing hit.

        Returns
        -------
        end : (n, 3) float64, corrected copy ; hit : (n,) bool
        """
        d = end - start
        ln = np.linalg.norm(d, axis=1)
        out = np.array(end, dtype=np.float64)
        moving = ln > min_move_cm
        if not moving.any():
            return out, np.zeros(len(end), dtype=bool)
        idx = np.flatnonzero(moving)
        rays = np.concatenate([start[idx], d[idx] / ln[idx, None]], axis=1)
        res = self.scene.cast_rays(self._t(rays))
        t = res["t_hit"].numpy().astype(np.float64)
        n = res["primitive_normals"].numpy().astype(np.float64)
        hit = np.isfinite(t) & (t < ln[idx])
        # only crossings from outside (the ray meets the outer side of a face)
        hit &= np.einsum("ij,ij->i", n, rays[:, 3:]) < 0
        j = idx[hit]
        out[j] = start[j] + rays[hit, 3:] * t[hit, None] + offset_cm * n[hit]
        mask = np.zeros(len(end), dtype=bool)
        mask[j] = True
        return out, mask

    def signed_distance(self, points: np.ndarray) -> np.ndarray:
        """(n,) float64 signed distance, cm, negative inside (ray-parity inside test)."""
        return self.scene.compute_signed_distance(self._t(points)).numpy().astype(np.float64)

    def crossing_edges(self, a: np.ndarray, b: np.ndarray) -> np.ndarray:
        """(n,) bool: the segment from ``a[i]`` to ``b[i]`` (n, 3) meets the skin.

        A ray is cast from ``a`` toward ``b``; the segment crosses the skin
        when the ray hits it before reaching ``b``.
        """
        d = np.asarray(b, dtype=np.float64) - np.asarray(a, dtype=np.float64)
        ln = np.linalg.norm(d, axis=1)
        ok = ln > 1e-9
        out = np.zeros(len(d), dtype=bool)
        if not ok.any():
            return out
        rays = np.concatenate([a[ok], d[ok] / ln[ok, None]], axis=1)
        t = self.scene.cast_rays(self._t(rays))["t_hit"].numpy().astype(np.float64)
        out[ok] = np.isfinite(t) & (t < ln[ok])
        return out

    def crossing_triangles(self, vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
        """(F,) bool: a triangle of the mesh ``vertices`` (V, 3) / ``faces`` (F, 3) crosses the skin.

        The test runs on the triangle edges (each cast as a ray in both
        directions): an edge that enters or leaves the body marks both
        triangles beside it.
        """
        v = np.asarray(vertices, dtype=np.float64)
        f = np.asarray(faces, dtype=np.int64)
        a = v[f].reshape(-1, 3)
        b = v[np.roll(f, -1, axis=1)].reshape(-1, 3)
        hit = self.crossing_edges(a, b) | self.crossing_edges(b, a)
        return hit.reshape(-1, 3).any(axis=1)

    @cached_property
    def _skin_edges(self) -> np.ndarray:
        """The body's unique edges (E, 2), made on first use."""
        f = self.faces
        return np.unique(np.sort(np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]]), axis=1), axis=0)

    def skin_through(self, vertices: np.ndarray, faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Where the skin pokes through a cloth mesh between its vertices (a nipple, a knuckle).

        The cloth's own edges can all stay outside the body while a tip of
        the skin passes through the inside of a triangle; this casts the
        body's edges near the cloth against it.

        Returns
        -------
        triangles : (k,) int64, the cloth triangle each piercing skin edge meets
        edges : (k, 2) int64, those skin edges (body vertex ids)
        """
        x = np.asarray(vertices, dtype=np.float64)
        f = np.asarray(faces, dtype=np.int64)
        edges = self._skin_edges
        none = (np.zeros(0, np.int64), np.zeros((0, 2), np.int64))
        if len(f) == 0 or len(edges) == 0:
            return none
        cloth = self._scene(x, f)
        a, b = self.vertices[edges[:, 0]], self.vertices[edges[:, 1]]
        length = np.linalg.norm(b - a, axis=1)
        # only edges with an end nearer the cloth than the edge is long can reach it
        near = cloth.compute_distance(self._t(self.vertices)).numpy().astype(np.float64)
        cand = np.flatnonzero((np.minimum(near[edges[:, 0]], near[edges[:, 1]]) <= length) & (length > 1e-9))
        if len(cand) == 0:
            return none
        d = (b[cand] - a[cand]) / length[cand, None]
        out_t, out_e = [], []
        for start, direction in ((a[cand], d), (b[cand], -d)):
            hit = cloth.cast_rays(self._t(np.concatenate([start, direction], axis=1)))
            t = hit["t_hit"].numpy().astype(np.float64)
            prim = hit["primitive_ids"].numpy().astype(np.int64)
            ok = np.isfinite(t) & (t < length[cand])
            out_t.append(prim[ok])
            out_e.append(edges[cand[ok]])
        tri = np.concatenate(out_t)
        e = np.concatenate(out_e)
        key = np.unique(np.concatenate([tri[:, None], e], axis=1), axis=0)
        return key[:, 0], key[:, 1:]

    def lift_over_skin(
        self, vertices: np.ndarray, faces: np.ndarray, offset_cm: float, *, rounds: int = 4
    ) -> np.ndarray:
        """Lift cloth triangles the skin pokes through (:meth:`skin_through`) off it.

        The corners of a pierced triangle move out from the skin, round after
        round farther (1.5, 2, 2.5 ... × ``offset_cm``), until the tip no
        longer reaches through.

        A corner whose push would end inside the body (in a crease such as an
        armpit, out of one surface is into the other) leaves the crease by
        the shortest free way instead (:meth:`escape`). A long triangle whose
        corners all lie farther out than the push (stretched over an elbow)
        moves along its own normal, past the skin edges through it on the
        nearer side, when that leaves fewer through; and every round also
        tries that move for all the pierced triangles at once, kept when it
        leaves fewer than the pushes (beside an armpit the corners' pushes
        drove an edge into the arm: A's shirt, seed 2). The round that left
        the fewest triangles through the skin either way (this test and
        :meth:`crossing_triangles`) is returned; cloth still caught (a cuff
        tangled round a thumb) is left for the report.

        Returns
        -------
        (V, 3) float64, the moved copy
        """
        x = np.array(vertices, dtype=np.float64)
        f = np.asarray(faces, dtype=np.int64)

        def through(y: np.ndarray) -> tuple[int, np.ndarray, np.ndarray]:
            """Triangles through the skin either way, and where the skin pokes through."""
            tri, edges = self.skin_through(y, f)
            return len(np.unique(tri)) + int(np.count_nonzero(self.crossing_triangles(y, f))), tri, edges

        bad, tri, edges = through(x)
        best = x
        for k in range(rounds):
            if len(tri) == 0:
                break
            # every pierced triangle moved along its own normal past the tip,
            # kept when it beats pushing the corners out (below): near a crease
            # the corners' pushes can drive an edge into the other surface
            slid = self._slide_off(x, f, tri, edges, 0.5 * offset_cm)
            slid_bad, slid_tri, slid_edges = through(slid)
            x = x.copy()
            corners = np.unique(f[tri])
            moved, pushed = self.push_out(x[corners], offset_cm * (1.5 + 0.5 * k), robust=True)
            jammed = pushed & self.inside(moved)
            pushed &= ~jammed
            x[corners[pushed]] = moved[pushed]
            if jammed.any():
                # in a crease (an armpit) the way out of one surface is into the
                # other: out of the crease by the shortest free way instead
                x[corners[jammed]] = self.escape(x[corners[jammed]], offset_cm * (1.5 + 0.5 * k))
            now, tri, edges = through(x)
            # a long triangle whose corners are all farther out than the push
            # (stretched over an elbow) moves along its own normal instead
            far = ~np.isin(f[tri], corners[pushed | jammed]).any(axis=1)
            if far.any():
                y = self._slide_off(x, f, tri[far], edges[far], 0.5 * offset_cm)
                then, tri_y, edges_y = through(y)
                if then < now:
                    x, now, tri, edges = y, then, tri_y, edges_y
            if slid_bad < now:
                x, now, tri, edges = slid, slid_bad, slid_tri, slid_edges
            if now < bad:
                best, bad = x, now
        return best

    def _slide_off(
        self, x: np.ndarray, f: np.ndarray, tri: np.ndarray, edges: np.ndarray, offset_cm: float
    ) -> np.ndarray:
        """Move triangles along their normals past the skin edges through them, to the nearer side.

        A corner shared by several takes the largest move; a corner the move
        would put inside the body stays.
        """
        p = x[f[tri]]  # (k, 3, 3)
        n = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
        n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-12)
        d = np.einsum("kij,kj->ki", self.vertices[edges] - p[:, :1], n)  # both ends of each skin edge
        up, down = d.max(axis=1), -d.min(axis=1)
        step = np.where(up <= down, up + offset_cm, -(down + offset_cm))
        corners = f[tri].ravel()
        moves = np.repeat(step[:, None] * n, 3, axis=0)
        order = np.argsort(np.abs(np.repeat(step, 3)), kind="stable")
        corners, moves = corners[order], moves[order]
        last = len(corners) - 1 - np.unique(corners[::-1], return_index=True)[1]  # each corner's largest move
        target = x[corners[last]] + moves[last]
        ok = ~self.inside(target)
        out = x.copy()
        out[corners[last][ok]] = target[ok]
        return out

    def clear_triangles(
        self,
        vertices: np.ndarray,
        faces: np.ndarray,
        offset_cm: float,
        *,
        rounds: int = 16,
    ) -> np.ndarray:
        """Move the corners of triangles that cross the skin until none does (or ``rounds`` run out).

        Points at a quarter, half and three quarters of every edge of a
        crossing triangle, and its centroid, that lie inside the skin or
        closer than ``offset_cm`` are pushed to ``offset_cm`` outside; each
        push moves the corners the point is made of (averaged per vertex).
        A corner that the move would put inside the body (out of one
        surface into another, where an arm lies against the torso) stays.

        Returns
        -------
        (V, 3) float64, the moved copy
        """
        x = np.array(vertices, dtype=np.float64)
        f = np.asarray(faces, dtype=np.int64)
        w = np.array(
            [
                [0.75, 0.25, 0.0],
                [0.5, 0.5, 0.0],
                [0.25, 0.75, 0.0],
                [1 / 3, 1 / 3, 1 / 3],
            ]
        )
        for _ in range(rounds):
            bad = f[self.crossing_triangles(x, f)]
            if len(bad) == 0:
                break
            # the three edges of each bad triangle (rolled corners) and its centroid
            corners = np.concatenate([bad, np.roll(bad, -1, axis=1), np.roll(bad, -2, axis=1)])
            wts = np.concatenate([np.tile(w[:3], (len(bad), 1)) for _ in range(3)])
            idx = np.repeat(corners, 3, axis=0)
            wts = wts.reshape(-1, 3)
            idx = np.concatenate([idx, bad])
            wts = np.concatenate([wts, np.tile(w[3], (len(bad), 1))])
            m = np.einsum("sk,skj->sj", wts, x[idx])
            q, n, _, _, _ = self.closest(m)
            ins = self.inside(m)
            away = m - q
            dist = np.linalg.norm(away, axis=1)
            fix = ins | (dist < offset_cm)
            if not fix.any():
                break
            direction = np.where(
                (ins | (dist < 1e-6))[:, None],
                n,
                away / np.maximum(dist, 1e-12)[:, None],
            )
            corr = q + offset_cm * direction - m
            corr, idx, wts = corr[fix], idx[fix], wts[fix]
            delta = np.zeros_like(x)
            cnt = np.zeros(len(x))
            for k in range(3):
                np.add.at(delta, idx[:, k], corr * (wts[:, k] > 0)[:, None])
                np.add.at(cnt, idx[:, k], (wts[:, k] > 0).astype(float))
            moved = np.flatnonzero(cnt > 0)
            step = x[moved] + delta[moved] / cnt[moved, None]
            # out of one surface must not be into another (cloth in an armpit)
            keep = ~self.inside(step)
            if not keep.any():
                break
            x[moved[keep]] = step[keep]
        return x

    def escape(
        self, points: np.ndarray, offset_cm: float, *, reach_cm: float = 20.0, step_cm: float = 0.25
    ) -> np.ndarray:
        """Move points out of the body along the shortest straight way out (the last resort).

        For a point caught where two parts of the body touch (cloth between
        an arm pressed against the hip), pushing it out of one surface puts
        it into the other. Here 26 directions (the cube's faces, edges and
        corners) are sampled every ``step_cm`` up to ``reach_cm``; the point
        goes to the nearest sample that is outside and at least
        ``offset_cm`` from the skin. Points with no such sample stay.

        Returns
        -------
        (n, 3) float64, the moved copy
        """
        p = np.array(points, dtype=np.float64)
        if len(p) == 0:
            return p
        g = np.array([-1.0, 0.0, 1.0])
        dirs = np.stack(np.meshgrid(g, g, g, indexing="ij"), axis=-1).reshape(-1, 3)
        dirs = dirs[np.any(dirs != 0, axis=1)]
        dirs /= np.linalg.norm(dirs, axis=1, keepdims=True)
        ts = np.arange(step_cm, reach_cm + 1e-9, step_cm)
        cand = p[:, None, None, :] + ts[None, None, :, None] * dirs[None, :, None, :]  # (n, 26, T, 3)
        flat = cand.reshape(-1, 3)
        free = ~self.scene.compute_occupancy(self._t(flat)).numpy().astype(bool)
        free &= np.abs(self.signed_distance(flat)) >= offset_cm
        free = free.reshape(len(p), len(dirs), len(ts))
        first = np.where(free.any(axis=2), np.argmax(free, axis=2), len(ts))  # (n, 26)
        best = np.argmin(first, axis=1)
        k = first[np.arange(len(p)), best]
        ok = k < len(ts)
        p[ok] = cand[np.flatnonzero(ok), best[ok], k[ok]]
        return p

    def inside(self, points: np.ndarray) -> np.ndarray:
        """(n,) bool, True where the point is inside the body (or a helper volume)."""
        points = np.asarray(points, dtype=np.float64)
        out = self.scene.compute_occupancy(self._t(points)).numpy() > 0.5
        for scene, (lo, hi) in zip(self._proxies, self._boxes, strict=True):
            ask = np.flatnonzero(np.all((points >= lo) & (points <= hi), axis=1) & ~out)
            if len(ask):
                out[ask] = scene.compute_occupancy(self._t(points[ask])).numpy() > 0.5
        return out

    def radial_clearance(self, cyl, theta: np.ndarray, h: np.ndarray, r: np.ndarray, clearance_cm: float) -> np.ndarray:
        """Radii that keep wrapped points outside the skin along their radius.

        From the axis point at height ``h`` a ray runs out at angle ``theta``;
        where the axis point is inside the body and the ray leaves the skin
        beyond ``r - clearance_cm`` (but within 1.6 r, so a ray running down
        a limb does not count), the radius grows to the exit plus
        ``clearance_cm``.
        """
        theta = np.asarray(theta, dtype=np.float64)
        origin = cyl.center + h[:, None] * cyl.axis
        direction = np.cos(theta)[:, None] * cyl.e0 + np.sin(theta)[:, None] * cyl.e1
        rays = np.concatenate([origin, direction], axis=1)
        t = self.scene.cast_rays(self._t(rays))["t_hit"].numpy().astype(np.float64)
        inside = self.inside(origin)
        grow = inside & np.isfinite(t) & (t + clearance_cm > r) & (t < 1.6 * r)
        return np.where(grow, t + clearance_cm, r)

    def push_out(self, points: np.ndarray, offset_cm: float, *, robust: bool = False) -> tuple[np.ndarray, np.ndarray]:
        """Move points closer than ``offset_cm`` (or inside) to ``offset_cm`` outside.

        ``robust`` decides inside/outside by ray parity instead of the face
        normal (slower, right also for points deep inside).

        Returns
        -------
        points : (n, 3) float64 moved copy ; moved : (n,) bool
        """
        q, n, signed, _, _ = self.closest(points)
        if robust:
            inside = self.inside(points)
            dist = np.linalg.norm(points - q, axis=1)
            signed = np.where(inside, -dist, dist)
            away = points - q
            away_n = np.linalg.norm(away, axis=1, keepdims=True)
            use_face = (away_n[:, 0] < 1e-6) | inside
            n = np.where(use_face[:, None], n, away / np.maximum(away_n, 1e-12))
        moved = signed < offset_cm
        out = np.array(points, dtype=np.float64)
        out[moved] = q[moved] + offset_cm * n[moved]
        return out, moved


def thigh_fill(body: np.ndarray, legs: np.ndarray, crotch_y: float | None) -> tuple[tuple[np.ndarray, np.ndarray], ...]:
    """A closed volume filling the space between the thighs, for tops that reach below the crotch.

    A shirt hangs straight down from the hips; without it the hem is drawn
    in between the legs like a bodysuit. The volume is the convex hull of
    the leg vertices from 2 cm above the crotch to 30 cm below it.

    Parameters
    ----------
    body : (V, 3) float64, cm
    legs : (V,) bool, the leg vertices
    crotch_y : height of the crotch point, cm (None: the top of the legs)

    Returns
    -------
    ``((vertices (n, 3), faces (m, 3)),)`` for :class:`BodyCollider`'s
    ``proxies``, or ``()`` when the body has no legs.
    """
    import trimesh

    if not legs.any():
        return ()
    top = float(body[legs, 1].max()) if crotch_y is None else float(crotch_y)
    band = body[legs & (body[:, 1] > top - 30.0) & (body[:, 1] < top + 2.0)]
    if len(band) < 10:
        return ()
    hull = trimesh.convex.convex_hull(band)
    return ((np.asarray(hull.vertices), np.asarray(hull.faces)),)


def hand_mitts(body: np.ndarray, hands: list[np.ndarray]) -> tuple[tuple[np.ndarray, np.ndarray], ...]:
    """Closed volumes over the hands (convex hulls, like mittens) that a sleeve slides on.

    A cuff laid round the hand in the dressing pose had the thumb through
    it; cloth caught on both sides of a finger cannot get free, and sewing
    tore the sleeve hem open round it. The cloth stays out of the hull
    instead, which has no gaps to catch in.

    Parameters
    ----------
    body : (V, 3) float64, cm, the body in the current pose
    hands : (V,) bool masks of the hand vertices (:func:`~patternbridge.assemble.bodyparts.hand_masks`)

    Returns
    -------
    ``((vertices, faces), ...)`` for :class:`BodyCollider`'s ``proxies``.
    """
    return tuple((np.asarray(body)[ids], f) for ids, f in mitt_hulls(body, hands))


def mitt_hulls(body: np.ndarray, hands: list[np.ndarray]) -> tuple[tuple[np.ndarray, np.ndarray], ...]:
    """The hand mitts of :func:`hand_mitts` as body vertex ids (n,) and faces (m, 3) over them.

    The hull is taken once, in the pose of ``body``; a body moving in small
    steps moves the mitt with it by moving its corners (the same vertices
    of the posed body), without taking the hull again.
    """
    import trimesh
    from scipy.spatial import cKDTree

    v = np.asarray(body, dtype=np.float64)
    out = []
    for mask in hands:
        if np.count_nonzero(mask) < 10:
            continue
        ids = np.flatnonzero(mask)
        hull = trimesh.convex.convex_hull(v[ids])
        corner = ids[cKDTree(v[ids]).query(np.asarray(hull.vertices))[1]]
        out.append((corner.astype(np.int64), np.asarray(hull.faces, dtype=np.int64)))
    return tuple(out)
