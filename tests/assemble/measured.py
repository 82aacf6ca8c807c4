"""A drape's measured quantities with nothing wrong, for tests that change one of them."""

from __future__ import annotations

from patternbridge.assemble.verdict import Measured


def clean_measured(**changed) -> Measured:
    """A :class:`Measured` of a drape with no seam, crossing, skin, stretch or level fault, ``changed`` applied."""
    clean = dict(
        seam_gaps_mm={},
        seam_excess_cm={},
        self_crossing={},
        skin_depth_mm=0.0,
        skin_share=0.0,
        skin_pieces=(),
        stretch_share=0.0,
        torn_share=0.0,
        stretch_pieces=(),
        levels_cm={},
    )
    return Measured(**{**clean, **changed})
