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
"""

from __future__ import annotations

import logging
from typing import Any

__all__ = ["WORKER_ENVIRON_KEY", "local_cluster", "worker_config", "worker_environ"]

WORKER_ENVIRON_KEY = "distributed.nanny.pre-spawn-environ"
PROFILE_KEY = "distributed.worker.profile.enabled"
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


def worker_config() -> dict[str, Any]:
    """Dask settings of the local cluster: :func:`worker_environ`, no profiler thread, slower periodic checks."""
    return {WORKER_ENVIRON_KEY: worker_environ(), PROFILE_KEY: False, **QUIET_CHECKS}


def local_cluster(
    n_workers: int,
    *,
    memory_limit: str | float | None = "auto",
    silence_logs: int = logging.CRITICAL,
    dashboard_address: str | None = ":8787",
):
    """A ``LocalCluster`` of ``n_workers`` single-threaded worker processes (see the module's note)."""
    import dask.config
    from distributed import LocalCluster

    # the nannies hand the configuration in force here to their worker processes
    with dask.config.set(worker_config()):
        return LocalCluster(
            n_workers=n_workers,
            threads_per_worker=1,
            processes=True,
            memory_limit=memory_limit,
            silence_logs=silence_logs,
            dashboard_address=dashboard_address,
        )
