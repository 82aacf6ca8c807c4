"""PatternBridge: real tailoring patterns on animation characters.

Import stages from their subpackages (``patternbridge.pattern``,
``patternbridge.io``, ``patternbridge.geodesic`` ...); this module stays light so
that ``patternbridge --help`` never loads open3d, pymoo or ezdxf.
``patternbridge.fit`` (the whole workflow, :func:`patternbridge.workflow.fit`)
is imported on first use.
"""

from __future__ import annotations

__version__ = "0.1.0"
__all__ = ["__version__", "fit"]


def __getattr__(name: str):
    if name == "fit":
        from .workflow.run import fit

        return fit
    raise AttributeError(f"module 'patternbridge' has no attribute {name!r}")
