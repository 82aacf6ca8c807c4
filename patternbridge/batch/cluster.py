"""A local Dask cluster whose worker processes run the fit as fast as a plain process does.

``distributed`` starts each worker process with ``MALLOC_TRIM_THRESHOLD_``
set (its ``distributed.nanny.pre-spawn-environ``), so that idle workers give
memory back. Setting that variable at all also turns off glibc's sliding
``mmap`` threshold: every large numpy temporary of the grader is then mapped
and unmapped afresh, and its pages faulted in again. Measured on one fit
(B_slim_female × trousers, population 16, 10 generations, no drape): 8.6 s of
CPU and 0.13 M minor page faults in a plain process, 17.6 s and 4.5 M with the
variable set — the workers did twice the work of the serial loop. The
workers here start without it and keep the one-thread BLAS/OpenMP settings.

Each worker also runs ``distributed``'s statistical profiler, a thread that
samples the running task's stack every 10 ms (for the dashboard's profile
page) and takes the GIL from the fit to do so. Measured on one fit
(B_slim_female × trousers, population 16, 10 generations, no drape; three
runs each, machine loaded): 8.8 CPU s in a plain process, 11.5 in a default
worker, 10.0 with the profiler off, 7.9 with the profiler off and the
cluster's periodic checks slowed (event-loop health every 1 s instead of
20 ms, system monitor every 5 s instead of 0.5 s, memory monitor every 1 s
instead of 0.1 s). The cluster here runs with these settings; a worker over
its memory limit is still restarted, within a second.

The workers are forked from the client process after it has imported what a
fit uses (:data:`FIT_MODULES`, and :data:`DRAPE_MODULES` when the batch
drapes), instead of spawned as new interpreters that each import
``distributed``, numpy, pymoo, matplotlib… again before their first task.
Measured (two workers, the client's CPU from before its imports counted):
0.4 CPU s in all instead of 1.6, and on the machine at load 25, both
workers ready with the fit's modules 3.8 s after the cluster began to
start instead of 15 s. A
forked worker inherits the client's BLAS thread pools, so every worker
limits them to one thread at start (:mod:`.worker_setup`). A worker the
nanny restarts later (memory limit, crash) is spawned as Dask does by
default, with the same settings.
"""

from __future__ import annotations

import importlib
import logging
from collections.abc import Sequence
from typing import Any

__all__ = [
    "DRAPE_MODULES",
    "FIT_MODULES",
    "WORKER_ENVIRON_KEY",
    "local_cluster",
    "worker_config",
    "worker_environ",
]

WORKER_ENVIRON_KEY = "distributed.nanny.pre-spawn-environ"
PROFILE_KEY = "distributed.worker.profile.enabled"
START_METHOD_KEY = "distributed.worker.multiprocessing-method"
PRELOAD_KEY = "distributed.worker.preload"
# what a fit without the drape imports (measuring, grading, DXF/RUL, pictures); the drape adds open3d
FIT_MODULES = (
    "patternbridge.workflow.run",
    "patternbridge.workflow.outputs",
    "patternbridge.bridge.fit_input",
    "patternbridge.measure.run",
    "patternbridge.grade.run",
    "patternbridge.grade.refine",
    "patternbridge.grade.report",
    "patternbridge.io.dxf_aama.write",
    "patternbridge.io.plot",
    "patternbridge.io.plot_fit",
)
DRAPE_MODULES = ("patternbridge.assemble",)
# the cluster's periodic checks, slowed (see the module's note)
QUIET_CHECKS = {
    "distributed.admin.tick.interval": "1s",
    "distributed.admin.system-monitor.interval": "5s",
    "distributed.worker.memory.monitor-interval": "1s",
}


def worker_environ() -> dict[str, Any]:
    """The environment ``distributed`` gives new worker processes, without ``MALLOC_TRIM_THRESHOLD_``."""
    import dask.config

    environ = dict(dask.config.get(WORKER_ENVIRON_KEY, default={}) or {})
    environ.pop("MALLOC_TRIM_THRESHOLD_", None)
    return environ


def worker_config(start_method: str = "spawn") -> dict[str, Any]:
    """Dask settings of the local cluster.

    :func:`worker_environ`, no profiler thread, slower periodic checks, one
    BLAS thread per worker (:mod:`.worker_setup`) and workers started by
    ``start_method`` (``"spawn"``, ``"fork"`` or ``"forkserver"``).
    """
    preload = [*dict.fromkeys([*dask_preload(), "patternbridge.batch.worker_setup"])]
    return {
        WORKER_ENVIRON_KEY: worker_environ(),
        PROFILE_KEY: False,
        START_METHOD_KEY: start_method,
        PRELOAD_KEY: preload,
        **QUIET_CHECKS,
    }


def dask_preload() -> list[str]:
    """The worker preloads already configured (kept beside the batch's own)."""
    import dask.config

    return list(dask.config.get(PRELOAD_KEY, default=[]) or [])


def local_cluster(
    n_workers: int,
    *,
    memory_limit: str | float | None = "auto",
    silence_logs: int = logging.CRITICAL,
    dashboard_address: str | None = ":8787",
    modules: Sequence[str] = FIT_MODULES,
):
    """A ``LocalCluster`` of ``n_workers`` single-threaded worker processes (see the module's note).

    ``modules``: what the client imports before it forks the workers (those
    of a fit: :data:`FIT_MODULES`; add :data:`DRAPE_MODULES` for a batch with
    the drape). Without ``fork`` on the platform, the workers are spawned.
    """
    import multiprocessing

    import dask.config
    from distributed import LocalCluster

    method = "fork" if "fork" in multiprocessing.get_all_start_methods() else "spawn"
    if method == "fork":
        for name in modules:
            importlib.import_module(name)
    # the nannies hand the configuration in force here to their worker processes
    with dask.config.set(worker_config(method)):
        return LocalCluster(
            n_workers=n_workers,
            threads_per_worker=1,
            processes=True,
            memory_limit=memory_limit,
            silence_logs=silence_logs,
            dashboard_address=dashboard_address,
        )
