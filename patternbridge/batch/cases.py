"""The cases of a batch: character × garment, where each one's files go, and what earlier runs left."""

from __future__ import annotations

import json
import os
import shutil
from dataclasses import dataclass
from enum import Enum
from pathlib import Path
from typing import Any

from ..workflow.model import FitFigures, Verdict, figures_from_report
from ..workflow.subject import safe_name

__all__ = [
    "Case",
    "CaseOutcome",
    "CaseStatus",
    "check_inputs",
    "clear_failure",
    "earlier_outcome",
    "make_cases",
    "remove_partial",
    "write_failure",
]

FAILED_SUFFIX = ".failed.json"
PARTIAL_PREFIX = ".part-"


class CaseStatus(str, Enum):
    """How a case ended: ``done`` (files written), ``failed`` (it raised) or ``lost`` (its worker died)."""

    DONE = "done"
    FAILED = "failed"
    LOST = "lost"


@dataclass(frozen=True, slots=True, kw_only=True)
class Case:
    """One character × garment.

    character : short name of the character (its file stem), the first folder level
    character_path : its mesh or measurements JSON
    garment : short name of the garment (library name or file stem), the second folder level
    garment_spec : library name or pattern file given to the fit
    """

    character: str
    character_path: str
    garment: str
    garment_spec: str

    @property
    def key(self) -> str:
        """``character/garment``: the case's folder relative to OUT/, and its name in progress lines."""
        return f"{self.character}/{self.garment}"

    def folder(self, out_dir: Path) -> Path:
        return Path(out_dir) / self.character / self.garment

    def failure_record(self, out_dir: Path) -> Path:
        return Path(out_dir) / self.character / f"{self.garment}{FAILED_SUFFIX}"


@dataclass(frozen=True, slots=True, kw_only=True)
class CaseOutcome:
    """The result of one case.

    status : how it ended
    seconds : wall time of the fit (0 when not run)
    cpu_seconds : CPU time of the worker process while it ran the case (all its threads: the fit and
        the worker's own housekeeping; 0 when not run in this batch)
    peak_rss_mb : the worker process's peak resident memory when the case ended (0 when not run in this batch)
    figures : the key figures of its report (done cases)
    error : one line naming the error (failed and lost cases)
    worker : address of the worker that ran it ("" when not run in this batch)
    reused : True when an earlier run made this result and it was kept
    files : the names in the case folder
    """

    case: Case
    status: CaseStatus
    seconds: float = 0.0
    cpu_seconds: float = 0.0
    peak_rss_mb: float = 0.0
    figures: FitFigures | None = None
    error: str = ""
    worker: str = ""
    reused: bool = False
    files: tuple[str, ...] = ()

    @property
    def verdict(self) -> Verdict | None:
        return self.figures.verdict if self.figures else None


def _stem(spec: str) -> str:
    return safe_name(Path(spec).stem if Path(spec).suffix else spec)


def make_cases(characters: list[str], garments: list[str]) -> list[Case]:
    """Every character × garment, in the order given.

    Raises
    ------
    InputError
        Two characters or two garments would share a folder (same file stem).
    """
    from ..errors import InputError

    for kind, specs in (("character", characters), ("garment", garments)):
        seen: dict[str, str] = {}
        for spec in specs:
            name = _stem(spec)
            if name in seen and seen[name] != spec:
                raise InputError(
                    f"{spec}: the {kind} {seen[name]} has the same name {name!r}; "
                    f"rename one so each {kind} gets its own folder"
                )
            seen[name] = spec
    characters = list(dict.fromkeys(characters))
    garments = list(dict.fromkeys(garments))
    return [
        Case(character=_stem(c), character_path=str(c), garment=_stem(g), garment_spec=str(g))
        for c in characters
        for g in garments
    ]


def check_inputs(characters: list[str], garments: list[str]) -> list[Case]:
    """The cases of ``characters`` × ``garments`` after checking each input exists.

    Raises
    ------
    InputError
        A character file is missing, a garment is neither a file nor a library
        garment, or two inputs would share a folder.
    """
    from ..errors import InputError
    from ..library import garment_names

    for path in characters:
        if not Path(path).is_file():
            raise InputError(f"{path}: no such character file; give meshes (OBJ/PLY/STL/glTF) or measurements JSONs")
    library = set(garment_names())
    for spec in garments:
        if not Path(spec).is_file() and spec not in library:
            known = ", ".join(sorted(library))
            raise InputError(f"{spec}: neither a pattern file nor a library garment (library: {known})")
    return make_cases(characters, garments)


def _report_seconds(report: dict[str, Any]) -> float:
    drape = report.get("drape") or {}
    return float(report.get("seconds", 0.0)) + float(drape.get("seconds", 0.0) or 0.0)


def earlier_outcome(case: Case, out_dir: Path) -> CaseOutcome | None:
    """What an earlier run left for ``case``: a finished folder, a failure record, or None."""
    folder = case.folder(out_dir)
    report_path = folder / "fit_report.json"
    if report_path.is_file():
        report = json.loads(report_path.read_text(encoding="utf-8"))
        seconds = _report_seconds(report)
        return CaseOutcome(
            case=case,
            status=CaseStatus.DONE,
            figures=figures_from_report(report),
            seconds=seconds,
            reused=True,
            files=tuple(sorted(p.name for p in folder.iterdir() if not p.name.startswith("."))),
        )
    record = case.failure_record(out_dir)
    if record.is_file():
        data = json.loads(record.read_text(encoding="utf-8"))
        return CaseOutcome(
            case=case,
            status=CaseStatus.FAILED,
            error=str(data.get("error", "")),
            seconds=float(data.get("seconds", 0.0)),
            worker=str(data.get("worker", "")),
            reused=True,
        )
    return None


def write_failure(outcome: CaseOutcome, out_dir: Path) -> None:
    """Record a failed case beside where its folder would be (``<garment>.failed.json``)."""
    from ..atomic import write_text

    data = {
        "case": outcome.case.key,
        "status": outcome.status.value,
        "error": outcome.error,
        "seconds": round(outcome.seconds, 2),
        "worker": outcome.worker,
    }
    write_text(outcome.case.failure_record(out_dir), json.dumps(data, indent=1) + "\n")


def clear_failure(case: Case, out_dir: Path) -> None:
    case.failure_record(out_dir).unlink(missing_ok=True)


def remove_partial(case: Case, out_dir: Path) -> None:
    """Delete what a run of ``case`` killed mid-way left (``.part-<garment>-*`` folders)."""
    parent = Path(out_dir) / case.character
    if parent.is_dir():
        for p in parent.glob(f"{PARTIAL_PREFIX}{case.garment}-*"):
            shutil.rmtree(p, ignore_errors=True) if p.is_dir() else os.unlink(p)
