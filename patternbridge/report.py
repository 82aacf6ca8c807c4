"""Findings: recoverable problems reported beside a result instead of guessed away.

A reader returns ``(result, Report)``; the CLI prints each finding as a
warning and ``--strict`` turns them into errors.
"""

from __future__ import annotations

from dataclasses import dataclass, field

__all__ = ["Finding", "Report"]


@dataclass(frozen=True, slots=True, kw_only=True)
class Finding:
    """One recoverable problem.

    ``code`` is a stable kebab-case identifier (``"units-assumed"``), ``where``
    names the file, piece or element, ``fixed`` says whether it was repaired.
    ``severity`` is ``"warning"`` (the result may not be what the user meant;
    ``--strict`` refuses it) or ``"info"`` (a normal, expected adjustment such as
    dropping validation curves, printed as a note).
    """

    code: str
    message: str
    where: str = ""
    fixed: bool = False
    severity: str = "warning"

    def __post_init__(self) -> None:
        if self.severity not in ("warning", "info"):
            raise ValueError(f"finding severity must be 'warning' or 'info', got {self.severity!r}")

    def __str__(self) -> str:
        prefix = f"{self.where}: " if self.where else ""
        return f"{prefix}{self.message} [{self.code}]"


@dataclass(slots=True)
class Report:
    """An ordered collection of findings (the one mutable helper object)."""

    findings: list[Finding] = field(default_factory=list)

    def add(
        self, code: str, message: str, where: str = "", fixed: bool = False, severity: str = "warning"
    ) -> None:
        """Record a finding; one already recorded word for word (two writers of one pattern) is kept once."""
        finding = Finding(code=code, message=message, where=where, fixed=fixed, severity=severity)
        if finding not in self.findings:
            self.findings.append(finding)

    @property
    def warnings(self) -> list[Finding]:
        """The findings ``--strict`` refuses (everything but ``info``)."""
        return [f for f in self.findings if f.severity == "warning"]

    def extend(self, other: Report) -> None:
        for f in other.findings:
            self.add(f.code, f.message, f.where, f.fixed, f.severity)

    def codes(self) -> list[str]:
        return [f.code for f in self.findings]

    def __iter__(self):
        return iter(self.findings)

    def __len__(self) -> int:
        return len(self.findings)

    def __bool__(self) -> bool:
        return bool(self.findings)
