"""Dress a cast: every character × garment as one task on a Dask cluster.

:func:`run_batch` measures each character once, fits every case with
:func:`patternbridge.workflow.fit` into ``OUT/<character>/<garment>/``,
records failures without stopping, skips what an earlier run finished, and
writes ``OUT/batch.json`` (:mod:`.manifest`) and ``OUT/index.html``
(:mod:`.html`). ``dask.distributed`` is imported only when a batch runs.
"""

from __future__ import annotations

from .cases import Case, CaseOutcome, CaseStatus, check_inputs, make_cases
from .run import BatchResult, StageEvent, plan, run_batch

__all__ = [
    "BatchResult",
    "Case",
    "CaseOutcome",
    "CaseStatus",
    "StageEvent",
    "check_inputs",
    "make_cases",
    "plan",
    "run_batch",
]
