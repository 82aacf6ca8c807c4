"""Cases, what earlier runs left, the manifest and the page's HTML (no cluster needed)."""

from __future__ import annotations

import json

import pytest

from patternbridge.batch import CaseOutcome, CaseStatus, make_cases, plan
from patternbridge.batch.cases import write_failure
from patternbridge.batch.html import index_html
from patternbridge.batch.manifest import BatchInputs, manifest_dict
from patternbridge.errors import InputError
from patternbridge.workflow import FitFigures, FitOptions, Verdict


def test_cases_are_characters_times_garments_named_by_stem():
    cases = make_cases(["chars/A_hero.obj", "chars/B.json", "chars/A_hero.obj"], ["shirt", "lib/My Skirt.dxf"])
    assert [c.key for c in cases] == ["A_hero/shirt", "A_hero/My_Skirt", "B/shirt", "B/My_Skirt"]
    assert cases[1].garment_spec == "lib/My Skirt.dxf" and cases[2].character_path == "chars/B.json"


def test_two_garments_with_one_name_are_refused():
    with pytest.raises(InputError, match="same name 'shirt'"):
        make_cases(["a.obj"], ["shirt", "mine/shirt.json"])


def _done(folder, mean=0.2):
    folder.mkdir(parents=True)
    report = {"mean_error_cm": mean, "max_error_cm": 0.4, "max_seam_mm": 0.1, "shape_error": 0.02, "seconds": 7.0,
              "baseline": {"shape_error": 0.05, "mean_error_cm": 1.0},
              "drape": {"seconds": 20.0, "verdict": "flawed", "max_seam_gap_before_weld_mm": 3.0}}
    (folder / "fit_report.json").write_text(json.dumps(report))
    (folder / "fit_front.png").write_bytes(b"png")


def test_plan_keeps_finished_and_failed_cases_and_clears_what_a_killed_run_left(tmp_path):
    cases = make_cases(["a.obj", "b.obj"], ["shirt", "trousers"])
    _done(tmp_path / "a" / "shirt")
    write_failure(CaseOutcome(case=cases[1], status=CaseStatus.FAILED, error="InputError: bad"), tmp_path)
    (tmp_path / "b" / ".part-shirt-x1").mkdir(parents=True)  # a worker died while writing b/shirt
    kept, todo = plan(cases, tmp_path)
    assert [o.case.key for o in kept] == ["a/shirt", "a/trousers"]
    assert [c.key for c in todo] == ["b/shirt", "b/trousers"]
    assert not (tmp_path / "b" / ".part-shirt-x1").exists()
    done, failed = kept
    assert done.reused and done.status is CaseStatus.DONE and done.verdict is Verdict.FLAWED
    assert done.seconds == 27.0 and done.files == ("fit_front.png", "fit_report.json")
    assert failed.status is CaseStatus.FAILED and failed.error == "InputError: bad"
    kept, todo = plan(cases, tmp_path, retry_failed=True)
    assert [o.case.key for o in kept] == ["a/shirt"] and [c.key for c in todo] == ["a/trousers", "b/shirt",
                                                                                    "b/trousers"]


def _manifest():
    cases = make_cases(["a&b.obj", "plain.obj"], ["shirt", "trousers"])
    fig = FitFigures(mean_error_cm=0.25, max_error_cm=0.5, max_seam_mm=0.1, shape_error=0.0312,
                     baseline_shape_error=0.0571, baseline_mean_error_cm=1.4, seam_gap_before_weld_mm=2.5,
                     verdict=Verdict.OK, grading_seconds=9.0, drape_seconds=30.0)
    outcomes = [CaseOutcome(case=cases[0], status=CaseStatus.DONE, seconds=41.0, figures=fig,
                            files=("fit_front.png", "pattern.png")),
                CaseOutcome(case=cases[2], status=CaseStatus.LOST, error="KilledWorker: <gone>")]
    inputs = BatchInputs(characters={c.character: c.character_path for c in cases},
                         garments={c.garment: c.garment_spec for c in cases}, seed=7, options=FitOptions(n_gen=3))
    return manifest_dict(inputs, outcomes, seconds=50.0)


def test_manifest_records_inputs_seed_options_and_cases():
    m = _manifest()
    assert m["seed"] == 7 and m["options"]["n_gen"] == 3 and m["counts"] == {"done": 1, "lost": 1}
    assert [c["name"] for c in m["inputs"]["characters"]] == ["a_b", "plain"]
    first = m["cases"][0]
    assert first["verdict"] == "ok" and first["figures"]["shape_error"] == 0.0312 and first["seed"] == 7
    assert json.loads(json.dumps(m)) == m


def test_page_has_a_row_per_character_a_column_per_garment_and_escapes_text():
    page = index_html(_manifest())
    assert page.count("<tr data-character=") == 2
    assert '<th data-col="0">shirt</th><th data-col="1">trousers</th>' in page
    assert "KilledWorker: &lt;gone&gt;" in page and "<gone>" not in page.split('id="batch-data"')[0]
    assert 'src="a_b/shirt/fit_front.png"' in page
    assert page.count("not run") == 2  # a_b/trousers and plain/trousers
    assert "0.0312 (prop. 0.0571)" in page
