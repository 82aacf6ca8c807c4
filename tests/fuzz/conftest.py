"""Fuzz-suite fixtures: the example tee as DXF + RUL, a real measurements JSON, the CLI in-process."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from patternbridge.io.dxf_aama.write import write_dxf
from patternbridge.testing import example_pattern

REPO = Path(__file__).resolve().parents[2]
LIBRARY = REPO / "garment_library"
CRLF = "\r\n"


@pytest.fixture()
def tee_dxf_text(tmp_path) -> tuple[str, str]:
    """The example tee as sample-size DXF-AAMA text and its RUL text."""
    dxf, rul = tmp_path / "tee_src.dxf", tmp_path / "tee_src.rul"
    write_dxf(example_pattern(), dxf, rul_path=rul)
    return dxf.read_bytes().decode("ascii"), rul.read_bytes().decode("ascii")


@pytest.fixture()
def shorts_dict() -> dict:
    """The library shorts as a parsed pattern JSON (a fresh copy per test)."""
    return json.loads((LIBRARY / "shorts" / "shorts.json").read_text(encoding="utf-8"))


@pytest.fixture(scope="session")
def measurements_json(tmp_path_factory) -> Path:
    """A measurements JSON of the E character (measured once per session)."""
    from fuzz_run import measurements_file

    if not (REPO.parent / "shared" / "characters").is_dir():
        pytest.skip("../shared is not beside the checkout")
    return measurements_file(tmp_path_factory.mktemp("measured"))


@pytest.fixture()
def cli(capsys):
    """Run the CLI in-process: ``cli(*argv) -> (exit code, stdout, stderr)``."""

    def run(*argv):
        from patternbridge.cli.main import main

        try:
            code = main([str(a) for a in argv])
        except SystemExit as exc:  # argparse's usage errors
            code = exc.code
        out, err = capsys.readouterr()
        return code, out, err

    return run
