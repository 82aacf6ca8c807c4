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
