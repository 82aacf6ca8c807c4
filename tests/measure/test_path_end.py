"""A landmark as a geodesic path end: the tape starts where the landmark is, not at its nearest vertex."""

from __future__ import annotations

import numpy as np
import pytest

from patternbridge.geodesic import SurfaceMesh, geodesic_path
from patternbridge.measure.lengths import landmark_path_end
from patternbridge.mesh.character import Landmark


def _plate(n: int = 11, size: float = 20.0):
    """Flat triangulated square [0, size]^2 at z = 0 (2 cm edges): (V, 3), (F, 3)."""
    t = np.linspace(0.0, size, n)
    x, y = np.meshgrid(t, t)
    v = np.c_[x.ravel(), y.ravel(), np.zeros(n * n)]
    idx = np.arange(n * n).reshape(n, n)
    a, b = idx[:-1, :-1].ravel(), idx[:-1, 1:].ravel()
    c, d = idx[1:, :-1].ravel(), idx[1:, 1:].ravel()
    return v, np.r_[np.c_[a, b, d], np.c_[a, d, c]]


def test_a_position_only_landmark_starts_the_tape_at_its_position():
    v, f = _plate()
    at = np.array([9.3, 9.4, 0.0])  # inside a face, 0.92 cm from the nearest vertex (10, 10)
    end, nearest = landmark_path_end(Landmark(name="p", position=at), v, f)
    assert nearest == int(np.argmin(np.linalg.norm(v - at, axis=1)))
    assert end.vertex_id is None
    np.testing.assert_allclose(np.asarray(end.bary) @ v[f[end.face]], at, atol=1e-9)
    # on a plane the geodesic is the straight line from vertex 0 at the origin
    length = geodesic_path(SurfaceMesh(v, f), 0, end, tape=False).length
    assert length == pytest.approx(float(np.hypot(9.3, 9.4)), abs=1e-6)
    snapped = geodesic_path(SurfaceMesh(v, f), 0, nearest, tape=False).length
    assert abs(snapped - length) > 0.3  # the nearest vertex would have moved the tape's end


def test_vertex_and_face_landmarks_are_taken_as_given():
    v, f = _plate()
    end, nearest = landmark_path_end(Landmark(name="v", position=v[17], vertex=17), v, f)
    assert (end.vertex_id, nearest) == (17, 17)
    bary = (0.2, 0.3, 0.5)
    end, nearest = landmark_path_end(Landmark(name="f", position=np.asarray(bary) @ v[f[5]], face=5, bary=bary), v, f)
    assert (end.face, tuple(end.bary)) == (5, bary)
    assert nearest == f[5][2]  # no vertex given: the corner with the largest weight
