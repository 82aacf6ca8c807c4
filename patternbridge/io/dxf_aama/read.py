"""Placeholder while the reader is being written."""

from __future__ import annotations

__all__ = ["read_dxf"]


def read_dxf(path, *, rul=None, units=None, unfold=False, strict=False):
    raise NotImplementedError("DXF reader not available yet")
