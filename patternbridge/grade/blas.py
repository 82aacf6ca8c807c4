"""Run the grader's small dense linear algebra on one BLAS thread.

The grader's matrices are small (a few hundred rows): OpenBLAS gains nothing
from threads there, and on a busy machine its spinning worker threads make a
300 × 300 solve a hundred times slower (measured: 0.16 s instead of 2 ms with
the machine's two cores shared). :func:`single_blas_thread` sets the thread
count of every OpenBLAS the process has loaded (numpy's and scipy's bundled
copies) to one and restores it afterwards. Where the library cannot be found
(not Linux, another BLAS) it does nothing.
"""

from __future__ import annotations

import contextlib
import ctypes
import logging
from collections.abc import Iterator

__all__ = ["single_blas_thread"]

log = logging.getLogger(__name__)

_SYMBOLS = (
    ("scipy_openblas_set_num_threads64_", "scipy_openblas_get_num_threads64_"),
    ("scipy_openblas_set_num_threads", "scipy_openblas_get_num_threads"),
    ("openblas_set_num_threads64_", "openblas_get_num_threads64_"),
    ("openblas_set_num_threads", "openblas_get_num_threads"),
)


def _openblas_controls() -> list[tuple[object, object]]:
    """(set, get) function pairs of every loaded OpenBLAS."""
    try:
        with open("/proc/self/maps", encoding="utf-8") as fh:
            paths = sorted({line.split()[-1] for line in fh if "openblas" in line.lower() and "/" in line})
    except OSError:
        return []
    out = []
    for path in paths:
        try:
            lib = ctypes.CDLL(path)
        except OSError:
            continue
        for set_name, get_name in _SYMBOLS:
            if hasattr(lib, set_name) and hasattr(lib, get_name):
                setter, getter = getattr(lib, set_name), getattr(lib, get_name)
                setter.argtypes = [ctypes.c_int]
                getter.restype = ctypes.c_int
                out.append((setter, getter))
                break
    return out


@contextlib.contextmanager
def single_blas_thread() -> Iterator[None]:
    """Context manager: OpenBLAS on one thread inside, the previous count after."""
    controls = _openblas_controls()
    previous = []
    for setter, getter in controls:
        try:
            previous.append((setter, int(getter())))
            setter(1)
        except (OSError, ValueError):  # pragma: no cover - exotic builds
            log.debug("could not set the OpenBLAS thread count")
    try:
        yield
    finally:
        for setter, n in previous:
            setter(n)
