"""Same inputs and seed, same bytes: two ``fit`` runs compared file by file.

The two runs are separate processes with different ``PYTHONHASHSEED`` values,
so any output that depends on set or dict-of-set order, on object ids or on
the clock shows up as a difference. Only ``seconds`` fields may differ. The
DXF/RUL creation date is masked here; that it follows ``SOURCE_DATE_EPOCH`` is
``test_regressions_reader.py::test_dxf_rul_honour_source_date_epoch``.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest
from fuzz_run import REPO

SECONDS = re.compile(rb'"seconds": -?[0-9.e+-]+')
DXF_DATE = re.compile(rb"(?im)^(creation (date|time):).*$")


def _fit(measurements: Path, out: Path, hash_seed: str) -> subprocess.Popen:
    env = {**os.environ, "PYTHONHASHSEED": hash_seed, "SOURCE_DATE_EPOCH": "86400", "PYTHONPATH": str(REPO)}
    argv = [sys.executable, "-m", "patternbridge.cli.main", "fit", str(measurements), "--garment", "shorts",
            "--pop-size", "8", "--generations", "2", "--no-drape", "--seed", "7", "-q", "-o", str(out)]
    return subprocess.Popen(argv, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE)


def _masked(path: Path) -> bytes:
    data = path.read_bytes()
    if path.suffix == ".json":
        data = SECONDS.sub(b'"seconds": 0', data)
    if path.suffix.lower() in (".dxf", ".rul"):
        data = DXF_DATE.sub(rb"\1", data)
    return data


@pytest.mark.slow
def test_fit_twice_gives_the_same_bytes(measurements_json, tmp_path):
    runs = [_fit(measurements_json, tmp_path / f"run{k}", seed) for k, seed in ((1, "1"), (2, "2"))]
    for proc in runs:
        _, err = proc.communicate(timeout=600)
        assert proc.returncode == 0, err.decode()[-2000:]
    first = sorted(p.relative_to(tmp_path / "run1") for p in (tmp_path / "run1").rglob("*") if p.is_file())
    second = sorted(p.relative_to(tmp_path / "run2") for p in (tmp_path / "run2").rglob("*") if p.is_file())
    assert first == second
    assert {p.suffix for p in first} >= {".json", ".dxf", ".rul", ".png"}
    for rel in first:
        a, b = _masked(tmp_path / "run1" / rel), _masked(tmp_path / "run2" / rel)
        assert a == b, f"{rel} differs between two runs with the same seed"
