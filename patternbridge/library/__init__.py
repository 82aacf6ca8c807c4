"""The garment library: drafted, graded garments with seams, landmarks and placement.

``garment_names()`` lists them, ``load_garment(name)`` loads one as a
:class:`~patternbridge.pattern.model.Pattern`; the drafting code of each
garment is ``garment_library/<name>/draft.py``.
"""

from __future__ import annotations

from .catalogue import garment_dir, garment_names, load_garment

__all__ = ["garment_dir", "garment_names", "load_garment"]
