"""Seam inference on files without bridge data."""

from __future__ import annotations

import pytest

from patternbridge.io.dxf_aama import read_dxf
from patternbridge.library import garment_dir, garment_names, load_garment
from patternbridge.library.infer import infer_seams, stretches, with_proposals
from patternbridge.library.seams import check_seams


def _recovered(name: str) -> tuple[int, int, int]:
    """(true primary seams, proposals, proposals that are a true seam) for a library garment's DXF."""
    truth_pattern = load_garment(name)
    d = garment_dir(name)
    bare, _ = read_dxf(d / f"{name}_aama.dxf", rul=d / f"{name}.rul")
    proposals = infer_seams(bare)
    truth = set()
    for s in truth_pattern.seams:
        if s.a.copy == s.b.copy == "primary":
            pa, pb = truth_pattern.piece(s.a.piece), truth_pattern.piece(s.b.piece)
            truth.add(
                frozenset(
                    [
                        (s.a.piece, pa.marks[s.a.start], pa.marks[s.a.end]),
                        (s.b.piece, pb.marks[s.b.start], pb.marks[s.b.end]),
                    ]
                )
            )
    hits = sum(
        frozenset([(p.a.piece, p.a.start, p.a.end), (p.b.piece, p.b.start, p.b.end)])
        in truth
        for p in proposals
    )
    return len(truth), len(proposals), hits


def test_inference_recovers_a_share_of_the_library_seams():
    totals = [_recovered(n) for n in garment_names()]
    n_true = sum(t for t, _, _ in totals)
    n_prop = sum(p for _, p, _ in totals)
    n_hit = sum(h for _, _, h in totals)
    # measured 32 of 69 with 63 proposals (docs/library.md); guard against regressions
    assert n_hit >= 28, totals
    assert n_hit / n_prop >= 0.4
    assert n_true == 69


def test_trouser_side_seam_and_inside_leg_are_found():
    d = garment_dir("trousers")
    bare, _ = read_dxf(d / "trousers_aama.dxf", rul=d / "trousers.rul")
    truth = load_garment("trousers")
    front, back = truth.piece("front"), truth.piece("back")
    pairs = {
        frozenset([(p.a.piece, p.a.start, p.a.end), (p.b.piece, p.b.start, p.b.end)])
        for p in infer_seams(bare)
    }
    side = frozenset(
        [
            ("front", front.marks["side_waist"], front.marks["side_hem"]),
            ("back", back.marks["side_hem"], back.marks["side_waist"]),
        ]
    )
    assert side in pairs


def test_proposals_are_exclusive_and_become_checkable_seams():
    bare, _ = read_dxf(
        garment_dir("skirt") / "skirt_aama.dxf", rul=garment_dir("skirt") / "skirt.rul"
    )
    proposals = infer_seams(bare)
    assert proposals and all(0 < p.confidence <= 1 for p in proposals)
    used = [k for p in proposals for k in p.a.parts + p.b.parts]
    assert len(used) == len(set(used))
    marked = with_proposals(bare, proposals)
    results = check_seams(marked)
    assert len(results) == len(proposals) * len(bare.rules.sizes)


def test_stretches_split_at_turn_points_and_notches():
    shirt = load_garment("shirt")
    singles = [s for s in stretches(shirt, max_run=1) if s.piece == "cuff"]
    assert sorted(round(s.length_cm, 3) for s in singles)[:2] == pytest.approx(
        [6.0, 6.0]
    )


@pytest.mark.shared
def test_inference_on_the_shared_accumark_file(aama_dir):
    from patternbridge.io.load import load_pattern

    pattern, _ = load_pattern(aama_dir / "simple.DXF")
    proposals = infer_seams(pattern)
    assert 3 <= len(proposals) <= 20
    marked = with_proposals(pattern, proposals)
    results = check_seams(marked)
    # the strongest proposals hold in every one of the 14 graded sizes
    best = proposals[0].seam_id
    assert all(r.ok for r in results if r.seam == best)
