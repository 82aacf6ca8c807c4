"""The order a batch hands out its work: characters first, then cases by their garment's estimated work."""

from __future__ import annotations

from patternbridge.batch.cases import make_cases
from patternbridge.batch.dispatch import _Queue
from patternbridge.batch.order import garment_work, pattern_work, run_order
from patternbridge.library import garment_names, load_garment


def test_library_garments_are_estimated_from_the_graders_grid():
    from patternbridge.grade.grid import build_grid

    work = {name: garment_work(name) for name in garment_names()}
    for name, value in work.items():
        grid = build_grid(load_garment(name))
        assert value == pattern_work(grid.x0.size, int(grid.point_offsets[-1])) > 0
    # known contents: the shirt (203 outline points) and the dress (136) outrank the trousers (71)
    assert min(work["shirt"], work["dress"]) > 4 * max(work["trousers"], work["shorts"])


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
