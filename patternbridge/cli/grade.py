"""``patternbridge grade``: a pattern in another size of its size list, by its rules."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from ._common import add_pattern_arguments, load_pattern_args

HELP = "grade a pattern to another size of its size list (rules from its .RUL or nest)"

__all__ = ["HELP", "add_arguments", "run"]


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_pattern_arguments(parser)
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


def run(args: argparse.Namespace) -> int:
    from ..errors import InputError
    from ._common import print_findings

    out = Path(args.output)
    suffix = out.suffix.lower()
    if suffix not in (".json", ".dxf", ".svg", ".png"):
        raise InputError(
            f"{out}: unknown output type {out.suffix!r}; give .json, .dxf, .svg or .png"
        )
    pattern, report = load_pattern_args(args)
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
        print(
            f"wrote {out}: {graded.style} in size {size} ({len(graded.pieces)} pieces)",
            file=sys.stdout,
        )
    return 0
