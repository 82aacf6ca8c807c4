"""Exception hierarchy: bad input is an ``InputError`` (exit 2), bugs stay bugs.

Messages are one line: ``"{path}: {what is wrong} ({evidence}); {what to do}"``.
Subclasses also inherit the matching builtin so callers may catch ``ValueError``.
"""

from __future__ import annotations

__all__ = [
    "DXFFormatError",
    "InputError",
    "LandmarkError",
    "MeshError",
    "PatternBridgeError",
    "RULFormatError",
    "SolverError",
    "UnitsError",
]


class PatternBridgeError(Exception):
    """Base of every error PatternBridge raises on purpose."""


class InputError(PatternBridgeError):
    """The input is unusable; the CLI prints the message and exits with 2."""


class DXFFormatError(InputError, ValueError):
    """A DXF-AAMA/ASTM file is corrupt, truncated or structurally wrong."""


class RULFormatError(InputError, ValueError):
    """A .RUL grade-rule table is malformed or disagrees with its DXF."""


class UnitsError(InputError, ValueError):
    """Units are unknown or implausible for the data."""


class MeshError(InputError, ValueError):
    """A character mesh cannot be used (holes, no body component, bad file)."""


class LandmarkError(InputError, KeyError):
    """A landmark is missing, unknown or cannot be placed."""

    def __str__(self) -> str:  # KeyError would quote the message
        return str(self.args[0]) if self.args else ""


class SolverError(PatternBridgeError, RuntimeError):
    """An optimisation or simulation did not converge or is infeasible."""
