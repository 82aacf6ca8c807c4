"""Vertex attributes every garment export writes, in each file format's convention.

The garment keeps its texture coordinates as pattern coordinates in cm with
+y up (``Garment.uv``). A texture spans one metre of cloth, so the coordinates
written are ``uv / 100``; what changes between formats is where the texture
image's origin is:

============  =====================  =================================
format        origin of the image    written
============  =====================  =================================
OBJ, USD      bottom-left, v up      ``(x / 100, y / 100)``
glTF 2.0      top-left, v down       ``(x / 100, 1 - y / 100)``
============  =====================  =================================

So one texel lands on the same point of the cloth whichever file is opened
(Blender's glTF importer turns ``t`` back into ``1 - t``).

The coordinates are those of the fabric seen from its face side
(:func:`fabric_uv`): the mirrored copy of a pair is the outline turned over,
so its ``x`` is negated and a print reads the right way on both sleeves, not
backwards on one.

Skin weights are written with four slots a vertex; a slot without weight names
joint 0, as the glTF specification asks of unused joint indices.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "SKIN_SLOTS",
    "fabric_uv",
    "skin_slots",
    "texcoords_bottom_left",
    "texcoords_top_left",
    "vertex_normals",
]

SKIN_SLOTS = 4
"""Joint influences written per vertex (glTF's ``JOINTS_0``/``WEIGHTS_0``, UsdSkel's element size)."""


def vertex_normals(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Area-weighted unit vertex normals of a triangle mesh.

    Parameters
    ----------
    vertices : (V, 3) float64
    faces : (F, 3) int64, counter-clockwise seen from the side the normal points to

    Returns
    -------
    (V, 3) float64 unit vectors; +Y for a vertex no triangle uses.
    """
    v = np.asarray(vertices, dtype=np.float64)
    f = np.asarray(faces, dtype=np.int64)
    fn = np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]])
    vn = np.zeros_like(v)
    for k in range(3):
        np.add.at(vn, f[:, k], fn)
    ln = np.linalg.norm(vn, axis=1, keepdims=True)
    return np.where(ln > 0, vn / np.maximum(ln, 1e-30), np.array([0.0, 1.0, 0.0]))


def fabric_uv(uv_cm: np.ndarray, faces: np.ndarray, instance: np.ndarray) -> np.ndarray:
    """Where each garment vertex lies on the fabric, face side up.

    A cut piece is laid face up, so its triangles (counter-clockwise seen from
    outside) wind counter-clockwise in fabric coordinates too. A copy whose
    pattern coordinates wind clockwise is a mirrored copy (the outline turned
    over); its ``x`` is negated.

    Parameters
    ----------
    uv_cm : (N, 2) float64, cm — pattern coordinates of each vertex
    faces : (F, 3) int64, counter-clockwise seen from outside
    instance : (N,) int64 — the cut copy each vertex belongs to

    Returns
    -------
    (N, 2) float64, cm

    Examples
    --------
    >>> uv = np.array([[0.0, 0], [1, 0], [0, 1], [0, 0], [1, 0], [0, 1]])
    >>> fabric_uv(uv, np.array([[0, 1, 2], [3, 5, 4]]), np.array([0, 0, 0, 1, 1, 1]))[:, 0].tolist()
    [0.0, 1.0, 0.0, 0.0, -1.0, 0.0]
    """
    uv = np.array(uv_cm, dtype=np.float64)
    f = np.asarray(faces, dtype=np.int64)
    inst = np.asarray(instance, dtype=np.int64)
    a, b, c = uv[f[:, 0]], uv[f[:, 1]], uv[f[:, 2]]
    area = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
    turned = np.bincount(inst[f[:, 0]], weights=area, minlength=inst.max(initial=-1) + 1) < 0
    flip = turned[inst]
    uv[flip, 0] = 0.0 - uv[flip, 0]  # 0 - x: no negative zeros in the files
    return uv


def texcoords_bottom_left(uv_cm: np.ndarray) -> np.ndarray:
    """(n, 2) texture coordinates for OBJ and USD (origin bottom-left, v up): ``uv / 100``.

    Examples
    --------
    >>> texcoords_bottom_left(np.array([[50.0, 25.0]])).tolist()
    [[0.5, 0.25]]
    """
    return np.asarray(uv_cm, dtype=np.float64) / 100.0


def texcoords_top_left(uv_cm: np.ndarray) -> np.ndarray:
    """(n, 2) texture coordinates for glTF (origin top-left, v down): ``(x / 100, 1 - y / 100)``.

    Examples
    --------
    >>> texcoords_top_left(np.array([[50.0, 25.0]])).tolist()
    [[0.5, 0.75]]
    """
    st = texcoords_bottom_left(uv_cm)
    return np.stack([st[:, 0], 1.0 - st[:, 1]], axis=1)


def skin_slots(joints: np.ndarray, weights: np.ndarray, *, n_slots: int = SKIN_SLOTS) -> tuple[np.ndarray, np.ndarray]:
    """Skin weights as ``n_slots`` joint/weight pairs a vertex, unused slots on joint 0.

    Parameters
    ----------
    joints : (n, k) int64, -1 for an unused slot (k > ``n_slots``: the heaviest
        ``n_slots`` are kept)
    weights : (n, k) float64, rows summing to 1
    n_slots : slots written per vertex

    Returns
    -------
    joints : (n, n_slots) int64 ≥ 0, 0 wherever the weight is 0
    weights : (n, n_slots) float64, rows summing to 1 (a row without weight
        goes wholly to joint 0)

    Examples
    --------
    >>> j, w = skin_slots(np.array([[3, 5, -1]]), np.array([[0.75, 0.0, 0.0]]))
    >>> j.tolist(), w.tolist()
    ([[3, 0, 0, 0]], [[1.0, 0.0, 0.0, 0.0]])
    """
    j = np.asarray(joints, dtype=np.int64)
    w = np.where(j >= 0, np.asarray(weights, dtype=np.float64), 0.0)
    j = np.maximum(j, 0)
    if j.shape[1] > n_slots:
        top = np.argsort(-w, axis=1, kind="stable")[:, :n_slots]
        j = np.take_along_axis(j, top, axis=1)
        w = np.take_along_axis(w, top, axis=1)
    pad = n_slots - j.shape[1]
    j = np.pad(j, ((0, 0), (0, pad)), constant_values=0)
    w = np.pad(w, ((0, 0), (0, pad)), constant_values=0.0)
    total = w.sum(axis=1, keepdims=True)
    w = np.where(total > 0, w / np.where(total > 0, total, 1.0), np.eye(1, n_slots))
    return np.where(w > 0, j, 0), w
