"""``patternbridge batch`` on a 2-worker LocalCluster: same results as separate fits, failures, resuming."""

from __future__ import annotations

import json
import os

import pytest
from batch_fixtures import BUDGET, timeless, without_stamps

from patternbridge.cli.main import main
from patternbridge.io.pattern_json import save_pattern_json


@pytest.mark.slow
def test_batch_equals_separate_fits_records_failures_and_resumes(batch_inputs, tmp_path, capsys):
    p = batch_inputs
    out = tmp_path / "out"
    argv = [
        "batch",
        str(p["hero"]),
        str(p["big"]),
        "--garments",
        str(p["skirt"]),
        str(p["bare"]),
        "-o",
        str(out),
        "--workers",
        "2",
        "--seed",
        "4",
        *BUDGET,
    ]
    assert main(argv) == 1  # the bare skirt fails on both characters
    err = capsys.readouterr().err
    assert "dashboard" in err and "--retry-failed" in err

    manifest = json.loads((out / "batch.json").read_text())
    status = {c["folder"]: c["status"] for c in manifest["cases"]}
    assert status == {"hero/skirt": "done", "hero/bare": "failed", "big/skirt": "done", "big/bare": "failed"}
    assert manifest["seed"] == 4 and manifest["options"]["pop_size"] == 20
    assert manifest["cluster"]["workers"] == 2 and "dask" in manifest["versions"]
    # each case's worker CPU time (no more than the cores can give in its wall time) and the worker's peak memory
    # (a process with numpy and the grader loaded holds tens of MB)
    done = [c for c in manifest["cases"] if c["status"] == "done"]
    assert len(done) == 2
    assert all(0 < c["cpu_seconds"] <= (os.cpu_count() or 1) * c["seconds"] + 0.05 for c in done)
    assert all(c["peak_rss_mb"] > 30 for c in done)
    failed = json.loads((out / "hero" / "bare.failed.json").read_text())
    assert "no measurement links" in failed["error"] and not (out / "hero" / "bare").exists()
    assert (out / "index.html").is_file()
    assert not [q for q in out.rglob(".*")]  # no partial folders or temporary files left

    # every finished case is what a separate `fit` with the same seed writes
    for character in ("hero", "big"):
        alone = tmp_path / f"alone_{character}"
        assert (
            main(
                ["fit", str(p[character]), "--garment", str(p["skirt"]), "-o", str(alone), "-q", "--seed", "4", *BUDGET]
            )
            == 0
        )
        case = out / character / "skirt"
        assert sorted(q.name for q in case.iterdir()) == sorted(q.name for q in alone.iterdir())
        for f in alone.iterdir():
            if f.name == "fit_report.json":
                assert timeless(json.loads(f.read_text())) == timeless(json.loads((case / f.name).read_text()))
            elif f.suffix != ".png":
                assert without_stamps(f.read_bytes()) == without_stamps((case / f.name).read_bytes()), f.name

    # the same command again: finished and failed cases are kept, nothing is rewritten
    stamp = (out / "hero" / "skirt" / "fit_report.json").stat().st_mtime_ns
    assert main(argv) == 1
    again = json.loads((out / "batch.json").read_text())
    assert all(c["reused"] for c in again["cases"])
    assert (out / "hero" / "skirt" / "fit_report.json").stat().st_mtime_ns == stamp

    # the garment repaired, --retry-failed redoes the failed cases only
    save_pattern_json(json_pattern(p["skirt"]), p["bare"])
    assert main([*argv, "--retry-failed"]) == 0
    final = json.loads((out / "batch.json").read_text())
    assert {c["folder"]: (c["status"], c["reused"]) for c in final["cases"]} == {
        "hero/skirt": ("done", True),
        "hero/bare": ("done", False),
        "big/skirt": ("done", True),
        "big/bare": ("done", False),
    }
    assert not (out / "hero" / "bare.failed.json").exists()


def json_pattern(path):
    from patternbridge.io.pattern_json import load_pattern_json

    return load_pattern_json(path)


def test_batch_refuses_two_characters_with_one_name(batch_inputs, tmp_path, capsys):
    other = tmp_path / "elsewhere"
    other.mkdir()
    twin = other / "hero.json"
    twin.write_text(batch_inputs["hero"].read_text())
    code = main(["batch", str(batch_inputs["hero"]), str(twin), "--garments", "skirt", "-o", str(tmp_path / "o")])
    assert code == 2
    assert "same name 'hero'" in capsys.readouterr().err
    assert not (tmp_path / "o").exists()


def test_batch_output_must_be_a_folder(batch_inputs, tmp_path, capsys):
    target = tmp_path / "file"
    target.write_text("x")
    code = main(["batch", str(batch_inputs["hero"]), "--garments", "skirt", "-o", str(target)])
    assert code == 2
    assert "is not a folder" in capsys.readouterr().err


def test_batch_names_a_missing_character_or_garment_before_starting(batch_inputs, tmp_path, capsys):
    out = tmp_path / "o"
    assert main(["batch", str(tmp_path / "nobody.obj"), "--garments", "skirt", "-o", str(out)]) == 2
    assert "nobody.obj: no such character file" in capsys.readouterr().err
    assert main(["batch", str(batch_inputs["hero"]), "--garments", "kilt", "-o", str(out)]) == 2
    assert "kilt: neither a pattern file nor a library garment" in capsys.readouterr().err
    assert not out.exists()


@pytest.mark.slow
@pytest.mark.shared
def test_a_real_character_measured_on_one_worker_fits_as_alone(characters_dir, tmp_path):
    # the measured mesh (rig, skin, detected landmarks) travels between worker processes
    mesh = str(characters_dir / "D_cartoon_child.obj")
    opts = ["--seed", "2", "--pop-size", "8", "--generations", "2", "--no-drape", "-q"]
    assert main(["batch", mesh, "--garments", "trousers", "-o", str(tmp_path / "out"), "--workers", "1", *opts]) == 0
    assert main(["fit", mesh, "--garment", "trousers", "-o", str(tmp_path / "alone"), *opts]) == 0
    case = tmp_path / "out" / "D_cartoon_child" / "trousers"
    for f in (tmp_path / "alone").iterdir():
        if f.name == "fit_report.json":
            assert timeless(json.loads(f.read_text())) == timeless(json.loads((case / f.name).read_text()))
        elif f.suffix != ".png":
            assert without_stamps(f.read_bytes()) == without_stamps((case / f.name).read_bytes()), f.name


@pytest.mark.slow
def test_batch_on_a_running_scheduler(batch_inputs, tmp_path):
    from distributed import LocalCluster

    p = batch_inputs
    out = tmp_path / "out"
    with LocalCluster(n_workers=1, threads_per_worker=1, processes=False, dashboard_address=None) as cluster:
        code = main(
            [
                "batch",
                str(p["hero"]),
                "--garments",
                str(p["skirt"]),
                "-o",
                str(out),
                "-q",
                "--scheduler",
                cluster.scheduler_address,
                *BUDGET,
            ]
        )
        assert code == 0
        assert len(cluster.scheduler.workers) == 1  # the batch leaves a cluster it did not start running
    manifest = json.loads((out / "batch.json").read_text())
    assert manifest["cluster"]["scheduler"] == cluster.scheduler_address
    assert [c["status"] for c in manifest["cases"]] == ["done"]
    assert (out / "hero" / "skirt" / "fit_report.json").is_file()
