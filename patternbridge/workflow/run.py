"""``fit``: measure a character, grade a garment to it, write everything (the whole workflow)."""

from __future__ import annotations

import dataclasses
import os
import shutil
import tempfile
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from ..errors import InputError
from ..report import Report
from .model import FitOptions, FitResult, figures_from_report
from .outputs import FitOutputs, write_outputs
from .subject import Subject, load_subject, safe_name

if TYPE_CHECKING:  # pragma: no cover
    from ..grade.run import FitResult as GradingResult
    from ..pattern.model import Pattern

__all__ = ["Garment", "fit", "load_garment_spec"]

Progress = Callable[[str, int, int], None] | None


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class Garment:
    """A loaded garment: its pattern, its name (file names, report) and where it came from (messages)."""

    pattern: Pattern
    name: str
    source: str
    sidecar: Path | None = None
    inferred: tuple[tuple[str, bytes], ...] = ()
    summary: str | None = None

    @property
    def drape_sidecar_name(self) -> str | None:
        """File name of the inferred sidecar among :attr:`inferred` (None when the bridge data were given)."""
        return next((name for name, _ in self.inferred if name.endswith(".seams.json")), None)


def _bridged(
    garment: str | os.PathLike,
) -> tuple[Pattern, Report, Path | None, tuple[tuple[str, bytes], ...], str | None]:
    """A pattern file with its bridge data: the sidecar beside a DXF, or inferred (kept in memory) without one."""
    from ..bridge.fit_input import pattern_for_fit

    with tempfile.TemporaryDirectory(prefix="patternbridge-bridge-") as scratch:
        loaded = pattern_for_fit(garment, scratch)
        inferred = tuple(
            (p.name, p.read_bytes())
            for p in (loaded.sidecar, loaded.picture)
            if p is not None and loaded.summary is not None
        )
    given = loaded.sidecar if loaded.summary is None else None
    return loaded.pattern, loaded.report, given, inferred, loaded.summary


def load_garment_spec(garment: str | os.PathLike | Pattern | Garment) -> tuple[Garment, Report]:
    """``(garment, findings)`` of a library garment name, a pattern file or a loaded pattern.

    A DXF uses the bridge sidecar beside it (``<stem>.seams.json``); without
    one its bridge data are inferred, and the inferred sidecar and its review
    picture travel with the garment into the fit's output folder, where the
    user can correct the sidecar and run again.

    Raises
    ------
    InputError
        The garment cannot be loaded, or it has no measurement links (nothing tells the grader where it sits).
    """
    from ..pattern.model import Pattern

    if isinstance(garment, Garment):
        return garment, Report()
    sidecar, inferred, summary = None, (), None
    if isinstance(garment, Pattern):
        pattern, findings, source = garment, Report(), garment.style or "garment"
    else:
        pattern, findings, sidecar, inferred, summary = _bridged(garment)
        source = str(garment)
    if not pattern.measurements:
        raise InputError(
            f"{source}: the pattern has no landmark-to-measurement mapping (no measurement links); "
            "add them with `patternbridge seams infer` or in the pattern's bridge-data sidecar, then run fit again"
        )
    name = pattern.style or Path(source).stem
    return Garment(
        pattern=pattern, name=name, source=source, sidecar=sidecar, inferred=inferred, summary=summary
    ), findings


def _check_measurements(subject: Subject, pattern: Pattern, garment: str) -> dict[str, float]:
    values = subject.measurements.values_cm()
    lacking = sorted({lk.measurement for lk in pattern.measurements} - set(values))
    if lacking:
        reasons = subject.measurements.missing
        detail = ", ".join(f"{m} ({reasons[m]})" if m in reasons else m for m in lacking)
        raise InputError(
            f"{subject.source}: the character lacks measurements {garment!r} needs: {detail}; "
            "add the landmarks they need (--landmarks) or give them in a measurements JSON"
        )
    return values


def fit(
    character: Subject | str | os.PathLike,
    garment: str | os.PathLike | Pattern | Garment,
    *,
    seed: int = 0,
    options: FitOptions | None = None,
    out_dir: str | os.PathLike,
    progress: Progress = None,
) -> FitResult:
    """Fit ``garment`` to ``character`` and write every output into ``out_dir``.

    Stages: load the pattern → measure the character (unless a measured
    :class:`Subject` is given) → grade with NSGA-II and the final
    least-change step → DXF-AAMA/ASTM + RUL → drape (``options.drape`` and a
    mesh) → pictures → ``fit_report.json``. Everything is written into a
    temporary folder inside ``out_dir`` and moved into place at the end, so a
    failed run leaves no partial output (and no ``out_dir`` it created).

    Parameters
    ----------
    character : a :class:`Subject` (see :func:`load_subject`), a mesh file or a measurements JSON
    garment : library garment name, pattern file (JSON, DXF with bridge data), a :class:`Pattern`, or a
        :class:`Garment` from :func:`load_garment_spec` (checked before a long measuring)
    seed : seed of the grader and the drape (same inputs and seed, same files)
    options : :class:`FitOptions` (defaults: those of ``patternbridge fit``)
    out_dir : output folder (created when missing)
    progress : ``progress(stage, done, total)``; stages ``girths``/``lengths``
        (measuring), ``seed``/``grade``/``refine``/``repair`` (grading),
        ``export``, the drape's stages, ``plot``

    Returns
    -------
    FitResult

    Raises
    ------
    InputError
        Bad character, garment or output folder. ``SolverError`` when grading fails.
    """
    t0 = time.perf_counter()
    options = options or FitOptions()
    out = Path(out_dir)
    if out.exists() and not out.is_dir():
        raise InputError(f"{out}: exists and is not a folder; give a folder for the output")
    loaded, findings = load_garment_spec(garment)
    if not isinstance(character, Subject):
        character, char_findings = load_subject(character, progress=progress)
        findings.extend(char_findings)
    graded = _grade(character, loaded, seed=seed, options=options, progress=progress)
    written = _write_into(out, character, loaded, graded, seed=seed, options=options, progress=progress)
    findings.extend(written.findings)
    return FitResult(
        character=character.name,
        garment=loaded.name,
        size=graded.size,
        out_dir=out,
        files=written.names,
        report=written.report,
        figures=figures_from_report(written.report),
        findings=findings,
        seconds=time.perf_counter() - t0,
        grading=graded.grading,
    )


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class _Graded:
    """The grader's result for one character, the size name the character is graded as and the fit report."""

    grading: GradingResult
    size: str
    report: dict[str, Any]


def _grade(character: Subject, loaded: Garment, *, seed: int, options: FitOptions, progress: Progress) -> _Graded:
    """Grade the garment to the character's measurements (a size named after the character) and report the fit."""
    from ..grade.report import fit_report
    from ..grade.run import fit_pattern

    pattern = loaded.pattern
    values = _check_measurements(character, pattern, loaded.name)
    size = safe_name(character.name)
    if size in pattern.sizes:
        size = f"{size}_fit"
    grading = fit_pattern(
        pattern, values, seed=seed, size=size, source=loaded.source, progress=progress, **options.grader_kwargs()
    )
    if options.choose is not None:
        from ..grade.run import choose_member

        grading = choose_member(grading, options.choose, size=size)
    report = fit_report(grading, character=character.name, garment=loaded.name)
    return _Graded(grading=grading, size=size, report=report)


def _write_into(
    out: Path,
    character: Subject,
    loaded: Garment,
    graded: _Graded,
    *,
    seed: int,
    options: FitOptions,
    progress: Progress,
) -> FitOutputs:
    """Write every output into a temporary folder inside ``out`` and move it into place (none on failure)."""
    created = not out.exists()
    out.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix=".fit-", dir=out))
    try:
        for name, data in loaded.inferred:  # the inferred bridge data, for the user to check and correct
            (tmp / name).write_bytes(data)
        inferred_sidecar = loaded.drape_sidecar_name
        written = write_outputs(
            tmp,
            original=loaded.pattern,
            grading=graded.grading,
            report=graded.report,
            subject=character,
            size=graded.size,
            garment=loaded.name,
            seed=seed,
            drape=options.drape,
            progress=progress,
            drape_sidecar=tmp / inferred_sidecar if inferred_sidecar else loaded.sidecar,
        )
        written = dataclasses.replace(written, names=(*(n for n, _ in loaded.inferred), *written.names))
        for name in written.names:
            dst = out / name
            if (tmp / name).is_dir() and dst.exists():
                shutil.rmtree(dst)
            (tmp / name).replace(dst)
    except BaseException:
        if created:  # nothing half-written: not even the folder
            shutil.rmtree(out, ignore_errors=True)
        raise
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return written
