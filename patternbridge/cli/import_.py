"""``patternbridge import``: a DXF-AAMA/ASTM file (+ .RUL) into canonical pattern JSON."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

HELP = "import a DXF-AAMA/ASTM pattern (and its .RUL) into canonical pattern JSON"

__all__ = ["HELP", "add_arguments", "run"]


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "file", metavar="FILE.dxf", help="DXF-AAMA or DXF-ASTM pattern file"
    )
    parser.add_argument(
        "-o",
        "--output",
        required=True,
        metavar="PATTERN.json",
        help="canonical pattern JSON to write",
    )
    parser.add_argument(
        "--rul",
        metavar="FILE.rul",
        help="grade-rule table (default: a .rul with the DXF's name beside it)",
    )
    parser.add_argument(
        "--units",
        choices=("METRIC", "ENGLISH"),
        type=str.upper,
        help="override the file's Units: text (METRIC = mm, ENGLISH = inch)",
    )
    parser.add_argument(
        "--json",
        action="store_true",
        help="print a summary of the imported pattern as JSON (the 'info --json' "
        "contract, formats/info.md) instead of the 'wrote' line",
    )
    parser.add_argument(
        "--unfold",
        action="store_true",
        help="unfold half pieces about their mirror line into whole pieces",
    )
    parser.add_argument(
        "--seams",
        metavar="FILE.seams.json",
        help="seam sidecar (marks, seams, landmarks, measurements, placement); "
        "default: <dxf stem>.seams.json beside the DXF when present",
    )
    parser.add_argument(
        "--exact-nest",
        action="store_true",
        help="graded nest: make every boundary vertex a rule point so each size's own "
        "curves are reproduced exactly (default: only when the file's '# n' points alone "
        "would miss them by more than 0.5 mm)",
    )
    parser.add_argument(
        "--strict", action="store_true", help="treat every warning as an error"
    )


def _sidecar(args: argparse.Namespace, dxf: Path) -> tuple[Path | None, bool]:
    """(sidecar path, given explicitly) or (None, False)."""
    if args.seams:
        return Path(args.seams), True
    try:
        from ..library.sidecar import sidecar_beside
    except ImportError:
        return None, False
    return sidecar_beside(dxf), False


def run(args: argparse.Namespace) -> int:
    from ..errors import InputError
    from ..io.pattern_json import save_pattern_json
    from ._common import print_findings

    dxf = Path(args.file)
    if not dxf.is_file():
        raise InputError(f"{dxf}: no such file")
    if dxf.suffix.lower() != ".dxf":
        raise InputError(
            f"{dxf}: not a .dxf file; 'import' reads DXF-AAMA/ASTM (use 'info' or "
            "'export' for pattern JSON)"
        )
    from ..io.dxf_aama import read_dxf

    pattern, report = read_dxf(
        dxf,
        rul=args.rul,
        units=args.units,
        unfold=args.unfold,
        strict=args.strict,
        exact_nest=args.exact_nest,
    )
    sidecar, explicit = _sidecar(args, dxf)
    applied = None
    if sidecar is not None:
        try:
            from ..library.sidecar import apply_sidecar
        except ImportError:
            if explicit:
                raise InputError(
                    f"{sidecar}: seam sidecars cannot be read by this installation "
                    "(patternbridge.library.sidecar is missing)"
                ) from None
            report.add(
                "sidecar-skipped",
                "seam sidecar found but sidecar support is missing; ignored",
                where=str(sidecar),
            )
        else:
            if not sidecar.is_file():
                raise InputError(
                    f"{sidecar}: no such file; give an existing seam sidecar"
                )
            pattern = apply_sidecar(pattern, sidecar)
            applied = sidecar
    # the reader applied --strict itself (informational findings pass)
    print_findings(report)
    if args.strict and "sidecar-skipped" in report.codes():
        raise InputError(f"{sidecar}: sidecar not applied and --strict was given")
    out = save_pattern_json(pattern, args.output)
    if args.json:
        from ._common import print_json
        from .info import pattern_info

        print_json(pattern_info(pattern))
    elif args.quiet <= 0:
        sizes = ", ".join(pattern.sizes) if pattern.sizes else pattern.sample_size
        extra = f"; seams from {applied}" if applied is not None else ""
        print(
            f"wrote {out}: {pattern.style}, {len(pattern.pieces)} pieces, sizes {sizes} "
            f"(sample {pattern.sample_size}), {pattern.units}{extra}",
            file=sys.stdout,
        )
    return 0
