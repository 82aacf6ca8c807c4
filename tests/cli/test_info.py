"""``info --json``: the contract of formats/info.md on hand-made and real files."""

from __future__ import annotations

import json

import numpy as np
import pytest

from patternbridge.pattern.geometry import area, perimeter

KEYS = {"style", "units", "sample_size", "sizes", "pieces"}
PIECE_KEYS = {
    "name",
    "quantity",
    "vertices",
    "notches",
    "grade_rules",
    "area_cm2",
    "perimeter_cm",
}


def test_info_json_contract(cli, tee, tee_json):
    code, out, err = cli("info", tee_json, "--json")
    assert code == 0 and err == ""
    info = json.loads(out)
    assert set(info) == KEYS
    assert info["style"] == "EXAMPLE TEE" and info["units"] == "METRIC"
    assert info["sample_size"] == "M" and info["sizes"] == ["S", "M", "L", "XL"]
    assert [p["name"] for p in info["pieces"]] == ["FRONT", "BACK", "SLEEVE"]
    for entry, piece in zip(info["pieces"], tee.pieces, strict=True):
        assert set(entry) == PIECE_KEYS
        assert entry["quantity"] == piece.quantity.total
        assert entry["vertices"] == len(piece.outline)
        assert entry["notches"] == len(piece.notches)
        assert entry["grade_rules"] == sum(r is not None for r in piece.rules)
        assert entry["area_cm2"] == pytest.approx(float(area(piece.outline)), abs=1e-4)
        assert entry["perimeter_cm"] == pytest.approx(
            float(perimeter(piece.outline)), abs=1e-4
        )
    back = info["pieces"][1]
    # the back is a 6-corner polygon: area by hand (shoelace in cm)
    xy = np.array([[0, 0], [24, 0], [25, 40], [17, 60], [6, 62], [0, 61]], float)
    assert back["area_cm2"] == pytest.approx(
        0.5
        * abs(
            np.dot(xy[:, 0], np.roll(xy[:, 1], -1))
            - np.dot(np.roll(xy[:, 0], -1), xy[:, 1])
        )
    )


def test_info_reads_dxf_with_rul_beside(cli, tee_dxf):
    code, out, _ = cli("info", tee_dxf, "--json")
    assert code == 0
    info = json.loads(out)
    assert (
        info["sizes"] == ["S", "M", "L", "XL"] and info["pieces"][0]["grade_rules"] == 6
    )


def test_info_table_for_people(cli, tee_json):
    code, out, _ = cli("info", tee_json)
    assert code == 0
    assert "EXAMPLE TEE" in out and "FRONT" in out and "perimeter cm" in out


@pytest.mark.shared
@pytest.mark.parametrize(
    "name, units, sample, n_sizes, pieces, notches",
    [
        ("GLX4802S19_AAMA.DXF", "METRIC", "36", 14, 3, 11),
        ("GLX4802S19_ASTM.DXF", "METRIC", "36", 14, 3, 11),
        ("simple.DXF", "ENGLISH", "36", 14, 4, 7),
        ("clo-pattern.dxf", "METRIC", "M", 1, 9, 18),
    ],
)
def test_info_on_real_exports(
    cli, aama_file, name, units, sample, n_sizes, pieces, notches
):
    code, out, _ = cli("info", aama_file(name), "--json")
    assert code == 0
    info = json.loads(out)
    assert info["units"] == units and info["sample_size"] == sample
    assert len(info["sizes"]) == n_sizes and sample in info["sizes"]
    assert len(info["pieces"]) == pieces
    assert sum(p["notches"] for p in info["pieces"]) == notches
    assert all(
        p["area_cm2"] > 0 and p["perimeter_cm"] > 0 and p["vertices"] >= 3
        for p in info["pieces"]
    )


def test_info_on_missing_file_is_one_line_exit_2(cli, tmp_path):
    code, out, err = cli("info", tmp_path / "nope.dxf")
    assert code == 2 and out == ""
    assert (
        err.count("\n") == 1
        and "nope.dxf" in err
        and err.startswith("patternbridge: error: ")
    )


def test_dxf_options_on_a_json_pattern_are_reported(tmp_path, capsys):
    # --units / --rul mean nothing for canonical JSON: say so instead of ignoring them
    from patternbridge.cli.main import main as cli_main
    from patternbridge.io.pattern_json import save_pattern_json
    from patternbridge.testing import example_pattern

    path = save_pattern_json(example_pattern(), tmp_path / "tee.json")
    assert cli_main(["info", str(path), "--units", "ENGLISH"]) == 0
    err = capsys.readouterr().err
    assert "--units ENGLISH applies to a DXF only" in err and "[option-ignored]" in err
    assert cli_main(["info", "shirt", "--rul", "x.rul"]) == 0
    assert "--rul x.rul applies to a DXF only" in capsys.readouterr().err
