"""The fit workflow as a library function: measure → grade → DXF + RUL → drape → report.

:func:`fit` runs one character × garment and returns a :class:`FitResult`;
:func:`load_subject` measures a character once so several fits can share it.
The command line (``patternbridge fit``) and the batch (``patternbridge
batch``) both call it. Heavy stages are imported only when a fit runs.
"""

from __future__ import annotations

from .model import FitFigures, FitOptions, FitResult, Verdict, figures_from_report
from .run import Garment, fit, load_garment_spec
from .subject import Subject, is_measurements_json, load_subject, safe_name

__all__ = [
    "FitFigures",
    "FitOptions",
    "FitResult",
    "Garment",
    "Subject",
    "Verdict",
    "figures_from_report",
    "fit",
    "is_measurements_json",
    "load_garment_spec",
    "load_subject",
    "safe_name",
]
