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
    """

    code: str
    message: str
    where: str = ""
    fixed: bool = False

    def __str__(self) -> str:
        prefix = f"{self.where}: " if self.where else ""
        return f"{prefix}{self.message} [{self.code}]"


@dataclass(slots=True)
class Report:
    """An ordered collection of findings (the one mutable helper object)."""

    findings: list[Finding] = field(default_factory=list)

    def add(self, code: str, message: str, where: str = "", fixed: bool = False) -> None:
        self.findings.append(Finding(code=code, message=message, where=where, fixed=fixed))

    def extend(self, other: Report) -> None:
        self.findings.extend(other.findings)

    def codes(self) -> list[str]:
        return [f.code for f in self.findings]

    def __iter__(self):
        return iter(self.findings)

    def __len__(self) -> int:
        return len(self.findings)

    def __bool__(self) -> bool:
        return bool(self.findings)
