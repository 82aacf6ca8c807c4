"""Hypothesis at the input boundary: any value anywhere in a real file gives a model or an ``InputError``.

Each test takes a real file, lets hypothesis pick a place in it and a
replacement (any JSON value: NaN, huge numbers, long strings, wrong types,
nesting), and calls the reader directly. The property: the reader either
returns an object whose numbers are finite, or raises the documented
``InputError`` subclass; no other exception escapes. ``derandomize=True``
keeps the examples the same on every run.
"""

from __future__ import annotations

import json
import struct

import numpy as np
import pytest
from fuzz_mutate import _glb, _glb_parts, _paths, _set
from fuzz_run import LIBRARY, SHARED
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from patternbridge.errors import InputError, LandmarkError, MeshError

SETTINGS = settings(
    max_examples=40, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow]
)

scalars = st.one_of(
    st.none(),
    st.booleans(),
    st.integers(min_value=-(2**70), max_value=2**70),
    st.floats(allow_nan=True, allow_infinity=True),
    st.sampled_from([1e308, -1e308, 5e-324, 0.0, -0.0, 1e6, 1e7]),
    st.text(max_size=8),
    st.just("N" * 100_000),
)
json_values = st.recursive(
    scalars, lambda inner: st.lists(inner, max_size=3) | st.dictionaries(st.text(max_size=4), inner, max_size=3),
    max_leaves=6,
)


def _replace_somewhere(data, draw_index: int, value):
    paths = list(_paths(data))
    return _set(data, paths[draw_index % len(paths)], value)


@SETTINGS
@given(index=st.integers(min_value=0, max_value=10_000), value=json_values)
def test_pattern_json_any_value_anywhere(tmp_path_factory, index, value):
    from patternbridge.io.pattern_json import load_pattern_json
    from patternbridge.pattern.geometry import area

    data = json.loads((LIBRARY / "shorts" / "shorts.json").read_text(encoding="utf-8"))
    path = tmp_path_factory.mktemp("p") / "p.json"
    path.write_text(json.dumps(_replace_somewhere(data, index, value), allow_nan=True), encoding="utf-8")
    try:
        pattern = load_pattern_json(path)
    except InputError as exc:
        assert "\n" not in str(exc) and len(str(exc)) < 1000
        return
    assert pattern.pieces
    assert all(np.isfinite(area(p.outline)) for p in pattern.pieces)


@pytest.fixture(scope="module")
def measurements_text(measurements_json) -> str:
    return measurements_json.read_text(encoding="utf-8")


@SETTINGS
@given(index=st.integers(min_value=0, max_value=10_000), value=json_values)
def test_measurements_any_value_anywhere(tmp_path_factory, measurements_text, index, value):
    from patternbridge.measure.model import load_measurements

    data = json.loads(measurements_text)
    path = tmp_path_factory.mktemp("m") / "m.json"
    path.write_text(json.dumps(_replace_somewhere(data, index, value), allow_nan=True), encoding="utf-8")
    try:
        values = load_measurements(path).values_cm()
    except InputError:
        return
    assert all(0 < v <= 1e4 for v in values.values())


@pytest.fixture(scope="module")
def sidecar_text() -> str:
    path = SHARED / "characters" / "E_average_male.json"
    if not path.is_file():
        pytest.skip("../shared is not beside the checkout")
    data = json.loads(path.read_text(encoding="utf-8"))
    # the checks are per entry: 50 vertices' weights stand for 13 380
    data["vertex_count"] = 50
    for key in ("indices", "weights"):
        data["skinning"][key] = data["skinning"][key][:50]
    return json.dumps(data)


@SETTINGS
@given(index=st.integers(min_value=0, max_value=10_000), value=json_values)
def test_sidecar_any_value_anywhere(sidecar_text, index, value):
    from patternbridge.mesh.validate import check_sidecar

    try:
        check_sidecar(_replace_somewhere(json.loads(sidecar_text), index, value), "E.json")
    except (MeshError, LandmarkError) as exc:
        assert "\n" not in str(exc) and len(str(exc)) < 1000


GLB = SHARED / "characters" / "variants" / "D_cartoon_child_rigged.glb"


@SETTINGS
@given(index=st.integers(min_value=0, max_value=10_000), value=json_values)
def test_glb_document_any_value_anywhere(tmp_path_factory, index, value):
    from patternbridge.mesh.gltf import read_gltf

    if not GLB.is_file():
        pytest.skip("../shared is not beside the checkout")
    doc, binary = _glb_parts(GLB.read_bytes())
    path = tmp_path_factory.mktemp("g") / "c.glb"
    path.write_bytes(_glb(_replace_somewhere(doc, index, value), binary))
    try:
        out = read_gltf(path)
    except MeshError as exc:
        assert "\n" not in str(exc) and len(str(exc)) < 1000
        return
    assert np.all(np.isfinite(out["vertices"]))
    assert out["faces"].min() >= 0 and out["faces"].max() < len(out["vertices"])


@SETTINGS
@given(cut=st.integers(min_value=0, max_value=2**31), junk=st.binary(min_size=1, max_size=16))
def test_glb_bytes_spliced(tmp_path_factory, cut, junk):
    """Random bytes written over the header, the chunk table or the binary data."""
    from patternbridge.mesh.gltf import read_gltf

    if not GLB.is_file():
        pytest.skip("../shared is not beside the checkout")
    data = GLB.read_bytes()
    n_json = struct.unpack_from("<I", data, 12)[0]
    hot = [0, 8, 12, 16, 20 + n_json, 24 + n_json, 28 + n_json]  # header, chunk lengths and types
    at = hot[cut % len(hot)] if cut % 2 else cut % len(data)
    path = tmp_path_factory.mktemp("b") / "c.glb"
    path.write_bytes(data[:at] + junk + data[at + len(junk) :])
    try:
        out = read_gltf(path)
    except MeshError:
        return
    assert np.all(np.isfinite(out["vertices"]))


@pytest.fixture(scope="module")
def shorts_dxf_pattern():
    from patternbridge.io.dxf_aama import read_dxf

    pattern, _ = read_dxf(LIBRARY / "shorts" / "shorts_aama.dxf")
    return pattern


@SETTINGS
@given(index=st.integers(min_value=0, max_value=10_000), value=json_values)
def test_bridge_sidecar_any_value_anywhere(tmp_path_factory, shorts_dxf_pattern, index, value):
    """The ``*.seams.json`` beside a DXF: applied, or one InputError."""
    from patternbridge.library.sidecar import apply_sidecar

    data = json.loads((LIBRARY / "shorts" / "shorts.seams.json").read_text(encoding="utf-8"))
    path = tmp_path_factory.mktemp("s") / "shorts.seams.json"
    path.write_text(json.dumps(_replace_somewhere(data, index, value), allow_nan=True), encoding="utf-8")
    try:
        pattern = apply_sidecar(shorts_dxf_pattern, path)
    except InputError as exc:
        assert "\n" not in str(exc) and len(str(exc)) < 1000
        return
    names = set(pattern.piece_names)
    assert all(s.a.piece in names and s.b.piece in names for s in pattern.seams)
