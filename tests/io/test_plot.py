"""Pattern pictures: real images, pieces never overlap, labels and sizes shown."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from patternbridge.errors import InputError
from patternbridge.io.plot import layout_offsets, plot_overlay, plot_pattern
from patternbridge.pattern.grading import grade
from patternbridge.testing import example_pattern

SHARED_AAMA = Path(__file__).resolve().parents[2] / ".." / "shared" / "aama"


@pytest.fixture(scope="module")
def pattern():
    return example_pattern()


def _overlaps(boxes: np.ndarray) -> bool:
    lo, hi = boxes[:, :2], boxes[:, 2:]
    for i in range(len(boxes)):
        for j in range(i + 1, len(boxes)):
            if np.all(lo[i] < hi[j] - 1e-9) and np.all(lo[j] < hi[i] - 1e-9):
                return True
    return False


@settings(max_examples=60, deadline=None)
@given(
    sizes=st.lists(
        st.tuples(st.floats(0.5, 120), st.floats(0.5, 120)), min_size=1, max_size=25
    ),
    origin=st.tuples(st.floats(-500, 500), st.floats(-500, 500)),
)
def test_layout_never_overlaps(sizes, origin):
    wh = np.array(sizes)
    boxes = np.hstack(
        [np.tile(origin, (len(wh), 1)), np.tile(origin, (len(wh), 1)) + wh]
    )
    moved = boxes + np.tile(layout_offsets(boxes), 2)
    assert not _overlaps(moved)
    np.testing.assert_allclose(moved[:, 2:] - moved[:, :2], wh)  # translation only
    assert moved[:, 0].min() == pytest.approx(0, abs=1e-9) and moved[
        :, 1
    ].min() == pytest.approx(0, abs=1e-9)


def test_layout_is_compact_for_equal_boxes():
    boxes = np.tile([0.0, 0.0, 10.0, 10.0], (9, 1))
    moved = boxes + np.tile(layout_offsets(boxes, gap=0.0, aspect=1.0), 2)
    assert np.ptp(moved[:, [0, 2]]) == pytest.approx(30) and np.ptp(
        moved[:, [1, 3]]
    ) == pytest.approx(30)


def test_png_is_an_image(pattern, tmp_path):
    from PIL import Image

    out = plot_pattern(pattern, tmp_path / "tee.png")
    with Image.open(out) as img:
        assert img.format == "PNG"
        w, h = img.size
        assert w >= 1200 and 0.3 < h / w < 2.5
        pixels = np.asarray(img.convert("RGB"), dtype=float)
    # something is drawn: paper-coloured fill and dark outlines
    assert (pixels.std(axis=(0, 1)) > 10).all()
    assert [p.name for p in tmp_path.iterdir()] == [
        "tee.png"
    ]  # no temporary left behind


def test_svg_has_every_label_and_element(pattern, tmp_path):
    svg = plot_pattern(pattern, tmp_path / "tee.svg").read_text(encoding="utf-8")
    assert svg.lstrip().startswith("<?xml") and "</svg>" in svg
    for name in ("FRONT", "BACK", "SLEEVE"):
        assert name in svg
    assert "cut 2 (1 R + 1 L)" in svg and "cut 1" in svg
    assert "FOLD" in svg  # the back is cut on the fold
    assert "EXAMPLE TEE" in svg
    assert "<dc:date>" not in svg  # reproducible output


def test_all_sizes_overlay_draws_each_size(pattern, tmp_path):
    one = plot_pattern(pattern, tmp_path / "one.svg").read_text(encoding="utf-8")
    every = plot_pattern(pattern, tmp_path / "all.svg", sizes="all").read_text(
        encoding="utf-8"
    )
    for size in ("S", "M (sample)", "L", "XL"):
        assert f">{size}<" in every or f"{size}" in re.sub(r"<[^>]+>", " ", every)
    assert every.count("<path") > one.count("<path") + 3 * len(pattern.pieces)
    listed = plot_pattern(pattern, tmp_path / "sl.svg", sizes=["S", "L"]).read_text(
        encoding="utf-8"
    )
    assert "sizes S, L" in listed


def test_bad_picture_requests_write_nothing(pattern, tmp_path):
    with pytest.raises(InputError, match="unknown picture type"):
        plot_pattern(pattern, tmp_path / "tee.gif")
    with pytest.raises(InputError, match="XXL"):
        plot_pattern(pattern, tmp_path / "tee.png", sizes="XXL")
    assert list(tmp_path.iterdir()) == []


def test_overlay_labels_area_change(pattern, tmp_path):
    graded = grade(pattern, "XL").pieces
    svg = plot_overlay(
        pattern.pieces, graded, tmp_path / "ov.svg", labels=("M", "XL")
    ).read_text(encoding="utf-8")
    text = re.sub(r"<[^>]+>", " ", svg)
    assert "Δarea +0.0 cm²" in text  # the sleeve has no rules
    assert len(re.findall(r"Δarea \+\d+\.\d cm²", text)) == 3
    with pytest.raises(ValueError, match="2 graded pieces"):
        plot_overlay(pattern.pieces, graded[:2], tmp_path / "bad.svg")


@pytest.mark.shared
def test_real_nest_plot(tmp_path):
    from PIL import Image

    from patternbridge.io.dxf_aama import read_dxf

    src = SHARED_AAMA / "GLX4802S19_AAMA.DXF"
    if not src.is_file():
        pytest.skip("../shared/aama is not beside the checkout")
    pattern, _ = read_dxf(src)
    out = plot_pattern(pattern, tmp_path / "glx.png", sizes="all")
    with Image.open(out) as img:
        assert img.size[0] >= 1200
