"""``patternbridge geodesic``: check one tape path between two points of a character."""

from __future__ import annotations

import argparse

HELP = "tape (geodesic) length between two vertices or landmarks of a character, in cm"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("mesh", metavar="MESH", help="character mesh: OBJ, PLY, STL, GLB or glTF")
    parser.add_argument(
        "--from",
        dest="source",
        required=True,
        metavar="A",
        help="start: a vertex id of the loaded mesh or a landmark name",
    )
    parser.add_argument(
        "--to",
        dest="target",
        required=True,
        metavar="B",
        help="end: a vertex id of the loaded mesh or a landmark name",
    )
    parser.add_argument(
        "--landmarks",
        metavar="FILE",
        help='landmark JSON: {"landmarks": {name: {"vertex": id} | {"position": [x, y, z]}}}',
    )
    parser.add_argument(
        "--no-tape",
        action="store_true",
        help="follow the skin over concave stretches (no tape correction)",
    )
    parser.add_argument(
        "--json",
        action="store_true",
        help="print {length_cm, points, seconds, ...} as JSON",
    )
    parser.add_argument("--units", help="source length unit (m, cm, mm, in); detected by default")
    parser.add_argument("--up", help="up axis of the file (Y, Z, -Y, -Z); detected by default")
    parser.add_argument(
        "--method",
        default="lsq",
        choices=("lsq", "euler", "exact", "flow", "dijkstra"),
        help="path method (default lsq: curvature flow, projection and exact straightening)",
    )


def _resolve(spec: str, character, what: str):
    """(path end, nearest vertex id) for a vertex-id string or a landmark name.

    A landmark is a path end as the measuring takes it
    (:func:`~patternbridge.measure.lengths.landmark_path_end`).
    """
    from ..errors import LandmarkError
    from ..measure.lengths import landmark_path_end

    text = spec.strip()
    if text.lstrip("-").isdigit():
        v = int(text)
        n = len(character.vertices)
        if not 0 <= v < n:
            raise LandmarkError(
                f"--{what} {spec}: vertex id out of range (the loaded mesh has "
                f"{n} vertices); pass 0..{n - 1} or a landmark name"
            )
        return v, v
    lm = character.landmarks.get(text)
    if lm is None:
        known = ", ".join(sorted(character.landmarks)) or "none"
        raise LandmarkError(
            f"--{what} {spec}: no such landmark (known: {known}); pass a vertex id, a known name, or --landmarks FILE"
        )
    return landmark_path_end(lm, character.vertices, character.faces)


def run(args: argparse.Namespace) -> int:
    import time

    from ..geodesic import SurfaceMesh, geodesic_path
    from ..mesh.load import load_character
    from ._common import print_findings, print_json

    character, report = load_character(args.mesh, units=args.units, up=args.up, landmarks=args.landmarks)
    print_findings(report)
    a, a_vertex = _resolve(args.source, character, "from")
    b, b_vertex = _resolve(args.target, character, "to")
    t0 = time.perf_counter()
    mesh = SurfaceMesh(character.vertices, character.faces)
    path = geodesic_path(mesh, a, b, tape=not args.no_tape, method=args.method)
    seconds = time.perf_counter() - t0
    if args.json:
        print_json(
            {
                "mesh": str(args.mesh),
                "from": args.source,
                "to": args.target,
                "from_vertex": a_vertex,
                "to_vertex": b_vertex,
                "length_cm": round(path.length, 6),
                "surface_length_cm": round(path.surface_length, 6),
                "tape": not args.no_tape,
                "method": args.method,
                "points": [[round(x, 6) for x in p] for p in path.points.tolist()],
                "seconds": round(seconds, 4),
                "assumed": dict(character.assumed),
            }
        )
    elif args.quiet <= 0:
        tape = "tape" if not args.no_tape else "skin"
        print(
            f"{args.source} -> {args.target}: {path.length:.2f} cm ({tape}; "
            f"on the skin "
            f"{path.surface_length:.2f} cm; {len(path.points)} points; {seconds:.2f} s)"
        )
    else:
        print(f"{path.length:.4f}")
    return 0
