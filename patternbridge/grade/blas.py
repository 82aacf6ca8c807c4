"""Run the grader's small dense linear algebra on one BLAS thread.

The grader's matrices are small (a few hundred rows): a threaded BLAS gains
nothing there, and on a busy machine its spinning worker threads make a
300 × 300 solve a hundred times slower (measured: 0.16 s instead of 2 ms with
the machine's two cores shared). :func:`single_blas_thread` limits every BLAS
the process has loaded (OpenBLAS, MKL, BLIS) to one thread through
threadpoolctl and restores the previous counts afterwards.
"""

from __future__ import annotations

import contextlib
from collections.abc import Iterator

__all__ = ["single_blas_thread"]


@contextlib.contextmanager
def single_blas_thread() -> Iterator[None]:
    """Context manager: BLAS on one thread inside, the previous count after."""
    from threadpoolctl import threadpool_limits

    with threadpool_limits(limits=1, user_api="blas"):
        yield
