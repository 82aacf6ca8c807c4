"""Single source, all destinations (wavefront propagation with curvature flow)."""

from __future__ import annotations

import numpy as np
import pytest

from patternbridge.errors import MeshError
from patternbridge.geodesic import SurfaceMesh, geodesic_distances
from patternbridge.geodesic.propagate import solve_lateral, solve_windows


def test_full_form_is_exact_on_a_plane(shapes):
    v, f, idx = shapes.grid(15, size=14.0, jitter=0.2, seed=7)
    mesh = SurfaceMesh(v, f)
    src = int(idx[7, 7])
    d = geodesic_distances(mesh, src, window="full")
    np.testing.assert_allclose(d, np.linalg.norm(v - v[src], axis=1), atol=1e-9)


def test_windowed_error_on_a_plane(shapes):
    v, f, idx = shapes.grid(31, size=30.0, jitter=0.2, seed=8)
    mesh = SurfaceMesh(v, f)
    src = int(idx[15, 15])
    exact = np.linalg.norm(v - v[src], axis=1)
    far = exact > 3.0
    errs = {}
    for w in (4, 16):
        d = geodesic_distances(mesh, src, window=w)
        errs[w] = np.mean(np.abs(d[far] - exact[far]) / exact[far])
        assert np.all(d[far] >= exact[far] - 1e-9)  # paths on the plane are never short
    assert errs[16] < errs[4]
    assert errs[16] < 0.015


def test_r_max_limits_the_propagation(sphere):
    v, f = sphere
    mesh = SurfaceMesh(v, f)
    d = geodesic_distances(mesh, 0, r_max=5.0, window=6)
    gc = 10.0 * np.arccos(np.clip(v @ v[0] / 100.0, -1, 1))
    assert np.all(np.isinf(d[gc > 6.0]))
    assert np.all(np.isfinite(d[gc < 4.5]))


def test_other_component_is_unreached(shapes):
    v, f, _ = shapes.grid(6)
    mesh = SurfaceMesh(np.r_[v, v + np.array([0, 0, 5.0])], np.r_[f, f + len(v)])
    d = geodesic_distances(mesh, 0, window=5)
    assert np.all(np.isfinite(d[: len(v)])) and np.all(np.isinf(d[len(v) :]))


def test_bad_arguments(shapes):
    v, f, _ = shapes.grid(5)
    mesh = SurfaceMesh(v, f)
    with pytest.raises(MeshError, match="window"):
        geodesic_distances(mesh, 0, window=2)
    with pytest.raises(MeshError, match="window"):
        geodesic_distances(mesh, 0, window="half")
    with pytest.raises(MeshError, match="r_max"):
        geodesic_distances(mesh, 0, r_max=-1.0)
    with pytest.raises(MeshError, match="SurfaceMesh"):
        geodesic_distances((v, f), 0)
    with pytest.raises(MeshError, match="out of range"):
        geodesic_distances(mesh, 10_000)


def _random_windows(seed: int, n: int, w: int):
    """``n`` random polylines of ``w`` samples, unit normals, ends fixed."""
    rng = np.random.default_rng(seed)
    pts = np.cumsum(rng.normal(size=(n, w, 3)), axis=1)
    nrm = rng.normal(size=(n, w, 3))
    nrm /= np.linalg.norm(nrm, axis=2, keepdims=True)
    free = np.ones((n, w), dtype=bool)
    free[:, [0, -1]] = False
    return pts, nrm, free


def test_batched_window_solve_matches_lsq():
    from patternbridge.geodesic.flow import lsq_step

    pts, nrm, free = _random_windows(9, 3, 7)
    out = solve_windows(pts, nrm, pts, free)
    for b in range(3):
        np.testing.assert_allclose(out[b], lsq_step(pts[b], nrm[b], pts[b]), atol=1e-8)


@pytest.mark.parametrize("w", [7, 30])
def test_banded_window_solve_matches_lsq(w):
    """The windows laid end to end and solved as one banded system give the
    least-squares flow step of each window, with given or derived tangent
    bases; samples before a filling window's start stay put."""
    from patternbridge.geodesic import propagate
    from patternbridge.geodesic.flow import lsq_step

    pts, nrm, free = _random_windows(w, 4, w)
    free[1, : w // 2] = False  # a window still filling up
    t1, t2 = propagate._tangent_bases(nrm)
    tng = np.stack([t1, t2], axis=-1)
    out = solve_windows(pts, nrm, pts, free)
    np.testing.assert_allclose(solve_windows(pts, nrm, pts, free, tangents=tng), out)
    for b in (0, 2, 3):
        np.testing.assert_allclose(out[b], lsq_step(pts[b], nrm[b], pts[b]), atol=1e-8)
    np.testing.assert_array_equal(out[1, : w // 2], pts[1, : w // 2])  # fixed stay
    k = w // 2 - 1  # the filling window is the lsq step of its own samples
    np.testing.assert_allclose(out[1, k:], lsq_step(pts[1, k:], nrm[1, k:], pts[1, k:]), atol=1e-8)


def _lateral_windows(rng, B, w):
    pts = np.cumsum(rng.normal(size=(B, w, 3)) + np.array([1.0, 0.0, 0.0]), axis=1)
    nrm = rng.normal(size=(B, w, 3))
    nrm /= np.linalg.norm(nrm, axis=2, keepdims=True)
    free = np.ones((B, w), dtype=bool)
    free[:, [0, -1]] = False
    return pts.reshape(-1, 3), nrm.reshape(-1, 3), free.ravel()


def test_lateral_solve_zeroes_geodesic_curvature():
    """Each free sample ends on its tangent plane, moved across the path only
    (along b = n x chord), with no geodesic curvature left:
    b . ((p+ - p) / h+ - (p - p-) / h-) = 0."""
    rng = np.random.default_rng(3)
    B, w = 5, 9
    x, n, fr = _lateral_windows(rng, B, w)
    anchors = x + rng.normal(scale=0.3, size=x.shape)
    out = solve_lateral(x, anchors, n, fr)
    np.testing.assert_array_equal(out[~fr], x[~fr])
    f = np.flatnonzero(fr)
    on_plane = np.einsum("ij,ij->i", out[f] - anchors[f], n[f])
    np.testing.assert_allclose(on_plane, 0, atol=1e-9)
    base = x - (np.einsum("ij,ij->i", x - anchors, n) * fr)[:, None] * n
    b = np.cross(n[f], base[f + 1] - base[f - 1])
    b /= np.linalg.norm(b, axis=1, keepdims=True)
    move = out[f] - base[f]
    np.testing.assert_allclose(np.cross(move, b), 0, atol=1e-9)  # across the path
    h = np.linalg.norm(np.diff(base, axis=0), axis=1)
    lap = (out[f + 1] - out[f]) / h[f, None] - (out[f] - out[f - 1]) / h[f - 1, None]
    np.testing.assert_allclose(np.einsum("ij,ij->i", b, lap), 0, atol=1e-9)
    assert np.abs(move).max() > 0.1  # it did move


@pytest.mark.parametrize("wiggle", [0.1, 0.3])
def test_lateral_steps_straighten_a_planar_window(wiggle):
    """Repeated lateral solves on a plane reach the straight segment between
    the fixed ends (the geodesic) in a few steps, however unevenly sampled."""
    rng = np.random.default_rng(5)
    w = 12
    t = np.cumsum(rng.uniform(0.2, 1.8, w))
    x = np.c_[t, wiggle * rng.normal(size=w), np.zeros(w)]
    n = np.tile([0.0, 0.0, 1.0], (w, 1))
    fr = np.ones(w, dtype=bool)
    fr[[0, -1]] = False
    for _ in range(5):
        x = solve_lateral(x, np.zeros((w, 3)), n, fr)
    np.testing.assert_allclose(x[:, 2], 0.0, atol=1e-12)
    chord = x[-1] - x[0]
    off = np.cross(x - x[0], chord)[:, 2] / np.linalg.norm(chord)
    np.testing.assert_allclose(off, 0.0, atol=1e-9)
    length = np.linalg.norm(np.diff(x, axis=0), axis=1).sum()
    assert length == pytest.approx(np.linalg.norm(chord), rel=1e-12)


@pytest.mark.parametrize("flow", ["lateral", "lsq"])
def test_great_circles_on_a_sphere(sphere, flow):
    """Distances from one vertex of a 2.5K-vertex sphere against the great
    circle, automatic window: within 1 % on average, never more than 4 % off
    and never short by more than the polyhedral approximation allows."""
    v, f = sphere
    mesh = SurfaceMesh(v, f)
    gc = 10.0 * np.arccos(np.clip(v @ v[0] / 100.0, -1, 1))
    d = geodesic_distances(mesh, 0, flow=flow)
    ok = gc > 1.0
    rel = (d[ok] - gc[ok]) / gc[ok]
    assert np.mean(np.abs(rel)) < 0.01
    assert rel.max() < 0.04
    assert rel.min() > -0.002  # chords of a convex polyhedron are slightly short


def test_wider_windows_are_closer_on_a_sphere(sphere):
    v, f = sphere
    mesh = SurfaceMesh(v, f)
    gc = 10.0 * np.arccos(np.clip(v @ v[0] / 100.0, -1, 1))
    ok = gc > 1.0
    err = [np.mean(np.abs(geodesic_distances(mesh, 0, window=w)[ok] - gc[ok]) / gc[ok]) for w in (6, 24)]
    assert err[1] < 0.5 * err[0]


def test_bad_flow(shapes):
    v, f, _ = shapes.grid(5)
    with pytest.raises(MeshError, match="flow"):
        geodesic_distances(SurfaceMesh(v, f), 0, flow="euler")


def test_auto_window_spans_a_length(shapes):
    """The automatic window is a length: finer meshes get more samples."""
    from patternbridge.geodesic.propagate import WINDOW_CM, auto_window

    coarse = SurfaceMesh(*shapes.grid(11, size=20.0)[:2])  # 2 cm edges (and diagonals)
    fine = SurfaceMesh(*shapes.grid(81, size=20.0)[:2])
    wc, wf = auto_window(coarse), auto_window(fine)
    assert wf > wc >= 8
    assert wf == int(np.ceil(WINDOW_CM / fine.edge_mean))


# exact polyhedral distances (cm) on D_cartoon_child.obj from the back neck point
# (vertex 857), by pygeodesic's MMP, to 40 vertices drawn with seed 11
EXACT_D_FROM_857 = {
    380: 18.6471, 957: 14.1225, 1754: 25.3648, 1772: 24.5312, 1823: 23.6252,
    1883: 23.7126, 1985: 55.2544, 2012: 55.1666, 3339: 27.2529, 3706: 19.3422,
    4669: 69.8266, 4947: 98.8709, 5374: 16.4547, 5941: 97.0060, 6148: 95.9227,
    6487: 97.5471, 6667: 96.7967, 6838: 23.1816, 6857: 23.1922, 7249: 19.2668,
    7315: 21.2416, 7347: 21.6761, 7902: 24.7473, 8054: 19.4778, 8342: 18.1344,
    8890: 57.4109, 8995: 53.1973, 9531: 57.8388, 10099: 32.7385, 10556: 41.2156,
    10653: 30.9131, 10942: 47.0140, 11241: 64.4017, 11453: 82.8059, 11613: 98.3670,
    12400: 96.9920, 12596: 97.1067, 12672: 96.1345, 13086: 98.5509, 13294: 96.7825,
}  # fmt: skip


@pytest.mark.shared
def test_character_distances_within_one_percent(characters_dir):
    """On the shared child (the finest of the six 13K-vertex characters), the
    windowed distances from the back neck point agree with exact MMP distances
    within 1 % on average, and no more than 3 % off at any of 40 vertices
    (head, hands and feet included)."""
    import trimesh

    m = trimesh.load(characters_dir / "D_cartoon_child.obj", process=False)
    mesh = SurfaceMesh(np.asarray(m.vertices), np.asarray(m.faces))
    d = geodesic_distances(mesh, 857)
    assert np.all(np.isfinite(d)) and d[857] == 0.0
    ids = np.array(list(EXACT_D_FROM_857))
    exact = np.array(list(EXACT_D_FROM_857.values()))
    rel = (d[ids] - exact) / exact
    assert np.mean(np.abs(rel)) < 0.01
    assert np.all(np.abs(rel) < 0.03)


def test_dropping_finished_windows_changes_nothing(sphere, monkeypatch):
    """Windows of vertices that can no longer be parents are dropped when the
    buffer fills: with a tiny buffer (many drops) the distances are the same
    to the last bit."""
    from patternbridge.geodesic import propagate

    v, f = sphere
    mesh = SurfaceMesh(v, f)
    ref = geodesic_distances(mesh, 0, window=9)
    monkeypatch.setattr(propagate, "_ROWS_MIN", 50)
    np.testing.assert_array_equal(geodesic_distances(SurfaceMesh(v, f), 0, window=9), ref)


def test_cylinder_helices_and_the_cut_locus(shapes):
    """On an open cylinder (unrolls to a plane: the geodesic is the shorter
    helix) the two sides of the wavefront meet on the far line. The diagonals
    of the triangulation all lean one way, so one side advances faster in
    rings; the radius limit follows the slower side, so neither runs past the
    meeting line (a limit that only grows band by band let it: 45 % errors)."""
    v, f, idx = shapes.cylinder(radius=5.0, height=20.0, n_around=48, n_up=25)
    src = int(idx[0, 0])
    d = geodesic_distances(SurfaceMesh(v, f), src)
    ang = np.abs(np.angle(np.exp(1j * np.arctan2(v[:, 1], v[:, 0]))))
    # exact on the 48-gon prism: the arc measured along its chords
    exact = np.hypot(5.0 * ang * np.sin(np.pi / 48) / (np.pi / 48), v[:, 2])
    ok = exact > 1.0
    rel = (d[ok] - exact[ok]) / exact[ok]
    assert np.mean(np.abs(rel)) < 0.01
    assert rel.max() < 0.06 and rel.min() > -0.005


def test_banded_fallback_when_cholesky_refuses(monkeypatch):
    """If the banded Cholesky reports a matrix that is not definite, the same
    system goes through the general banded solver: same answer."""
    from patternbridge.geodesic import propagate
    from patternbridge.geodesic.flow import lsq_step

    pts, nrm, free = _random_windows(2, 2, 9)
    monkeypatch.setattr(propagate, "_pbsv", lambda *a, **k: (None, None, 1))
    out = solve_windows(pts, nrm, pts, free)
    for b in range(2):
        np.testing.assert_allclose(out[b], lsq_step(pts[b], nrm[b], pts[b]), atol=1e-8)


def test_banded_fallback_solves_the_matrix_the_cholesky_refused():
    """A real refusal (tangent columns longer than 1 make the matrix
    indefinite): the general banded solver gets the matrix itself, not what a
    failed factorisation left of it, and solves it as a dense solve does."""
    from patternbridge.geodesic import propagate

    pts, nrm, free = _random_windows(5, 3, 8)
    t1, t2 = propagate._tangent_bases(nrm)
    S = pts.shape[0] * pts.shape[1]
    T = 1.8 * np.stack([t1, t2], axis=-1).reshape(S, 3, 2)
    fr = free.reshape(S)
    base = pts.reshape(S, 3)
    # the same system written densely
    M = np.diag(np.repeat(np.where(fr, 2.0, 1.0), 2))
    for s in range(S - 1):
        if fr[s] and fr[s + 1]:
            C = T[s].T @ T[s + 1]  # C[a, b] = t_{s,a} . t_{s+1,b}
            M[2 * s : 2 * s + 2, 2 * s + 2 : 2 * s + 4] = -C
            M[2 * s + 2 : 2 * s + 4, 2 * s : 2 * s + 2] = -C.T
    lap = np.zeros((S, 3))
    lap[1:-1] = base[:-2] + base[2:] - 2.0 * base[1:-1]
    rhs = np.einsum("ski,sk->si", T, lap) * fr[:, None]
    assert np.linalg.eigvalsh(M).min() < 0  # Cholesky must refuse
    u = np.linalg.solve(M, rhs.ravel()).reshape(S, 2)
    want = base + np.einsum("ski,si->sk", T, u)
    np.testing.assert_allclose(propagate._solve_stack(base, T, fr), want, rtol=1e-9, atol=1e-9)
