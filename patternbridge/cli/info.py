"""``patternbridge info``: what a pattern holds; ``--json`` is a documented contract.

The JSON form is documented in ``formats/info.md`` and kept stable: an object
with ``style``, ``units`` (the source file's, ``METRIC`` or ``ENGLISH``),
``sample_size``, ``sizes`` (size-list order) and ``pieces``, one entry per
distinct piece with ``name``, ``quantity``, ``vertices``, ``notches``,
``grade_rules``, ``area_cm2`` and ``perimeter_cm`` (sample size).
"""

from __future__ import annotations

import argparse
import sys
from typing import Any

from ._common import add_pattern_arguments, load_pattern_args

HELP = (
    "show a pattern's style, units, sizes and pieces (--json: the documented contract)"
)

__all__ = ["HELP", "add_arguments", "pattern_info", "run"]

_DUPLICATE_CM = 1e-6  # consecutive vertices closer than this count once


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_pattern_arguments(parser)
    parser.add_argument(
        "--json", action="store_true", help="print the info as JSON (formats/info.md)"
    )


def pattern_info(pattern) -> dict[str, Any]:
    """The ``info --json`` object of ``pattern`` (see ``formats/info.md``).

    Examples
    --------
    >>> from patternbridge.pattern.model import Pattern, Piece
    >>> p = Pattern(style="S", sample_size="M", sizes=("M",),
    ...             pieces=(Piece(name="a", outline=[(0, 0), (2, 0), (2, 1), (0, 1)]),))
    >>> info = pattern_info(p)
    >>> info["pieces"][0]["area_cm2"], info["pieces"][0]["perimeter_cm"]
    (2.0, 6.0)
    """
    import numpy as np

    from ..pattern.geometry import area, perimeter

    pieces = []
    for piece in pattern.pieces:
        outline = np.asarray(piece.outline)
        step = np.linalg.norm(np.roll(outline, -1, axis=0) - outline, axis=1)
        vertices = int(np.count_nonzero(step > _DUPLICATE_CM)) or len(outline)
        pieces.append(
            {
                "name": piece.name,
                "quantity": piece.quantity.total,
                "vertices": vertices,
                "notches": len(piece.notches),
                "grade_rules": sum(r is not None for r in piece.rules),
                "area_cm2": round(float(area(outline)), 4),
                "perimeter_cm": round(float(perimeter(outline)), 4),
            }
        )
    return {
        "style": pattern.style,
        "units": str(pattern.units),
        "sample_size": pattern.sample_size,
        "sizes": list(pattern.sizes) if pattern.sizes else [pattern.sample_size],
        "pieces": pieces,
    }


def _table(info: dict[str, Any]) -> str:
    lines = [
        f"style        {info['style']}",
        f"units        {info['units']}",
        f"sample size  {info['sample_size']}",
        f"sizes        {' '.join(info['sizes'])} ({len(info['sizes'])})",
        f"pieces       {len(info['pieces'])}",
        "",
    ]
    head = ("piece", "qty", "vertices", "notches", "rules", "area cm2", "perimeter cm")
    rows = [
        (
            p["name"],
            str(p["quantity"]),
            str(p["vertices"]),
            str(p["notches"]),
            str(p["grade_rules"]),
            f"{p['area_cm2']:.1f}",
            f"{p['perimeter_cm']:.1f}",
        )
        for p in info["pieces"]
    ]
    widths = [max(len(r[i]) for r in (head, *rows)) for i in range(len(head))]
    for r in (head, *rows):
        cells = [r[0].ljust(widths[0])] + [
            c.rjust(w) for c, w in zip(r[1:], widths[1:], strict=True)
        ]
        lines.append("  ".join(cells).rstrip())
    return "\n".join(lines)


def run(args: argparse.Namespace) -> int:
    from ._common import print_findings, print_json

    pattern, report = load_pattern_args(args)
    print_findings(report)
    info = pattern_info(pattern)
    if args.json:
        print_json(info)
    else:
        print(_table(info), file=sys.stdout)
    return 0
