"""The hand labels are what a pattern maker would write: every labelled seam sews."""

from __future__ import annotations

import numpy as np
import pytest

from patternbridge.bridge.evaluate import LABELS_DIR
from patternbridge.library.seams import graded_sew_lines
from patternbridge.pattern.model import Role

pytestmark = pytest.mark.shared


def _length(line: np.ndarray, s: int, e: int) -> float:
    n = len(line)
    idx = np.arange(s, e + 1) if e > s else np.r_[s:n, 0 : e + 1]
    return float(np.linalg.norm(np.diff(line[idx], axis=0), axis=1).sum())


def test_every_label_names_real_pieces_roles_and_has_a_picture(labelled):
    pattern, label, pairs, _ = labelled
    assert set(label["pieces"]) == set(pattern.piece_names)
    assert {Role(v["role"]) for v in label["pieces"].values()}
    assert (LABELS_DIR / (label["file"].split("/")[-1] + ".png")).is_file()
    for oa, ob in pairs:
        for piece, s, e in oa + ob:
            assert 0 <= s < pattern.piece(piece).n_vertices and 0 <= e < pattern.piece(piece).n_vertices


def test_labelled_seams_sew_in_the_sample_size(labelled):
    """One-to-one seams are equal within 4 % (sleeve-cap ease aside); a band is within 25 % of its edges."""
    pattern, label, pairs, _ = labelled
    lines = graded_sew_lines(pattern)
    k = max(pattern.rules.size_index(pattern.sample_size), 0) if pattern.rules.sizes else 0
    bands = {
        n
        for n, v in label["pieces"].items()
        if v["role"] in ("neck_binding", "armhole_binding", "neckband", "cuff", "collar", "waistband")
    }
    for oa, ob in pairs:
        (pa, sa, ea), (pb, sb, eb) = oa[0], ob[0]
        la, lb = _length(lines[pa][k], sa, ea), _length(lines[pb][k], sb, eb)
        if pa in bands or pb in bands:
            continue  # a band runs along several edges of an opening
        roles = {label["pieces"][pa]["role"], label["pieces"][pb]["role"]}
        tol = 0.10 if "sleeve" in roles and len(roles) > 1 else 0.04
        assert abs(la - lb) <= 0.3 + tol * max(la, lb), f"{label['file']}: {oa[0]} {la:.2f} vs {ob[0]} {lb:.2f} cm"


def test_band_labels_fit_their_openings(labelled):
    """A band's partner edges together are within 30 % of the band (a neckline's halves on the fold count twice)."""
    pattern, label, pairs, _ = labelled
    if label.get("seams_from_sidecar"):
        pytest.skip("library seams are checked in every size by patternbridge check")
    lines = graded_sew_lines(pattern)
    k = max(pattern.rules.size_index(pattern.sample_size), 0) if pattern.rules.sizes else 0
    bands = {
        n for n, v in label["pieces"].items() if v["role"] in ("neck_binding", "armhole_binding", "neckband", "cuff")
    }
    for band in bands - set(label.get("sewn_to_internal_lines", ())):
        sewn = [(oa, ob) if oa[0][0] == band else (ob, oa) for oa, ob in pairs if band in (oa[0][0], ob[0][0])]
        sewn = [(own, other) for own, other in sewn if other[0][0] not in bands]  # not the ends joined to a band
        partners = [other[0] for _, other in sewn]
        if not partners:
            continue
        # one long edge: the longest range, or the band's ranges together when it is sewn in several parts
        ranges = {own[0] for own, _ in sewn}
        edge = max(
            max(_length(lines[band][k], s, e) for own, _ in sewn for (_, s, e) in own),
            sum(_length(lines[band][k], s, e) for _, s, e in ranges),
        )
        neck = label["pieces"][band]["role"] in ("neck_binding", "neckband")
        total = sum(
            _length(lines[p][k], s, e) * (2 if neck and pattern.piece(p).mirror_line is not None else 1)
            for p, s, e in partners
        )
        # a band cut once per armhole or sleeve: the partners of both copies are listed
        fronts = {(p, s, e) for p, s, e in partners if label["pieces"][p]["role"] in ("front", "sleeve")}
        total /= 1 if neck else max(len(fronts), 1)
        assert 0.7 * edge <= total <= 1.45 * edge, f"{label['file']}: band {band} {edge:.1f} cm, edges {total:.1f} cm"
