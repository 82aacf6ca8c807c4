"""``patternbridge grade``: a pattern in another size of its size list, by its rules."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

HELP = "grade a pattern to another size of its size list (rules from its .RUL or nest)"

__all__ = ["HELP", "add_arguments", "run"]


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "pattern",
        metavar="PATTERN",
        help="pattern: .json, .dxf or a library garment name",
    )
    parser.add_argument(
        "--size", required=True, help="target size (one of the pattern's sizes)"
    )
    parser.add_argument(
        "-o",
        "--output",
        required=True,
        metavar="OUT.json",
        help="graded pattern: .json (canonical), .dxf (sample-size DXF-AAMA) "
        "or .svg/.png (picture)",
    )
    parser.add_argument(
        "--rul", metavar="FILE.rul", help="grade-rule table of a sample-size DXF"
    )
    parser.add_argument(
        "--units",
        choices=("METRIC", "ENGLISH"),
        type=str.upper,
        help="override a DXF's Units: text",
    )


def run(args: argparse.Namespace) -> int:
    from ..errors import InputError
    from ..io.load import load_pattern
    from ._common import print_findings

    out = Path(args.output)
    suffix = out.suffix.lower()
    if suffix not in (".json", ".dxf", ".svg", ".png"):
        raise InputError(
            f"{out}: unknown output type {out.suffix!r}; give .json, .dxf, .svg or .png"
        )
    pattern, report = load_pattern(args.pattern, rul=args.rul, units=args.units)
    print_findings(report)
    size = str(args.size)
    sizes = list(pattern.sizes) or [pattern.sample_size]
    if size not in sizes:
        raise InputError(
            f"{args.pattern}: size {size!r} is not in the size list {sizes}; "
            "choose one of them"
        )
    if size != pattern.sample_size and not pattern.rules.deltas:
        raise InputError(
            f"{args.pattern}: the pattern has no grade rules; import it with its .RUL "
            "or as a graded nest"
        )
    from ..pattern.grading import grade

    try:
        graded = grade(pattern, size)
    except KeyError as exc:
        raise InputError(
            f"{args.pattern}: cannot grade to {size!r} ({exc.args[0]})"
        ) from None
    if suffix == ".json":
        from ..io.pattern_json import save_pattern_json

        save_pattern_json(graded, out)
    elif suffix == ".dxf":
        from ..io.dxf_aama.write import write_dxf

        write_dxf(graded, out)
    else:
        from ..io.plot import plot_pattern

        plot_pattern(graded, out)
    if args.quiet <= 0:
        print(  # noqa: T201
            f"wrote {out}: {graded.style} in size {size} ({len(graded.pieces)} pieces)",
            file=sys.stdout,
        )
    return 0
