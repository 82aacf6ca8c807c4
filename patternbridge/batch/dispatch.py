"""Hand a batch's tasks to the cluster one free worker thread at a time, the most work first.

Submitted all at once, Dask binds each ready task to a worker as soon as its
inputs exist and balances later by stealing, which judges tasks by the mean
duration of their kind: a long case can wait behind short ones on one
worker while another worker runs dry at the end. Here the client keeps
exactly as many tasks on the cluster as it has worker threads, so a task
starts on whichever worker frees first, in the order of :func:`.order.run_order`
(list scheduling: the batch ends at most one case after the busiest worker's
share of the work).

Characters are measured first (one task each, in the order of their largest
case), since their cases cannot start before; a case is handed out once its
character's measured :class:`~patternbridge.workflow.subject.Subject` exists.
"""

from __future__ import annotations

import time
from collections.abc import Iterator, Mapping, Sequence
from pathlib import Path
from typing import Any

from ..workflow.model import FitOptions
from .cases import Case, CaseOutcome, CaseStatus
from .order import run_order

__all__ = ["dispatch", "error_outcome"]


def error_outcome(case: Case, exc: BaseException, worker: str = "") -> CaseOutcome:
    """The outcome of a case whose task raised ``exc``: *lost* when its worker died, else *failed*."""
    from distributed import KilledWorker
    from distributed.client import FutureCancelledError

    lost = isinstance(exc, KilledWorker | FutureCancelledError)
    text = f"{type(exc).__name__}: {exc}".strip().splitlines()[0]
    return CaseOutcome(case=case, status=CaseStatus.LOST if lost else CaseStatus.FAILED, error=text, worker=worker)


def _exception(future) -> BaseException:
    try:
        return future.exception()
    except Exception as cancelled:  # a cancelled future raises instead of returning its error
        return cancelled


def _threads(client) -> int:
    """Worker threads of the cluster now (at least 1, so a batch waits for workers instead of stalling)."""
    return max(1, sum(client.nthreads().values()))


class _Queue:
    """What is still to hand out: characters to measure, then measured characters' cases by rank."""

    def __init__(self, todo: Sequence[Case], work: Mapping[str, float]) -> None:
        order = run_order(todo, work)
        self.rank = {case.key: i for i, case in enumerate(order)}
        self.to_measure = list(dict.fromkeys(case.character for case in order))
        self.paths = {case.character: case.character_path for case in order}
        self.waiting = {name: [c for c in order if c.character == name] for name in self.to_measure}
        self.ready: list[Case] = []
        self.subjects: dict[str, Any] = {}

    def measured(self, character: str, future) -> None:
        self.subjects[character] = future
        self.ready = sorted(self.ready + self.waiting.pop(character), key=lambda c: self.rank[c.key])

    def unmeasured(self, character: str) -> list[Case]:
        return self.waiting.pop(character)

    def next_case(self) -> tuple[Case, Any]:
        """The highest-ranked measured case and its character's future (released after its last case)."""
        case = self.ready.pop(0)
        subject = self.subjects[case.character]
        if not any(c.character == case.character for c in self.ready):
            del self.subjects[case.character]
        return case, subject


def _outcomes(item: Case | str, future, queue: _Queue) -> list[CaseOutcome]:
    """What a finished task means for its cases (a measured character: none yet)."""
    if isinstance(item, str):  # a character measured, or not
        if future.status == "finished":
            queue.measured(item, future)
            return []
        exc = _exception(future)
        return [error_outcome(case, exc) for case in queue.unmeasured(item)]
    outcome = future.result() if future.status == "finished" else error_outcome(item, _exception(future))
    future.release()
    return [outcome]


def dispatch(
    client, todo: Sequence[Case], out_dir: Path, *, seed: int, options: FitOptions, work: Mapping[str, float]
) -> Iterator[CaseOutcome]:
    """Run every case of ``todo`` on ``client``'s cluster; yield each one's outcome as it ends.

    ``work``: the relative work of each garment spec (:func:`.order.garment_work`).
    A character whose measuring fails or is lost fails or loses its cases
    with that error; a case that raises fails; one whose worker dies is lost.
    """
    from distributed import as_completed

    from .tasks import fit_case, measure_character

    queue = _Queue(todo, work)
    running: dict[Any, Case | str] = {}
    finished = as_completed()

    def submit_next() -> bool:
        stamp = time.time_ns()
        if queue.to_measure:
            name = queue.to_measure.pop(0)
            future = client.submit(measure_character, queue.paths[name], key=f"measure-{name}-{stamp}", pure=False)
            running[future] = name
        elif queue.ready:
            case, subject = queue.next_case()
            future = client.submit(
                fit_case, subject, case, str(out_dir), seed, options, key=f"fit-{case.key}-{stamp}", pure=False
            )
            running[future] = case
        else:
            return False
        finished.add(future)
        return True

    def fill() -> None:
        threads = _threads(client)
        while len(running) < threads and submit_next():
            pass

    fill()
    for future in finished:
        outcomes = _outcomes(running.pop(future), future, queue)
        fill()  # the freed thread gets its next task before the client writes anything
        yield from outcomes
