"""``patternbridge check PATTERN``: seam lengths and notches in every graded size."""

from __future__ import annotations

import argparse
import sys

from ._common import add_pattern_arguments, load_pattern_args

HELP = "check that every seam sews to equal length (or its declared ease) in every size"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_pattern_arguments(parser)
    parser.add_argument(
        "--sidecar",
        help="bridge-data sidecar (default: <pattern>.seams.json beside a .dxf)",
    )
    parser.add_argument(
        "--tol-mm",
        type=_non_negative,
        default=1.0,
        help="allowed seam length mismatch (default 1 mm)",
    )
    parser.add_argument(
        "--notch-tol-mm",
        type=_non_negative,
        default=1.5,
        help="allowed notch misalignment (default 1.5 mm)",
    )
    parser.add_argument(
        "--json", action="store_true", help="print every seam result as JSON"
    )


def _non_negative(text: str) -> float:
    value = float(text)
    if not value >= 0:
        raise argparse.ArgumentTypeError(f"{text}: a tolerance must be >= 0")
    return value


def load_with_sidecar(args: argparse.Namespace):
    """``(pattern, report)`` of PATTERN with its bridge-data sidecar applied.

    The sidecar is ``args.sidecar`` when given, else the one beside a ``.dxf``
    (:func:`patternbridge.library.sidecar.sidecar_beside`).
    """
    from pathlib import Path

    from ..library.sidecar import apply_sidecar, sidecar_beside

    pattern, report = load_pattern_args(args)
    sidecar = args.sidecar
    if sidecar is None and Path(args.pattern).suffix.lower() == ".dxf":
        sidecar = sidecar_beside(args.pattern)
    if sidecar is not None:
        pattern = apply_sidecar(pattern, sidecar)
    return pattern, report


def run(args: argparse.Namespace) -> int:
    from ..library.seams import check_seams
    from ._common import print_findings, print_json

    pattern, report = load_with_sidecar(args)
    print_findings(report)
    if not pattern.seams:
        print(
            f"patternbridge: warning: {args.pattern}: no seams to check; propose some with "
            "'patternbridge seams infer'",
            file=sys.stderr,
        )
        if args.json:  # the machine-readable answer: no seam results
            print_json([])
        return 0
    results = check_seams(
        pattern, tol_cm=args.tol_mm / 10, notch_tol_cm=args.notch_tol_mm / 10
    )
    failed = [r for r in results if not r.ok]
    if args.json:
        print_json(
            [
                {
                    "seam": r.seam,
                    "size": r.size,
                    "length_a_cm": round(r.length_a_cm, 4),
                    "length_b_cm": round(r.length_b_cm, 4),
                    "ease_cm": r.ease_cm,
                    "mismatch_mm": round(r.mismatch_cm * 10, 3),
                    "notch_error_mm": round(r.notch_error_cm * 10, 3),
                    "ok": r.ok,
                    "problems": list(r.problems),
                }
                for r in results
            ]
        )
    else:
        for r in failed:
            print(f"FAIL {r.seam} size {r.size}: " + "; ".join(r.problems))
        sizes = len({r.size for r in results})
        print(
            f"{pattern.style}: {len(pattern.seams)} seams x {sizes} sizes: "
            f"{len(results) - len(failed)} passed, {len(failed)} failed"
        )
    return 1 if failed else 0
