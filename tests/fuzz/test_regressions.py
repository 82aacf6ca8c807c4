"""Minimal reproducers of issue 20's malformed-input classes: each gets one line, exit 2, nothing written.

The DXF/RUL-reader and unit-detection classes are in ``test_regressions_reader.py``.
"""

from __future__ import annotations

import json
import struct
import time
from pathlib import Path

import numpy as np
import pytest
from fuzz_mutate import _glb, _glb_parts
from fuzz_run import SHARED, Case, Outcome, assert_clean_error, run_case

CHARACTERS = SHARED / "characters"
E_OBJ = CHARACTERS / "E_average_male.obj"
CHILD_GLB = CHARACTERS / "variants" / "D_cartoon_child_rigged.glb"

needs_shared = pytest.mark.skipif(not CHARACTERS.is_dir(), reason="../shared is not beside the checkout")


def _write_json(path: Path, obj) -> Path:
    path.write_text(json.dumps(obj, allow_nan=True), encoding="utf-8")
    return path


# ------------------------------------------------------------------ pattern JSON
@pytest.mark.parametrize("top", ["[]", "null", '"shirt"', "3"])
def test_pattern_json_top_level_not_an_object(cli, tmp_path, top):
    path = tmp_path / "p.json"
    path.write_text(top, encoding="utf-8")
    assert_clean_error(cli("info", path), "p.json", "top level: expected an object")


def test_pattern_json_deeply_nested(cli, tmp_path, shorts_dict):
    text = json.dumps(shorts_dict).replace('"pieces": [', '"pieces": [' + "[" * 100_000 + "]" * 100_000 + ",", 1)
    path = tmp_path / "p.json"
    path.write_text(text, encoding="utf-8")
    assert_clean_error(cli("info", path), "nests 100002 levels deep")


def test_pattern_json_coordinate_1e308(cli, tmp_path, shorts_dict):
    shorts_dict["pieces"][1]["outline"][3][1] = 1e308
    out = tmp_path / "out" / "e.dxf"
    err = assert_clean_error(cli("export", _write_json(tmp_path / "p.json", shorts_dict), "-o", out), outputs=(out,))
    assert "pieces[1].outline[3][1]" in err and "1e+308" in err


@pytest.mark.parametrize("literal", ["NaN", "Infinity", "-Infinity", "1e400"])
def test_pattern_json_non_finite_number(cli, tmp_path, shorts_dict, literal):
    text = json.dumps(shorts_dict).replace('"ease_cm": 0.0', f'"ease_cm": {literal}', 1)
    assert literal in text
    path = tmp_path / "p.json"
    path.write_text(text, encoding="utf-8")
    assert_clean_error(cli("check", path), "not valid JSON")


def test_pattern_json_no_pieces(cli, tmp_path, shorts_dict):
    shorts_dict["pieces"] = []
    out = tmp_path / "out" / "e.dxf"
    err = assert_clean_error(cli("export", _write_json(tmp_path / "p.json", shorts_dict), "-o", out), outputs=(out,))
    assert "pieces: expected at least 1 item" in err


@pytest.mark.parametrize(
    ("where", "value", "needle"),
    [
        (("pieces", 0, "name"), ["FRONT"], "pieces[0].name: expected a string, got an array"),
        (("pieces", 0, "quantity"), {"right": "two", "left": 0}, "pieces[0].quantity.right: expected an integer"),
        (("pieces", 0, "notches"), {"vertex": 1}, "pieces[0].notches: expected an array, got an object"),
        (("seams", 0, "a"), None, "seams[0].a: expected an object, got null"),
        (("measurements", 0, "legs", 0), 7, "measurements[0].legs[0]: expected an object, got a number"),
        (("pieces", 0, "outline"), [[0, 0], [1, 1]], "pieces[0].outline: expected at least 3 item(s)"),
        (("pieces", 0, "annotation"), "x" * 70_000, "text of 70000 characters"),
        (("pieces", 0, "quantity", "right"), True, "expected an integer, got a boolean"),
    ],
)
def test_pattern_json_wrong_types(cli, tmp_path, shorts_dict, where, value, needle):
    target = shorts_dict
    for key in where[:-1]:
        target = target[key]
    target[where[-1]] = value
    assert_clean_error(cli("info", _write_json(tmp_path / "p.json", shorts_dict)), needle)


def test_pattern_json_unknown_keys_are_kept_readable(cli, tmp_path, shorts_dict):
    """A newer writer's extra field does not make the file unreadable."""
    shorts_dict["pieces"][0]["role"] = "front"
    shorts_dict["pieces"][0]["future_piece_field"] = [1, 2]
    shorts_dict["future_field"] = {"x": 1}
    code, out, err = cli("info", _write_json(tmp_path / "p.json", shorts_dict), "--json")
    assert code == 0, err
    assert json.loads(out)["pieces"][0]["name"] == shorts_dict["pieces"][0]["name"]


# ------------------------------------------------------------------ plot
def test_plot_long_piece_name_is_fast_and_cut(cli, tmp_path, shorts_dict):
    name = "N" * 60_000
    shorts_dict["pieces"][0]["name"] = name
    for seam in shorts_dict["seams"]:
        for side in ("a", "b"):
            if seam[side]["piece"] == "FRONT":
                seam[side]["piece"] = name
    for link in shorts_dict["measurements"]:
        for leg in link["legs"]:
            if leg["piece"] == "FRONT":
                leg["piece"] = name
    out = tmp_path / "out" / "p.svg"
    t0 = time.perf_counter()
    code, _, err = cli("plot", _write_json(tmp_path / "p.json", shorts_dict), "-o", out, "--title", "T" * 100_000)
    assert code == 0, err[-2000:]
    assert time.perf_counter() - t0 < 30
    svg = out.read_text(encoding="utf-8")
    assert "N" * 59 + "…" in svg and "N" * 61 not in svg
    assert "T" * 200 not in svg
    assert not list(out.parent.glob(".p.*"))


def test_plot_failure_leaves_no_temporary_file(cli, tmp_path, monkeypatch):
    from matplotlib.figure import Figure

    from patternbridge.errors import InputError

    def broken(self, fname, **kwargs):
        Path(fname).write_bytes(b"half")
        raise InputError("disk full (simulated)")

    monkeypatch.setattr(Figure, "savefig", broken)
    out = tmp_path / "out" / "p.png"
    assert_clean_error(cli("plot", "shorts", "-o", out), "disk full", outputs=(out,))


def test_terminated_command_leaves_no_temporary_file(tmp_path, monkeypatch):
    """SIGTERM in the middle of a write: the temporary file beside the target is removed."""
    import os
    import signal

    from patternbridge.atomic import atomic_path
    from patternbridge.cli.main import _terminate_cleanly

    target = tmp_path / "out.png"
    with pytest.raises(BaseException) as info, _terminate_cleanly(), atomic_path(target) as tmp:
        tmp.write_bytes(b"half")
        os.kill(os.getpid(), signal.SIGTERM)
        time.sleep(5)
    assert type(info.value).__name__ == "_Terminated"
    assert not target.exists()
    assert list(tmp_path.iterdir()) == []


# ------------------------------------------------------------------ CLI arguments
@pytest.mark.parametrize(
    ("option", "value", "needle"),
    [("--pop-size", "-3", "outside 4..10000"), ("--generations", "0", "outside 1..100000"),
     ("--seed", "-5", "outside 0..4294967295"), ("--seed", "x", "not a whole number")],
)
def test_fit_bad_numbers_are_usage_errors(cli, tmp_path, option, value, needle):
    code, _, err = cli("fit", tmp_path / "m.json", "--garment", "shorts", option, value, "-o", tmp_path / "out")
    assert code == 2 and "Traceback" not in err
    assert needle in err.splitlines()[-1]
    assert not (tmp_path / "out").exists()


# ------------------------------------------------------------------ measurements JSON as fit's character
@needs_shared
@pytest.mark.parametrize(("literal", "needle"), [("NaN", "not valid JSON"), ("-3.0", "outside (0, 10000] cm"),
                                                 ("0", "outside (0, 10000] cm"), ('"wide"', "must be a number")])
def test_measurements_bad_girth_fit(cli, tmp_path, measurements_json, literal, needle):
    text = measurements_json.read_text(encoding="utf-8")
    value = json.loads(text)["measurements"]["hip_girth"]["value_cm"]
    path = tmp_path / "m.json"
    path.write_text(text.replace(f'"value_cm": {value}', f'"value_cm": {literal}', 1), encoding="utf-8")
    out = tmp_path / "out"
    assert_clean_error(cli("fit", path, "--garment", "shorts", "--no-drape", "-o", out), needle)
    assert not out.exists()


def test_measurements_deep_nesting_fit(cli, tmp_path):
    path = tmp_path / "m.json"
    path.write_text('{"measurements": ' + "[" * 50_000 + "]" * 50_000 + "}", encoding="utf-8")
    assert_clean_error(cli("fit", path, "--garment", "shorts", "-o", tmp_path / "out"), "nests")


# ------------------------------------------------------------------ meshes
def _glb_case(tmp_path: Path, data: bytes) -> Path:
    path = tmp_path / "c.glb"
    path.write_bytes(data)
    return path


@needs_shared
def test_glb_truncated(cli, tmp_path):
    data = CHILD_GLB.read_bytes()
    path = _glb_case(tmp_path, data[: len(data) // 2])
    out = tmp_path / "out" / "m.json"
    assert_clean_error(cli("measure", path, "-o", out), "truncated GLB", outputs=(out,))


@needs_shared
def test_glb_without_binary_chunk(cli, tmp_path):
    doc, _ = _glb_parts(CHILD_GLB.read_bytes())
    out = tmp_path / "out" / "m.json"
    err = assert_clean_error(cli("measure", _glb_case(tmp_path, _glb(doc, None)), "-o", out), outputs=(out,))
    assert "binary chunk" in err


@needs_shared
@pytest.mark.parametrize("factor", [2, 1000])
def test_glb_accessor_count_beyond_buffer(cli, tmp_path, factor):
    doc, binary = _glb_parts(CHILD_GLB.read_bytes())
    doc["accessors"][0]["count"] *= factor
    out = tmp_path / "out" / "m.json"
    err = assert_clean_error(cli("measure", _glb_case(tmp_path, _glb(doc, binary)), "-o", out), outputs=(out,))
    assert "accessor 0 needs" in err


@needs_shared
@pytest.mark.parametrize(
    ("edit", "needle"),
    [
        (lambda d: d["nodes"][-1].setdefault("children", []).append(1), "two parents"),
        (lambda d: d["nodes"][0].update(mesh=9), "meshes[9]"),
        (lambda d: d["accessors"][0].update(componentType=1), "componentType 1"),
        (lambda d: d["nodes"][0].update(scale=[1e300, 1e300, 1e300]), "scale"),
        (lambda d: d["skins"][0].update(joints=[]), "joints"),
    ],
)
def test_glb_inconsistent_structure(cli, tmp_path, edit, needle):
    doc, binary = _glb_parts(CHILD_GLB.read_bytes())
    edit(doc)
    out = tmp_path / "out" / "m.json"
    assert_clean_error(cli("measure", _glb_case(tmp_path, _glb(doc, binary)), "-o", out), needle, outputs=(out,))


def _scaled_obj(tmp_path: Path, factor: float, sidecar: bool) -> Path:
    lines = []
    for line in E_OBJ.read_text(encoding="utf-8").splitlines():
        if line.startswith("v "):
            xyz = np.array(line.split()[1:4], dtype=float) * factor
            line = "v " + " ".join(repr(float(c)) for c in xyz)
        lines.append(line)
    path = tmp_path / "E_average_male.obj"
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    if sidecar:  # the sidecar says cm: no unit detection stands in the way
        (tmp_path / "E_average_male.json").write_bytes(E_OBJ.with_suffix(".json").read_bytes())
    return path


@needs_shared
@pytest.mark.parametrize("sidecar", [True, False])
def test_obj_coordinates_times_1e300_measure(cli, tmp_path, sidecar):
    out = tmp_path / "out" / "m.json"
    assert_clean_error(cli("measure", _scaled_obj(tmp_path, 1e300, sidecar), "-o", out), outputs=(out,))


@needs_shared
def test_obj_coordinates_times_1e300_geodesic(cli, tmp_path):
    err = assert_clean_error(cli("geodesic", _scaled_obj(tmp_path, 1e300, True), "--from", "0", "--to", "881"))
    assert "beyond" in err


@needs_shared
def test_obj_all_vertices_equal(cli, tmp_path):
    out = tmp_path / "out" / "m.json"
    assert_clean_error(cli("measure", _scaled_obj(tmp_path, 0.0, True), "-o", out), "within", outputs=(out,))


# ------------------------------------------------------------------ sidecars and landmark files
@needs_shared
@pytest.mark.parametrize(
    ("edit", "needle"),
    [
        (lambda d: d["skeleton"]["bones"][3].update(head=[1e30, 0, 0]), "bone 3 head"),
        (lambda d: d["skinning"].update(indices=d["skinning"]["indices"][:-1]), "do not match"),
        (lambda d: d["skinning"]["indices"][5].__setitem__(0, 9999), "indices outside"),
        (lambda d: d.update(vertex_count="many"), "vertex_count"),
        (lambda d: d["landmarks"]["top_of_head"].update(vertex=True), "not a vertex id"),
        (lambda d: d.update(skeleton=[]), "skeleton"),
    ],
)
def test_sidecar_malformed_fields(cli, tmp_path, edit, needle):
    mesh = tmp_path / "E_average_male.obj"
    mesh.write_bytes(E_OBJ.read_bytes())
    data = json.loads(E_OBJ.with_suffix(".json").read_text(encoding="utf-8"))
    edit(data)
    _write_json(tmp_path / "E_average_male.json", data)
    out = tmp_path / "out" / "m.json"
    assert_clean_error(cli("measure", mesh, "-o", out), needle, outputs=(out,))


@needs_shared
@pytest.mark.parametrize(
    ("table", "needle"),
    [
        ({"landmarks": {"top_of_head": {"position": [0, 1e308, 0]}}}, "position"),
        ({"landmarks": {"top_of_head": {"position": [0, "up", 0]}}}, "position"),
        ({"landmarks": {"top_of_head": {"vertex": 1.5}}}, "not a vertex id"),
        ({"landmarks": [1, 2]}, "landmarks"),
        ({"landmarks": {"N" * 5000: {"vertex": 1}}}, "landmark name"),
    ],
)
def test_landmark_file_malformed(cli, tmp_path, table, needle):
    path = _write_json(tmp_path / "lm.json", table)
    out = tmp_path / "out" / "m.json"
    assert_clean_error(cli("measure", E_OBJ, "--landmarks", path, "-o", out), needle, outputs=(out,))


def test_landmark_file_deeply_nested(cli, tmp_path):
    path = tmp_path / "lm.json"
    path.write_text('{"landmarks": ' + "[" * 100_000 + "]" * 100_000 + "}", encoding="utf-8")
    assert_clean_error(cli("geodesic", E_OBJ, "--landmarks", path, "--from", "0", "--to", "1"), "nests")


# ------------------------------------------------------------------ the runner itself
def test_runner_reports_a_hang(tmp_path):
    """A case that does not finish is killed and reported, not waited for."""
    case = Case("args", json.dumps(["plot", "{IN}", "-o", "{OUT}/p.png"]), "argv", 0, "plot")
    result = run_case(case, tmp_path, tmp_path / "m.json", timeout_s=0.05)
    assert result.outcome is Outcome.HANG
    assert result.seconds < 5


def test_glb_helpers_round_trip():
    """The GLB re-writer used by the mutations keeps an untouched file readable byte for byte."""
    if not CHILD_GLB.is_file():
        pytest.skip("../shared is not beside the checkout")
    data = CHILD_GLB.read_bytes()
    doc, binary = _glb_parts(data)
    again = _glb(doc, binary)
    assert struct.unpack_from("<I", again, 8)[0] == len(again)
    assert _glb_parts(again) == (doc, binary)
