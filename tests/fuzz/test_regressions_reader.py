"""Issue 20's reproducers whose fix lives in the DXF/RUL reader and writer or in unit detection.

They pin the promised behaviour end to end through the CLI: a bad DXF or RUL
gets one line and exit 2 (or a warning when it is usable), what we export
re-imports, dates follow ``SOURCE_DATE_EPOCH``, and a measured stature is a
body's.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest
from fuzz_run import SHARED, assert_clean_error

CRLF = "\r\n"
E_OBJ = SHARED / "characters" / "E_average_male.obj"
needs_shared = pytest.mark.skipif(not E_OBJ.is_file(), reason="../shared is not beside the checkout")


def _with_coordinate(dxf: str, value: str) -> str:
    """The tee DXF with the x of one BACK boundary vertex replaced by ``value``."""
    back = dxf.index("Piece Name: BACK")
    vertex = dxf.index("VERTEX" + CRLF, back)
    m = re.compile(r" 10\r\n([-0-9.]+)\r\n").search(dxf, vertex)
    return dxf[: m.start(1)] + value + dxf[m.end(1) :]


def _write(folder: Path, dxf: str, rul: str | None = None) -> Path:
    folder.mkdir(exist_ok=True)
    path = folder / "tee.dxf"
    path.write_bytes(dxf.encode("ascii"))
    if rul is not None:
        (folder / "tee.rul").write_bytes(rul.encode("ascii"))
    return path


@pytest.mark.parametrize("value", ["nan", "NaN", "inf", "-inf", "1e400", "1e308"])
def test_dxf_non_finite_or_overflowing_coordinate(cli, tmp_path, tee_dxf_text, value):
    dxf, rul = tee_dxf_text
    out = tmp_path / "out" / "p.json"
    path = _write(tmp_path / "in", _with_coordinate(dxf, value), rul)
    assert_clean_error(cli("import", path, "-o", out), "tee.dxf", outputs=(out,))


def test_dxf_nan_coordinate_export(cli, tmp_path, tee_dxf_text):
    """The same file through export: no DXF with ``nan`` or ``inf`` in it is ever written."""
    dxf, rul = tee_dxf_text
    out = tmp_path / "out" / "e.dxf"
    path = _write(tmp_path / "in", _with_coordinate(dxf, "nan"), rul)
    assert_clean_error(cli("export", path, "-o", out), outputs=(out,))


def test_dxf_huge_piece_name_import(cli, tmp_path, tee_dxf_text):
    dxf, rul = tee_dxf_text
    path = _write(tmp_path / "in", dxf.replace("Piece Name: FRONT", "Piece Name: " + "N" * 2**21, 1), rul)
    out = tmp_path / "out" / "p.json"
    assert_clean_error(cli("import", path, "-o", out), outputs=(out,))


def test_dxf_quantity_huge(cli, tmp_path, tee_dxf_text):
    dxf, rul = tee_dxf_text
    path = _write(tmp_path / "in", dxf.replace("Quantity: 2", "Quantity: 999999999", 1), rul)
    out = tmp_path / "out" / "p.json"
    code, _, err = cli("import", path, "-o", out)
    assert code == 2 or "999999999" in err, "an absurd quantity is accepted without a word"


def test_rul_duplicate_size(cli, tmp_path, tee_dxf_text):
    dxf, rul = tee_dxf_text
    assert "SIZE LIST:  S M L XL" in rul
    path = _write(tmp_path / "in", dxf, rul.replace("SIZE LIST:  S M L XL", "SIZE LIST:  S M M XL", 1))
    out = tmp_path / "out" / "p.json"
    code, _, err = cli("import", path, "-o", out)
    assert code == 2 or "warning" in err, "a size listed twice loses the last size silently"


def test_rul_english_beside_metric_dxf(cli, tmp_path, tee_dxf_text):
    dxf, rul = tee_dxf_text
    path = _write(tmp_path / "in", dxf, rul.replace("UNITS: METRIC", "UNITS: ENGLISH", 1))
    out = tmp_path / "out" / "p.json"
    code, _, err = cli("import", path, "-o", out)
    assert code == 2 or ("ENGLISH" in err and "METRIC" in err), "RUL units disagreeing with the DXF pass silently"


def test_dxf_rul_honour_source_date_epoch(cli, tmp_path, monkeypatch):
    """Exports carry the date of SOURCE_DATE_EPOCH (1971-01-01 00:00 UTC), so two runs give the same bytes."""
    monkeypatch.setenv("SOURCE_DATE_EPOCH", str(365 * 86400))
    for k in (1, 2):
        code, _, err = cli("export", "shorts", "-o", tmp_path / f"r{k}" / "e.dxf", "-q")
        assert code == 0, err
    rul = (tmp_path / "r1" / "e.rul").read_text(encoding="ascii")
    assert "01-01-1971" in rul and "00:00" in rul, rul[:300]
    for name in ("e.dxf", "e.rul"):
        assert (tmp_path / "r1" / name).read_bytes() == (tmp_path / "r2" / name).read_bytes()


# ------------------------------------------------------------------ unit detection (mesh/load.py)
def _obj_with(tmp_path: Path, scale: float, extra: str = "", sidecar: dict | None = None) -> Path:
    lines = []
    for line in E_OBJ.read_text(encoding="utf-8").splitlines():
        if line.startswith("v "):
            line = "v " + " ".join(repr(float(c) * scale) for c in np.array(line.split()[1:4], dtype=float))
        lines.append(line)
    path = tmp_path / "body.obj"
    path.write_text("\n".join(lines) + "\n" + extra, encoding="utf-8")
    if sidecar is not None:
        (tmp_path / "body.json").write_text(json.dumps(sidecar), encoding="utf-8")
    return path


def _stature_or_error(cli, mesh: Path, out: Path) -> float | None:
    code, _, err = cli("measure", mesh, "-o", out, "--partial")
    if code == 2:
        assert_clean_error((code, "", err))
        return None
    assert code == 0, err
    return json.loads(out.read_text())["measurements"]["stature"]["value_cm"]


@needs_shared
def test_measure_stray_triangle_keeps_units(cli, tmp_path):
    """One triangle 5 m above the body must not turn a cm body into millimetres."""
    n = sum(1 for line in E_OBJ.read_text().splitlines() if line.startswith("v "))
    mesh = _obj_with(tmp_path, 1.0, f"v 0 680 0\nv 1 680 0\nv 0 681 0\nf {n + 1} {n + 2} {n + 3}\n")
    stature = _stature_or_error(cli, mesh, tmp_path / "m.json")
    assert stature is None or 150 < stature < 200, f"stature {stature} cm"


@needs_shared
def test_tiny_mesh_with_cm_sidecar_refused(cli, tmp_path):
    """A sidecar saying cm on a body 0.002 cm tall: an error, not a 0.002 cm stature."""
    mesh = _obj_with(tmp_path, 1e-5, sidecar={"units": "cm"})
    stature = _stature_or_error(cli, mesh, tmp_path / "m.json")
    assert stature is None or stature > 40, f"stature {stature} cm"
