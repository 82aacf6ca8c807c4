"""Bands on their openings: a ring sewn to a sloping edge is turned rigidly about its anchor to follow the slope."""

from __future__ import annotations

import numpy as np
import pytest

from patternbridge.assemble.place.openings import MAX_TILT_DEG, opening_slope, tilted_about
from patternbridge.assemble.place.wrap import Cylinder
from patternbridge.pattern.model import BodyPart

R, HEIGHT = 7.0, 4.0  # a collar stand's radius and height, cm


def _ring() -> tuple[np.ndarray, Cylinder]:
    """A band of 5 rows x 36 columns about the vertical axis through the origin; row 0 (its seam side) at height 0."""
    th = np.linspace(-np.pi, np.pi, 36, endpoint=False)
    rows = np.linspace(0.0, HEIGHT, 5)
    t, h = np.meshgrid(th, rows)
    band = np.stack([R * np.sin(t.ravel()), h.ravel(), R * np.cos(t.ravel())], axis=1)  # angle 0 = +z, the front
    cyl = Cylinder(
        part=BodyPart.HEAD,
        center=np.zeros(3),
        axis=np.array([0.0, 1.0, 0.0]),
        e0=np.array([0.0, 0.0, 1.0]),
        e1=np.array([1.0, 0.0, 0.0]),
        radius_cm=R,
        body_radius_cm=R - 1.0,
        h_min=-10.0,
        h_max=10.0,
    )
    return band, cyl


def _turned(x: np.ndarray, pivot: np.ndarray, deg: float) -> np.ndarray:
    """``x`` turned by ``deg`` about the left-right line through ``pivot``, the front (+z) going down."""
    a = np.radians(deg)
    rot = np.array([[1.0, 0.0, 0.0], [0.0, np.cos(a), -np.sin(a)], [0.0, np.sin(a), np.cos(a)]])
    return (x - pivot) @ rot.T + pivot


def test_the_slope_of_a_plane_cut_is_its_first_harmonic():
    th = np.linspace(0, 2 * np.pi, 50, endpoint=False)
    dh = 1.5 - 3.0 * np.cos(th) + 0.5 * np.sin(th)
    np.testing.assert_allclose(opening_slope(th, dh), [-3.0, 0.5], atol=1e-12)


@pytest.mark.parametrize("deg", [10.0, 25.0])
def test_a_band_on_an_edge_tilted_about_its_anchor_is_turned_onto_it(deg):
    band, cyl = _ring()
    seam = np.arange(36)  # row 0
    anchor = 0  # the centre back (angle -π)
    edge = _turned(band, band[anchor], deg)[seam]  # the opening: the band's seam side turned, its front down
    x, turned = tilted_about(band, seam, edge, cyl, band[anchor])
    # the seam side lies on the edge and the whole band is the rigid turn (nothing stretched)
    np.testing.assert_allclose(x[seam], edge, atol=1e-9)
    np.testing.assert_allclose(x, _turned(band, band[anchor], deg), atol=1e-9)
    np.testing.assert_allclose(x[anchor], band[anchor])
    np.testing.assert_allclose(turned.axis, [0.0, np.cos(np.radians(deg)), np.sin(np.radians(deg))], atol=1e-12)
    # the front of its seam side is 2 R sin(deg) lower than the back
    assert x[18, 1] == pytest.approx(-2 * R * np.sin(np.radians(deg)))


def test_a_level_edge_leaves_the_band_and_a_steep_one_is_turned_at_most_the_limit():
    band, cyl = _ring()
    seam = np.arange(36)
    x, _ = tilted_about(band, seam, band[seam] + [0.0, -2.0, 0.0], cyl, band[0])
    assert x is band  # an edge lower all round (not sloping) does not turn it
    steep = _turned(band, band[0], 70.0)[seam]
    x, turned = tilted_about(band, seam, steep, cyl, band[0])
    assert np.degrees(np.arccos(turned.axis @ cyl.axis)) == pytest.approx(MAX_TILT_DEG)
    np.testing.assert_allclose(x, _turned(band, band[0], MAX_TILT_DEG), atol=1e-9)
