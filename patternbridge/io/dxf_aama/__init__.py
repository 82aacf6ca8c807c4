"""DXF-AAMA and DXF-ASTM (D6673) pattern files: reader, writer and the layer table.

``read_dxf`` turns a file into a :class:`~patternbridge.pattern.model.Pattern`
in the sample size plus its grade rules (from a ``.RUL`` or derived from a
graded nest); ``write_dxf`` writes one back in either flavour.
"""

from __future__ import annotations

from .layers import LAYERS, Layer, LayerInfo
from .read import INFO_FINDINGS, read_dxf

__all__ = ["INFO_FINDINGS", "LAYERS", "Layer", "LayerInfo", "read_dxf"]

try:  # the writer lives in its own module
    from .write import write_dxf  # noqa: F401
except ImportError:  # pragma: no cover - only while the writer is absent
    pass
else:
    __all__.append("write_dxf")
