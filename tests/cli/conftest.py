"""CLI test inputs: the example tee as JSON and as DXF + RUL, and the real exports."""

from __future__ import annotations

from pathlib import Path

import pytest

from patternbridge.io.dxf_aama.write import write_dxf
from patternbridge.io.pattern_json import save_pattern_json
from patternbridge.testing import example_pattern

SHARED_AAMA = Path(__file__).resolve().parents[2] / ".." / "shared" / "aama"


@pytest.fixture()
def tee():
    return example_pattern()


@pytest.fixture()
def tee_json(tee, tmp_path) -> Path:
    return save_pattern_json(tee, tmp_path / "tee.json")


@pytest.fixture()
def tee_dxf(tee, tmp_path) -> Path:
    """Sample-size DXF-AAMA with its .rul beside it (same stem)."""
    src = tmp_path / "src"
    src.mkdir()
    return write_dxf(tee, src / "tee.dxf", rul_path=src / "tee.rul")


@pytest.fixture()
def aama_file():
    def get(name: str) -> Path:
        path = SHARED_AAMA / name
        if not path.is_file():
            pytest.skip("../shared/aama is not beside the checkout")
        return path

    return get


def run_cli(capsys, *argv) -> tuple[int, str, str]:
    from patternbridge.cli.main import main

    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


@pytest.fixture()
def cli(capsys):
    return lambda *argv: run_cli(capsys, *argv)
