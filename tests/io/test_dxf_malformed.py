"""Malformed DXF input derived from a real AccuMark export: one line naming the file, exit 2, nothing written.

Each case mutates one tag of ``../shared/aama/WM LOOSE SHAPE TANK.DXF`` (the
first boundary vertex, the first piece name, the sample block's quantity) and
runs it through every command that reads a DXF.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from patternbridge.cli.main import main
from patternbridge.errors import DXFFormatError
from patternbridge.io.dxf_aama import read_dxf

pytestmark = pytest.mark.shared

TANK = "WM LOOSE SHAPE TANK.DXF"
VERTEX_X = " 10\n0.6047\n"  # first boundary vertex of the first block
NAME = "Piece Name: RELAXED TANK FR V2\n"
QUANTITY = "Quantity: 1\n"

MUTANTS = {
    "nan": (VERTEX_X, " 10\nnan\n", ["line", "not a finite number"]),
    "inf": (VERTEX_X, " 10\n-inf\n", ["line", "not a finite number"]),
    "overflow": (VERTEX_X, " 10\n1e400\n", ["line", "not a finite number"]),
    "absurd": (VERTEX_X, " 10\n6.047e300\n", ["line", "exceeds"]),
    "name_2mb": (NAME, "Piece Name: " + "X" * 2_000_000 + "\n", ["2,000,012 characters"]),
    "quantity": (QUANTITY, "Quantity: 999999999\n", ["Quantity: 999999999"]),
}


@pytest.fixture(scope="module")
def tank_text(aama_dir) -> str:
    return (aama_dir / TANK).read_bytes().decode("ascii")


def _mutant(tank_text: str, case: str, tmp_path: Path) -> Path:
    old, new, _ = MUTANTS[case]
    assert old in tank_text  # the mutation must hit the file
    path = tmp_path / "in" / f"{case}.dxf"
    path.parent.mkdir(exist_ok=True)
    path.write_text(tank_text.replace(old, new, 1), encoding="ascii", newline="")
    return path


@pytest.mark.parametrize("case", sorted(MUTANTS))
def test_reader_refuses_with_one_line(tank_text, tmp_path, case):
    path = _mutant(tank_text, case, tmp_path)
    with pytest.raises(DXFFormatError) as info:
        read_dxf(path)
    message = str(info.value)
    assert "\n" not in message and message.startswith(str(path))
    for needle in MUTANTS[case][2]:
        assert needle in message
    assert len(message) < 400


@pytest.mark.parametrize("case", sorted(MUTANTS))
@pytest.mark.parametrize("command", ["import", "info", "export", "plot", "check"])
def test_every_command_exits_2_without_output(tank_text, tmp_path, capsys, case, command):
    path = _mutant(tank_text, case, tmp_path)
    out = tmp_path / "out" / {"import": "p.json", "export": "p.dxf", "plot": "p.png"}.get(command, "x")
    out.parent.mkdir()
    argv = [command, str(path)] + (["-o", str(out)] if command in ("import", "export", "plot") else [])
    code = main(argv)
    err = capsys.readouterr().err
    assert code == 2, err
    assert len(err.splitlines()) == 1 and err.startswith("patternbridge: error: ") and path.name in err
    assert "Traceback" not in err
    assert not list(out.parent.iterdir()), "output or temporary file left behind"


def test_unmutated_tank_still_reads(aama_dir):
    pattern, _ = read_dxf(aama_dir / TANK)
    assert [p.name for p in pattern.pieces] == ["RELAXED TANK FR V2", "RELAXED TANK BK V2"]
    assert len(pattern.sizes) == 14


def test_autocad_no_extents_marker_in_header_is_fine(tank_text, tmp_path):
    """AutoCAD writes $EXTMIN 1e+20 for an empty drawing: only geometry is held to garment size."""
    header = "  0\nSECTION\n  2\nHEADER\n  0\nENDSEC\n"
    assert tank_text.startswith(header)
    extents = "  0\nSECTION\n  2\nHEADER\n  9\n$EXTMIN\n 10\n1.0E+20\n 20\n1.0E+20\n  0\nENDSEC\n"
    path = tmp_path / "extents.dxf"
    path.write_text(extents + tank_text[len(header):], encoding="ascii", newline="")
    pattern, _ = read_dxf(path)
    assert len(pattern.pieces) == 2


def _every_real_file():
    from pathlib import Path as _P

    folder = _P(__file__).resolve().parents[2].parent / "shared" / "aama"
    return sorted(p.name for p in folder.glob("*") if p.suffix.lower() == ".dxf") if folder.is_dir() else []


@pytest.mark.parametrize("value, needle", [("nan", "not a finite number"), ("inf", "not a finite number"),
                                           ("-1e999", "not a finite number"), ("3e300", "exceeds")])
@pytest.mark.parametrize("name", _every_real_file())
def test_one_bad_coordinate_in_any_real_file_is_refused_with_its_line(aama_dir, tmp_path, name, value, needle):
    """The first boundary vertex of the first block: one line naming the file and the line, whatever the producer."""
    text = (aama_dir / name).read_bytes().decode("latin-1")
    blocks = text.index("BLOCKS")
    vertex = text.index("VERTEX", blocks)
    m = re.compile(r"(\r?\n *10\r?\n)([^\r\n]+)").search(text, vertex)
    line = text[: m.start(2)].count("\n") + 1
    path = tmp_path / name
    path.write_bytes((text[: m.start(2)] + value + text[m.end(2):]).encode("latin-1"))
    with pytest.raises(DXFFormatError) as info:
        read_dxf(path)
    message = str(info.value)
    assert "\n" not in message and message.startswith(str(path)) and needle in message
    assert f"line {line}:" in message
