"""Shape and dtype checks for public array arguments."""

from __future__ import annotations

import numpy as np

__all__ = ["as_float_array", "as_index_array", "frozen"]


def _check_shape(a: np.ndarray, shape: tuple[int | None, ...], name: str) -> None:
    if a.ndim != len(shape) or any(
        want is not None and got != want for got, want in zip(a.shape, shape, strict=True)
    ):
        want = "(" + ", ".join("n" if s is None else str(s) for s in shape) + ")"
        raise ValueError(f"{name}: expected shape {want}, got {a.shape}")


def as_float_array(a, shape: tuple[int | None, ...], name: str) -> np.ndarray:
    """Return ``a`` as a new float64 array of ``shape`` (``None`` = any length)."""
    out = np.array(a, dtype=np.float64)
    if out.size == 0 and len(shape) > 1:
        out = out.reshape((0, *(s or 0 for s in shape[1:])))
    _check_shape(out, shape, name)
    if not np.all(np.isfinite(out)):
        raise ValueError(f"{name}: contains NaN or infinite values")
    return out


def as_index_array(a, shape: tuple[int | None, ...], name: str) -> np.ndarray:
    """Return ``a`` as a new int64 array of ``shape``."""
    out = np.array(a, dtype=np.int64)
    if out.size == 0 and len(shape) > 1:
        out = out.reshape((0, *(s or 0 for s in shape[1:])))
    _check_shape(out, shape, name)
    return out


def frozen(a: np.ndarray) -> np.ndarray:
    """Mark ``a`` read-only and return it (model arrays are immutable)."""
    a.flags.writeable = False
    return a
