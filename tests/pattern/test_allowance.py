"""The seam allowance is re-added around a graded sew line instead of being stretched with it."""

from __future__ import annotations

import numpy as np
import shapely

from patternbridge.pattern.geometry import carry_allowance


def _mitred(ring: np.ndarray, width: float) -> shapely.Polygon:
    return shapely.Polygon(ring).buffer(width, join_style="mitre", mitre_limit=10.0)


def _hausdorff(points: np.ndarray, polygon: shapely.Polygon) -> float:
    return shapely.hausdorff_distance(shapely.LinearRing(points), polygon.exterior)


def test_rectangle_becomes_a_trapezoid_with_the_same_mitred_allowance():
    sew = np.array([[0.0, 0.0], [20.0, 0.0], [20.0, 40.0], [0.0, 40.0]])
    cut = np.array([[-1.0, -1.0], [21.0, -1.0], [21.0, 41.0], [-1.0, 41.0]])
    new_sew = np.array([[0.0, 0.0], [20.0, 0.0], [25.0, 40.0], [-5.0, 40.0]])
    new_cut = carry_allowance(sew, cut, new_sew)
    # shapely's mitred buffer is the independent reference for a 1 cm allowance
    assert _hausdorff(new_cut, _mitred(new_sew, 1.0)) < 1e-9


def test_curved_piece_keeps_its_allowance_where_a_stretch_would_not():
    angle = np.linspace(0.0, 2 * np.pi, 96, endpoint=False)
    circle = np.stack([np.cos(angle), np.sin(angle)], axis=1)
    sew, cut = 10.0 * circle, 11.0 * circle
    stretch = np.array([1.5, 0.8])
    new_sew = sew * stretch
    new_cut = carry_allowance(sew, cut, new_sew)
    reference = shapely.Polygon(new_sew).buffer(1.0, quad_segs=32)
    assert _hausdorff(new_cut, reference) < 0.02
    assert _hausdorff(cut * stretch, reference) > 0.4  # what moving the cut line with the piece gives


def test_dart_point_takes_the_mapped_cut_line():
    # a waist edge with a dart: the cut line runs straight across the dart, 1 cm above the sew line's rims
    sew = np.array([[0.0, 0.0], [20.0, 0.0], [20.0, 10.0], [11.0, 10.0], [10.0, 2.0], [9.0, 10.0], [0.0, 10.0]])
    cut = np.array([[-1.0, -1.0], [21.0, -1.0], [21.0, 11.0], [11.0, 11.0], [10.0, 11.0], [9.0, 11.0], [-1.0, 11.0]])
    new_sew = sew * np.array([1.2, 1.0])
    mapped = cut * np.array([1.2, 1.0])
    new_cut = carry_allowance(sew, cut, new_sew, mapped)
    np.testing.assert_allclose(new_cut[4], mapped[4])
    assert abs(new_cut[4, 1] - 11.0) < 1e-9  # not dragged down into the dart
    without = carry_allowance(sew, cut, new_sew)
    assert np.allclose(without[[0, 1, 2, 6]], new_cut[[0, 1, 2, 6]])


def test_unchanged_sew_line_gives_the_original_cut_line():
    rng = np.random.default_rng(0)
    angle = np.sort(rng.uniform(0, 2 * np.pi, 40))
    radius = 10 + rng.uniform(-1, 1, 40)
    sew = np.stack([radius * np.cos(angle), radius * np.sin(angle)], axis=1)
    cut = sew * 1.1
    np.testing.assert_allclose(carry_allowance(sew, cut, sew, cut), cut, atol=1e-12)
