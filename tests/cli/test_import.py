"""``patternbridge import``: real exports, .RUL beside or given, unfold, sidecar."""

from __future__ import annotations

import json

import numpy as np
import pytest

from patternbridge.io.pattern_json import load_pattern_json
from patternbridge.testing import NOT_IN_DXF, assert_patterns_equal


def test_import_sample_dxf_with_rul_beside(cli, tee, tee_dxf, tmp_path):
    out = tmp_path / "t.json"
    code, stdout, _err = cli("import", tee_dxf, "-o", out)
    assert code == 0 and str(out) in stdout and "sizes S, M, L, XL" in stdout
    assert_patterns_equal(tee, load_pattern_json(out), ignore=NOT_IN_DXF)


def test_import_with_explicit_rul_and_units(cli, tee, tee_dxf, tmp_path):
    rul = tee_dxf.with_suffix(".rul").rename(tmp_path / "elsewhere.rul")
    out = tmp_path / "t.json"
    code, _, err = cli("import", tee_dxf, "--rul", rul, "-o", out)
    assert code == 0
    assert load_pattern_json(out).rules.sizes == ("S", "M", "L", "XL")
    # without the .RUL only the sample size is left, with a warning
    code, _, err = cli("import", tee_dxf, "-o", tmp_path / "bare.json")
    assert (
        code == 0
        and "warning" in err
        and load_pattern_json(tmp_path / "bare.json").sizes == ("M",)
    )
    # --units reinterprets the numbers: mm read as inches are 25.4 times larger
    code, _, _ = cli(
        "import",
        tee_dxf,
        "--rul",
        rul,
        "--units",
        "english",
        "-o",
        tmp_path / "in.json",
    )
    assert code == 0
    big = load_pattern_json(tmp_path / "in.json")
    assert big.units.value == "ENGLISH"
    np.testing.assert_allclose(
        big.piece("BACK").outline, tee.piece("BACK").outline * 25.4, atol=1e-3
    )


def test_import_unfold_makes_whole_pieces(cli, tee, tee_dxf, tmp_path):
    code, _, _ = cli("import", tee_dxf, "--unfold", "-o", tmp_path / "u.json")
    assert code == 0
    whole = load_pattern_json(tmp_path / "u.json").piece("BACK")
    half = tee.piece("BACK")
    assert whole.mirror_line is None
    from patternbridge.pattern.geometry import area

    assert float(area(whole.outline)) == pytest.approx(
        2 * float(area(half.outline)), rel=1e-6
    )


def test_import_applies_sidecar_beside_or_given(cli, tee, tee_dxf, tmp_path):
    from patternbridge.library.sidecar import write_sidecar

    write_sidecar(tee, tee_dxf.with_name("tee.seams.json"))
    code, stdout, _ = cli("import", tee_dxf, "-o", tmp_path / "s.json")
    assert code == 0 and "seams from" in stdout
    got = load_pattern_json(tmp_path / "s.json")
    assert got.seams == tee.seams and got.measurements == tee.measurements
    assert dict(got.piece("FRONT").marks) == dict(tee.piece("FRONT").marks)
    assert got.piece("FRONT").placement == tee.piece("FRONT").placement
    other = write_sidecar(tee, tmp_path / "other.json")
    assert cli("import", tee_dxf, "--seams", other, "-o", tmp_path / "o.json")[0] == 0
    code, _, err = cli(
        "import",
        tee_dxf,
        "--seams",
        tmp_path / "missing.json",
        "-o",
        tmp_path / "m.json",
    )
    assert code == 2 and "missing.json" in err and not (tmp_path / "m.json").exists()


def test_import_strict_accepts_a_clean_file(cli, tee_dxf, tmp_path):
    out = tmp_path / "t.json"
    code, _, err = cli("import", tee_dxf, "--strict", "-o", out)
    assert code == 0 and out.is_file(), (
        err
    )  # finding the .rul beside is only informational


def test_import_strict_turns_warnings_into_errors(cli, tee_dxf, tmp_path):
    tee_dxf.with_suffix(".rul").unlink()
    out = tmp_path / "t.json"
    code, _, err = cli("import", tee_dxf, "--strict", "-o", out)
    assert code == 2 and "strict" in err.splitlines()[-1] and not out.exists()


@pytest.mark.shared
@pytest.mark.parametrize(
    "name, pieces, sizes, sample, units, notches",
    [
        ("GLX4802S19_AAMA.DXF", 3, 14, "36", "METRIC", 11),
        ("GLX4802S19_ASTM.DXF", 3, 14, "36", "METRIC", 11),
        ("simple.DXF", 4, 14, "36", "ENGLISH", 7),
        ("clo-pattern.dxf", 9, 1, "M", "METRIC", 18),
    ],
)
def test_import_real_exports(
    cli, aama_file, tmp_path, name, pieces, sizes, sample, units, notches
):
    out = tmp_path / "p.json"
    code, _, _ = cli("import", aama_file(name), "-o", out)
    assert code == 0
    doc = json.loads(out.read_text(encoding="utf-8"))
    assert doc["units"] == units and doc["sample_size"] == sample
    assert len(doc["pieces"]) == pieces and len(doc["sizes"] or [sample]) == sizes
    assert sum(len(p["notches"]) for p in doc["pieces"]) == notches


def test_import_refuses_non_dxf(cli, tee_json, tmp_path):
    code, _, err = cli("import", tee_json, "-o", tmp_path / "x.json")
    assert code == 2 and "not a .dxf" in err and not (tmp_path / "x.json").exists()


def test_import_json_prints_the_info_contract(cli, tee, tee_dxf, tmp_path):
    import json

    out = tmp_path / "t.json"
    code, stdout, _err = cli("import", tee_dxf, "-o", out, "--json")
    assert code == 0 and out.is_file()
    info = json.loads(stdout)
    assert info["style"] == tee.style and info["sizes"] == list(tee.sizes)
    assert [p["name"] for p in info["pieces"]] == [p.name for p in tee.pieces]
