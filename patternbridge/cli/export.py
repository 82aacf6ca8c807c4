"""``patternbridge export``: a pattern as DXF-AAMA/ASTM (sample + .RUL, or a nest)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from ._common import add_pattern_arguments, load_pattern_args

HELP = "export a pattern as DXF-AAMA or DXF-ASTM: sample size + .RUL, or a graded nest"

__all__ = [
    "HELP",
    "add_arguments",
    "add_output_arguments",
    "export_pattern",
    "run",
]


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_pattern_arguments(parser, rul_flag="--in-rul", units=False)
    add_output_arguments(parser)


def add_output_arguments(parser: argparse.ArgumentParser) -> None:
    """``-o OUT.dxf`` and the options of a DXF export (``export``, ``library export``)."""
    parser.add_argument(
        "-o", "--output", required=True, metavar="OUT.dxf", help="DXF file to write"
    )
    parser.add_argument(
        "--flavor",
        "--flavour",
        choices=("aama", "astm"),
        default="aama",
        type=str.lower,
        help="DXF-AAMA (default) or DXF-ASTM D6673",
    )
    parser.add_argument(
        "--sizes",
        default="sample",
        metavar="sample|all|S,M",
        help="'sample' (default): the sample size plus a .RUL; 'all' or a "
        "comma-separated list: a graded nest with one block per piece per size",
    )
    parser.add_argument(
        "--rul",
        metavar="OUT.rul",
        help="where to write the grade-rule table (default with --sizes sample: "
        "OUT.rul beside the DXF when the pattern has grade rules)",
    )
    parser.add_argument("--no-rul", action="store_true", help="do not write a .RUL")
    parser.add_argument(
        "--units",
        choices=("METRIC", "ENGLISH"),
        type=str.upper,
        help="units of the written file (default: the pattern's source units)",
    )
    parser.add_argument(
        "--strict", action="store_true", help="treat every warning as an error"
    )


def run(args: argparse.Namespace) -> int:
    pattern, report = load_pattern_args(args)
    return export_pattern(pattern, report, args)


def export_pattern(pattern, report, args: argparse.Namespace) -> int:
    """Write ``pattern`` as DXF (+ ``.RUL``) by the options of :func:`add_output_arguments`.

    ``report`` holds the findings of loading the pattern; they are printed with
    the export's own and, with ``--strict``, block the export like them.
    """
    from ..errors import InputError
    from ..io.dxf_aama.write import format_dxf, write_dxf
    from ..report import Report
    from ._common import print_findings

    out = Path(args.output)
    if out.suffix.lower() != ".dxf":
        raise InputError(f"{out}: the output must be a .dxf file")
    sizes = args.sizes.strip()
    sample_only = sizes.lower() == "sample"
    rul = None
    if args.rul and not args.no_rul:
        if not sample_only:
            raise InputError(
                f"{args.rul}: a .RUL goes with --sizes sample; a graded nest carries "
                "every size itself"
            )
        rul = Path(args.rul)
    elif (
        sample_only
        and not args.no_rul
        and pattern.rules.deltas
        and len(pattern.rules.sizes) > 1
    ):
        rul = out.with_suffix(".rul")
    written = Report()
    if args.strict:
        # dry run first: with --strict a finding must leave nothing behind
        format_dxf(
            pattern, flavor=args.flavor, sizes=sizes, units=args.units, report=written
        )
        report.extend(written)
        print_findings(report)
        blocking = report.warnings
        if blocking:
            raise InputError(
                f"{out}: {len(blocking)} warning(s) and --strict was given "
                f"(first: {blocking[0].code}); nothing written"
            )
        written = Report()
    write_dxf(
        pattern,
        out,
        flavor=args.flavor,
        sizes=sizes,
        rul_path=rul,
        units=args.units,
        report=written,
    )
    if not args.strict:
        report.extend(written)
        print_findings(report)
    if args.quiet <= 0:
        what = "sample size" if sample_only else "graded nest"
        extra = f" + {rul}" if rul is not None else ""
        print(f"wrote {out}{extra} ({args.flavor.upper()}, {what})", file=sys.stdout)
    return 0
