"""The order a batch hands out its work: characters first, then cases by their garment's estimated work."""

from __future__ import annotations

import pytest

from patternbridge.batch.cases import make_cases
from patternbridge.batch.dispatch import _Queue
from patternbridge.batch.order import garment_work, pattern_work, run_order
from patternbridge.library import garment_names, load_garment


def test_library_garments_are_estimated_from_their_outline_vertices():
    for name in garment_names():
        n = sum(piece.n_vertices for piece in load_garment(name).pieces)
        assert garment_work(name) == pattern_work(n) == n**2
    # the shirt has three times the trousers' vertices (203 against 71): nine times their work
    assert garment_work("shirt") / garment_work("trousers") == pytest.approx((203 / 71) ** 2)


def test_a_garment_that_does_not_load_is_estimated_zero(tmp_path):
    bad = tmp_path / "broken.json"
    bad.write_text("{not json")
    assert garment_work(str(bad)) == 0.0
    assert garment_work(str(tmp_path / "missing.dxf")) == 0.0


def test_run_order_is_most_work_first_and_stable():
    cases = make_cases(["a.obj", "b.obj", "c.obj"], ["trousers", "shirt", "odd.json"])
    work = {"trousers": 1.0, "shirt": 9.0}  # odd.json unknown: last
    order = [c.key for c in run_order(cases, work)]
    assert order == [
        "a/shirt",
        "b/shirt",
        "c/shirt",
        "a/trousers",
        "b/trousers",
        "c/trousers",
        "a/odd",
        "b/odd",
        "c/odd",
    ]
    assert sorted(order) == sorted(c.key for c in cases)


def test_queue_measures_first_then_hands_out_measured_cases_by_rank():
    cases = make_cases(["a.obj", "b.obj"], ["trousers", "shirt"])
    queue = _Queue(cases, {"trousers": 1.0, "shirt": 9.0})
    assert queue.to_measure == ["a", "b"]
    assert not queue.ready
    queue.measured("b", "subject-b")
    queue.measured("a", "subject-a")
    handed = [queue.next_case() for _ in range(4)]
    assert [(c.key, s) for c, s in handed] == [
        ("a/shirt", "subject-a"),
        ("b/shirt", "subject-b"),
        ("a/trousers", "subject-a"),
        ("b/trousers", "subject-b"),
    ]
    assert queue.subjects == {}  # each character's result released with its last case
    assert queue.waiting == {} and queue.ready == []


def test_queue_gives_back_the_cases_of_a_character_that_could_not_be_measured():
    cases = make_cases(["a.obj", "b.obj"], ["trousers", "shirt"])
    queue = _Queue(cases, {"trousers": 1.0, "shirt": 9.0})
    assert [c.key for c in queue.unmeasured("a")] == ["a/shirt", "a/trousers"]
    queue.measured("b", "subject-b")
    assert [c.key for c in queue.ready] == ["b/shirt", "b/trousers"]
