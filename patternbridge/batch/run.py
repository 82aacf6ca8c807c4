"""``run_batch``: every character × garment as one Dask task, resumable, each case on its own."""

from __future__ import annotations

import threading
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

from ..workflow.model import FitOptions
from .cases import (
    Case,
    CaseOutcome,
    CaseStatus,
    clear_failure,
    earlier_outcome,
    make_cases,
    remove_partial,
    write_failure,
)
from .dispatch import dispatch
from .manifest import BatchInputs, manifest_dict, write_manifest
from .order import garment_work

__all__ = ["BatchResult", "StageEvent", "plan", "run_batch"]


@dataclass(frozen=True, slots=True, kw_only=True)
class StageEvent:
    """A running case's progress, sent by its worker: ``stage`` reached ``done`` of ``total``."""

    case: str
    stage: str
    done: int
    total: int
    worker: str = ""


StageProgress = Callable[[StageEvent], None] | None
CaseProgress = Callable[[CaseOutcome, int, int], None] | None


@dataclass(frozen=True, slots=True, kw_only=True)
class BatchResult:
    """Every case's outcome (in case order), the wall time and where the files are."""

    outcomes: tuple[CaseOutcome, ...]
    seconds: float
    out_dir: Path

    def count(self, status: CaseStatus) -> int:
        return sum(o.status is status for o in self.outcomes)

    @property
    def is_complete(self) -> bool:
        """True when every case is done."""
        return self.count(CaseStatus.DONE) == len(self.outcomes)


def plan(cases: Sequence[Case], out_dir: Path, *, retry_failed: bool = False) -> tuple[list[CaseOutcome], list[Case]]:
    """Split ``cases`` into the outcomes earlier runs left (kept) and the cases to run now.

    A finished case is kept; a failed one is kept unless ``retry_failed``; a
    lost or never-run one is run (what a killed run left of it is removed).
    """
    kept, todo = [], []
    for case in cases:
        earlier = earlier_outcome(case, out_dir)
        if earlier is not None and (earlier.status is CaseStatus.DONE or not retry_failed):
            kept.append(earlier)
            continue
        remove_partial(case, out_dir)
        todo.append(case)
    return kept, todo


def _subscribe(client, stage_progress: StageProgress) -> Callable[[], None]:
    from .tasks import PROGRESS_TOPIC

    if stage_progress is None:
        return lambda: None
    lock = threading.Lock()

    def handler(event) -> None:
        msg = event[1]
        with lock:
            stage_progress(
                StageEvent(
                    case=msg["case"],
                    stage=msg["stage"],
                    done=msg["done"],
                    total=msg["total"],
                    worker=msg.get("worker", ""),
                )
            )

    client.subscribe_topic(PROGRESS_TOPIC, handler)
    return lambda: client.unsubscribe_topic(PROGRESS_TOPIC)


def run_batch(
    characters: Sequence[str],
    garments: Sequence[str],
    out_dir: str | Path,
    *,
    client,
    seed: int = 0,
    options: FitOptions | None = None,
    retry_failed: bool = False,
    stage_progress: StageProgress = None,
    case_progress: CaseProgress = None,
) -> BatchResult:
    """Fit every garment to every character on the Dask cluster of ``client``.

    Each character is measured once, on one worker; its cases use that
    result. Tasks go to the cluster one free worker thread at a time,
    characters first, then cases with the most estimated work first
    (:mod:`.dispatch`, :mod:`.order`). Each case writes ``OUT/<character>/<garment>/`` atomically; a
    case that raises is recorded as failed (``<garment>.failed.json`` and the
    manifest), one whose worker dies as lost, and neither stops the others.
    ``OUT/batch.json`` and ``OUT/index.html`` are rewritten after every case.

    Parameters
    ----------
    characters : mesh files or measurements JSONs
    garments : library garment names or pattern files
    out_dir : output folder
    client : a ``distributed.Client``
    seed : seed of every case (the same as ``patternbridge fit --seed``)
    options : fit options of every case
    retry_failed : run again the cases an earlier run recorded as failed
    stage_progress : ``stage_progress(event)`` with a :class:`StageEvent` from the workers
    case_progress : ``case_progress(outcome, n_finished, n_cases)`` as each case ends

    Returns
    -------
    BatchResult
    """
    t0 = time.perf_counter()
    options = options or FitOptions()
    out = Path(out_dir)
    cases = make_cases(list(characters), list(garments))
    out.mkdir(parents=True, exist_ok=True)
    kept, todo = plan(cases, out, retry_failed=retry_failed)
    inputs = _batch_inputs(cases, client, seed=seed, options=options)
    results: dict[str, CaseOutcome] = {o.case.key: o for o in kept}
    for n, outcome in enumerate(kept, 1):
        if case_progress is not None:
            case_progress(outcome, n, len(cases))
    _save(out, inputs, [results[c.key] for c in cases if c.key in results], t0)
    work = {
        spec: garment_work(spec, deformation=options.deformation)
        for spec in dict.fromkeys(c.garment_spec for c in todo)
    }
    unsubscribe = _subscribe(client, stage_progress)
    try:
        for outcome in dispatch(client, todo, out, seed=seed, options=options, work=work):
            _record(outcome, out)
            results[outcome.case.key] = outcome
            if case_progress is not None:
                case_progress(outcome, len(results), len(cases))
            _save(out, inputs, [results[c.key] for c in cases if c.key in results], t0)
    finally:
        unsubscribe()
    return BatchResult(outcomes=tuple(results[c.key] for c in cases), seconds=time.perf_counter() - t0, out_dir=out)


def _batch_inputs(cases: Sequence[Case], client, *, seed: int, options: FitOptions) -> BatchInputs:
    """What the batch was run on: its characters and garments, seed, options and cluster."""
    return BatchInputs(
        characters={c.character: c.character_path for c in cases},
        garments={c.garment: c.garment_spec for c in cases},
        seed=seed,
        options=options,
        scheduler=str(client.scheduler.address),
        dashboard=str(client.dashboard_link or ""),
        n_workers=len(client.scheduler_info().get("workers", {})),
    )


def _save(out: Path, inputs: BatchInputs, outcomes: Sequence[CaseOutcome], t0: float) -> None:
    """Rewrite ``OUT/batch.json`` and ``OUT/index.html`` with the outcomes so far (in case order)."""
    from .html import write_index

    manifest = manifest_dict(inputs, outcomes, seconds=time.perf_counter() - t0)
    write_manifest(out, manifest)
    write_index(out, manifest)


def _record(outcome: CaseOutcome, out: Path) -> None:
    """A finished case clears an earlier run's failure record; a failed one writes its own."""
    if outcome.status is CaseStatus.DONE:
        clear_failure(outcome.case, out)
    elif outcome.status is CaseStatus.FAILED:
        write_failure(outcome, out)
