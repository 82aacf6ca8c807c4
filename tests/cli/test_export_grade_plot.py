"""export, grade and plot: files where asked, right content, nothing on error."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from patternbridge.io.dxf_aama import read_dxf
from patternbridge.io.pattern_json import load_pattern_json
from patternbridge.pattern.grading import grade
from patternbridge.testing import NOT_IN_DXF, assert_patterns_equal


@pytest.mark.parametrize("flavor", ["aama", "astm"])
def test_export_sample_writes_rul_beside(cli, tee, tee_json, tmp_path, flavor):
    out = tmp_path / "out" / "tee.dxf"
    code, stdout, err = cli("export", tee_json, "-o", out, "--flavor", flavor)
    assert code == 0 and err == ""
    assert out.is_file() and out.with_suffix(".rul").is_file()
    assert str(out) in stdout
    back, _ = read_dxf(out)
    assert_patterns_equal(tee, back, ignore=NOT_IN_DXF)
    assert (b"ASTM/D13Proposal" in out.read_bytes()) == (flavor == "astm")


def test_export_explicit_rul_and_no_rul(cli, tee_json, tmp_path):
    code, _, _ = cli(
        "export",
        tee_json,
        "-o",
        tmp_path / "a.dxf",
        "--rul",
        tmp_path / "rules" / "t.rul",
    )
    assert (
        code == 0
        and (tmp_path / "rules" / "t.rul").is_file()
        and not (tmp_path / "a.rul").exists()
    )
    code, _, _ = cli("export", tee_json, "-o", tmp_path / "b.dxf", "--no-rul")
    assert code == 0 and not (tmp_path / "b.rul").exists()


def test_export_nest_of_listed_sizes(cli, tee, tee_json, tmp_path):
    out = tmp_path / "nest.dxf"
    code, _, _ = cli(
        "export", tee_json, "-o", out, "--sizes", "S,XL", "--flavor", "astm"
    )
    assert code == 0 and not out.with_suffix(".rul").exists()
    back, _ = read_dxf(out)
    assert back.sizes == ("S", "M", "XL")
    for size in ("S", "XL"):
        np.testing.assert_allclose(
            grade(back, size).piece("FRONT").outline,
            grade(tee, size).piece("FRONT").outline,
            atol=1e-4,
        )


def test_export_english_override(cli, tee_json, tmp_path):
    out = tmp_path / "in.dxf"
    assert cli("export", tee_json, "-o", out, "--units", "ENGLISH")[0] == 0
    assert b"Units: ENGLISH" in out.read_bytes()
    assert read_dxf(out)[0].units.value == "ENGLISH"


def test_export_errors_write_nothing(cli, tee_json, tmp_path):
    for argv, needle in [
        (("--sizes", "XXL"), "XXL"),
        (("--sizes", "all", "--rul", tmp_path / "x.rul"), "graded nest"),
    ]:
        code, _out, err = cli("export", tee_json, "-o", tmp_path / "x.dxf", *argv)
        assert code == 2 and needle in err and err.count("\n") == 1
    code, _, err = cli("export", tee_json, "-o", tmp_path / "x.svg")
    assert code == 2 and "x.svg" in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["tee.json"]


def test_export_strict_refuses_lossy_output(cli, tee, tmp_path):
    from dataclasses import replace

    from patternbridge.io.pattern_json import save_pattern_json

    odd = replace(tee, style="Jupe plissée")  # non-ASCII: transliterated, reported
    src = save_pattern_json(odd, tmp_path / "odd.json")
    code, _, err = cli("export", src, "-o", tmp_path / "odd.dxf", "--strict")
    assert code == 2 and "warning" in err and "--strict" in err
    assert not (tmp_path / "odd.dxf").exists() and not (tmp_path / "odd.rul").exists()
    code, _, err = cli("export", src, "-o", tmp_path / "odd.dxf")
    assert (
        code == 0 and "non-ascii-replaced" in err and (tmp_path / "odd.dxf").is_file()
    )


def test_grade_to_json_dxf_and_picture(cli, tee, tee_json, tmp_path):
    out = tmp_path / "xl.json"
    code, stdout, _ = cli("grade", tee_json, "--size", "XL", "-o", out)
    assert code == 0 and "XL" in stdout
    graded = load_pattern_json(out)
    assert graded.sample_size == "XL" and graded.piece("FRONT").size == "XL"
    np.testing.assert_allclose(
        graded.piece("BACK").outline, grade(tee, "XL").piece("BACK").outline
    )
    # grading the graded pattern back to M returns the original (exact at rule points)
    back = tmp_path / "m.json"
    assert cli("grade", out, "--size", "M", "-o", back)[0] == 0
    np.testing.assert_allclose(
        load_pattern_json(back).piece("BACK").outline,
        tee.piece("BACK").outline,
        atol=1e-9,
    )
    assert cli("grade", tee_json, "--size", "L", "-o", tmp_path / "l.dxf")[0] == 0
    assert read_dxf(tmp_path / "l.dxf")[0].sample_size == "L"
    assert cli("grade", tee_json, "--size", "S", "-o", tmp_path / "s.png")[0] == 0
    assert (tmp_path / "s.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_grade_errors_write_nothing(cli, tee, tee_json, tmp_path):
    code, _, err = cli("grade", tee_json, "--size", "XXL", "-o", tmp_path / "x.json")
    assert code == 2 and "XXL" in err and "['S', 'M', 'L', 'XL']" in err
    from dataclasses import replace

    from patternbridge.io.pattern_json import save_pattern_json
    from patternbridge.pattern.model import GradeRuleTable

    flat = save_pattern_json(
        replace(tee, rules=GradeRuleTable()), tmp_path / "flat.json"
    )
    code, _, err = cli("grade", flat, "--size", "L", "-o", tmp_path / "x.json")
    assert code == 2 and "no grade rules" in err
    code, _, err = cli("grade", tee_json, "--size", "L", "-o", tmp_path / "x.txt")
    assert code == 2 and "x.txt" in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["flat.json", "tee.json"]


def test_plot_png_and_svg_with_all_sizes(cli, tee_json, tmp_path):
    code, stdout, _ = cli("plot", tee_json, "-o", tmp_path / "t.png")
    assert code == 0 and "t.png" in stdout
    assert (tmp_path / "t.png").read_bytes()[:4] == b"\x89PNG"
    code, _, _ = cli(
        "plot",
        tee_json,
        "-o",
        tmp_path / "t.svg",
        "--sizes",
        "all",
        "--title",
        "Tee graded",
    )
    svg = (tmp_path / "t.svg").read_text(encoding="utf-8")
    assert code == 0 and "Tee graded" in svg and "XL" in svg


def test_plot_errors_write_nothing(cli, tee_json, tmp_path):
    code, _, err = cli("plot", tee_json, "-o", tmp_path / "t.gif")
    assert code == 2 and "t.gif" in err
    code, _, err = cli("plot", tee_json, "-o", tmp_path / "t.png", "--sizes", "XXS")
    assert code == 2 and "XXS" in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["tee.json"]


@pytest.mark.shared
def test_real_export_pipeline(cli, aama_file, tmp_path):
    src = aama_file("simple.DXF")
    js = tmp_path / "simple.json"
    assert cli("import", src, "-o", js)[0] == 0
    assert (
        cli("export", js, "-o", tmp_path / "simple_astm.dxf", "--flavor", "astm")[0]
        == 0
    )
    code, out, _ = cli("info", tmp_path / "simple_astm.dxf", "--json")
    info = json.loads(out)
    assert code == 0 and info["units"] == "ENGLISH" and len(info["pieces"]) == 4
    assert sum(p["notches"] for p in info["pieces"]) == 7
    assert cli("plot", js, "-o", tmp_path / "simple.png", "--sizes", "all")[0] == 0
    assert Path(tmp_path / "simple.png").stat().st_size > 10_000


def test_export_strict_passes_a_clean_pattern(cli, tee_dxf, tmp_path):
    # reading tee.dxf reports its .rul beside it: informational, not a reason to refuse
    out = tmp_path / "clean.dxf"
    code, _, err = cli("export", tee_dxf, "-o", out, "--flavor", "astm", "--strict")
    assert code == 0 and out.is_file(), err
