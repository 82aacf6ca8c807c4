"""The size chart a tailor's file is read against (``bridge.size_chart``) and the ease it gives on the real files."""

from __future__ import annotations

import json

import pytest

from patternbridge.bridge import infer_bridge
from patternbridge.bridge.links import measurement_links
from patternbridge.bridge.sidecar import inference_sidecar
from patternbridge.bridge.size_chart import REFERENCE_BODY_CM, SizeSystem, body_at, choose_chart
from patternbridge.io.dxf_aama import read_dxf
from patternbridge.library.sidecar import apply_sidecar
from patternbridge.library.sizes import MEN, WOMEN
from patternbridge.pattern.json_check import check_sidecar_dict

WOMEN_SIZES = tuple(str(s) for s in range(26, 54, 2))
MEN_SIZES = tuple(str(s) for s in range(42, 72, 2))


def test_a_chart_read_at_one_of_its_sizes_is_that_size():
    for chart, key in ((MEN, "chest_girth"), (WOMEN, "bust_girth")):
        for size in chart.sizes:
            body = body_at(chart, key, chart.body(size)[key])
            assert body == pytest.approx(chart.body(size)), (chart.name, size)
    # past its last size a chart goes on with its own steps
    assert body_at(MEN, "chest_girth", 108.0)["waist_girth"] == pytest.approx(96.0)


def test_size_systems_from_the_labels():
    women = choose_chart(WOMEN_SIZES, "36")
    assert women.system is SizeSystem.WOMEN_EU
    assert women.body_cm["chest_girth"] == pytest.approx(84.0)
    assert choose_chart(WOMEN_SIZES, "40").body_cm["chest_girth"] == pytest.approx(92.0)
    men = choose_chart(MEN_SIZES, "50")
    assert men.system is SizeSystem.MEN_EU
    chart_dims = {k: v for k, v in men.body_cm.items() if k in MEN.dims}
    assert chart_dims == pytest.approx(MEN.body("100"))  # size 50 is a chest of 100 cm
    assert men.body_cm["calf_girth_right"] == pytest.approx(men.body_cm["knee_girth_right"])  # the one it adds
    for sizes, sample in ((("M",), "M"), (("S", "M", "L"), "M"), (("88", "92", "96", "100", "104"), "96")):
        chosen = choose_chart(sizes, sample)
        assert chosen.system is SizeSystem.REFERENCE and dict(chosen.body_cm) == dict(REFERENCE_BODY_CM)
    # every measurement a link reads is in every chart
    for chosen in (women, men):
        assert set(REFERENCE_BODY_CM) <= set(chosen.body_cm)


@pytest.mark.shared
@pytest.mark.parametrize(
    ("stem", "link", "system", "lo", "hi"),
    [
        # knit tanks: within a few cm of the bust (they read -15.2 to -8 cm against the men's chest of 96)
        ("WM LOOSE SHAPE TANK.DXF", "chest_girth", SizeSystem.WOMEN_EU, -5.0, 8.0),
        ("GLX0924S16_NEW.DXF", "chest_girth", SizeSystem.WOMEN_EU, -5.0, 8.0),
        ("GLX0926S16.DXF", "chest_girth", SizeSystem.WOMEN_EU, -5.0, 8.0),
        ("simple.DXF", "chest_girth", SizeSystem.WOMEN_EU, -5.0, 8.0),
        # leggings: at the waist, not 17.8 cm under it
        ("GLX4802S19_AAMA.DXF", "waist_girth", SizeSystem.WOMEN_EU, -5.0, 5.0),
        # a men's T-shirt and polo: a little over the chest of size 50
        ("GMH1004F15-2.DXF", "chest_girth", SizeSystem.MEN_EU, 0.0, 12.0),
        ("GMX1016S18_AAMA.DXF", "chest_girth", SizeSystem.MEN_EU, 0.0, 12.0),
    ],
)
def test_real_files_get_their_chart_and_a_plausible_ease(aama_dir, stem, link, system, lo, hi):
    pattern, _ = read_dxf(aama_dir / stem)
    chosen = choose_chart(pattern.sizes, pattern.sample_size)
    assert chosen.system is system
    links = {m.id: m for m in measurement_links(pattern, infer_bridge(pattern))}
    assert lo <= links[link].ease_cm <= hi, links[link].ease_cm


@pytest.mark.shared
def test_the_sidecar_records_the_chart_and_loads_with_or_without_it(aama_dir, tmp_path):
    pattern, _ = read_dxf(aama_dir / "simple.DXF")
    data = inference_sidecar(pattern, infer_bridge(pattern))
    assert data["size_chart"]["system"] == "women_eu" and "36" in data["size_chart"]["why"]
    assert data["size_chart"]["body_cm"]["chest_girth"] == pytest.approx(84.0)
    path = tmp_path / "simple.seams.json"
    path.write_text(json.dumps(data))
    with_chart = apply_sidecar(pattern, path)
    del data["size_chart"]  # a sidecar written before the field
    path.write_text(json.dumps(data))
    without = apply_sidecar(pattern, path)
    assert [m.ease_cm for m in with_chart.measurements] == [m.ease_cm for m in without.measurements]
    with pytest.raises(ValueError, match="size_chart"):
        check_sidecar_dict({**data, "size_chart": {"system": "women_eu", "body_cm": {"chest_girth": "84"}}})
