"""Self-crossing: where a garment piece passes through itself."""

import numpy as np

from patternbridge.assemble.selfcross import keep_uncrossed, self_crossing


def _grid(nx: int, ny: int, size: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
    """A flat nx × ny grid of squares in the xy plane, two triangles each."""
    xs, ys = np.meshgrid(np.arange(nx + 1) * size, np.arange(ny + 1) * size)
    v = np.stack([xs.ravel(), ys.ravel(), np.zeros(xs.size)], axis=1)
    i = np.arange(nx)[None, :] + (nx + 1) * np.arange(ny)[:, None]
    a, b, c, d = i.ravel(), i.ravel() + 1, i.ravel() + nx + 2, i.ravel() + nx + 1
    return v, np.concatenate([np.stack([a, b, c], 1), np.stack([a, c, d], 1)])


def test_a_flat_sheet_and_a_clean_fold_do_not_cross():
    # (edges lying in the plane of other triangles: the ray caster's grazing hits must not count)
    v, f = _grid(6, 6)
    assert not self_crossing(v, f, np.zeros(len(f), int)).any()
    # folded in two along x = 3, the halves 0.5 apart: a fold, not a crossing
    folded = v.copy()
    right = v[:, 0] > 3
    folded[right, 0] = 6 - v[right, 0]
    folded[right, 2] = 0.5 * (v[right, 0] - 3) / 3
    assert not self_crossing(folded, f, np.zeros(len(f), int)).any()


def test_a_piece_pushed_through_itself_is_found_and_only_where_it_crosses():
    # a strip bent so that its far end comes back down through its near half
    v, f = _grid(8, 2)
    s = v[:, 0]
    bent = v.copy()
    far = s > 4
    # the far half turns back over the near half at x = 4 and dives through it at x = 2.5
    bent[far, 0] = 4 - (s[far] - 4) * 0.9
    bent[far, 2] = 1.0 - (s[far] - 4) * 0.6
    crossed = self_crossing(bent, f, np.zeros(len(f), int))
    assert crossed.any()
    centroids = bent[f].mean(axis=1)
    # the crossing triangles lie where the diving end meets the near half, not by the turn
    assert np.all(np.abs(centroids[crossed, 0] - 2.5) < 0.5)
    # the same two layers as two pieces: cloth of two pieces lying through
    # each other is not a piece passing through itself
    near_half = v[f, 0].mean(axis=1) < 4
    assert not self_crossing(bent, f, np.where(near_half, 0, 1)).any()


def test_triangles_sharing_a_vertex_never_count():
    # a fan of triangles round one vertex, folded sharply: they touch at the centre only
    centre = np.zeros((1, 3))
    ring = np.array([[np.cos(t), np.sin(t), 0.3 * np.cos(3 * t)] for t in np.linspace(0, 2 * np.pi, 9)[:-1]])
    v = np.concatenate([centre, ring])
    f = np.array([[0, 1 + k, 1 + (k + 1) % 8] for k in range(8)])
    assert not self_crossing(v, f, np.zeros(len(f), int)).any()


def _one_triangle_and_a_vertex(start, end):
    tri = np.array([[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0]])
    x0 = np.concatenate([tri, [start]])
    x = np.concatenate([tri, [end]])
    return x0, x, np.array([[0, 1, 2]])


def test_a_vertex_through_a_triangle_goes_back_to_its_side_at_the_thickness():
    from patternbridge.assemble.selfcross import keep_sides

    x0, x, f = _one_triangle_and_a_vertex([0.5, 0.5, 0.5], [0.5, 0.5, -0.4])
    out = keep_sides(x, x0, f, np.arange(4), 0.35)
    # the vertex and the triangle share the move: the vertex rises, the corners sink
    assert out[3, 2] > 0 and np.all(out[:3, 2] <= 0) and out[:3, 2].min() < 0
    # at the vertex's foot the cloth now lies the thickness below it
    foot = out[0] + (out[1] - out[0]) * 0.25 + (out[2] - out[0]) * 0.25  # barycentric (0.5, 0.25, 0.25)
    assert abs((out[3] - foot)[2] - 0.35) < 1e-9
    # the same move from below is held below
    x0, x, f = _one_triangle_and_a_vertex([0.5, 0.5, -0.5], [0.5, 0.5, 0.4])
    assert keep_sides(x, x0, f, np.arange(4), 0.35)[3, 2] < 0


def test_keep_sides_leaves_far_vertices_sewn_vertices_and_free_edges_alone():
    from patternbridge.assemble.selfcross import keep_sides

    # farther than the thickness, on its side: nothing moves
    x0, x, f = _one_triangle_and_a_vertex([0.5, 0.5, 0.8], [0.5, 0.5, 0.5])
    np.testing.assert_array_equal(keep_sides(x, x0, f, np.arange(4), 0.35), x)
    # sewn to a corner (one weld group): a seam closing is not a layer passing through
    x0, x, f = _one_triangle_and_a_vertex([0.5, 0.5, 0.5], [0.5, 0.5, -0.4])
    np.testing.assert_array_equal(keep_sides(x, x0, f, np.array([0, 1, 2, 0]), 0.35), x)
    # coming round the triangle's free edge (outside it at the start): a fold turning over, not a crossing
    x0, x, f = _one_triangle_and_a_vertex([2.5, 0.5, 0.3], [0.5, 0.5, -0.3])
    np.testing.assert_array_equal(keep_sides(x, x0, f, np.arange(4), 0.35), x)


def _sheet_and_spike(dz: float = 0.0):
    """A triangle in the xy plane (vertices 0-2) and a spike (3-5) standing over its middle, ``dz`` lower."""
    v = np.array(
        [[-4, -4, 0], [4, -4, 0], [0, 4, 0], [0, 0, 1], [1, 0, 1], [0, 1, 3]],
        dtype=float,
    )
    v[3:, 2] -= dz
    return v, np.array([[0, 1, 2], [3, 4, 5]])


def test_vertices_sewn_together_count_as_one():
    # the spike pushed 2 cm down cuts the sheet with its two edges to its
    # top (5); if the top is labelled one with a sheet corner (they are
    # sewn), the triangles meet there and the crossing does not count
    v, f = _sheet_and_spike(2.0)
    one_piece = np.zeros(2, int)
    np.testing.assert_array_equal(self_crossing(v, f, one_piece), [True, True])
    same = np.array([0, 1, 2, 3, 4, 0])
    assert not self_crossing(v, f, one_piece, same).any()


def test_a_triangle_pushed_through_its_piece_goes_back_and_other_pieces_and_old_crossings_are_left():
    # piece 0: the spike is pushed down through the sheet in the step (sent
    # back); piece 1: the same motion far away, across already at the start
    # (left to move); piece 2: one triangle of its own moves through piece
    # 0's sheet (not this guard's business)
    a0, f = _sheet_and_spike(0.0)
    b0, _ = _sheet_and_spike(2.0)
    b0[:, 0] += 50.0
    c0 = np.array([[-1, -1, 0.5], [1, -1, 0.5], [0, -0.5, 2.0]])
    x0 = np.concatenate([a0, b0, c0])
    faces = np.concatenate([f, f + 6, [[12, 13, 14]]])
    group = np.array([0, 0, 1, 1, 2])
    same = np.arange(len(x0))
    crossed0 = self_crossing(x0, faces, group, same)
    np.testing.assert_array_equal(crossed0, [False, False, True, True, False])
    x = x0.copy()
    x[3:6, 2] -= 2.0
    x[9:12, 2] -= 0.5
    x[12:15, 2] -= 1.0
    out, crossed = keep_uncrossed(x, x0, faces, group, same, crossed0)
    np.testing.assert_array_equal(out[:6], x0[:6])
    np.testing.assert_array_equal(out[6:], x[6:])
    np.testing.assert_array_equal(crossed, [False, False, True, True, False])
    # the spike's top sewn to piece 2 (one label): the seam moves it, the
    # rest of the spike goes back
    same[5] = 14
    out, _ = keep_uncrossed(x, x0, faces, group, same, crossed0)
    np.testing.assert_array_equal(out[[3, 4]], x0[[3, 4]])
    np.testing.assert_array_equal(out[5], x[5])
