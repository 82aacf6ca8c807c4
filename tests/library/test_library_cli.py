"""The library, check and seams commands."""

from __future__ import annotations

import json
from dataclasses import replace

import numpy as np

from patternbridge.cli.main import main
from patternbridge.io.pattern_json import save_pattern_json
from patternbridge.library import load_garment
from patternbridge.pattern.model import Polyline


def test_library_list_json(capsys):
    assert main(["library", "list", "--json"]) == 0
    rows = json.loads(capsys.readouterr().out)
    assert {r["name"] for r in rows} == {
        "shirt",
        "trousers",
        "skirt",
        "dress",
        "tshirt",
        "shorts",
    }
    for r in rows:
        assert (
            set(r) == {"name", "pieces", "sizes", "description"}
            and len(r["sizes"]) >= 5
            and r["description"]
        )


def test_library_list_and_show_text(capsys):
    assert main(["library", "list"]) == 0
    assert "trousers" in capsys.readouterr().out
    assert main(["library", "show", "shirt"]) == 0
    out = capsys.readouterr().out
    assert "armhole_front_right" in out and "chest_girth" in out
    # the one-sided hem link says so; two-sided links do not
    assert "hip_girth              ease +6 cm, at least" in out and "chest_girth            ease +12 cm  (" in out


def test_library_show_picture(tmp_path):
    out = tmp_path / "skirt.png"
    assert main(["library", "show", "skirt", "-o", str(out)]) == 0
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_library_show_unknown_picture_type_exits_2(tmp_path, capsys):
    out = tmp_path / "skirt.txt"
    assert main(["library", "show", "skirt", "-o", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "skirt.txt: unknown picture type" in err[0]
    assert not out.exists()


def test_library_export_then_check_the_dxf(tmp_path, capsys):
    dxf = tmp_path / "tr.dxf"
    assert (
        main(
            [
                "library",
                "export",
                "trousers",
                "-o",
                str(dxf),
                "--flavor",
                "astm",
                "--rul",
                str(tmp_path / "tr.rul"),
            ]
        )
        == 0
    )
    assert (tmp_path / "tr.seams.json").is_file()
    assert main(["check", str(dxf)]) == 0
    assert "0 failed" in capsys.readouterr().out


def test_library_export_keeps_the_grading_by_default(tmp_path, capsys):
    # a sample-size DXF without its .RUL would come back as one size only
    dxf = tmp_path / "skirt.dxf"
    assert main(["library", "export", "skirt", "-o", str(dxf)]) == 0
    assert (tmp_path / "skirt.rul").is_file()
    capsys.readouterr()
    assert main(["info", str(dxf), "--json"]) == 0
    info = json.loads(capsys.readouterr().out)
    assert info["sizes"] == list(load_garment("skirt").sizes)


def test_unknown_garment_exits_2(capsys):
    assert main(["library", "show", "cape"]) == 2
    assert "not a library garment" in capsys.readouterr().err
    assert main(["check", "cape"]) == 2


def test_check_fails_with_exit_1_on_a_broken_seam(tmp_path, capsys):
    shirt = load_garment("shirt")
    cuff = shirt.piece("cuff")
    sew = cuff.sew_lines[0]
    broken = replace(
        cuff,
        sew_lines=(
            Polyline(
                points=np.asarray(sew.points) * 1.05,
                kinds=sew.kinds,
                rules=sew.rules,
                closed=True,
            ),
        ),
    )
    path = save_pattern_json(
        replace(
            shirt, pieces=tuple(broken if p.name == "cuff" else p for p in shirt.pieces)
        ),
        tmp_path / "shirt.json",
    )
    assert main(["check", str(path)]) == 1
    out = capsys.readouterr().out
    assert "FAIL cuff_right size 88" in out and "mm" in out
    assert main(["check", str(path), "--json"]) == 1
    rows = json.loads(capsys.readouterr().out)
    assert any(not r["ok"] and r["seam"] == "cuff_right" for r in rows)
    assert all(
        r["ok"] for r in rows if r["seam"] == "cuff_closure_right"
    )  # both ends grew alike


def test_check_json_passes_for_every_library_garment(capsys):
    for name in ("shirt", "trousers", "skirt", "dress", "tshirt", "shorts"):
        assert main(["check", name]) == 0
    capsys.readouterr()


def test_seams_infer_writes_an_applicable_sidecar(tmp_path, capsys):
    d = tmp_path
    assert (
        main(
            [
                "library",
                "export",
                "shorts",
                "-o",
                str(d / "s.dxf"),
                "--rul",
                str(d / "s.rul"),
            ]
        )
        == 0
    )
    (d / "s.seams.json").unlink()
    side = d / "proposal.json"
    assert main(["seams", "infer", str(d / "s.dxf"), "-o", str(side)]) == 0
    data = json.loads(side.read_text())
    assert data["seams"] and all(
        s["status"] == "proposed" and 0 < s["confidence"] <= 1 for s in data["seams"]
    )
    capsys.readouterr()
    code = main(["check", str(d / "s.dxf"), "--sidecar", str(side)])
    assert code in (0, 1)
    assert "seams x 5 sizes" in capsys.readouterr().out


def test_check_without_seams_warns(tmp_path, capsys):
    shirt = load_garment("shirt")
    path = save_pattern_json(replace(shirt, seams=()), tmp_path / "plain.json")
    assert main(["check", str(path)]) == 0
    assert "no seams" in capsys.readouterr().err


def test_out_of_range_tolerance_and_confidence_exit_2(tmp_path, capsys):
    import pytest

    for argv in (
        ["check", "shirt", "--tol-mm", "-1"],
        [
            "seams",
            "infer",
            "shirt",
            "-o",
            str(tmp_path / "s.json"),
            "--min-confidence",
            "2",
        ],
    ):
        with pytest.raises(SystemExit) as exc:
            main(argv)
        assert exc.value.code == 2
    assert not (tmp_path / "s.json").exists()
    assert main(["check", str(tmp_path)]) == 2
    assert "is a directory" in capsys.readouterr().err
