"""Export refusals and deterministic bytes: what we write, a CAD system (and our own import) can read."""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest

from patternbridge.cli.main import main
from patternbridge.errors import InputError
from patternbridge.io.dxf_aama import read_dxf, write_dxf
from patternbridge.io.pattern_json import save_pattern_json
from patternbridge.pattern.model import GradeRuleTable
from patternbridge.testing import example_pattern


def _cli_refuses(capsys, tmp_path, argv, *needles) -> None:
    code = main([str(a) for a in argv])
    err = capsys.readouterr().err
    assert code == 2 and len(err.splitlines()) == 1 and err.startswith("patternbridge: error: "), err
    for needle in needles:
        assert needle in err
    assert not [p for p in (tmp_path / "out").iterdir()], "nothing may be written"


@pytest.fixture()
def tee_json(tmp_path):
    return save_pattern_json(example_pattern(), tmp_path / "tee.json")


def test_pattern_without_pieces_is_refused(tee_json, tmp_path, capsys):
    data = json.loads(tee_json.read_text())
    data.update(pieces=[], seams=[], measurements=[])
    bad = tmp_path / "empty.json"
    bad.write_text(json.dumps(data))
    (tmp_path / "out").mkdir()
    _cli_refuses(capsys, tmp_path, ["export", bad, "-o", tmp_path / "out" / "e.dxf"], "pieces", "at least 1")


def test_writer_refuses_a_pattern_without_pieces(tmp_path):
    empty = dataclasses.replace(example_pattern(), pieces=(), seams=(), measurements=())
    with pytest.raises(InputError, match="no pieces"):
        write_dxf(empty, tmp_path / "e.dxf")
    assert not list(tmp_path.iterdir())


@pytest.mark.parametrize("value", [1e308, -1e300, 2e6])
def test_coordinates_a_dxf_cannot_hold_are_refused(tee_json, tmp_path, capsys, value):
    data = json.loads(tee_json.read_text())
    data["pieces"][0]["outline"][0][0] = value  # 1e308 cm is infinite in mm; 2e6 cm is 20 km
    bad = tmp_path / "huge.json"
    bad.write_text(json.dumps(data))
    (tmp_path / "out").mkdir()
    _cli_refuses(capsys, tmp_path, ["export", bad, "-o", tmp_path / "out" / "h.dxf"], "outline[0][0]", "outside")


@pytest.mark.parametrize("value", [1e308, -1e300, 2e6])
def test_writer_refuses_coordinates_a_dxf_cannot_hold(tmp_path, value):
    pattern = example_pattern()
    outline = np.array(pattern.pieces[0].outline)
    outline[0, 0] = value
    huge = dataclasses.replace(pattern.pieces[0], outline=outline)
    with pytest.raises(InputError, match="finite numbers"):
        write_dxf(dataclasses.replace(pattern, pieces=(huge, *pattern.pieces[1:])), tmp_path / "h.dxf")
    assert not list(tmp_path.iterdir())


def test_huge_rule_delta_is_refused(tmp_path):
    pattern = example_pattern()
    deltas = {k: np.asarray(v) * 1e305 for k, v in pattern.rules.deltas.items()}
    pattern = dataclasses.replace(pattern, rules=GradeRuleTable(
        name=pattern.rules.name, sizes=pattern.rules.sizes, sample_size=pattern.sample_size, deltas=deltas))
    with pytest.raises(InputError, match="grade rule"):
        write_dxf(pattern, tmp_path / "x.dxf", rul_path=tmp_path / "x.rul")
    assert not list(tmp_path.iterdir())


@pytest.mark.shared
@pytest.mark.parametrize("flavor", ["aama", "astm"])
def test_same_inputs_give_the_same_bytes(aama_dir, tmp_path, monkeypatch, flavor):
    monkeypatch.delenv("SOURCE_DATE_EPOCH", raising=False)
    pattern, _ = read_dxf(aama_dir / "GLX4802S19_ASTM.DXF")
    a, b = tmp_path / "a.dxf", tmp_path / "b.dxf"
    write_dxf(pattern, a, flavor=flavor, rul_path=tmp_path / "a.rul")
    write_dxf(read_dxf(aama_dir / "GLX4802S19_ASTM.DXF")[0], b, flavor=flavor, rul_path=tmp_path / "b.rul")
    assert a.read_bytes() == b.read_bytes()
    assert (tmp_path / "a.rul").read_bytes() == (tmp_path / "b.rul").read_bytes()
    text = a.read_text(encoding="ascii")
    assert "Creation Date: 04-12-2017" in text  # the source's own date ( 4-12-2017), not today's
    monkeypatch.setenv("SOURCE_DATE_EPOCH", "1700000000")
    write_dxf(pattern, a, flavor=flavor, rul_path=tmp_path / "a.rul")
    assert "Creation Date: 14-11-2023" in a.read_text(encoding="ascii")
    assert "CREATION DATE: 14-11-2023" in (tmp_path / "a.rul").read_text(encoding="ascii")


@pytest.mark.shared
@pytest.mark.parametrize("form", ["sample", "all"])
def test_a_character_size_gets_a_cad_code_and_comes_back_by_name(aama_dir, tmp_path, form):
    from patternbridge.io.dxf_aama.sizes import rename_sizes
    from patternbridge.io.rul import read_rul
    from patternbridge.pattern.grading import graded_outlines

    source, _ = read_dxf(aama_dir / "GLX4802S19_AAMA.DXF")
    pattern = rename_sizes(source, {"52": "E_average_male"})  # a character graded in as one more size
    report = __import__("patternbridge.report", fromlist=["Report"]).Report()
    out = tmp_path / "fit.dxf"
    write_dxf(pattern, out, sizes=form, rul_path=out.with_suffix(".rul") if form == "sample" else None,
              report=report)
    assert "size-coded" in report.codes()
    text = out.read_text(encoding="ascii")
    assert "Size 901: E_average_male" in text and "E_average_male_" not in text  # no block named after it
    written = {line.split(":", 1)[1].strip() for line in text.split("\r\n") if line.startswith("Size:")}
    assert all(s.isdigit() for s in written)  # no name among numeric sizes
    if form == "sample":
        table, _ = read_rul(out.with_suffix(".rul"))
        assert table.sizes[-1] == "901" and all(s.isdigit() for s in table.sizes)
    back, _ = read_dxf(out)
    assert back.sizes == pattern.sizes and back.sizes[-1] == "E_average_male"
    a, b = graded_outlines(pattern)["E_average_male"], graded_outlines(back)["E_average_male"]
    for name, outline in a.items():
        np.testing.assert_allclose(b[name], outline, atol=1e-3)
