"""The software renderer: framing, depth test, polylines, PNG output."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh
from PIL import Image

from patternbridge.mesh.render import render, render_views, save_png


@pytest.fixture(scope="module")
def box():
    m = trimesh.creation.box(extents=(40.0, 100.0, 20.0))
    return np.asarray(m.vertices) + [0, 50, 0], np.asarray(m.faces)


def test_shape_background_and_object(box):
    v, f = box
    img = render(v, f, size=(200, 300))
    assert img.shape == (300, 200, 3) and img.dtype == np.uint8
    assert (img[2, 2] == 255).all()  # background corner
    centre = img[150, 100].astype(int)
    assert centre.max() < 250 and centre[0] > centre[2]  # shaded skin tone


def test_face_colours(box):
    v, f = box
    colours = np.tile(np.array([0, 0, 255], dtype=np.uint8), (len(f), 1))
    img = render(v, f, face_colors=colours, size=(100, 150))
    c = img[75, 50].astype(int)
    assert c[2] > 100 and c[0] < 30 and c[1] < 30


def test_polylines_are_depth_tested(box):
    v, f = box
    front = np.array([[-30.0, 50, 10.5], [30.0, 50, 10.5]])  # on the front face
    back = np.array([[-30.0, 70, -10.5], [30.0, 70, -10.5]])  # behind the box
    img = render(
        v,
        f,
        polylines=[front, back],
        polyline_colors=[(0, 200, 0), (200, 0, 200)],
        size=(200, 300),
    )
    green = (img[:, :, 1] > 150) & (img[:, :, 0] < 80)
    magenta = (img[:, :, 0] > 150) & (img[:, :, 1] < 80) & (img[:, :, 2] > 150)
    assert green.sum() > 50
    # only the parts outside the silhouette of the box are visible
    cols = np.flatnonzero(magenta.any(axis=0))
    assert len(cols) > 0 and not ((cols > 80) & (cols < 120)).any()
    img_b = render(
        v,
        f,
        polylines=[front, back],
        polyline_colors=[(0, 200, 0), (200, 0, 200)],
        size=(200, 300),
        view="back",
    )
    magenta_b = (img_b[:, :, 0] > 150) & (img_b[:, :, 1] < 80) & (img_b[:, :, 2] > 150)
    assert (
        (np.flatnonzero(magenta_b.any(axis=0)) > 80)
        & (np.flatnonzero(magenta_b.any(axis=0)) < 120)
    ).any()


def test_views_and_labels(box, tmp_path):
    v, f = box
    line = np.array([[-20.0, 90, 10.5], [20.0, 90, 10.5]])
    img = render_views(v, f, polylines=[line], labels=["chest 99.9"], size=(150, 200))
    assert img.shape == (200, 450, 3)
    side = render(v, f, view="side", size=(150, 200))
    front = render(v, f, view="front", size=(150, 200))
    # the box is 40 wide and 20 deep: the side silhouette is narrower
    assert (side < 250).any(axis=2).sum() < (front < 250).any(axis=2).sum()
    path = tmp_path / "out" / "pic.png"
    save_png(path, img)
    back = np.asarray(Image.open(path))
    np.testing.assert_array_equal(back, img)
    with pytest.raises(ValueError, match="view"):
        render(v, f, view="above")
