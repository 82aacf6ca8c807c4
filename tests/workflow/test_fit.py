"""``patternbridge.fit``: the workflow as a library function, its options, result and verdict."""

from __future__ import annotations

import json
import pickle
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import patternbridge
from patternbridge.cli.main import main
from patternbridge.errors import InputError
from patternbridge.io.pattern_json import save_pattern_json
from patternbridge.report import Report
from patternbridge.testing import timeless, without_stamps
from patternbridge.workflow import FitOptions, Subject, Verdict, figures_from_report, load_subject
from patternbridge.workflow.outputs import relative_files

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "grade"))
from grade_fixtures import skirt_pattern, write_skirt_inputs

TINY = FitOptions(pop_size=20, n_gen=10)


@pytest.fixture
def inputs(tmp_path):
    return write_skirt_inputs(tmp_path)


def test_fit_returns_what_it_wrote(inputs, tmp_path):
    pattern_path, body_path = inputs
    out = tmp_path / "out"
    result = patternbridge.fit(body_path, pattern_path, seed=3, options=TINY, out_dir=out)
    assert result.character == "hero" and result.garment == "skirt" and result.size == "hero"
    assert sorted(result.files) == sorted(p.name for p in out.iterdir())
    assert result.files[-1] == "fit_report.json"
    on_disk = json.loads((out / "fit_report.json").read_text())
    assert on_disk == json.loads(json.dumps(dict(result.report)))
    fig = result.figures
    assert fig.mean_error_cm == on_disk["mean_error_cm"] and fig.shape_error == on_disk["shape_error"]
    assert fig.baseline_shape_error == on_disk["baseline"]["shape_error"]
    assert fig.mean_error_cm <= 0.5 and fig.shape_error < fig.baseline_shape_error
    # measurements only: no mesh to drape, so no verdict and no seam gap
    assert result.verdict is None and fig.seam_gap_before_weld_mm is None
    assert on_disk["drape"] == {"skipped": "measurements given without a character mesh"}
    assert on_disk["settings"]["seed"] == 3 and on_disk["settings"]["pop_size"] == 20
    with pytest.raises(TypeError):
        result.report["extra"] = 1


def test_fit_is_the_cli_fit(inputs, tmp_path):
    pattern_path, body_path = inputs
    lib = patternbridge.fit(body_path, pattern_path, seed=2, options=TINY, out_dir=tmp_path / "lib")
    assert main(["fit", str(body_path), "--garment", str(pattern_path), "-o", str(tmp_path / "cli"), "-q",
                 "--seed", "2", "--pop-size", "20", "--generations", "10"]) == 0
    for name in lib.files:
        a, b = (tmp_path / "lib" / name), (tmp_path / "cli" / name)
        if name == "fit_report.json":
            assert timeless(json.loads(a.read_text())) == timeless(json.loads(b.read_text()))
        elif not name.endswith(".png"):
            assert without_stamps(a.read_bytes()) == without_stamps(b.read_bytes()), name


def test_a_failed_fit_leaves_no_folder(inputs, tmp_path):
    _, body_path = inputs
    bare = tmp_path / "bare.json"
    save_pattern_json(skirt_pattern(links=False), bare)
    with pytest.raises(InputError, match="no measurement links"):
        patternbridge.fit(body_path, bare, options=TINY, out_dir=tmp_path / "o")
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [({"deformation": "spline"}, "deformation 'spline' is unknown"), ({"pop_size": 0}, "pop_size must be"),
     ({"n_gen": 2.5}, "n_gen must be"), ({"n_gen": True}, "n_gen must be")],
)
def test_fit_options_refuse_bad_values(kwargs, message):
    with pytest.raises(InputError, match=message):
        FitOptions(**kwargs)


def test_fit_options_reach_the_grader_by_name():
    assert FitOptions().grader_kwargs() == {"deformation": "bilinear", "do_repair": True}
    assert FitOptions(pop_size=8, n_gen=2, repair=False).grader_kwargs() == {
        "deformation": "bilinear", "do_repair": False, "pop_size": 8, "n_gen": 2}


REPORT = {"mean_error_cm": 0.1, "max_error_cm": 0.3, "max_seam_mm": 0.2, "shape_error": 0.01, "seconds": 5.0,
          "baseline": {"shape_error": 0.05, "mean_error_cm": 1.2}}


@pytest.mark.parametrize(
    ("drape", "verdict"),
    [(None, None), ({"seconds": 9.0}, None), ({"verdict": "failed"}, Verdict.FAILED),
     ({"verdict": "OK"}, Verdict.OK), ({"verdict": {"verdict": "flawed", "reasons": []}}, Verdict.FLAWED),
     ({"verdict": "splendid"}, None)],
)
def test_the_verdict_is_read_from_the_drape_report(drape, verdict):
    report = {**REPORT, **({"drape": drape} if drape is not None else {})}
    assert figures_from_report(report).verdict is verdict


def test_figures_of_a_draped_report():
    fig = figures_from_report({**REPORT, "drape": {"seconds": 30.0, "max_seam_gap_before_weld_mm": 4.5}})
    assert (fig.seam_gap_before_weld_mm, fig.drape_seconds, fig.grading_seconds) == (4.5, 30.0, 5.0)
    assert (fig.baseline_shape_error, fig.baseline_mean_error_cm) == (0.05, 1.2)


def _box_subject(body_path):
    """The measured skirt body with a small box as its mesh (enough for a stand-in drape)."""
    from patternbridge.mesh.character import Character

    subject, _ = load_subject(body_path)
    v = np.array([[x, y, z] for x in (0, 30) for y in (0, 170) for z in (0, 20)], dtype=float)
    f = np.array([[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1],
                  [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]])
    return Subject(name="hero", source=str(body_path), measurements=subject.measurements,
                   character=Character(vertices=v, faces=f, name="hero"))


def test_cli_exits_3_on_a_failed_drape_and_still_writes_the_files(inputs, tmp_path, monkeypatch, capsys):
    import patternbridge.assemble as assemble
    import patternbridge.workflow as workflow

    pattern_path, body_path = inputs
    subject = _box_subject(body_path)

    def failed_drape(character, pattern, out_dir, *, seed, progress):
        (Path(out_dir) / "fit_front.png").write_bytes(b"png")
        return {"verdict": "failed", "seconds": 1.0, "max_seam_gap_before_weld_mm": 80.0,
                "verdict_reasons": [{"check": "seam_gap", "message": "seams open before welding by up to 80.0 mm"}],
                "fabric": {"class": "stretch_knit"},
                "files": [str(Path(out_dir) / "fit_front.png")]}

    monkeypatch.setattr(workflow, "load_subject", lambda *a, **k: (subject, Report()))
    monkeypatch.setattr(assemble, "dress", failed_drape)
    out = tmp_path / "out"
    code = main(["fit", str(body_path), "--garment", str(pattern_path), "-o", str(out), "-q",
                 "--pop-size", "20", "--generations", "10"])
    assert code == 3
    last = capsys.readouterr().err.strip().splitlines()[-1]  # the verdict is said last, with its reasons
    assert last.startswith(
        "patternbridge: drape verdict failed (judged as a stretch knit): seams open before welding by up to 80.0 mm"
    )
    rep = json.loads((out / "fit_report.json").read_text())
    assert rep["drape"]["verdict"] == "failed" and rep["drape"]["files"] == ["fit_front.png"]
    assert (out / "fit_front.png").is_file() and (out / "skirt_aama.dxf").is_file()


def test_a_subject_survives_pickling_frozen(inputs):
    # the batch measures a character on one worker and fits it on another
    _, body_path = inputs
    subject = _box_subject(body_path)
    back = pickle.loads(pickle.dumps(subject))
    assert back.name == "hero" and back.measurements.values_cm() == subject.measurements.values_cm()
    np.testing.assert_array_equal(back.character.vertices, subject.character.vertices)
    assert not back.character.vertices.flags.writeable
    with pytest.raises(TypeError):
        back.measurements.measurements["x"] = None


def test_drape_files_are_named_relative_to_out():
    files = ["/x/OUT/.fit-abc/drape/garment.glb", "/x/OUT/.fit-abc/drape/garment.obj", "/elsewhere/not_moved.png"]
    assert relative_files(files, ["garment.glb", "garment.mtl", "garment.obj"]) == ["garment.glb", "garment.obj"]
    assert relative_files(None, ["b.png", "a.png"]) == ["a.png", "b.png"]


def test_import_patternbridge_stays_light():
    code = ("import sys, patternbridge, patternbridge.workflow, patternbridge.batch; "
            "heavy = [m for m in ('pymoo', 'open3d', 'ezdxf', 'distributed', 'matplotlib') if m in sys.modules]; "
            "print(heavy); assert callable(patternbridge.fit)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                         cwd=Path(__file__).resolve().parents[2])
    assert out.stdout.strip() == "[]"


def test_cli_refuses_a_garment_without_links_before_measuring(inputs, tmp_path, monkeypatch, capsys):
    import patternbridge.workflow as workflow

    _, body_path = inputs
    bare = tmp_path / "bare.json"
    save_pattern_json(skirt_pattern(links=False), bare)
    measured = []
    monkeypatch.setattr(workflow, "load_subject", lambda *a, **k: measured.append(a))
    assert main(["fit", str(body_path), "--garment", str(bare), "-o", str(tmp_path / "o")]) == 2
    assert "no measurement links" in capsys.readouterr().err
    assert measured == [] and not (tmp_path / "o").exists()
