"""``patternbridge plot``: a picture of every piece (SVG/PNG), sizes overlaid on request."""

from __future__ import annotations

import argparse
import sys

from ._common import add_pattern_arguments, load_pattern_args

HELP = "draw every piece with grain lines, notches, internal lines and labels (SVG/PNG)"

__all__ = ["HELP", "add_arguments", "run"]


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_pattern_arguments(parser)
    parser.add_argument(
        "-o",
        "--output",
        required=True,
        metavar="OUT.svg|OUT.png",
        help="picture to write; the suffix picks the format",
    )
    parser.add_argument(
        "--sizes",
        default="sample",
        metavar="sample|all|S,M",
        help="sizes to overlay: 'sample' (default), 'all' or a comma-separated list",
    )
    parser.add_argument(
        "--title", help="figure title (default: style, piece count and sizes)"
    )


def run(args: argparse.Namespace) -> int:
    from ..errors import InputError
    from ..io.plot import plot_pattern
    from ._common import print_findings

    if not str(args.output).lower().endswith((".svg", ".png", ".pdf")):
        raise InputError(
            f"{args.output}: unknown picture type; give a .svg or .png file name"
        )
    pattern, report = load_pattern_args(args)
    print_findings(report)
    sizes = args.sizes.strip()
    if (
        sizes.lower() != "sample"
        and not pattern.rules.deltas
        and (pattern.sizes or ()) not in ((), (pattern.sample_size,))
    ):
        raise InputError(
            f"{args.pattern}: the pattern has no grade rules to draw other sizes with"
        )
    out = plot_pattern(
        pattern,
        args.output,
        sizes=None if sizes.lower() == "sample" else sizes,
        title=args.title,
    )
    if args.quiet <= 0:
        print(f"wrote {out}", file=sys.stdout)
    return 0
