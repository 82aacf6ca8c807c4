"""Constraint data of the cloth: stretch, bending and seam springs, and their projective-dynamics operator.

Every spring joins two vertices and wants a target length. In projective
dynamics (Bouaziz et al. 2014) a spring ``(i, j)`` of weight ``w`` adds
``w/2 |(x_i - x_j) - p|²`` to the energy, where the local step sets ``p`` to
the current difference scaled to the target length. The differences of all
springs are one sparse operator ``S`` (M, N); the global matrix
``M/h² + Sᵀ W S`` is constant for a set of weights and is factorised once.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import IntEnum

import numpy as np

__all__ = [
    "SpringKind",
    "Springs",
    "difference_operator",
    "edges_and_bends",
    "gathered_lengths",
    "project_springs",
]


class SpringKind(IntEnum):
    """What a spring holds: a mesh edge, a bending pair, or a sewn pair."""

    STRETCH = 0
    BEND = 1
    SEAM = 2


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class Springs:
    """All springs of a cloth.

    pairs : (M, 2) int64 vertex ids ; kind : (M,) int64 :class:`SpringKind` values ;
    weight : (M,) float64, in units of the mean vertex mass / h²
    """

    pairs: np.ndarray
    kind: np.ndarray
    weight: np.ndarray

    def __post_init__(self) -> None:
        for name, dtype in (("pairs", np.int64), ("kind", np.int64), ("weight", np.float64)):
            a = np.array(getattr(self, name), dtype=dtype)
            a.flags.writeable = False
            object.__setattr__(self, name, a)
        if self.pairs.ndim != 2 or self.pairs.shape[1:] != (2,):
            raise ValueError(f"pairs: expected (M, 2), got {self.pairs.shape}")
        if not (len(self.kind) == len(self.weight) == len(self.pairs)):
            raise ValueError("kind, weight: expected one per pair")

    def of(self, kind: SpringKind) -> np.ndarray:
        """(M,) bool: the springs of ``kind``."""
        return self.kind == int(kind)


def edges_and_bends(faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Unique edges (E, 2) and bending pairs (B, 2) (opposite corners of adjacent triangles) of ``faces`` (F, 3)."""
    faces = np.asarray(faces, dtype=np.int64)
    he = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    opp = np.concatenate([faces[:, 2], faces[:, 0], faces[:, 1]])
    key = np.sort(he, axis=1)
    order = np.lexsort((key[:, 1], key[:, 0]))
    key, opp = key[order], opp[order]
    same = np.all(key[1:] == key[:-1], axis=1)
    edges = np.unique(key, axis=0).reshape(-1, 2)
    bends = np.stack([opp[:-1][same], opp[1:][same]], axis=1).reshape(-1, 2)
    return edges, bends


def gathered_lengths(edges: np.ndarray, rest: np.ndarray, seams: list[tuple[np.ndarray, np.ndarray]]) -> np.ndarray:
    """(E,) stretch-spring lengths with the longer side of every sewn edge pair gathered to the shorter.

    A seam joins two edges of different lengths where one side is eased or
    gathered into the other (a sleeve hem into a narrower cuff, a sleeve
    cap into its armhole). The mesh matches their vertices one to one, so
    each segment of the longer side faces a shorter one: sewn flat, the
    longer side's segment takes the shorter one's length and the cloth
    beside it folds (the gathers). Springs at the pattern lengths on both
    sides would fight the seam springs and hold the seam open by the
    difference.

    Parameters
    ----------
    edges : (E, 2) int64 sorted vertex pairs ; rest : (E,) float64, cm
    seams : per seam the sewn vertices of its two sides, in order (global ids)
    """
    out = np.array(rest, dtype=np.float64)
    if len(edges) == 0:
        return out
    n = int(edges.max()) + 1
    keys = edges[:, 0] * n + edges[:, 1]
    order = np.argsort(keys)
    sorted_keys = keys[order]

    def find(p: np.ndarray, q: np.ndarray) -> np.ndarray:
        k = np.minimum(p, q) * n + np.maximum(p, q)
        pos = np.clip(np.searchsorted(sorted_keys, k), 0, len(keys) - 1)
        return np.where(sorted_keys[pos] == k, order[pos], -1)

    for va, vb in seams:
        if len(va) < 2:
            continue
        ea, eb = find(va[:-1], va[1:]), find(vb[:-1], vb[1:])
        ok = (ea >= 0) & (eb >= 0) & (ea != eb)
        ea, eb = ea[ok], eb[ok]
        short = np.minimum(out[ea], out[eb])
        out[ea] = short
        out[eb] = short
    return out


def difference_operator(n: int, pairs: np.ndarray):
    """The sparse (M, N) operator ``S`` with ``(S x)_k = x[pairs[k, 0]] - x[pairs[k, 1]]`` (scipy CSR)."""
    from scipy.sparse import coo_matrix

    m = len(pairs)
    rows = np.repeat(np.arange(m), 2)
    return coo_matrix((np.tile([1.0, -1.0], m), (rows, np.asarray(pairs).ravel())), shape=(m, n)).tocsr()


def project_springs(d: np.ndarray, targets: np.ndarray) -> np.ndarray:
    """(M, 3) the local step: each difference ``d`` (M, 3) scaled to its target length ``targets`` (M,), cm.

    A spring of target 0 projects to 0; a spring of zero length keeps zero
    (its direction is unknown).
    """
    ln = np.linalg.norm(d, axis=1, keepdims=True)
    return d * (np.asarray(targets)[:, None] / np.maximum(ln, 1e-9))
