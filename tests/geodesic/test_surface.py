"""SurfaceMesh validation, welding, tangent planes and surface points."""

from __future__ import annotations

import numpy as np
import pytest

from patternbridge.errors import MeshError
from patternbridge.geodesic import SurfaceMesh, SurfacePoint


def test_rejects_bad_shapes_and_values(shapes):
    v, f, _ = shapes.grid(5)
    with pytest.raises(MeshError, match="vertices must be"):
        SurfaceMesh(v[:, :2], f)
    with pytest.raises(MeshError, match="faces must be"):
        SurfaceMesh(v, f[:, :2])
    bad = v.copy()
    bad[3, 1] = np.nan
    with pytest.raises(MeshError, match="NaN"):
        SurfaceMesh(bad, f)
    with pytest.raises(MeshError, match="out of range"):
        SurfaceMesh(v, np.r_[f, [[0, 1, 999]]])
    with pytest.raises(MeshError, match="not numeric"):
        SurfaceMesh([["a", "b", "c"]] * 3, f)


def test_rejects_mesh_of_only_zero_area_faces():
    v = np.array([[0.0, 0, 0], [1, 0, 0], [2, 0, 0], [3, 0, 0]])
    with pytest.raises(MeshError, match="zero area"):
        SurfaceMesh(v, [[0, 1, 2], [1, 2, 3]])


def test_surface_point_validation():
    with pytest.raises(MeshError, match="neither a vertex"):
        SurfacePoint()
    with pytest.raises(MeshError, match="barycentric"):
        SurfacePoint(face=0, bary=(0.0, 0.0, 0.0))
    p = SurfacePoint(face=2, bary=(2.0, 1.0, 1.0))
    assert p.bary == (0.5, 0.25, 0.25)
    assert SurfacePoint.vertex(7).vertex_id == 7


def test_check_point_errors_and_snapping(shapes):
    v, f, _ = shapes.grid(5)
    m = SurfaceMesh(v, f)
    with pytest.raises(MeshError, match="vertex 99 out of range"):
        m.check_point(99, "from")
    with pytest.raises(MeshError, match="face 999 out of range"):
        m.check_point(SurfacePoint(face=999, bary=(1, 0, 0)), "to")
    with pytest.raises(MeshError, match="negative"):
        m.check_point(SurfacePoint(face=0, bary=(1.5, -0.5, 0.0)), "to")
    with pytest.raises(MeshError, match="expected a vertex id"):
        m.check_point("x", "to")
    snapped = m.check_point(SurfacePoint(face=0, bary=(0.0, 1.0, 0.0)), "a")
    assert snapped.vertex_id == f[0, 1]


def test_weld_merges_exact_duplicates_only(shapes):
    v, f, idx = shapes.grid(5)
    # split the grid along x = 10: right half uses copies of the seam vertices
    seam = idx[:, 2]
    copies = np.arange(len(v), len(v) + len(seam))
    v2 = np.r_[v, v[seam]]
    f2 = f.copy()
    right = v[f].mean(axis=1)[:, 0] > 10.0
    remap = np.arange(len(v))
    remap[seam] = copies
    f2[right] = remap[f[right]]
    m = SurfaceMesh(v2, f2)
    assert np.array_equal(m.rep[copies], seam)
    assert m.faces.max() < len(v)
    unwelded = SurfaceMesh(v2, f2, weld=False)
    assert unwelded.faces.max() >= len(v)


def test_graph_is_symmetric_edge_lengths(shapes):
    v, f, _ = shapes.grid(6, size=5.0)
    g = SurfaceMesh(v, f).graph
    assert (abs(g - g.T)).max() < 1e-12
    assert g.nnz == 2 * (2 * 5 * 6 + 25)  # horizontal + vertical + diagonal edges
    np.testing.assert_allclose(sorted(set(np.round(g.data, 9))), [1.0, np.sqrt(2.0)])


def test_vertex_normals_by_pca(sphere):
    v, f = sphere
    m = SurfaceMesh(v, f)
    ids = np.arange(0, len(v), 37)
    n = m.vertex_normals(ids)
    radial = v[ids] / np.linalg.norm(v[ids], axis=1)[:, None]
    assert np.all(np.einsum("ij,ij->i", n, radial) > 0.999)
    np.testing.assert_allclose(np.linalg.norm(n, axis=1), 1.0)


def test_vertex_normals_are_kept_and_agree_with_the_full_table(sphere):
    v, f = sphere
    m = SurfaceMesh(v, f)
    first = m.vertex_normals([5, 3, 5, 11])  # repeated ids, any order
    later = m.vertex_normals(np.arange(20))  # part known, part new
    np.testing.assert_array_equal(first, later[[5, 3, 5, 11]])
    full = SurfaceMesh(v, f).all_vertex_normals
    np.testing.assert_allclose(later, full[:20], atol=1e-12)
    np.testing.assert_allclose(m.all_vertex_normals[[5, 3]], first[:2], atol=1e-12)


def test_graph_of_an_open_inconsistently_wound_mesh(shapes):
    """Edge keys pair up only on closed, consistently wound meshes; otherwise
    every edge still appears once in each direction."""
    v, f, _ = shapes.grid(4, size=3.0, jitter=0.0, seed=1)
    f = f.copy()
    f[::3] = f[::3, ::-1]  # flip every third face
    g = SurfaceMesh(v, f).graph
    assert (g != g.T).nnz == 0
    n_edges = len({tuple(sorted(e)) for t in f.tolist() for e in zip(t, t[1:] + t[:1], strict=True)})
    assert g.nnz == 2 * n_edges


def _flipped_open_grid(shapes):
    v, f, _ = shapes.grid(6, size=5.0, jitter=0.3, seed=3)
    f = f.copy()
    f[::3] = f[::3, ::-1]
    return v, f


def test_corners_and_rings_agree_with_the_edge_graph(sphere, shapes):
    """Lazily built corner lists give each vertex's faces and, next and
    previous corners together, exactly the neighbours of the edge graph."""
    for v, f in (sphere, _flipped_open_grid(shapes)):
        m = SurfaceMesh(v, f)
        indptr, cor = m.corners
        owner = np.repeat(np.arange(len(v)), np.diff(indptr))
        assert np.array_equal(m.faces.ravel()[cor], owner)
        vf_ptr, fl = m.vertex_faces
        for i in (0, 7, len(v) // 2, len(v) - 1):
            want = np.flatnonzero((f == i).any(axis=1))
            np.testing.assert_array_equal(fl[vf_ptr[i] : vf_ptr[i + 1]], want)
        g = m.graph
        vids = np.arange(len(v))
        counts, nxt, prv = m.ring_entries(vids)
        owner = np.repeat(vids, counts)
        got = set(zip(owner.tolist(), nxt.tolist(), strict=True))
        got |= set(zip(owner.tolist(), prv.tolist(), strict=True))
        coo = g.tocoo()
        assert got == set(zip(coo.row.tolist(), coo.col.tolist(), strict=True))
        _, nxt2, none = m.ring_entries(vids[::5], prev=False)
        assert none is None
        assert len(nxt2) == np.diff(indptr)[::5].sum()


def test_edge_statistics_match_the_graph(sphere):
    v, f = sphere
    m = SurfaceMesh(v, f)
    g = m.graph  # closed and consistently wound: one entry per half-edge
    assert m.edge_max == pytest.approx(g.data.max(), rel=1e-12)
    assert m.edge_mean == pytest.approx(g.data.mean(), rel=1e-12)


def test_edge_statistics_skip_zero_area_faces():
    v = np.array([[0.0, 0, 0], [3, 0, 0], [0, 4, 0], [6, 0, 0], [9, 0, 0]])
    m = SurfaceMesh(v, [[0, 1, 2], [1, 3, 4]])  # the second face is a sliver
    assert m.edge_max == pytest.approx(5.0)
    assert m.edge_mean == pytest.approx(4.0)


def test_box_vertices_cover_the_box(sphere):
    v, f = sphere
    m = SurfaceMesh(v, f)
    lo, hi = np.array([-3.0, 1.0, -10.0]), np.array([4.0, 10.0, 2.5])
    ids, (x, y, z) = m.box_vertices(lo, hi)
    inside = np.flatnonzero(np.all((v >= lo) & (v <= hi), axis=1))
    assert set(inside.tolist()) <= set(ids.tolist())
    assert len(ids) < len(v)  # a part of the grid only
    np.testing.assert_array_equal(np.c_[x, y, z], v[ids])
    # a cell test that drops every cell
    none, _ = m.box_vertices(lo, hi, lambda c, margin: np.zeros(len(c), dtype=bool))
    assert len(none) == 0
    far, _ = m.box_vertices(lo + 100.0, hi + 100.0)
    assert not np.any(np.all((v[far] >= lo + 100.0) & (v[far] <= hi + 100.0), axis=1))


def test_vertex_normals_of_vertices_without_faces_are_up():
    v = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [5, 5, 5], [0, -1, 0.3]])
    f = [[0, 1, 2], [0, 4, 1]]
    m = SurfaceMesh(v, f)
    n = m.vertex_normals([3, 2, 3])  # a lonely vertex first and last
    np.testing.assert_allclose(n[[0, 2]], [[0, 0, 1], [0, 0, 1]])
    np.testing.assert_allclose(n[1], [0, 0, 1], atol=1e-12)
    # a vertex with two faces right before a lonely one keeps both faces
    both = SurfaceMesh(v, f).vertex_normals([0, 3])[0]
    alone = SurfaceMesh(v, f).vertex_normals([0])[0]
    np.testing.assert_allclose(both, alone, atol=1e-12)
    assert 0.0 < both[1] < both[2]  # between the two face normals


def test_face_normals_table_and_rows_agree(sphere):
    v, f = sphere
    m = SurfaceMesh(v, f)
    ids = np.array([0, 5, 5, len(f) - 1])
    rows = m.normals_of(ids)  # from the columns, before any (F, 3) table
    n = np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]])
    n /= np.linalg.norm(n, axis=1)[:, None]
    np.testing.assert_allclose(m.face_normals, n, atol=1e-12)
    np.testing.assert_array_equal(rows, m.face_normals[ids])
    np.testing.assert_array_equal(m.normals_of(ids), rows)  # from the table
    with pytest.raises(ValueError):
        m.face_normals[0, 0] = 1.0
    sliver = SurfaceMesh([[0.0, 0, 0], [1, 0, 0], [2, 0, 0], [0, 1, 0]], [[0, 1, 2], [0, 1, 3]])
    np.testing.assert_array_equal(sliver.face_normals[0], 0.0)
    assert sliver.degenerate.tolist() == [True, False]


def test_corner_lists_without_packed_keys(sphere, shapes, monkeypatch):
    """Meshes too large to pack the next vertex into the sort key (over about
    a million vertices) get the same corner lists the other way."""
    from patternbridge.geodesic import surface

    for v, f in (sphere, _flipped_open_grid(shapes)):
        packed = SurfaceMesh(v, f)
        monkeypatch.setattr(surface, "_PACK_BITS", 0)
        split = SurfaceMesh(v, f)
        np.testing.assert_array_equal(split.corners[0], packed.corners[0])
        np.testing.assert_array_equal(split.corners[1], packed.corners[1])
        np.testing.assert_array_equal(split.corner_next, packed.corner_next)
        monkeypatch.setattr(surface, "_PACK_BITS", 63)


def test_ring_entry_lengths_are_the_edge_lengths(sphere, shapes):
    for v, f in (sphere, _flipped_open_grid(shapes)):
        m = SurfaceMesh(v, f)
        vids = np.arange(len(v))
        counts, nxt, length = m.ring_entries(vids, lengths=True)
        owner = np.repeat(vids, counts)
        want = np.sqrt(((v[owner] - v[nxt]) ** 2).sum(axis=1))
        np.testing.assert_allclose(length, want, rtol=1e-15, atol=0)
        # the side table recomputed from scratch gives the same corner lengths
        again = SurfaceMesh(v, f)
        again._cache.pop("sides")
        np.testing.assert_array_equal(again.ring_entries(vids, lengths=True)[2], length)
