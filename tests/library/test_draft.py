"""Drafting primitives: curves, outline walks and seam-allowance offsets."""

from __future__ import annotations

import numpy as np
import pytest
import shapely

from patternbridge.library.blocks import sleeve_cap_controls
from patternbridge.library.draft import (
    OutlineBuilder,
    bezier,
    bezier_length,
    bezier_split,
    insert_at_length,
    offset_outline,
)


def test_bezier_straight_line_is_evenly_sampled():
    pts = bezier((0, 0), (1, 0), (2, 0), (3, 0), 6)
    np.testing.assert_allclose(pts[:, 0], np.linspace(0, 3, 7))
    assert bezier_length(np.array([[0, 0], [1, 0], [2, 0], [3, 0]])) == pytest.approx(
        3.0
    )


def test_bezier_split_keeps_the_curve():
    c = np.array([[0, 0], [1, 3], [4, 3], [5, 0]], float)
    left, right = bezier_split(c, 0.3)
    np.testing.assert_allclose(left[-1], right[0])
    assert bezier_length(left) + bezier_length(right) == pytest.approx(
        bezier_length(c), rel=1e-4
    )


def test_insert_at_length_places_vertex_at_arc_length():
    pts = np.array([[0, 0], [10, 0], [10, 10]], float)
    out, i = insert_at_length(pts, 12.5)
    np.testing.assert_allclose(out[i], [10, 2.5])
    assert len(out) == 4


def test_offset_square_is_mitred():
    sq = np.array([[0, 0], [4, 0], [4, 4], [0, 4]], float)
    cut = offset_outline(sq, np.array([1.0, 2.0, 1.0, 1.0]))
    # edge 1 (right side) has 2 cm: corners move 2 cm right, others 1 cm
    np.testing.assert_allclose(cut, [[-1, -1], [6, -1], [6, 5], [-1, 5]])
    poly_cut, poly_net = shapely.Polygon(cut), shapely.Polygon(sq)
    assert poly_cut.contains(poly_net)


def test_offset_dart_closes_over_the_dart_mouth():
    # a square with a V dart cut into its top edge
    pts = np.array(
        [[0, 0], [10, 0], [10, 10], [6, 10], [5, 4], [4, 10], [0, 10]], float
    )
    cut = offset_outline(pts, np.ones(7), darts=[4])
    np.testing.assert_allclose(
        cut[3:6, 1], 11.0
    )  # straight across the mouth, 1 cm above
    assert shapely.is_simple(shapely.linearrings(cut))


def test_builder_marks_and_rejects_clockwise_walks():
    b = OutlineBuilder()
    b.start((0, 0), "a")
    b.line((0, 5), "b")
    b.line((5, 5), "c")
    with pytest.raises(ValueError, match="counter-clockwise"):
        b.close()
    b = OutlineBuilder()
    b.start((0, 0), "a")
    with pytest.raises(ValueError, match="twice"):
        b.line((1, 0), "a")


def test_builder_bezier_marks_keep_their_index_when_they_move():
    def walk(s):
        b = OutlineBuilder()
        b.start((0, 0), "bottom")
        b.line((10, -5))
        b.line((10, 0), "start")
        b.bezier(
            np.array([[10, 0], [7, 4], [3, 4], [0.5, 0.5]], float),
            "end",
            n=10,
            at=[(s, "notch", True)],
        )
        return b.close()

    one, two = walk(3.0), walk(9.0)
    assert one.marks == two.marks
    assert len(one.points) == len(two.points)
    assert one.length("start", "notch") == pytest.approx(3.0, abs=0.1)
    assert two.length("start", "notch") == pytest.approx(9.0, abs=0.1)


def test_sleeve_cap_hits_the_requested_lengths():
    front, back, h = sleeve_cap_controls(20.0, 25.0, 27.0)
    assert bezier_length(front) == pytest.approx(25.0, abs=1e-3)
    assert bezier_length(back) == pytest.approx(27.0, abs=1e-3)
    assert 5.0 < h < 25.0
    with pytest.raises(ValueError):
        sleeve_cap_controls(20.0, 19.0, 27.0)
