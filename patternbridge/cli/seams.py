"""``patternbridge seams infer PATTERN -o sidecar.json``: propose seams for a tailor's file."""

from __future__ import annotations

import argparse

from ._common import add_pattern_arguments, load_pattern_args

HELP = "propose seam pairs for a pattern without bridge data, as an editable sidecar"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    sub = parser.add_subparsers(dest="action", metavar="ACTION")
    sub.required = True
    p = sub.add_parser(
        "infer", help="match boundary stretches of equal length and shape"
    )
    add_pattern_arguments(p)
    p.add_argument(
        "-o", "--output", required=True, help="sidecar to write (e.g. style.seams.json)"
    )
    p.add_argument(
        "--min-confidence",
        type=_fraction,
        default=0.2,
        help="drop weaker proposals (0..1)",
    )
    p.add_argument("--json", action="store_true", help="print the proposals as JSON")


def _fraction(text: str) -> float:
    value = float(text)
    if not 0.0 <= value <= 1.0:
        raise argparse.ArgumentTypeError(f"{text}: a confidence lies in 0..1")
    return value


def run(args: argparse.Namespace) -> int:
    from dataclasses import replace

    from ..library.infer import infer_seams, with_proposals
    from ..library.sidecar import write_sidecar
    from ._common import print_findings, print_json

    pattern, report = load_pattern_args(args)
    print_findings(report)
    proposals = infer_seams(pattern, min_confidence=args.min_confidence)
    marked = with_proposals(pattern, proposals)
    rows = []
    for p in proposals:
        rows.append(
            {
                "id": p.seam_id,
                "kind": "seam",
                "reverse": True,
                "ease_cm": 0.0,
                "status": "proposed",
                "confidence": p.confidence,
                "a": {
                    "piece": p.a.piece,
                    "start": f"v{p.a.start}",
                    "end": f"v{p.a.end}",
                    "copy": "primary",
                },
                "b": {
                    "piece": p.b.piece,
                    "start": f"v{p.b.start}",
                    "end": f"v{p.b.end}",
                    "copy": "primary",
                },
                "length_a_cm": round(p.a.length_cm, 3),
                "length_b_cm": round(p.b.length_cm, 3),
            }
        )
    # the sidecar carries the new marks; proposed seams are listed with their confidence
    write_sidecar(replace(marked, seams=pattern.seams), args.output, proposals=rows)
    if args.json:
        print_json(rows)
    else:
        for r in rows:
            print(
                f"{r['confidence']:.2f}  {r['a']['piece']}:{r['a']['start']}-{r['a']['end']} "
                f"({r['length_a_cm']:.1f} cm)  <->  {r['b']['piece']}:{r['b']['start']}-{r['b']['end']} "
                f"({r['length_b_cm']:.1f} cm)"
            )
        print(
            f"{len(rows)} proposed seams written to {args.output}; confirm or edit them, then "
            "'patternbridge check' / 'import' read the sidecar"
        )
    return 0
