"""``OUT/index.html`` in a real headless browser (Debian's chromium driven by Playwright).

The page must load without console errors, show one row per character,
sort by a garment's figures, filter, and open a case's pictures.
"""

from __future__ import annotations

import os
import shutil
from pathlib import Path

import pytest
from PIL import Image

from patternbridge.batch import CaseOutcome, CaseStatus, make_cases
from patternbridge.batch.html import write_index
from patternbridge.batch.manifest import BatchInputs, manifest_dict
from patternbridge.workflow import FitFigures, FitOptions, Verdict

CHROMIUM = "/usr/bin/chromium"
ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--no-first-run", "--disable-background-networking",
        "--disable-component-update", "--disable-sync"]


def _browser():
    """Playwright's chromium API; in CI a missing browser is an error, elsewhere a skip."""
    missing = None
    try:
        from playwright.sync_api import sync_playwright
    except ImportError:
        missing = "Python playwright is not installed"
    if missing is None and not Path(CHROMIUM).is_file():
        missing = f"{CHROMIUM} is missing (apt-get install chromium)"
    if missing:
        if os.environ.get("CI"):
            pytest.fail(missing)
        pytest.skip(missing)
    return sync_playwright


def _case_folder(out: Path, key: str, colour: tuple[int, int, int]) -> tuple[str, ...]:
    folder = out / key
    folder.mkdir(parents=True)
    names = ("fit_front.png", "pattern.png", "pareto.png", "fit_report.json")
    for name in names[:3]:
        Image.new("RGB", (60, 90), colour).save(folder / name)
    (folder / "fit_report.json").write_text("{}")
    return names


@pytest.fixture
def batch_page(tmp_path) -> Path:
    """A batch of three characters × two garments: errors 0.30, 0.10, 0.20 cm on the shirt, one lost case."""
    cases = make_cases(["carl.obj", "anna.obj", "bert.obj"], ["shirt", "trousers"])
    outcomes = []
    for case, mean, colour in zip(cases[::2], (0.30, 0.10, 0.20), ((200, 40, 40), (40, 200, 40), (40, 40, 200)),
                                  strict=True):
        fig = FitFigures(mean_error_cm=mean, max_error_cm=2 * mean, max_seam_mm=0.1, shape_error=mean / 10,
                         baseline_shape_error=0.05, baseline_mean_error_cm=1.0, seam_gap_before_weld_mm=3.0,
                         verdict=Verdict.OK if mean < 0.25 else Verdict.FLAWED)
        outcomes.append(CaseOutcome(case=case, status=CaseStatus.DONE, seconds=60 * mean, figures=fig,
                                    files=_case_folder(tmp_path, case.key, colour)))
    outcomes.append(CaseOutcome(case=cases[1], status=CaseStatus.LOST, error="KilledWorker: worker died"))
    inputs = BatchInputs(characters={c.character: c.character_path for c in cases},
                         garments={c.garment: c.garment_spec for c in cases}, seed=0, options=FitOptions())
    write_index(tmp_path, manifest_dict(inputs, outcomes, seconds=100.0))
    return tmp_path / "index.html"


def _rows(page) -> list[str]:
    return page.eval_on_selector_all("#cases tbody tr:not([hidden])", "rows => rows.map(r => r.dataset.character)")


def test_the_page_loads_sorts_filters_and_opens_a_case(batch_page, tmp_path):
    sync_playwright = _browser()
    problems: list[str] = []
    with sync_playwright() as pw:
        browser = pw.chromium.launch(executable_path=CHROMIUM, args=ARGS)
        try:
            page = browser.new_page(viewport={"width": 1000, "height": 700})
            page.on("console", lambda m: problems.append(m.text) if m.type in ("error", "warning") else None)
            page.on("pageerror", lambda e: problems.append(str(e)))
            page.on("requestfailed", lambda r: problems.append(f"failed to load {r.url}"))
            page.goto(batch_page.as_uri())
            page.wait_for_load_state("load")
            assert _rows(page) == ["carl", "anna", "bert"]
            assert page.locator("#cases thead th").all_inner_texts() == ["character", "shirt", "trousers"]
            # every thumbnail decoded (a broken link has naturalWidth 0)
            widths = page.eval_on_selector_all("td.case img", "imgs => imgs.map(i => i.naturalWidth)")
            assert widths == [60, 60, 60]

            page.click("#cases thead th >> text=shirt")  # by measurement error, ascending
            assert _rows(page) == ["anna", "bert", "carl"]
            page.click("#cases thead th >> text=shirt")
            assert _rows(page) == ["carl", "bert", "anna"]
            page.click("#cases thead th >> text=character")
            assert _rows(page) == ["anna", "bert", "carl"]

            page.select_option("#status", "flawed")
            assert _rows(page) == ["carl"]
            page.select_option("#status", "lost")
            assert _rows(page) == ["carl"]
            page.select_option("#status", "all")
            page.fill("#filter", "ER")
            assert _rows(page) == ["bert"]
            page.fill("#filter", "")

            page.click("td.case[data-key='anna/shirt']")
            dialog = page.locator("#detail")
            assert dialog.is_visible()
            assert "anna × shirt — ok" in dialog.inner_text()
            assert dialog.locator("img").count() == 3
            assert dialog.locator("a[href='anna/shirt/fit_report.json']").count() == 1
            shot = tmp_path / "index.png"
            page.screenshot(path=str(shot), full_page=True)
        finally:
            browser.close()
    assert problems == []
    with Image.open(shot) as image:
        assert image.size[0] == 1000 and image.size[1] >= 300
        # the dialog shows anna's green picture
        assert (40, 200, 40) in {c for _, c in image.convert("RGB").getcolors(1 << 20)}
    keep = os.environ.get("PATTERNBRIDGE_KEEP_SCREENSHOT")
    if keep:
        shutil.copy(shot, keep)
