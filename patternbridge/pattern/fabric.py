"""The fabric a garment is cut from: its class and the stretch that class takes across and along the grain.

A pattern's girths are drafted against the fabric: a woven garment is larger
than the body everywhere it closes round it (positive ease), a knit may be
smaller (negative ease) because the fabric stretches across the grain. The
drape's verdict (:mod:`patternbridge.assemble.verdict`) judges the stretch
of the finished drape against the limits of the garment's class.

The figures (``docs/bridge.md``, *The fabric*) are strains (0.25 = 25 %),
two per direction:

- ``worn``: the stretch the fabric is worn at, the negative ease a pattern
  maker drafts it with (the middle of the usual range); the verdict's girth
  limits are a woven's shifted by it (a knit is judged as a woven garment
  that much larger: a size too small beyond it is flawed, two sizes failed);
- ``limit``: the stretch a stretch gauge reaches on the fabric (a 10 cm
  fold stretched by hand, as printed on knit patterns; measured by ASTM
  D2594 for knits and ASTM D3107 for woven stretch fabrics); a cloth edge
  stretched beyond it has torn the fabric's structure.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum
from types import MappingProxyType

import numpy as np

__all__ = ["FABRIC_STRETCH", "FabricClass", "FabricStretch", "directional"]


class FabricClass(str, Enum):
    """The class of fabric a garment or piece is cut from."""

    WOVEN = "woven"  # shirting, suiting, denim, twill: no stretch but the bias
    KNIT = "knit"  # jersey, pique, interlock, rib without elastane
    STRETCH_KNIT = "stretch_knit"  # knits with elastane (leggings, swimwear): two-way stretch

    def __str__(self) -> str:
        return self.value

    @property
    def stretch(self) -> FabricStretch:
        """The documented stretch of this class (:data:`FABRIC_STRETCH`)."""
        return FABRIC_STRETCH[self]


@dataclass(frozen=True, slots=True, kw_only=True)
class FabricStretch:
    """How far a fabric class stretches, as strains (0.25 = 25 %).

    across_worn, across_limit : across the grain (the girths of a garment)
    along_worn, along_limit : along the grain (the garment's lengths)
    source : where the figures come from
    """

    across_worn: float
    across_limit: float
    along_worn: float
    along_limit: float
    source: str

    def to_dict(self) -> dict:
        """JSON form (``fit_report.json``)."""
        return {
            "across_worn": self.across_worn,
            "across_limit": self.across_limit,
            "along_worn": self.along_worn,
            "along_limit": self.along_limit,
        }


FABRIC_STRETCH = MappingProxyType(
    {
        FabricClass.WOVEN: FabricStretch(
            across_worn=0.0,
            across_limit=0.05,
            along_worn=0.0,
            along_limit=0.03,
            source="shirting, twill, denim without elastane: worn without stretch on the grain; a few per cent "
            "before the yarns slip (the bias alone gives about 10 %)",
        ),
        FabricClass.KNIT: FabricStretch(
            across_worn=0.05,
            across_limit=0.25,
            along_worn=0.0,
            along_limit=0.10,
            source="single jersey, pique, rib: the 'moderate stretch' knit of the stretch gauges (10 cm crosswise "
            "to 12.5 cm); fitted jersey tops are drafted 0-10 % under the body",
        ),
        FabricClass.STRETCH_KNIT: FabricStretch(
            across_worn=0.15,
            across_limit=0.50,
            along_worn=0.05,
            along_limit=0.30,
            source="jersey with elastane, two-way stretch: the 'stretchy' knit of the stretch gauges "
            "(10 cm crosswise to 15 cm); leggings are drafted 10-20 % under the body",
        ),
    }
)


def directional(along: float, across: float, grain: np.ndarray, d: np.ndarray) -> np.ndarray:
    """The strain limit in each direction ``d``: ``along`` cos² + ``across`` sin² of its angle to the grain.

    The normal strain of a fabric stretched by ``along`` on the grain and
    ``across`` square to it, in a direction at angle θ to the grain.

    Parameters
    ----------
    grain : (E, 2) or (2,) float64, unit grain directions
    d : (E, 2) float64, directions (any length, not zero)

    Returns
    -------
    (E,) float64

    Examples
    --------
    >>> directional(0.1, 0.5, np.array([0.0, 1.0]), np.array([[0.0, 2.0], [3.0, 0.0], [1.0, 1.0]])).round(3)
    array([0.1, 0.5, 0.3])
    """
    d = np.asarray(d, dtype=np.float64)
    g = np.broadcast_to(np.asarray(grain, dtype=np.float64), d.shape)
    c2 = np.einsum("ij,ij->i", d, g) ** 2 / np.maximum(np.einsum("ij,ij->i", d, d), 1e-30)
    return along * c2 + across * (1.0 - c2)
