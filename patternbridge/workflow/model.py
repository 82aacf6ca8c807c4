"""The typed inputs and results of the fit workflow: options, verdict, key figures.

Light on purpose (stdlib only): the batch scheduler and ``import patternbridge``
import it without loading numpy-heavy stages.
"""

from __future__ import annotations

import logging
from collections.abc import Mapping
from dataclasses import dataclass, field
from enum import Enum
from pathlib import Path
from types import MappingProxyType
from typing import TYPE_CHECKING, Any

from ..report import Report

if TYPE_CHECKING:  # pragma: no cover
    from ..grade.run import FitResult as GradingResult

__all__ = ["DEFORMATIONS", "FitFigures", "FitOptions", "FitResult", "Verdict", "figures_from_report"]

log = logging.getLogger(__name__)

DEFORMATIONS = ("bilinear", "cubic")


class Verdict(str, Enum):
    """The drape's overall judgement of a dressed garment."""

    OK = "ok"
    FLAWED = "flawed"
    FAILED = "failed"


@dataclass(frozen=True, slots=True, kw_only=True)
class FitOptions:
    """Settings of one fit; every field has the ``patternbridge fit`` default.

    pop_size, n_gen : NSGA-II population and generations (None: the grader's defaults)
    deformation : grid map of the pieces, ``"bilinear"`` or ``"cubic"``
    repair : run the final least-change step after NSGA-II
    drape : assemble and drape the garment (needs a character mesh)
    choose : take row K of the Pareto front (numbered in ``pareto.png``) through the final step
        instead of the grader's own choice (None: the grader's choice)
    """

    pop_size: int | None = None
    n_gen: int | None = None
    deformation: str = "bilinear"
    repair: bool = True
    drape: bool = True
    choose: int | None = None

    def __post_init__(self) -> None:
        from ..errors import InputError

        if self.deformation not in DEFORMATIONS:
            raise InputError(f"deformation {self.deformation!r} is unknown; give one of {', '.join(DEFORMATIONS)}")
        if self.choose is not None and (isinstance(self.choose, bool) or int(self.choose) != self.choose
                                        or self.choose < 0):
            raise InputError(f"choose must be a row number of the Pareto front, 0 or more (got {self.choose!r})")
        for name in ("pop_size", "n_gen"):
            value = getattr(self, name)
            if value is not None and (isinstance(value, bool) or int(value) != value or value < 1):
                raise InputError(f"{name} must be a positive whole number (got {value!r})")

    def grader_kwargs(self) -> dict[str, Any]:
        """Keyword arguments of :func:`patternbridge.grade.run.fit_pattern` these options set."""
        kwargs: dict[str, Any] = {"deformation": self.deformation, "do_repair": self.repair}
        if self.pop_size is not None:
            kwargs["pop_size"] = int(self.pop_size)
        if self.n_gen is not None:
            kwargs["n_gen"] = int(self.n_gen)
        return kwargs


@dataclass(frozen=True, slots=True, kw_only=True)
class FitFigures:
    """The key figures of one fit, read from its ``fit_report.json``.

    mean_error_cm, max_error_cm : measurement error of the graded pattern, cm
    max_seam_mm : worst seam length or notch mismatch, mm
    shape_error : shape change of the graded pattern, rad
    baseline_shape_error, baseline_mean_error_cm : the same for proportional scaling
    seam_gap_before_weld_mm : widest seam gap the drape left before welding (None: not draped)
    verdict : the drape's verdict when its report has one
    grading_seconds, drape_seconds : time of the two long stages (drape: None when not draped)
    """

    mean_error_cm: float
    max_error_cm: float
    max_seam_mm: float
    shape_error: float
    baseline_shape_error: float
    baseline_mean_error_cm: float
    seam_gap_before_weld_mm: float | None = None
    verdict: Verdict | None = None
    grading_seconds: float = 0.0
    drape_seconds: float | None = None


def _verdict(drape: Mapping[str, Any]) -> Verdict | None:
    value = drape.get("verdict")
    if isinstance(value, Mapping):  # {"verdict": {"verdict": "ok", ...}} or {"status": ...}
        value = value.get("verdict", value.get("status"))
    if value is None:
        return None
    try:
        return Verdict(str(value).lower())
    except ValueError:
        log.warning("drape report: unknown verdict %r (known: ok, flawed, failed); ignored", value)
        return None


def _float_or_none(value: Any) -> float | None:
    return None if value is None else float(value)


def figures_from_report(report: Mapping[str, Any]) -> FitFigures:
    """The :class:`FitFigures` of a fit report (the ``fit_report.json`` object)."""
    baseline = report.get("baseline") or {}
    drape = report.get("drape") or {}
    draped = "max_seam_gap_before_weld_mm" in drape or "seconds" in drape
    return FitFigures(
        mean_error_cm=float(report["mean_error_cm"]),
        max_error_cm=float(report["max_error_cm"]),
        max_seam_mm=float(report["max_seam_mm"]),
        shape_error=float(report["shape_error"]),
        baseline_shape_error=float(baseline.get("shape_error", float("nan"))),
        baseline_mean_error_cm=float(baseline.get("mean_error_cm", float("nan"))),
        seam_gap_before_weld_mm=_float_or_none(drape.get("max_seam_gap_before_weld_mm")),
        verdict=_verdict(drape),
        grading_seconds=float(report.get("seconds", 0.0)),
        drape_seconds=_float_or_none(drape.get("seconds")) if draped else None,
    )


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class FitResult:
    """What :func:`patternbridge.fit` made.

    character, garment : names used in the report and the file names
    size : name of the character's size in the graded pattern and the RUL
    out_dir : folder the files are in
    files : names written into ``out_dir``, in order (``fit_report.json`` last)
    report : the ``fit_report.json`` object (read-only)
    figures : its key figures
    findings : recoverable problems met on the way (loading, DXF export)
    seconds : wall time of the whole workflow
    grading : the grader's full result (front, baselines, graded pattern)
    """

    character: str
    garment: str
    size: str
    out_dir: Path
    files: tuple[str, ...]
    report: Mapping[str, Any]
    figures: FitFigures
    findings: Report = field(default_factory=Report)
    seconds: float = 0.0
    grading: GradingResult | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "out_dir", Path(self.out_dir))
        object.__setattr__(self, "files", tuple(self.files))
        object.__setattr__(self, "report", MappingProxyType(dict(self.report)))

    @property
    def verdict(self) -> Verdict | None:
        """The drape report's verdict; None when it has none (not draped, or no verdict given)."""
        return self.figures.verdict
