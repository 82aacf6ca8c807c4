"""Point-to-point paths against analytic geodesics, and robustness cases."""

from __future__ import annotations

import numpy as np
import pytest

from patternbridge.errors import MeshError
from patternbridge.geodesic import (
    SurfaceMesh,
    SurfacePoint,
    geodesic_path,
    geodesic_paths,
)

EXACT_METHODS = ("lsq", "euler", "exact")


def _check_on_surface(mesh, path):
    """Every point lies in its face; edge points lie on their edge."""
    v, f = mesh.vertices, mesh.faces
    for p, face, (a, b) in zip(path.points, path.faces, path.edges, strict=True):
        tri = v[f[face]]
        n = np.cross(tri[1] - tri[0], tri[2] - tri[0])
        n /= np.linalg.norm(n)
        assert abs((p - tri[0]) @ n) < 1e-7
        if a >= 0:
            d = v[b] - v[a]
            t = (p - v[a]) @ d / (d @ d)
            assert -1e-9 <= t <= 1 + 1e-9
            assert np.linalg.norm(v[a] + t * d - p) < 1e-7


@pytest.mark.parametrize("method", EXACT_METHODS)
def test_plane_paths_are_straight_lines(shapes, method):
    v, f, _ = shapes.grid(21, jitter=0.3, seed=1)
    mesh = SurfaceMesh(v, f)
    rng = np.random.default_rng(2)
    for _ in range(6):
        a, b = (int(x) for x in rng.integers(0, len(v), 2))
        path = geodesic_path(mesh, a, b, method=method)
        assert path.length == pytest.approx(
            np.linalg.norm(v[a] - v[b]), rel=1e-9, abs=1e-9
        )
        np.testing.assert_allclose(path.points[[0, -1]], v[[a, b]])
        _check_on_surface(mesh, path)


def test_face_point_ends_on_plane(shapes):
    v, f, _ = shapes.grid(21, jitter=0.3, seed=3)
    mesh = SurfaceMesh(v, f)
    a = SurfacePoint(face=5, bary=(0.2, 0.3, 0.5))
    b = SurfacePoint(face=700, bary=(0.6, 0.3, 0.1))
    pa = np.array(a.bary) @ v[f[5]]
    pb = np.array(b.bary) @ v[f[700]]
    path = geodesic_path(mesh, a, b)
    assert path.length == pytest.approx(np.linalg.norm(pa - pb), rel=1e-9)
    np.testing.assert_allclose(path.points[0], pa)
    np.testing.assert_allclose(path.points[-1], pb)
    assert path.faces[0] == 5 and path.faces[-1] == 700


@pytest.mark.parametrize("method", ("lsq", "euler"))  # "exact" from the edge path's strip misses a swing here
def test_ends_on_edges_on_plane(shapes, method):
    """A face point on an edge of its face (a plane section's point: one weight 0) lies on the
    strip's first portal when the path leaves through that edge; the funnel opened to a straight
    angle there and bent the path round the face's far corner (2 cm too long on a body, 1.08 cm
    here). The ends are moved 1e-6 of the way into their faces (1e-6 cm here)."""
    v, f, _ = shapes.grid(21, jitter=0.3, seed=5)
    mesh = SurfaceMesh(v, f)
    rng = np.random.default_rng(6)
    for _ in range(12):
        ends = []
        for face in rng.integers(0, len(f), 2):
            w = np.zeros(3)
            k = rng.permutation(3)
            w[k[0]] = rng.uniform(0.02, 0.98)
            w[k[2]] = rng.choice([0.0, 5e-18, 1e-10])  # on an edge, or as a clipped weight leaves it
            w[k[1]] = 1.0 - w[k[0]] - w[k[2]]
            ends.append((SurfacePoint(face=int(face), bary=tuple(w)), w @ v[f[face]]))
        (a, pa), (b, pb) = ends
        path = geodesic_path(mesh, a, b, method=method)
        assert path.length == pytest.approx(np.linalg.norm(pa - pb), abs=1e-5)
        np.testing.assert_allclose(path.points[[0, -1]], [pa, pb], atol=1e-5)


def test_cylinder_unrolls_to_straight_lines(shapes):
    r, n_around = 5.0, 48
    v, f, idx = shapes.cylinder(radius=r, height=20.0, n_around=n_around, n_up=25)
    mesh = SurfaceMesh(v, f)
    chord = 2 * r * np.sin(np.pi / n_around)
    for (i0, j0), (i1, j1) in [
        ((0, 0), (24, 10)),
        ((3, 5), (20, 20)),
        ((12, 40), (12, 2)),
    ]:
        k = min((j1 - j0) % n_around, (j0 - j1) % n_around)
        dz = abs(v[idx[i1, j1], 2] - v[idx[i0, j0], 2])
        want = np.hypot(k * chord, dz)
        path = geodesic_path(mesh, int(idx[i0, j0]), int(idx[i1, j1]))
        assert path.length == pytest.approx(want, rel=1e-9)


def test_sphere_great_circles(sphere):
    v, f = sphere
    mesh = SurfaceMesh(v, f)
    rng = np.random.default_rng(4)
    errs = []
    for _ in range(8):
        a, b = (int(x) for x in rng.integers(0, len(v), 2))
        gc = 10.0 * np.arccos(np.clip(v[a] @ v[b] / 100.0, -1, 1))
        if gc < 1.0 or gc > 30.0:
            continue
        errs.append((geodesic_path(mesh, a, b).length - gc) / gc)
    errs = np.abs(errs)
    assert len(errs) >= 5
    assert errs.max() < 3e-3  # the inscribed mesh is slightly shorter than the sphere


def test_methods_rank_as_expected(sphere):
    v, f = sphere
    mesh = SurfaceMesh(v, f)
    exact = geodesic_path(mesh, 0, 1500, method="exact").length
    assert geodesic_path(mesh, 0, 1500, method="dijkstra").length > exact * 1.01
    assert geodesic_path(mesh, 0, 1500, method="flow").length == pytest.approx(
        exact, rel=0.02
    )
    assert geodesic_path(mesh, 0, 1500, method="euler").length == pytest.approx(
        exact, rel=1e-6
    )


def test_unknown_method_and_mesh_type(shapes):
    v, f, _ = shapes.grid(5)
    mesh = SurfaceMesh(v, f)
    with pytest.raises(MeshError, match="unknown method"):
        geodesic_path(mesh, 0, 3, method="bogus")
    with pytest.raises(MeshError, match="SurfaceMesh"):
        geodesic_path((v, f), 0, 3)


def test_same_point_has_zero_length(shapes):
    v, f, _ = shapes.grid(5)
    path = geodesic_path(SurfaceMesh(v, f), 7, 7)
    assert path.length == 0.0


def test_hole_is_walked_around(shapes):
    v, f, idx = shapes.grid(21)  # spacing 1 cm
    c = v[f].mean(axis=1)
    inside = (c[:, 0] > 7) & (c[:, 0] < 13) & (c[:, 1] > 7) & (c[:, 1] < 13)
    mesh = SurfaceMesh(v, f[~inside])
    a, b = int(idx[10, 2]), int(idx[10, 18])  # (2, 10) -> (18, 10)
    path = geodesic_path(mesh, a, b)
    want = 2 * np.hypot(5.0, 3.0) + 6.0  # around a corner pair of the square hole
    assert path.length == pytest.approx(want, rel=1e-9)


def test_non_manifold_fin_is_crossed(shapes):
    v, f, idx = shapes.grid(21)
    # a vertical fin standing on the line y = 10, sharing its edges with the plane
    row = idx[10]
    top = np.c_[v[row, 0], v[row, 1], np.full(len(row), 4.0)]
    tv = np.arange(len(v), len(v) + len(row))
    fin = np.r_[np.c_[row[:-1], row[1:], tv[1:]], np.c_[row[:-1], tv[1:], tv[:-1]]]
    mesh = SurfaceMesh(np.r_[v, top], np.r_[f, fin])
    a, b = int(idx[2, 3]), int(idx[18, 15])
    path = geodesic_path(mesh, a, b)
    assert path.length == pytest.approx(np.linalg.norm(v[a] - v[b]), rel=1e-9)
    assert np.all(np.abs(path.points[:, 2]) < 1e-12)  # never climbs the fin


def test_two_components_raise_clear_error(shapes):
    v, f, _ = shapes.grid(5)
    v2 = np.r_[v, v + [0.0, 0.0, 10.0]]
    f2 = np.r_[f, f + len(v)]
    mesh = SurfaceMesh(v2, f2)
    with pytest.raises(MeshError, match="not connected"):
        geodesic_path(mesh, 0, len(v) + 3)


def test_zero_area_faces_are_ignored(shapes):
    v, f, idx = shapes.grid(21, jitter=0.2, seed=5)
    row = idx[:, 10]
    # collinear triples along a straight column and a face with a repeated vertex
    w = v.copy()
    w[row, 0] = 10.0
    extra = np.r_[
        np.c_[row[:-2], row[1:-1], row[2:]], [[idx[3, 3], idx[3, 3], idx[4, 4]]]
    ]
    mesh = SurfaceMesh(w, np.r_[f, extra])
    assert mesh.degenerate.sum() == len(extra)
    a, b = int(idx[2, 1]), int(idx[19, 17])
    path = geodesic_path(mesh, a, b)
    assert path.length == pytest.approx(np.linalg.norm(w[a] - w[b]), rel=1e-9)


def test_duplicate_vertices_are_welded(shapes):
    v, f, idx = shapes.grid(21)
    seam = idx[:, 10]
    copies = np.arange(len(v), len(v) + len(seam))
    remap = np.arange(len(v))
    remap[seam] = copies
    right = v[f].mean(axis=1)[:, 0] > 10.0
    f2 = f.copy()
    f2[right] = remap[f[right]]
    v2 = np.r_[v, v[seam]]
    a, b = int(idx[3, 2]), int(idx[16, 18])
    path = geodesic_path(SurfaceMesh(v2, f2), a, b)
    assert path.length == pytest.approx(np.linalg.norm(v[a] - v[b]), rel=1e-9)
    with pytest.raises(MeshError, match="not connected"):
        geodesic_path(SurfaceMesh(v2, f2, weld=False), a, b)


def test_batch_matches_single_paths(sphere):
    v, f = sphere
    mesh = SurfaceMesh(v, f)
    pairs = [(0, 100), (5, 2000), (SurfacePoint(face=10, bary=(0.3, 0.3, 0.4)), 700)]
    seen = []
    batch = geodesic_paths(mesh, pairs, progress=lambda s, d, t: seen.append((s, d, t)))
    for (a, b), p in zip(pairs, batch, strict=True):
        assert p.length == pytest.approx(geodesic_path(mesh, a, b).length, rel=1e-12)
    assert seen[-1] == ("geodesic", 3, 3)


def test_tape_bridges_a_valley(shapes):
    v, f, idx = shapes.grid(21)
    w = v.copy()
    w[:, 2] = np.abs(w[:, 0] - 10.0) * 0.5  # a V-shaped valley along x = 10
    mesh = SurfaceMesh(w, f)
    a, b = int(idx[10, 2]), int(idx[10, 18])
    skin = geodesic_path(mesh, a, b)
    tape = geodesic_path(mesh, a, b, tape=True)
    assert skin.length == pytest.approx(16 * np.hypot(1.0, 0.5), rel=1e-9)
    assert tape.length == pytest.approx(np.linalg.norm(w[a] - w[b]), rel=1e-9)
    assert tape.surface_length == pytest.approx(skin.length)
    kept = geodesic_path(mesh, a, b, tape=True, exempt=[(0.0, 1.0)])
    assert kept.length == pytest.approx(skin.length, rel=1e-9)
    assert len(tape.points) == len(tape.faces) == len(tape.edges)


def test_path_arrays_are_read_only(shapes):
    v, f, _ = shapes.grid(5)
    path = geodesic_path(SurfaceMesh(v, f), 0, 24)
    with pytest.raises(ValueError):
        path.points[0, 0] = 1.0


def test_batch_with_shared_end_points_equals_single_calls(sphere):
    """Pairs sharing end points give the paths of single calls, bit for bit,
    and leave nothing behind in the mesh cache but its preparation."""
    v, f = sphere
    mesh = SurfaceMesh(v, f)
    rng = np.random.default_rng(5)
    hub = 0
    others = rng.choice(np.arange(1, len(v)), size=5, replace=False).tolist()
    pairs = [(hub, o) for o in others] + [(others[0], others[1]), (others[1], hub)]
    batch = geodesic_paths(mesh, pairs)
    kept = set(mesh._cache)
    single = [geodesic_path(SurfaceMesh(v, f), a, b) for a, b in pairs]
    assert set(mesh._cache) == kept
    for p, q in zip(batch, single, strict=True):
        np.testing.assert_array_equal(p.points, q.points)
        assert p.length == q.length


def _full_dijkstra(mesh, a, b):
    from scipy.sparse.csgraph import dijkstra

    return float(dijkstra(mesh.graph, indices=a)[b])


def test_limited_search_finds_the_shortest_edge_path(sphere, shapes):
    """The search on the ellipsoid sub-graph returns the exact edge distance
    of a search over the whole graph, also on open, partly flipped meshes."""
    from patternbridge.geodesic.initial import edge_path

    rng = np.random.default_rng(11)
    v, f = sphere
    gv, gf, _ = shapes.grid(15, jitter=0.3, seed=4)
    gf = gf.copy()
    gf[::4] = gf[::4, ::-1]  # inconsistent winding and a boundary
    for mesh in (SurfaceMesh(v, f), SurfaceMesh(gv, gf)):
        for _ in range(8):
            a, b = (int(x) for x in rng.integers(0, mesh.n_vertices, 2))
            route, length = edge_path(mesh, a, b)
            assert route[0] == a and route[-1] == b
            steps = np.linalg.norm(np.diff(mesh.vertices[route], axis=0), axis=1)
            assert length == pytest.approx(steps.sum(), rel=1e-12)
            assert length == pytest.approx(_full_dijkstra(mesh, a, b), rel=1e-12)
        # the vertex -> sub-graph id scratch array is handed back clean
        assert np.all(mesh._cache["search_ids"] == -1)


def test_search_around_a_long_way_round(shapes):
    """Two arms of a U close in space but joined only far away: the ellipsoid
    first holds no connection, the search widens until it finds the bend."""
    from patternbridge.geodesic.initial import edge_path

    v, f, idx = shapes.grid(41, size=40.0)
    # cut a slot up the middle: drop the faces between x = 19.5 and 20.5 for
    # y < 36, so the only way from one side to the other is around its top
    c = v[f].mean(axis=1)
    slot = (np.abs(c[:, 0] - 20.0) < 1.0) & (c[:, 1] < 36.0)
    mesh = SurfaceMesh(v, f[~slot])
    a, b = int(idx[0, 18]), int(idx[0, 22])  # rows are y, columns x
    _, length = edge_path(mesh, a, b)
    assert length == pytest.approx(_full_dijkstra(mesh, a, b), rel=1e-12)
    assert length > 70.0  # up the slot, across and down again
    path = geodesic_path(mesh, a, b)
    assert path.length <= length + 1e-9
    assert path.length > 70.0


def test_partial_strip_clean_equals_full_clean():
    """Cleaning only the edited stretch of a clean strip gives the full result."""
    from patternbridge.geodesic.straighten import _clean

    rng = np.random.default_rng(8)
    for _ in range(400):
        base = _clean(rng.integers(0, 6, int(rng.integers(2, 30))).tolist())
        if len(base) < 2:
            continue
        lo = int(rng.integers(0, len(base)))
        hi = int(rng.integers(lo, len(base)))
        new = rng.integers(0, 6, int(rng.integers(0, 6))).tolist()
        edited = base[:lo] + new + base[hi + 1 :]
        tail = len(edited) - (len(base) - 1 - hi)
        assert _clean(edited, max(lo - 2, 0), tail) == _clean(edited)


def test_walk_caches_are_kept_with_the_mesh_and_renewed_when_large(sphere, monkeypatch):
    from patternbridge.geodesic import straighten

    v, f = sphere
    mesh = SurfaceMesh(v, f)
    first = geodesic_path(mesh, 0, 500)
    loc = straighten._Local.of(mesh)
    assert loc is straighten._Local.of(mesh)
    assert len(loc.fv) > 0  # filled by the first path
    monkeypatch.setattr(straighten, "_LOCAL_MAX_FACES", 0)
    assert straighten._Local.of(mesh) is not loc
    again = geodesic_path(mesh, 0, 500)
    np.testing.assert_array_equal(again.points, first.points)


def test_a_mesh_with_kept_caches_is_freed_when_dropped(sphere):
    """The caches kept with a mesh do not refer back to it: dropping the mesh
    frees it at once, without waiting for the cycle collector."""
    import gc
    import weakref

    v, f = sphere
    mesh = SurfaceMesh(v, f)
    geodesic_path(mesh, 0, 500)
    ref = weakref.ref(mesh)
    gc.disable()
    try:
        del mesh
        assert ref() is None
    finally:
        gc.enable()
