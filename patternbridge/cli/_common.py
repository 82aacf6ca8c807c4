"""Small helpers shared by the sub-commands: warnings, progress lines, JSON output."""

from __future__ import annotations

import argparse
import json
import sys
import time
from collections.abc import Callable

from ..report import Report

__all__ = [
    "add_pattern_arguments",
    "bounded_int",
    "load_pattern_args",
    "print_findings",
    "print_json",
    "progress_printer",
]


def bounded_int(lo: int, hi: int) -> Callable[[str], int]:
    """An argparse ``type`` accepting whole numbers in ``lo..hi`` (bad values: usage error, exit 2).

    Examples
    --------
    >>> bounded_int(1, 10)("4")
    4
    """

    def parse(text: str) -> int:
        try:
            value = int(text, 10)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{text[:40]!r} is not a whole number") from None
        if not lo <= value <= hi:
            raise argparse.ArgumentTypeError(f"{value} is outside {lo}..{hi}")
        return value

    parse.__name__ = "whole number"  # argparse names the type in its messages
    return parse


def print_findings(report: Report, *, strict: bool = False) -> None:
    """Print findings on stderr (warnings, then notes); raise on warnings with ``strict``."""
    from ..errors import InputError

    for finding in report:
        label = "note" if finding.severity == "info" else "warning"
        print(f"patternbridge: {label}: {finding}", file=sys.stderr)
    if strict and report.warnings:
        raise InputError(f"{len(report.warnings)} warning(s) and --strict was given")


def progress_printer(quiet: bool = False) -> Callable[[str, int, int], None]:
    """Return a ``progress(stage, done, total)`` callback drawing per-stage lines.

    On a terminal the current line is redrawn as a bar; otherwise a line is
    printed for every 10 % so logs stay readable.
    """
    tty = sys.stderr.isatty()
    state: dict[str, float] = {}

    def progress(stage: str, done: int, total: int) -> None:
        if quiet:
            return
        total = max(total, 1)
        frac = min(done / total, 1.0)
        if tty:
            bar = "#" * int(frac * 30)
            end = "\n" if done >= total else ""
            print(
                f"\r[{stage}] {bar:<30} {done}/{total}",
                end=end,
                file=sys.stderr,
                flush=True,
            )
            return
        step = int(frac * 10)
        key = stage
        if state.get(key) == step and done < total:
            return
        state[key] = step
        print(
            f"[{stage}] {done}/{total} ({time.strftime('%H:%M:%S')})",
            file=sys.stderr,
            flush=True,
        )

    return progress


def print_json(obj) -> None:
    """Print ``obj`` as indented JSON on stdout."""
    json.dump(obj, sys.stdout, indent=2, ensure_ascii=False)
    sys.stdout.write("\n")


def add_pattern_arguments(
    parser: argparse.ArgumentParser, *, rul_flag: str = "--rul", units: bool = True
) -> None:
    """PATTERN (file or library name), its ``.RUL`` and a ``--units`` override.

    Shared by every command that reads a pattern; read them back with
    :func:`load_pattern_args`.
    """
    dest = rul_flag.lstrip("-").replace("-", "_")
    parser.add_argument(
        "pattern",
        metavar="PATTERN",
        help="pattern: .json, .dxf or a library garment name",
    )
    parser.add_argument(
        rul_flag,
        metavar="FILE.rul",
        dest=dest,
        help="grade-rule table of a sample-size DXF (default: the .rul beside it)",
    )
    parser.set_defaults(pattern_rul_dest=dest, pattern_units=units)
    if units:
        parser.add_argument(
            "--units",
            choices=("METRIC", "ENGLISH"),
            type=str.upper,
            help="override a DXF's Units: text (METRIC = mm, ENGLISH = inch)",
        )


def load_pattern_args(args: argparse.Namespace):
    """``(pattern, report)`` of the PATTERN given by :func:`add_pattern_arguments`."""
    from ..io.load import load_pattern

    units = args.units if args.pattern_units else None
    return load_pattern(
        args.pattern, rul=getattr(args, args.pattern_rul_dest), units=units
    )
