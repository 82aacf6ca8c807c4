"""``patternbridge measure``: tailoring measurements of a character mesh."""

from __future__ import annotations

import argparse

HELP = "measure a character mesh like a tailor: girths and tape lengths in cm (JSON, optional PNG)"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "mesh", metavar="MESH", help="character mesh: OBJ, PLY, STL, GLB or glTF"
    )
    parser.add_argument(
        "--landmarks",
        metavar="FILE",
        help='landmark JSON: {"landmarks": {name: {"vertex": id} | {"position": [x, y, z]}}}',
    )
    parser.add_argument(
        "--units",
        help="source length unit (m, cm, mm, in); detected from the stature by default",
    )
    parser.add_argument(
        "--up", help="up axis of the file (Y, Z, -Y, -Z); detected by default"
    )
    parser.add_argument(
        "--partial",
        action="store_true",
        help="write what could be measured and list the rest instead of failing",
    )
    parser.add_argument(
        "--no-detect",
        action="store_true",
        help="do not detect missing landmarks from the geometry",
    )
    parser.add_argument(
        "--strict", action="store_true", help="treat loader warnings as errors"
    )
    parser.add_argument(
        "-o",
        "--output",
        required=True,
        metavar="JSON",
        help="measurements JSON to write",
    )
    parser.add_argument(
        "--png", metavar="PNG", help="also draw the measurements on the character"
    )


def run(args: argparse.Namespace) -> int:
    import sys

    from ..errors import InputError
    from ..measure import measure, write_measurements
    from ..mesh.load import load_character
    from ._common import print_findings, progress_printer

    if args.png and not str(args.png).lower().endswith(".png"):
        raise InputError(
            f"{args.png}: --png writes a PNG picture; give a file name ending in .png"
        )
    character, report = load_character(
        args.mesh, units=args.units, up=args.up, landmarks=args.landmarks
    )
    print_findings(report, strict=args.strict)
    quiet = args.quiet > 0
    result = measure(
        character,
        progress=progress_printer(quiet=quiet) if args.verbose else None,
        partial=args.partial,
        detect=not args.no_detect,
    )
    picture = None
    if args.png:  # drawn before anything is written: a failure leaves no JSON behind
        from ..measure.picture import measurement_picture
        from ..mesh.render import save_png

        picture = measurement_picture(character, result)
    write_measurements(args.output, result)
    if picture is not None:
        save_png(args.png, picture)
    if not quiet:
        sources: dict[str, int] = {}
        for lm in result.landmarks.values():
            sources[lm.source] = sources.get(lm.source, 0) + 1
        assumed = ", ".join(f"{k} {v}" for k, v in character.assumed.items())
        print(
            f"{character.name}: {len(result.measurements)} measurements -> {args.output} "
            f"(landmarks: {', '.join(f'{n} {s}' for s, n in sources.items())}; {assumed})",
            file=sys.stderr,
        )
        for mid, reason in result.missing.items():
            print(
                f"patternbridge: warning: {mid} not measured: {reason}", file=sys.stderr
            )
        for name, lm in sorted(result.landmarks.items()):
            if lm.is_low_confidence or lm.evidence.checks:
                why = "; ".join((lm.evidence.rule, *lm.evidence.checks))
                print(
                    f"patternbridge: warning: landmark {name} ({lm.source}, confidence "
                    f"{lm.confidence:.2f}): {why}",
                    file=sys.stderr,
                )
    return 0
