"""The self-contact's edge-edge pairs against a brute-force search over every pair of edges."""

from __future__ import annotations

import numpy as np

from patternbridge.assemble.cloth.selfcontact import find_edge_pairs


def _point_segment(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Distance from points ``p`` (..., 3) to the segments ``a``-``b`` (..., 3) and the parameter of the foot."""
    ab = b - a
    t = np.clip(np.einsum("...k,...k->...", p - a, ab) / np.einsum("...k,...k->...", ab, ab), 0.0, 1.0)
    return np.linalg.norm(p - (a + t[..., None] * ab), axis=-1), t


def _brute_force(x: np.ndarray, edges: np.ndarray, i: np.ndarray, j: np.ndarray, n_scan: int = 1001):
    """The distance of the segments ``edges[i]``, ``edges[j]`` and where it is reached on each (s, t): a scan of s."""
    s = np.linspace(0.0, 1.0, n_scan)
    p1, p2 = x[edges[i, 0]], x[edges[i, 1]]
    on_i = p1[:, None] + s[None, :, None] * (p2 - p1)[:, None]
    dist, t = _point_segment(on_i, x[edges[j, 0]][:, None], x[edges[j, 1]][:, None])
    best = np.argmin(dist, axis=1)
    rows = np.arange(len(i))
    return dist[rows, best], s[best], t[rows, best]


def test_edge_pairs_are_those_a_brute_force_search_finds():
    # 120 free segments, all 3 cm long (the search radius then covers every pair), in a 9 cm box, so that many
    # pairs come within the reach near an end of both edges, their midpoints far apart
    rng = np.random.default_rng(7)
    m, reach = 120, 0.9
    d = rng.normal(size=(m, 3))
    centre = rng.uniform(0.0, 9.0, size=(m, 3))
    half = 1.5 * d / np.linalg.norm(d, axis=1, keepdims=True)
    # and, 30 cm away, two edges crossing 0.5 cm apart at 30 degrees near an end of each (at 0.95 of the first
    # and 0.05 of the second): their midpoints are 2.7 cm apart, farther than the reach and one half length
    theta = np.radians(30.0)
    u = np.array([np.cos(theta), np.sin(theta), 0.0])
    cross = np.array([2.85, 0.0, 0.0]) + 30.0
    centre = np.concatenate([centre, [[31.5, 30.0, 30.0], cross + [0.0, 0.0, 0.5] + 1.35 * u]])
    half = np.concatenate([half, [[1.5, 0.0, 0.0], 1.5 * u]])
    m += 2
    x = np.concatenate([centre - half, centre + half])
    edges = np.stack([np.arange(m), np.arange(m) + m], axis=1)
    n = len(x)
    i, j = np.triu_indices(m, k=1)
    far = np.linalg.norm(centre[i] - centre[j], axis=1) > 3.0 + reach + 0.5  # farther apart than the reach
    i, j = i[~far], j[~far]
    dist, s, t = _brute_force(x, edges, i, j)
    inner = (s > 0.01) & (s < 0.99) & (t > 0.01) & (t < 0.99)
    # near at rest: every vertex to itself, and five pairs within reach joined through their first corners
    close = np.flatnonzero((dist < reach - 1e-3) & inner)
    ex = close[rng.choice(len(close), size=5, replace=False)]
    a, b = edges[i[ex], 0], edges[j[ex], 0]
    near = np.unique(np.concatenate([np.arange(n) * (n + 1), a * n + b, b * n + a]))
    got = find_edge_pairs(x, edges, near, reach)
    found = set(zip(got.key // m, got.key % m, strict=True))

    is_near = np.zeros(len(i), dtype=bool)
    is_near[ex] = True
    must = (dist < reach - 1e-3) & inner & ~is_near
    must_not = (dist > reach + 1e-3) | is_near | (s == 0.0) | (s == 1.0) | (t == 0.0) | (t == 1.0)
    assert must.sum() >= 20 and must[-1] and (i[-1], j[-1]) == (m - 2, m - 1)
    assert np.linalg.norm(centre[-1] - centre[-2]) > 1.5 + reach
    assert {(int(a), int(b)) for a, b in zip(i[must], j[must], strict=True)} <= found
    assert not found & {(int(a), int(b)) for a, b in zip(i[must_not], j[must_not], strict=True)}
    assert not found - {(int(a), int(b)) for a, b in zip(i, j, strict=True)}  # none of the far pairs
    # each pair: its edges, and the unit direction from the second edge's closest point to the first's
    np.testing.assert_array_equal(got.edges[:, 0], edges[got.key // m])
    np.testing.assert_array_equal(got.edges[:, 1], edges[got.key % m])
    np.testing.assert_allclose(np.linalg.norm(got.direction, axis=1), 1.0)
    lookup = {(int(a), int(b)): k for k, (a, b) in enumerate(zip(i, j, strict=True))}
    for (a, b), u in zip(zip(got.key // m, got.key % m, strict=True), got.direction, strict=True):
        k = lookup[(int(a), int(b))]
        pi = x[edges[a, 0]] + s[k] * (x[edges[a, 1]] - x[edges[a, 0]])
        qj = x[edges[b, 0]] + t[k] * (x[edges[b, 1]] - x[edges[b, 0]])
        assert np.dot(u, pi - qj) > 0.99 * np.linalg.norm(pi - qj) - 1e-3
