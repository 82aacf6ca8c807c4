"""Worker preload: one BLAS/OpenMP thread in each batch worker, however the worker process started.

A worker forked from the client (see :mod:`.cluster`) inherits numpy with
the thread pools the client's BLAS made when it loaded (one per core), and
the one-thread environment variables Dask sets before starting a worker
come too late for it. With a single-threaded worker per core, a BLAS call
running on two threads would take the other worker's core. Dask imports
this module in every worker it starts (``distributed.worker.preload``) and
calls :func:`dask_setup`.
"""

from __future__ import annotations

__all__ = ["dask_setup"]

_LIMITS: list[object] = []  # the threadpoolctl limiter, kept alive for the worker's life


def dask_setup(worker: object) -> None:
    """Limit every BLAS and OpenMP pool of this process to one thread (``worker`` unused)."""
    from threadpoolctl import threadpool_limits

    _LIMITS.append(threadpool_limits(limits=1))
