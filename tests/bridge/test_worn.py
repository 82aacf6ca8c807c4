"""Bands as worn (``bridge.worn``): flat-applied bindings cut to their opening, spare copies not draped.

On the real tanks of ../shared/aama: ``simple.DXF`` cuts its neck and armhole
bindings 13.1-13.6 cm longer than their openings in all 14 sizes (sewn from one
end, the excess cut off); ``GLX0926S16`` cuts its neck binding as a pair and
``GLX0924S16_NEW`` twice (``2XFABRIC``) for one neckline, which one copy binds
whole.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from patternbridge.assemble.mesh2d import _instances
from patternbridge.bridge import infer_bridge
from patternbridge.bridge.sidecar import inference_sidecar
from patternbridge.bridge.worn import worn_pattern
from patternbridge.io.dxf_aama import read_dxf
from patternbridge.library.seams import range_indices, sew_line
from patternbridge.library.sidecar import apply_sidecar
from patternbridge.pattern.model import Copy

pytestmark = pytest.mark.shared


def _length(piece, start: str, end: str) -> float:
    pts = sew_line(piece)[0]
    idx = range_indices(piece, start, end)
    return float(np.linalg.norm(np.diff(pts[idx], axis=0), axis=1).sum())


def _perimeter(piece) -> float:
    pts = sew_line(piece)[0]
    return float(np.linalg.norm(np.roll(pts, -1, axis=0) - pts, axis=1).sum())


@pytest.fixture(scope="module")
def worn(aama_dir, tmp_path_factory):
    """name -> (sidecar dict, pattern with the sidecar applied, the same as worn)."""
    out = {}
    for name in ("simple.DXF", "GLX0926S16.DXF", "GLX0924S16_NEW.DXF"):
        pattern, _ = read_dxf(aama_dir / name)
        data = inference_sidecar(pattern, infer_bridge(pattern))
        path = tmp_path_factory.mktemp("worn") / "garment.seams.json"
        path.write_text(json.dumps(data))
        applied = apply_sidecar(pattern, path)
        out[name] = (data, applied, worn_pattern(applied, path))
    return out


def _opening_cm(pattern, band: str, copy: Copy) -> float:
    """The opening one copy of ``band`` is sewn to, measured on the pieces it meets (each range once)."""
    return sum(
        _length(pattern.piece(s.a.piece), s.a.start, s.a.end)
        for s in pattern.seams
        if s.b.piece == band and s.a.piece != band and s.b.copy is copy
    )


@pytest.mark.parametrize("band", ["C-S1615WWO206-NB", "C-S1615WWO206-AB"])
def test_a_flat_applied_binding_is_worn_cut_to_its_opening_and_closed(worn, band):
    """simple.DXF: the binding drawn 13 cm longer than its opening is worn as long as the opening, a loop
    whose two cut ends (straight across the 3.8 cm strip) are sewn to each other."""
    data, applied, as_worn = worn["simple.DXF"]
    entry = next(p for p in data["pieces"] if p["name"] == band)
    assert set(entry["trim"]) == {"start", "start_across", "end", "end_across"}
    drawn, cut = applied.piece(band), as_worn.piece(band)
    opening = _opening_cm(applied, band, Copy.PRIMARY)
    sewn = _length(drawn, entry["trim"]["start"], entry["trim"]["end"])
    assert sewn == pytest.approx(opening, abs=0.1)  # the sewn range between the cuts is the opening's length
    # drawn: two long edges 72.0 / 80.8 cm and 5 cm less, ends 3.8 and 6.3 cm; worn: a rectangle round the
    # opening, folded over the edge it binds (its outer half, 1.9 cm wide)
    width = 3.8 * entry["worn_width_share"]
    assert entry["worn_width_share"] == 0.5
    assert _perimeter(drawn) > 2 * opening + 2 * 3.8 + 20.0
    assert _perimeter(cut) == pytest.approx(2 * opening + 2 * width, abs=0.2)
    for start, across in (("end", "end_across"), ("start_across", "start")):
        a, b = entry["trim"][start], entry["trim"][across]
        assert _length(cut, a, b) == pytest.approx(width, abs=0.05)  # a cut straight across the strip
    closures = [s for s in as_worn.seams if s.a.piece == band and s.b.piece == band]
    copies = {s.b.copy for s in applied.seams if s.b.piece == band}
    assert {s.a.copy for s in closures} == copies  # closed on every copy sewn (both armholes)
    # the drape is cut from the worn piece: its sewn range is all of the long edge that is left
    assert _length(cut, entry["trim"]["start"], entry["trim"]["end"]) == pytest.approx(sewn, abs=1e-6)


def test_bindings_cut_shorter_than_their_opening_are_not_trimmed(worn):
    """GLX0924S16_NEW (neck binding 4.5 % short) and GLX0926S16 (1.8 % short, and as long as its neck):
    stretched on and closed as drawn."""
    for name in ("GLX0924S16_NEW.DXF", "GLX0926S16.DXF"):
        data, applied, as_worn = worn[name]
        assert not [p["name"] for p in data["pieces"] if "trim" in p]
        for p in applied.pieces:
            assert len(as_worn.piece(p.name).outline) == len(p.outline)


@pytest.mark.parametrize("name", ["GLX0926S16.DXF", "GLX0924S16_NEW.DXF"])
def test_a_neck_binding_cut_twice_is_worn_once(worn, aama_dir, name):
    """The file cuts the neck binding twice for one neckline that one copy binds whole: the other copy is not
    draped (the armhole binding's two copies bind the two armholes and stay)."""
    data, applied, as_worn = worn[name]
    binding = next(p["name"] for p in data["pieces"] if p["role"] == "neck_binding")
    ends = [e for s in data["seams"] for e in (s["a"], s["b"]) if e["piece"] == binding]
    assert ends and {e["copy"] for e in ends} == {"primary"}  # no seam, not even its closure, on a second copy
    draped = {(i.piece, i.copy) for i in _instances(as_worn)}
    assert (binding, Copy.PRIMARY) in draped and (binding, Copy.MIRROR) not in draped
    for p in data["pieces"]:
        if p["role"] == "armhole_binding":
            assert "worn_copies" not in p
            assert {(p["name"], Copy.PRIMARY), (p["name"], Copy.MIRROR)} <= draped
    # the designer's quantity is kept in the pattern the grader and the DXF writer see
    assert applied.piece(binding).quantity == read_dxf(aama_dir / name)[0].piece(binding).quantity


def test_a_piece_cut_twice_that_is_not_a_band_is_closed_on_both_copies(aama_dir):
    """The leggings' one-piece legs are sewn to themselves (the inseam) and to their mirror copies only: each
    leg is still closed on both legs (only a band's spare copy is left out)."""
    pattern, _ = read_dxf(aama_dir / "GLX4802S19_AAMA.DXF")
    data = inference_sidecar(pattern, infer_bridge(pattern))
    assert not [p["name"] for p in data["pieces"] if "worn_copies" in p or "trim" in p]
    inseams = [s for s in data["seams"] if s["a"]["piece"] == s["b"]["piece"] and s["a"]["copy"] == s["b"]["copy"]]
    legs = {s["a"]["piece"] for s in inseams}
    assert len(legs) == 3
    for leg in legs:
        assert {s["a"]["copy"] for s in inseams if s["a"]["piece"] == leg} == {"primary", "mirror"}, leg


def test_a_binding_is_worn_folded_over_the_edge_it_binds(worn):
    """GLX0926S16's bindings (3.2 cm strips) are worn at half their width, their sewn edge unchanged."""
    data, applied, as_worn = worn["GLX0926S16.DXF"]
    bindings = [p for p in data["pieces"] if p["role"] in ("neck_binding", "armhole_binding")]
    assert len(bindings) == 2
    for entry in bindings:
        assert entry["worn_width_share"] == 0.5
        drawn, folded = applied.piece(entry["name"]), as_worn.piece(entry["name"])
        sewn = [s for s in applied.seams if s.b.piece == entry["name"] and s.a.piece != entry["name"]]
        for s in sewn:
            assert _length(folded, s.b.start, s.b.end) == pytest.approx(_length(drawn, s.b.start, s.b.end), abs=1e-6)
        # each of its two short ends (3.2 cm drawn) is half as long worn
        ends = [s for s in applied.seams if s.a.piece == entry["name"] and s.b.piece == entry["name"]]
        assert ends
        for s in ends:
            for r in (s.a, s.b):
                assert _length(drawn, r.start, r.end) == pytest.approx(3.2, abs=0.05)
                assert _length(folded, r.start, r.end) == pytest.approx(1.6, abs=0.05)


def test_rib_neckbands_are_worn_as_drawn(aama_dir):
    """A T-shirt's rib neckband stands round the neck as drawn: nothing is trimmed, folded or left out."""
    for name in ("GMH1004F15-2.DXF", "MEN CLASSIC TEE.DXF"):
        pattern, _ = read_dxf(aama_dir / name)
        data = inference_sidecar(pattern, infer_bridge(pattern))
        assert not [p["name"] for p in data["pieces"] if {"trim", "worn_copies", "worn_width_share"} & set(p)]
