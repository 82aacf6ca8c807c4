"""Self-crossing: where a garment piece passes through itself."""

import numpy as np

from patternbridge.assemble.selfcross import self_crossing


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
    # the same two layers as two pieces: grouped by piece, cloth of two
    # pieces lying through each other is not a piece passing through itself;
    # for the garment (no groups, as the report counts) it is the same crossing
    near_half = v[f, 0].mean(axis=1) < 4
    assert not self_crossing(bent, f, np.where(near_half, 0, 1)).any()
    np.testing.assert_array_equal(self_crossing(bent, f), crossed)


def test_triangles_sharing_a_vertex_never_count():
    # a fan of triangles round one vertex, folded sharply: they touch at the centre only
    centre = np.zeros((1, 3))
    ring = np.array([[np.cos(t), np.sin(t), 0.3 * np.cos(3 * t)] for t in np.linspace(0, 2 * np.pi, 9)[:-1]])
    v = np.concatenate([centre, ring])
    f = np.array([[0, 1 + k, 1 + (k + 1) % 8] for k in range(8)])
    assert not self_crossing(v, f, np.zeros(len(f), int)).any()


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
