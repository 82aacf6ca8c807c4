"""What runs on a Dask worker: measure a character once, fit one case into its own folder."""

from __future__ import annotations

import resource
import shutil
import tempfile
import time
from pathlib import Path

from ..workflow.model import FitOptions
from ..workflow.subject import Subject
from .cases import PARTIAL_PREFIX, Case, CaseOutcome, CaseStatus

__all__ = ["PROGRESS_TOPIC", "fit_case", "measure_character", "peak_rss_mb", "process_cpu_seconds"]

PROGRESS_TOPIC = "patternbridge-progress"


def _reporter(key: str):
    """A ``progress(stage, done, total)`` that sends events to the client through the scheduler.

    Outside a worker (a plain call) it does nothing. Events are sent when the
    stage changes or every tenth of it, so a 200-generation grade sends about 10.
    """
    try:
        from distributed import get_worker

        worker = get_worker()
    except (ImportError, ValueError):
        return None
    last: dict[str, int] = {}

    def progress(stage: str, done: int, total: int) -> None:
        step = int(10 * done / max(total, 1))
        if last.get(stage) == step and done < total:
            return
        last[stage] = step
        worker.log_event(
            PROGRESS_TOPIC,
            {"case": key, "stage": stage, "done": int(done), "total": int(total), "worker": str(worker.address)},
        )

    return progress


def _worker_address() -> str:
    try:
        from distributed import get_worker

        return str(get_worker().address)
    except (ImportError, ValueError):
        return ""


def process_cpu_seconds() -> float:
    """User + system CPU time of this process so far (all its threads)."""
    usage = resource.getrusage(resource.RUSAGE_SELF)
    return usage.ru_utime + usage.ru_stime


def peak_rss_mb() -> float:
    """Peak resident memory of this process so far, MB (Linux reports ``ru_maxrss`` in KiB)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def measure_character(path: str) -> Subject:
    """Load and measure one character (a Dask task whose result its cases share)."""
    from ..workflow.subject import load_subject

    subject, _ = load_subject(path, progress=_reporter(f"{Path(path).stem}/*"))
    return subject


def fit_case(subject: Subject, case: Case, out_dir: str, seed: int, options: FitOptions) -> CaseOutcome:
    """Fit one case into ``OUT/<character>/<garment>/``, atomically.

    The fit writes into a hidden ``.part-<garment>-*`` folder beside the
    final one, renamed into place when everything is written: a folder named
    after the case is always complete. Errors propagate (the client records them).
    """
    from ..workflow.run import fit

    t0, cpu0 = time.perf_counter(), process_cpu_seconds()
    final = case.folder(Path(out_dir))
    final.parent.mkdir(parents=True, exist_ok=True)
    part = Path(tempfile.mkdtemp(prefix=f"{PARTIAL_PREFIX}{case.garment}-", dir=final.parent))
    try:
        result = fit(subject, case.garment_spec, seed=seed, options=options, out_dir=part, progress=_reporter(case.key))
        if final.exists():
            shutil.rmtree(final)
        part.replace(final)
    finally:
        shutil.rmtree(part, ignore_errors=True)
    return CaseOutcome(
        case=case,
        status=CaseStatus.DONE,
        seconds=time.perf_counter() - t0,
        cpu_seconds=process_cpu_seconds() - cpu0,
        peak_rss_mb=peak_rss_mb(),
        figures=result.figures,
        worker=_worker_address(),
        files=tuple(result.files),
    )
