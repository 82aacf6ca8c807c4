"""Write the files of one fit: measurements, graded pattern, DXF + RUL, drape, pictures, report."""

from __future__ import annotations

import dataclasses
import json
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..report import Report
from .subject import Subject, safe_name

if TYPE_CHECKING:  # pragma: no cover
    from ..grade.run import FitResult as GradingResult
    from ..pattern.model import Pattern

__all__ = ["FitOutputs", "json_default", "relative_files", "write_outputs"]

Progress = Callable[[str, int, int], None] | None


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class FitOutputs:
    """What :func:`write_outputs` wrote: file names (in order), the final report and the DXF findings."""

    names: tuple[str, ...]
    report: Mapping[str, Any]
    findings: Report


def _step(progress: Progress, stage: str, done: int) -> None:
    if progress is not None:
        progress(stage, done, 1)


def write_outputs(
    tmp: Path,
    *,
    original: Pattern,
    grading: GradingResult,
    report: Mapping[str, Any],
    subject: Subject,
    size: str,
    garment: str,
    seed: int,
    drape: bool,
    drape_sidecar: Path | None = None,
    progress: Progress = None,
) -> FitOutputs:
    """Write every output of a fit into the folder ``tmp``.

    Files: ``measurements.json``, ``<garment>_<size>.json`` (the graded
    pattern), ``<garment>_{aama,astm}.{dxf,rul}`` (the character as one more
    size), the drape's files when ``drape`` and a mesh is known,
    ``pattern.png``, ``pareto.png`` and ``fit_report.json`` (``report`` with
    the ``drape`` entry added). ``drape_sidecar``: the bridge sidecar of a DXF,
    whose recorded turns stand the pieces upright for the drape (the DXF
    written back keeps the designer's drawing).
    """
    from ..atomic import write_text
    from ..io.pattern_json import save_pattern_json
    from ..measure.model import write_measurements
    from ..pattern.grading import single_size

    names: list[str] = []
    write_measurements(tmp / "measurements.json", subject.measurements)
    names.append("measurements.json")
    stem = safe_name(garment)
    save_pattern_json(single_size(grading.pattern, size), tmp / f"{stem}_{size}.json")
    names.append(f"{stem}_{size}.json")
    _step(progress, "export", 0)
    findings = Report()
    names += _write_dxf(tmp, original, grading.pattern, size, stem, findings)
    _step(progress, "export", 1)

    rep = dict(report)
    if drape and subject.character is not None:
        from ..bridge.layers import draped_only

        draped = grading.pattern
        if drape_sidecar is not None:
            from ..bridge.upright import upright_pattern
            from ..bridge.worn import worn_pattern

            draped = worn_pattern(upright_pattern(draped, drape_sidecar), drape_sidecar)
        draped, kept_off = draped_only(draped)
        drape_names, drape_report = _write_drape(tmp, subject, draped, seed, progress)
        names += drape_names
        rep["drape"] = {**drape_report, "left_out": [x.as_dict() for x in kept_off]} if kept_off else drape_report
    elif drape:
        rep["drape"] = {"skipped": "measurements given without a character mesh"}

    _step(progress, "plot", 0)
    names += _write_plots(tmp, original, grading, size, garment)
    _step(progress, "plot", 1)
    write_text(tmp / "fit_report.json", json.dumps(rep, indent=1, default=json_default) + "\n")
    names.append("fit_report.json")
    return FitOutputs(names=tuple(names), report=rep, findings=findings)


def _write_dxf(tmp: Path, original: Pattern, graded: Pattern, size: str, stem: str, findings: Report) -> list[str]:
    """DXF-AAMA and DXF-ASTM with a RUL each: the character is one more size beside the original sizes."""
    from ..io.dxf_aama.write import write_dxf
    from ..pattern.grading import add_size

    base = original
    if not base.sizes:
        sample = base.sample_size or "base"
        base = dataclasses.replace(base, sample_size=sample, sizes=(sample,))
    combined = add_size(base, size, {p.name: p.outline for p in graded.pieces})
    names = []
    for flavor in ("aama", "astm"):
        dxf, rul = f"{stem}_{flavor}.dxf", f"{stem}_{flavor}.rul"
        write_dxf(combined, tmp / dxf, flavor=flavor, sizes="sample", rul_path=tmp / rul, report=findings)
        names += [dxf, rul]
    return names


def _write_drape(
    tmp: Path, subject: Subject, graded: Pattern, seed: int, progress: Progress
) -> tuple[list[str], dict[str, Any]]:
    """Dress the character; move the drape's files to ``tmp`` and name them there."""
    from ..assemble import dress

    drape_dir = tmp / "drape"
    drape_dir.mkdir()
    drape_report = dress(subject.character, graded, drape_dir, seed=seed, progress=progress)
    moved = []
    for f in sorted(drape_dir.iterdir()):
        if not f.name.startswith("."):
            f.replace(tmp / f.name)
            moved.append(f.name)
    drape_dir.rmdir()
    # the assembler names the files where it wrote them (the temporary
    # folder); the report names them where they end up, relative to OUT/
    drape_report = dict(drape_report)
    drape_report["files"] = relative_files(drape_report.get("files"), moved)
    return moved, drape_report


def _write_plots(tmp: Path, original: Pattern, grading: GradingResult, size: str, garment: str) -> list[str]:
    from ..grade.run import front_members
    from ..io.plot_fit import plot_fit_overlay, plot_pareto

    plot_fit_overlay(
        original.pieces,
        grading.pattern.pieces,
        tmp / "pattern.png",
        labels=(original.sample_size or "original", size),
        title=f"{garment}: original vs graded for {size}",
    )
    plot_pareto(
        grading.front_F,
        tmp / "pareto.png",
        chosen=grading.ga_choice.scores.F,
        final=grading.chosen.scores.F,
        refined=grading.front_refined,
        within=grading.front_within,
        baselines={n: s.scores.F for n, s in grading.baselines.items()},
        title=f"{garment} on {size}: final Pareto front",
        members=[(k, p.pieces) for k, p in front_members(grading)],
    )
    return ["pattern.png", "pareto.png"]


def relative_files(files, moved: list[str]) -> list[str]:
    """File names of the drape outputs relative to OUT/ (they land at its top level)."""
    if not files:
        return sorted(moved)
    return [Path(str(f)).name for f in files if Path(str(f)).name in moved] or sorted(moved)


def json_default(obj):
    """``json.dumps`` fallback for numpy arrays and scalars and paths."""
    import numpy as np

    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, (np.floating, np.integer)):
        return obj.item()
    if isinstance(obj, Path):
        return str(obj)
    raise TypeError(f"not JSON serialisable: {type(obj).__name__}")
