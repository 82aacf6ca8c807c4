"""Every real file survives import -> export (both flavours, sample + RUL and graded nest) -> import.

Within 0.01 mm at every vertex of every size (boundary, internal lines,
cutouts, sew lines, grain line, notches, drill holes), with its piece and
style texts, quantities as written, tolerance text and ATTDEF notch links.
The reference is the first import graded to each size, which reproduces the
file's own nest (``test_dxf_read``); the round trip is graded independently
from what was written.
"""

from __future__ import annotations

import functools
import re
from pathlib import Path

import numpy as np
import pytest

from patternbridge.io.dxf_aama import read_dxf, write_dxf
from patternbridge.pattern.grading import grade
from patternbridge.report import Report

pytestmark = pytest.mark.shared

AAMA = Path(__file__).resolve().parents[2].parent / "shared" / "aama"
FILES = sorted(p.name for p in AAMA.glob("*")) if AAMA.is_dir() else []
FILES = [f for f in FILES if f.lower().endswith(".dxf")]
TOL_CM = 1e-3  # 0.01 mm

FORMS = [("aama", "sample"), ("astm", "sample"), ("aama", "all"), ("astm", "all")]


def element_points(piece) -> dict[str, np.ndarray]:
    """Every point of a piece that a size moves, by element."""
    out = {"outline": piece.outline, "notches": piece.outline[[n.vertex for n in piece.notches]].reshape(-1, 2)}
    for name in ("internal_lines", "cutouts", "sew_lines"):
        for k, poly in enumerate(getattr(piece, name)):
            out[f"{name}[{k}]"] = poly.points
    if piece.grain_line is not None:
        out["grain_line"] = piece.grain_line.points
    out["drill_holes"] = np.array([h.position for h in piece.drill_holes]).reshape(-1, 2)
    return out


@functools.lru_cache(maxsize=2)
def source(name: str):
    """The first import of a real file and its points in every size."""
    pattern, _ = read_dxf(AAMA / name)
    return pattern, sized_points(pattern)


def sized_points(pattern) -> dict[str, dict[str, dict[str, np.ndarray]]]:
    return {size: {p.name: element_points(p) for p in grade(pattern, size).pieces} for size in pattern.sizes}


def worst_deviation(a, b) -> tuple[float, str]:
    """Largest distance (cm) between the same point of two patterns over every size, and where.

    ``a`` and ``b`` are :func:`sized_points` of the two patterns.
    """
    worst, where = 0.0, ""
    for size, pieces in a.items():
        for name, pa in pieces.items():
            pb = b[size][name]
            assert pa.keys() == pb.keys(), (name, size)
            for key, pts in pa.items():
                assert pts.shape == pb[key].shape, (name, size, key)
                d = float(np.max(np.linalg.norm(pts - pb[key], axis=1), initial=0.0))
                if d > worst:
                    worst, where = d, f"{name} size {size} {key}"
    return worst, where


def _export(pattern, tmp_path: Path, flavor: str, form: str) -> tuple[Path, Report]:
    out = tmp_path / f"out_{flavor}_{form}.dxf"
    report = Report()
    rul = out.with_suffix(".rul") if form == "sample" else None
    write_dxf(pattern, out, flavor=flavor, sizes=form, rul_path=rul, report=report)
    return out, report


@pytest.mark.parametrize("flavor, form", FORMS)
@pytest.mark.parametrize("name", FILES)
def test_round_trip_every_vertex_every_size(name, flavor, form, tmp_path):
    original, points = source(name)
    out, report = _export(original, tmp_path, flavor, form)
    back, _ = read_dxf(out)
    assert back.sizes == original.sizes and back.sample_size == original.sample_size
    assert [p.name for p in back.pieces] == [p.name for p in original.pieces]
    worst, where = worst_deviation(points, sized_points(back))
    assert "rule-position-conflict" not in report.codes()
    assert worst <= TOL_CM, f"{worst * 10:.4f} mm at {where}"
    # texts and quantities as written
    for a in original.pieces:
        b = back.piece(a.name)
        assert (b.quantity, b.category, b.annotation, b.fabric) == (a.quantity, a.category, a.annotation, a.fabric)
        assert dict(b.extra_text) == dict(a.extra_text)
        assert [(n.text, n.layer) for n in b.annotations] == [(n.text, n.layer) for n in a.annotations]
        assert [(n.type, n.vertex) for n in b.notches] == [(n.type, n.vertex) for n in a.notches]


def _raw_tags(path: Path) -> list[tuple[int, str]]:
    lines = path.read_bytes().decode("latin-1").replace("\r\n", "\n").split("\n")
    return [(int(c), v.strip()) for c, v in zip(lines[0::2], lines[1::2], strict=False) if c.strip()]



@pytest.mark.parametrize("name", FILES)
def test_quantity_and_tolerance_written_as_they_came(name, tmp_path):
    source_text = (AAMA / name).read_bytes().decode("latin-1")
    source, _ = read_dxf(AAMA / name)
    for flavor in ("aama", "astm"):
        out, _ = _export(source, tmp_path, flavor, "sample")
        text = out.read_text(encoding="ascii")
        for q in set(re.findall(r"Quantity: *(\d+ *, *\d+)", source_text)):  # a R,L pair stays a pair
            assert f"Quantity: {q.replace(' ', '')}" in text
        tolerance = re.search(r"(?:Curve Tolerance|TOLERANCE): *(\S+)", source_text)
        if tolerance:
            key = "TOLERANCE" if flavor == "aama" else "Curve Tolerance"
            assert f"{key}: {tolerance.group(1)}" in text


def _attdefs(path: Path) -> list[tuple[str, str, str, float, float]]:
    """(block size text, piece name, Link text, x, y of 11/21) of every ATTDEF, in file units."""
    tags = _raw_tags(path)
    out, piece, size = [], "", ""
    for k, (code, value) in enumerate(tags):
        if code == 0 and value == "BLOCK":
            piece = size = ""
        if code == 1 and value.upper().startswith("PIECE NAME:"):
            piece = value.split(":", 1)[1].strip()
        if code == 1 and value.upper().startswith("SIZE:"):
            size = value.split(":", 1)[1].strip()
        if code == 0 and value == "ATTDEF":
            ent = {}
            for c, v in tags[k + 1:]:
                if c == 0:
                    break
                ent.setdefault(c, v)
            out.append((size, piece, ent[1], float(ent[11]), float(ent[21])))
    return out


def test_attdef_links_written_back():
    """annotation.DXF's 135 ATTDEF Link:4 records all come back, at the same notch in the same block."""
    pytest.importorskip("numpy")
    source = AAMA / "annotation.DXF"
    links = _attdefs(source)
    assert len(links) == 135
    pattern, _ = read_dxf(source)
    import tempfile

    with tempfile.TemporaryDirectory() as tmp:
        out, _ = _export(pattern, Path(tmp), "astm", "all")
        ours = _attdefs(out)
    index = {}
    for size, piece, text, x, y in ours:
        index.setdefault((size, piece, text), []).append((x, y))
    for size, piece, text, x, y in links:
        cands = np.array(index.get((size, piece, text), [(np.inf, np.inf)]))
        assert np.min(np.hypot(cands[:, 0] - x, cands[:, 1] - y)) <= 0.01, (size, piece, text, x, y)


def test_turn_points_at_grain_line_ends_written_back(tmp_path):
    pattern, _ = read_dxf(AAMA / "GMX1016S18_AAMA.DXF")
    out, _ = _export(pattern, tmp_path, "aama", "sample")
    back_tags = _raw_tags(out)
    points2 = set()
    for k, (code, value) in enumerate(back_tags):
        if code == 0 and value == "POINT" and back_tags[k + 1] == (8, "2"):
            points2.add((back_tags[k + 2][1], back_tags[k + 3][1]))
    for piece in pattern.pieces:
        if piece.grain_line is None:
            continue
        for end in piece.grain_line.points * 10.0:
            assert (f"{end[0]:.4f}", f"{end[1]:.4f}") in points2, piece.name
