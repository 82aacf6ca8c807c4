"""Bands sewn along openings of several ranges (``bridge.band_spans``) on the real files of ../shared/aama."""

from __future__ import annotations

import json

import numpy as np
import pytest

from patternbridge.bridge import infer_bridge
from patternbridge.bridge.sidecar import inference_sidecar
from patternbridge.io.dxf_aama import read_dxf
from patternbridge.library.seams import range_indices, sew_line
from patternbridge.library.sidecar import apply_sidecar
from patternbridge.pattern.insert import insert_vertices
from patternbridge.pattern.model import Piece

pytestmark = pytest.mark.shared

#: garments whose bands bind openings of several ranges (necklines of front and back, armholes)
BANDED = ["simple.DXF", "GLX0924S16_NEW.DXF", "GLX0926S16.DXF", "MEN CLASSIC TEE.DXF", "GMH1004F15-2.DXF"]


def _length(piece, start: str, end: str) -> float:
    pts = sew_line(piece)[0]
    idx = range_indices(piece, start, end)
    return float(np.linalg.norm(np.diff(pts[idx], axis=0), axis=1).sum())


@pytest.fixture(scope="module", params=BANDED)
def applied(request, aama_dir, tmp_path_factory):
    pattern, _ = read_dxf(aama_dir / request.param)
    inference = infer_bridge(pattern)
    path = tmp_path_factory.mktemp("bands") / "garment.seams.json"
    data = inference_sidecar(pattern, inference)
    path.write_text(json.dumps(data))
    return pattern, inference, data, apply_sidecar(pattern, path)


def test_every_band_is_sewn_range_by_range_in_proportion(applied):
    """No band entry is left for a person; each band part is its opening range times one ratio per band copy."""
    _, inference, data, out = applied
    assert not [s["id"] for s in data["seams"] if s["status"] == "band"]
    bands = {j.b.piece for j in inference.joins if j.kind == "band"}
    assert bands
    for band in bands:
        seams = [s for s in out.seams if s.b.piece == band and s.a.piece != band]
        assert len(seams) >= 2, band
        for copy in {s.b.copy for s in seams}:
            ratios = [
                _length(out.piece(band), s.b.start, s.b.end) / _length(out.piece(s.a.piece), s.a.start, s.a.end)
                for s in seams
                if s.b.copy == copy
            ]
            # a strip applied flat is sewn at its own length (ratio 1), a loop eased or stretched evenly
            np.testing.assert_allclose(ratios, ratios[0], rtol=0.01, err_msg=band)
            assert 0.75 <= ratios[0] <= 1.06, (band, ratios)


def test_each_copy_of_an_opening_range_is_bound_once(applied):
    """In the garment (its default pieces), a range bound by a band is sewn once on each copy, never twice."""
    _, inference, _, out = applied
    bands = {j.b.piece for j in inference.joins if j.kind == "band"} & set(inference.chosen)
    bound = [
        (s.a.piece, s.a.start, s.a.end, s.a.copy) for s in out.seams if s.b.piece in bands and s.a.piece not in bands
    ]
    assert len(bound) == len(set(bound))


def test_band_parts_of_one_copy_do_not_overlap(applied):
    """The ranges a band copy sews are disjoint stretches of its edge (each band vertex range used once)."""
    _, inference, _, out = applied
    for band in {j.b.piece for j in inference.joins if j.kind == "band"}:
        piece = out.piece(band)
        for copy in ("primary", "mirror"):
            used: list[int] = []
            for s in out.seams:
                if s.b.piece == band and s.b.copy == copy and s.a.piece != band:
                    used += range_indices(piece, s.b.start, s.b.end)[:-1].tolist()
            assert len(used) == len(set(used)), (band, copy)


def test_joints_become_vertices_on_the_band_edge_and_the_outline_keeps_its_shape(applied):
    """Inserted joint vertices lie on the band's own edges: same area and perimeter, more vertices."""
    pattern, _, data, out = applied
    inserted = {p["name"]: [m for m in p["marks"].values() if m.get("insert")] for p in data["pieces"]}
    assert any(inserted.values())
    for name, marks in inserted.items():
        before, after = pattern.piece(name).outline, out.piece(name).outline
        assert len(after) == len(before) + len(marks)

        def area(p):
            return 0.5 * abs(np.dot(p[:, 0], np.roll(p[:, 1], -1)) - np.dot(p[:, 1], np.roll(p[:, 0], -1)))

        def perimeter(p):
            return float(np.linalg.norm(np.roll(p, -1, axis=0) - p, axis=1).sum())

        assert area(after) == pytest.approx(area(before), rel=1e-9)
        assert perimeter(after) == pytest.approx(perimeter(before), rel=1e-9)


def test_insert_vertices_keeps_the_sew_line_paired_and_renumbers_marks_and_notches():
    """Two joints on one segment: both sit at their fractions on the cut and the sew line; indices move up."""
    from patternbridge.pattern.model import Notch, Polyline

    outline = np.array([[0.0, 0.0], [10.0, 0.0], [10.0, 3.0], [0.0, 3.0]])
    sew = Polyline(points=[[1.0, 1.0], [9.0, 1.0], [9.0, 2.0], [1.0, 2.0]], closed=True)
    piece = Piece(name="band", outline=outline, sew_lines=(sew,), marks={"c": 2}, notches=(Notch(vertex=3),))
    out, index = insert_vertices(piece, [(0, 0.75), (0, 0.25), (2, 0.5)])
    np.testing.assert_allclose(out.outline[1:3], [[2.5, 0.0], [7.5, 0.0]])
    np.testing.assert_allclose(out.sew_lines[0].points[1:3], [[3.0, 1.0], [7.0, 1.0]])
    np.testing.assert_allclose(out.outline[5], [5.0, 3.0])
    assert index.tolist() == [0, 3, 4, 6]
    assert out.marks == {"c": 4} and out.notches[0].vertex == 6
    assert out.rules is None or out.rules[1] is None
