"""Infer the bridge data of any imported pattern: orientation, roles, seams, alternatives, marks.

Sits between :mod:`patternbridge.library` and :mod:`patternbridge.mesh`:
``infer_bridge(pattern)`` reads a tailor's pattern without a sidecar and
returns what a sidecar would hold (``formats/bridge.md``).
"""

from __future__ import annotations

from .infer import infer_bridge
from .model import BridgeInference, Join, Orientation, Role, RoleGuess, Side

__all__ = ["BridgeInference", "Join", "Orientation", "Role", "RoleGuess", "Side", "infer_bridge"]
