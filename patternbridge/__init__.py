"""PatternBridge: real tailoring patterns on animation characters.

Import stages from their subpackages (``patternbridge.pattern``,
``patternbridge.io``, ``patternbridge.geodesic`` ...); this module stays light so
that ``patternbridge --help`` never loads open3d, pymoo or ezdxf.
"""

from __future__ import annotations

__version__ = "0.1.0"
__all__ = ["__version__"]
