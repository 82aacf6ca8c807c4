"""Findings carry a severity; --strict refuses warnings, never notes."""

from __future__ import annotations

import pytest

from patternbridge.cli._common import print_findings
from patternbridge.errors import InputError
from patternbridge.report import Finding, Report


def test_strict_refuses_warnings_but_not_notes(capsys):
    notes = Report()
    notes.add("validation-curves-dropped", "dropped", severity="info")
    print_findings(notes, strict=True)
    assert "patternbridge: note: dropped" in capsys.readouterr().err

    mixed = Report()
    mixed.add("units-assumed", "assumed METRIC", where="a.dxf")
    mixed.extend(notes)
    assert [f.code for f in mixed.warnings] == ["units-assumed"]
    with pytest.raises(InputError, match="1 warning"):
        print_findings(mixed, strict=True)


def test_unknown_severity_is_rejected():
    with pytest.raises(ValueError, match="severity"):
        Finding(code="x", message="y", severity="fatal")



def test_closed_pipe_is_not_a_traceback(aama_dir, monkeypatch):
    import os
    import sys

    from patternbridge.cli.main import main

    read_end, write_end = os.pipe()
    os.close(read_end)  # the reader has gone, like `| head` after its lines
    stdout = open(write_end, "w")
    monkeypatch.setattr(sys, "stdout", stdout)
    try:
        assert main(["info", str(aama_dir / "simple.DXF"), "--json"]) == 0
    finally:
        stdout.close()


def test_a_finding_said_twice_is_kept_once_and_the_order_stays():
    first, second = Report(), Report()
    first.add("size-coded", "size 'hero' written as 901", "shirt")
    first.add("units-implausible", "largest piece 7 cm", "shirt")
    second.add("size-coded", "size 'hero' written as 901", "shirt")  # the ASTM writer says it again
    second.add("size-coded", "size 'hero' written as 901", "dress")  # another file: a finding of its own
    first.extend(second)
    assert [(f.code, f.where) for f in first] == [
        ("size-coded", "shirt"), ("units-implausible", "shirt"), ("size-coded", "dress")]
