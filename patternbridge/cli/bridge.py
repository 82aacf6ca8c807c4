"""``patternbridge bridge infer PATTERN``: infer the bridge data of a tailor's pattern."""

from __future__ import annotations

import argparse

from ._common import add_pattern_arguments, load_pattern_args

HELP = "infer a pattern's bridge data (orientation, roles, seams, alternatives) as a sidecar and a review picture"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    sub = parser.add_subparsers(dest="action", metavar="ACTION")
    sub.required = True
    p = sub.add_parser("infer", help="orientation, roles, seams and alternatives of every piece")
    add_pattern_arguments(p)
    p.add_argument("-o", "--output", metavar="SIDECAR", help="sidecar to write (e.g. style.seams.json)")
    p.add_argument("--png", metavar="PICTURE", help="review picture to write (PNG)")
    p.add_argument("--pieces", help="comma-separated pieces of the garment (default: the inferred default set)")
    p.add_argument("--exclude", default="", help="comma-separated pieces to leave out of the garment")
    p.add_argument("--json", action="store_true", help="print the sidecar as JSON")


def _names(text: str | None) -> list[str] | None:
    return None if text is None else [t.strip() for t in text.split(",") if t.strip()]


def run(args: argparse.Namespace) -> int:
    import json

    from ..atomic import write_bytes, write_text
    from ..bridge import infer_bridge
    from ..bridge.picture import review_png
    from ..bridge.sidecar import inference_sidecar
    from ..bridge.summary import summary_line
    from ..errors import InputError
    from ._common import print_findings, print_json

    pattern, report = load_pattern_args(args)
    print_findings(report)
    names = set(pattern.piece_names)
    for n in (_names(args.pieces) or []) + (_names(args.exclude) or []):
        if n not in names:
            raise InputError(
                f"{args.pattern}: no piece {n!r} (pieces: {', '.join(pattern.piece_names)}); fix --pieces/--exclude"
            )
    inference = infer_bridge(pattern, pieces=_names(args.pieces), exclude=_names(args.exclude) or ())
    data = inference_sidecar(pattern, inference)
    if args.output:
        write_text(args.output, json.dumps(data, indent=1, ensure_ascii=False) + "\n")
    if args.png:
        write_bytes(args.png, review_png(pattern, inference))
    if args.json:
        print_json(data)
    else:
        print(summary_line(pattern, inference))
        for n in pattern.piece_names:
            g = inference.roles[n]
            o = inference.orientations[n]
            alt = "" if n in inference.chosen else "  (alternative, not in the default garment)"
            print(f"  {n:24s} {g.role.value:16s} {g.confidence:.2f}  turn {o.turn_deg:6.1f} deg{alt}")
        if args.output:
            print(f"wrote {args.output}")
        if args.png:
            print(f"wrote {args.png}")
    return 0
