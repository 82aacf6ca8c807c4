"""Suspicious but usable real files: a warning with its evidence, and the pattern still read."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from patternbridge.io.dxf_aama import read_dxf

_COORD = re.compile(r"^( *(?:10|20|11|21)\r?\n)(-?[0-9.]+)(\r?)$", re.MULTILINE)


def _scaled(src: Path, dst: Path, factor: float) -> Path:
    """``src`` with every x/y coordinate multiplied by ``factor`` (a drawing to scale)."""
    text = src.read_bytes().decode("latin-1")
    text = _COORD.sub(lambda m: f"{m.group(1)}{float(m.group(2)) * factor:.6f}{m.group(3)}", text)
    dst.write_bytes(text.encode("latin-1"))
    return dst


@pytest.mark.shared
def test_real_files_read_at_garment_scale(aama_dir):
    for path in sorted(aama_dir.glob("*.[dD][xX][fF]")):
        _, report = read_dxf(path)
        assert "units-implausible" not in report.codes(), path.name


@pytest.mark.shared
def test_clo_shirt_at_a_tenth_is_too_small(aama_dir, tmp_path):
    path = _scaled(aama_dir / "clo-pattern.dxf", tmp_path / "shirt-tenth.dxf", 0.1)
    pattern, report = read_dxf(path)
    finding = next(f for f in report if f.code == "units-implausible")
    assert "7.3 cm" in finding.message and "too small" in finding.message  # the back is 72.9 cm long
    assert "--units ENGLISH" in finding.message
    assert len(pattern.pieces) == 9


@pytest.mark.shared
def test_mm_file_read_as_inches_is_too_large_and_metric_is_suggested(aama_dir):
    _, report = read_dxf(aama_dir / "clo-pattern.dxf", units="ENGLISH")
    finding = next(f for f in report if f.code == "units-implausible")
    assert "1851.7 cm" in finding.message and "too large" in finding.message
    assert "--units METRIC" in finding.message and "72.9 cm" in finding.message


def test_a_box_of_6_square_metres_is_too_large(tmp_path):
    # a 118 x 79 box labelled ENGLISH, as CLO 4.0 wrote clo-box.dxf: 3.0 x 2.0 m when read as inches
    tags = ["0", "SECTION", "2", "BLOCKS", "0", "BLOCK", "8", "0", "2", "BOX_M", "70", "64", "10", "0", "20", "0",
            "0", "TEXT", "8", "1", "10", "0", "20", "0", "1", "Piece Name: BOX",
            "0", "TEXT", "8", "1", "10", "0", "20", "0", "1", "Size: M",
            "0", "POLYLINE", "8", "1", "66", "1", "70", "1"]
    for x, y in [(0, 0), (118, 0), (118, 79), (0, 79)]:
        tags += ["0", "VERTEX", "8", "1", "10", str(x), "20", str(y)]
    tags += ["0", "SEQEND", "0", "ENDBLK", "0", "ENDSEC", "0", "SECTION", "2", "ENTITIES",
             "0", "TEXT", "8", "1", "10", "0", "20", "0", "1", "Units: ENGLISH",
             "0", "INSERT", "8", "1", "2", "BOX_M", "10", "0", "20", "0", "0", "ENDSEC", "0", "EOF"]
    path = tmp_path / "box.dxf"
    path.write_text("\n".join(tags) + "\n", encoding="ascii")
    _, report = read_dxf(path)
    finding = next(f for f in report if f.code == "units-implausible")
    assert "6.01 m^2" in finding.message and "--units METRIC" in finding.message


def test_english_rul_beside_metric_dxf_warns_with_evidence(tmp_path):
    from patternbridge.io.dxf_aama import write_dxf
    from patternbridge.io.rul import write_rul
    from patternbridge.testing import example_pattern

    pattern = example_pattern()  # METRIC
    dxf = write_dxf(pattern, tmp_path / "tee.dxf", rul_path=tmp_path / "tee.rul")
    _, report = read_dxf(dxf)
    assert "rul-units-differ" not in report.codes()
    write_rul(pattern.rules, tmp_path / "tee.rul", units="ENGLISH")
    back, report = read_dxf(dxf)
    finding = next(f for f in report if f.code == "rul-units-differ")
    assert "UNITS: ENGLISH" in finding.message and "METRIC" in finding.message and "largest" in finding.message
    # each file is still read in its own units: the grading is unchanged
    for rule, deltas in pattern.rules.deltas.items():
        np.testing.assert_allclose(back.rules.deltas[rule], deltas, atol=3e-4)


def _outward_offset(outline: np.ndarray, distance: float) -> np.ndarray:
    """Each vertex of a CCW outline moved ``distance`` out along its mitre (a cut line around a sew line)."""
    prev_edge = outline - np.roll(outline, 1, axis=0)
    next_edge = np.roll(outline, -1, axis=0) - outline
    normals = []
    for e in (prev_edge, next_edge):
        n = np.stack([e[:, 1], -e[:, 0]], axis=1)  # right of a CCW edge = outside
        normals.append(n / np.linalg.norm(n, axis=1, keepdims=True))
    m = normals[0] + normals[1]
    m /= np.linalg.norm(m, axis=1, keepdims=True)
    cos = np.clip(np.sum(m * normals[0], axis=1), 0.5, 1.0)
    return outline + distance * m / cos[:, None]


def _dxf(blocks: list[list[str]], style: list[str]) -> str:
    tags = ["0", "SECTION", "2", "BLOCKS"]
    for body in blocks:
        tags += body
    tags += ["0", "ENDSEC", "0", "SECTION", "2", "ENTITIES"]
    for text in style:
        tags += ["0", "TEXT", "8", "1", "10", "0", "20", "0", "1", text]
    tags += ["0", "ENDSEC", "0", "EOF"]
    return "\n".join(tags) + "\n"


def _polyline(layer: str, pts: np.ndarray) -> list[str]:
    tags = ["0", "POLYLINE", "8", layer, "66", "1", "70", "1"]
    for x, y in pts:
        tags += ["0", "VERTEX", "8", layer, "10", f"{x:.4f}", "20", f"{y:.4f}"]
    return [*tags, "0", "SEQEND"]


@pytest.mark.shared
def test_notches_on_the_sew_line_keep_the_cut_sew_vertex_match(aama_dir, tmp_path):
    """GMX1016S18's front exported with 10 mm allowance included, its notches on the sew line."""
    source, _ = read_dxf(aama_dir / "GMX1016S18_AAMA.DXF")
    front = source.piece("GMX1016S18FR")
    sew = front.outline * 10.0  # mm
    cut = _outward_offset(sew, 10.0)
    body = ["0", "BLOCK", "8", "0", "2", "FR_50", "70", "64", "10", "0", "20", "0",
            "0", "TEXT", "8", "1", "10", "0", "20", "0", "1", "Piece Name: FR",
            "0", "TEXT", "8", "1", "10", "0", "20", "0", "1", "Size: 50",
            *_polyline("1", cut), *_polyline("14", sew)]
    for notch in front.notches:
        x, y = sew[notch.vertex]
        body += ["0", "POINT", "8", "4", "10", f"{x:.4f}", "20", f"{y:.4f}", "30", "4.0"]
    body += ["0", "ENDBLK"]
    path = tmp_path / "allowance.dxf"
    path.write_text(_dxf([body], ["Units: METRIC", "Sample Size: 50"]), encoding="ascii")
    pattern, report = read_dxf(path)
    piece = pattern.piece("FR")
    assert "notch-vertex-inserted" not in report.codes() and "notch-on-sew-line" in report.codes()
    assert len(piece.outline) == len(cut) == len(piece.sew_lines[0].points)  # still one cut vertex per sew vertex
    # each notch on the cut-line vertex whose sew-line twin it marks
    sew_back = piece.sew_lines[0].points
    for notch, original in zip(piece.notches, front.notches, strict=True):
        twin = int(np.argmin(np.linalg.norm(sew_back - front.outline[original.vertex], axis=1)))
        np.testing.assert_allclose(piece.outline[notch.vertex], cut[twin] / 10.0, atol=1e-4)
