"""``patternbridge library list|show|export``: the garment library."""

from __future__ import annotations

import argparse

from .export import add_output_arguments, export_pattern

HELP = "list, show and export the library garments (shirt, trousers, skirt, dress, tshirt, shorts)"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    sub = parser.add_subparsers(dest="action", metavar="ACTION")
    sub.required = True
    p = sub.add_parser(
        "list", help="name, pieces, sizes and description of every garment"
    )
    p.add_argument(
        "--json",
        action="store_true",
        help="a JSON list of {name, pieces, sizes, description}",
    )
    p = sub.add_parser("show", help="describe a garment, or draw it with -o")
    p.add_argument("name", help="library garment name")
    p.add_argument(
        "-o",
        "--output",
        help="write the picture (pieces, seams, notches, all sizes) to this PNG",
    )
    p = sub.add_parser(
        "export",
        help="write a garment as DXF-AAMA/ASTM (+ RUL) and its bridge-data sidecar",
    )
    p.add_argument("name", help="library garment name")
    add_output_arguments(p)


def _load(name: str):
    from ..errors import InputError
    from ..library import garment_names, load_garment

    try:
        return load_garment(name)
    except KeyError:
        raise InputError(
            f"{name}: not a library garment (library: {', '.join(garment_names())}); "
            "see 'patternbridge library list'"
        ) from None


def run(args: argparse.Namespace) -> int:
    from ..library import garment_names
    from ._common import print_json

    if args.action == "list":
        rows = []
        for name in garment_names():
            p = _load(name)
            rows.append(
                {
                    "name": name,
                    "pieces": list(p.piece_names),
                    "sizes": list(p.sizes),
                    "description": p.description,
                }
            )
        if args.json:
            print_json(rows)
        else:
            for r in rows:
                print(
                    f"{r['name']:<9} {', '.join(r['pieces'])}  sizes {'/'.join(r['sizes'])}  — {r['description']}"
                )
        return 0
    pattern = _load(args.name)
    if args.action == "show":
        if args.output:
            from ..errors import InputError
            from ..io.plot_library import plot_library_garment

            if not str(args.output).lower().endswith((".png", ".svg", ".pdf")):
                raise InputError(
                    f"{args.output}: unknown picture type; give a .png, .svg or .pdf "
                    "file name"
                )

            print(plot_library_garment(pattern, args.output))
            return 0
        print(f"{pattern.style}: {pattern.description}")
        print(f"sizes {', '.join(pattern.sizes)} (sample {pattern.sample_size})")
        for piece in pattern.pieces:
            q = piece.quantity
            pl = piece.placement
            where = f"{pl.body_part}/{pl.side} at {pl.anchor}" if pl else "no placement"
            print(
                f"  {piece.name:<10} cut {q.right}+{q.left}  {piece.n_vertices} vertices  "
                f"{len(piece.notches)} notches  {where}"
            )
        print(f"seams: {len(pattern.seams)}")
        for s in pattern.seams:
            ease = f"  ease {s.ease_cm:g} cm" if s.ease_cm else ""
            print(
                f"  {s.id:<22} {s.a.piece}({s.a.copy}):{s.a.start}-{s.a.end}  <->  "
                f"{s.b.piece}({s.b.copy}):{s.b.start}-{s.b.end}{ease}"
            )
        print("measurements:")
        for m in pattern.measurements:
            least = ", at least" if m.at_least else ""
            print(f"  {m.id:<22} ease {m.ease_cm:+g} cm{least}  ({len(m.legs)} legs)")
        return 0
    # export: the DXF (+ .RUL) as 'patternbridge export' writes it, and the sidecar
    from pathlib import Path

    from ..library.sidecar import write_sidecar
    from ..report import Report

    code = export_pattern(pattern, Report(), args)
    sidecar = write_sidecar(pattern, Path(args.output).with_suffix(".seams.json"))
    if args.quiet <= 0:
        print(f"wrote {sidecar} (seams, landmarks, measurements, placement)")
    return code
