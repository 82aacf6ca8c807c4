"""``patternbridge fit``: measure a character, grade a garment to it, write everything.

Stages: load the pattern → measure the character (or read its measurements
JSON) → grade with NSGA-II and the final constrained step → drape (when the assembler is
available) → write ``measurements.json``, the graded pattern (canonical JSON),
DXF-AAMA and DXF-ASTM files with a ``.RUL`` in which the character is one more
size beside the original sizes, ``fit_report.json``, ``pattern.png`` and
``pareto.png``. Everything is written into a temporary folder inside OUT/ and
moved into place at the end, so a failed run leaves no partial outputs.
"""

from __future__ import annotations

import argparse
import os
import sys

from ..errors import InputError

HELP = "measure a character and grade a garment to it (NSGA-II), write pattern, DXF+RUL and report"

__all__ = ["HELP", "add_arguments", "add_fit_options", "drape_warnings", "fit_progress", "options_from_args", "run"]


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "character",
        metavar="CHARACTER",
        help="character mesh (OBJ/PLY/STL/glTF, with its .json sidecar if any) "
        "or a measurements JSON written by `patternbridge measure`",
    )
    parser.add_argument(
        "--garment",
        required=True,
        metavar="NAME|pattern.json",
        help="library garment name, canonical pattern JSON or DXF with bridge data",
    )
    parser.add_argument("--landmarks", metavar="FILE", help="landmarks JSON for the character")
    parser.add_argument(
        "--units",
        help="character mesh units when the file does not say (cm, mm, m, in)",
    )
    parser.add_argument("--up", help="character up axis when not +Y (e.g. +Z)")
    add_fit_options(parser)
    parser.add_argument("-o", "--output", required=True, metavar="OUT/", help="output folder")


def add_fit_options(parser: argparse.ArgumentParser) -> None:
    """The seed, grading and drape flags (shared with ``batch``); read them with :func:`options_from_args`."""
    from ._common import bounded_int

    parser.add_argument(
        "--seed", type=bounded_int(0, 2**32 - 1), default=0, help="random seed (same seed, same result)"
    )
    parser.add_argument("--pop-size", type=bounded_int(4, 10_000), default=None, help="NSGA-II population size")
    parser.add_argument("--generations", type=bounded_int(1, 100_000), default=None, help="NSGA-II generations")
    parser.add_argument(
        "--deformation",
        choices=("bilinear", "cubic"),
        default="bilinear",
        help="grid map of the pattern pieces: bilinear (default; least change at the critical points) or cubic "
        "(C1: curves crossing a grid line stay smooth); docs/grading.md compares them",
    )
    parser.add_argument(
        "--no-repair",
        action="store_true",
        help="skip the final step (least shape change under the fit); keep the NSGA-II choice",
    )
    parser.add_argument("--no-drape", action="store_true", help="do not assemble/drape the garment")
    parser.add_argument(
        "--choose",
        type=bounded_int(0, 10_000),
        metavar="K",
        help="re-run the final step from row K of the Pareto front (numbered in pareto.png) and take it",
    )


def options_from_args(args: argparse.Namespace):
    """The :class:`~patternbridge.workflow.FitOptions` of the fit flags (shared with ``batch``)."""
    from ..workflow import FitOptions

    return FitOptions(
        pop_size=args.pop_size or None,
        n_gen=args.generations or None,
        deformation=args.deformation,
        repair=not args.no_repair,
        drape=not args.no_drape,
        choose=args.choose,
    )


# the workflow's own steps, as the progress lines name them
STEPS = {
    "export": "writing DXF-AAMA / DXF-ASTM with the character as one more size",
    "plot": "drawing pattern.png and pareto.png",
}


def fit_progress(quiet: bool):
    """The CLI's progress callback: bars for long stages, one line per workflow step."""
    from ._common import progress_printer

    bars = progress_printer(quiet=quiet)

    def progress(stage: str, done: int, total: int) -> None:
        if stage in STEPS:
            if done == 0 and not quiet:
                print(f"[fit] {STEPS[stage]}", file=sys.stderr, flush=True)
            return
        bars(stage, done, total)

    return progress


def run(args: argparse.Namespace) -> int:
    from ..workflow import Verdict, fit, load_garment_spec, load_subject
    from ._common import print_findings

    quiet = args.quiet > 0
    progress = fit_progress(quiet)
    options = options_from_args(args)
    if os.path.exists(args.output) and not os.path.isdir(args.output):
        raise InputError(f"{args.output}: exists and is not a folder; give a folder for -o")
    if not quiet:
        print(f"[fit] loading garment {args.garment}", file=sys.stderr, flush=True)
    garment, findings = load_garment_spec(args.garment)  # a bad garment stops before the measuring
    print_findings(findings)
    if garment.summary and not quiet:
        print(
            f"[fit] inferred {garment.summary}; sidecar and picture written into {args.output}",
            file=sys.stderr,
            flush=True,
        )
    if not quiet:
        print(f"[fit] loading character {args.character}", file=sys.stderr, flush=True)
    subject, findings = load_subject(
        args.character, units=args.units, up=args.up, landmarks=args.landmarks, progress=progress
    )
    print_findings(findings)
    if not quiet:
        print(f"[fit] grading {args.garment} to {subject.name}", file=sys.stderr, flush=True)
    result = fit(subject, garment, seed=args.seed, options=options, out_dir=args.output, progress=progress)
    print_findings(result.findings)
    rep = result.report
    if not quiet:
        print(
            f"[fit] measurement error mean {rep['mean_error_cm']:.2f} cm, max {rep['max_error_cm']:.2f} cm; "
            f"worst seam {rep['max_seam_mm']:.2f} mm; shape error {rep['shape_error']:.4f} "
            f"(proportional scaling: {rep['baseline']['mean_error_cm']:.2f} cm, "
            f"{rep['baseline']['max_seam_mm']:.1f} mm, {rep['baseline']['shape_error']:.4f})",
            file=sys.stderr,
        )
        for line in drape_warnings(rep.get("drape") or {}):
            print(line, file=sys.stderr)
    print(f"wrote {len(result.files)} files to {result.out_dir}: " + ", ".join(result.files))
    if result.verdict is None:
        return 0
    drape = rep.get("drape") or {}
    reasons = [r.get("message", "") for r in drape.get("verdict_reasons", [])]
    fabric = (drape.get("fabric") or {}).get("class", "woven").replace("_", " ")
    print(
        f"patternbridge: drape verdict {result.verdict.value} (judged as a {fabric})"
        + (f": {'; '.join(reasons)}" if reasons else "")
        + ("" if result.verdict is Verdict.OK else " (failing regions in red in the fit_*.png pictures)"),
        file=sys.stderr,
    )
    return 3 if result.verdict is Verdict.FAILED else 0


def drape_warnings(drape: dict) -> list[str]:
    """One line per thing in the ``drape`` report a user should look at in the pictures."""
    from ..assemble.drape_measure import WELDED_OPEN_MM
    from ..bridge.layers import LeftOutReason

    out = []
    kept_off = drape.get("left_out") or []
    if kept_off:
        out.append(
            "[fit] not draped (graded and exported in the DXF): "
            + ", ".join(f"{r['piece']} ({LeftOutReason(r['why']).words})" for r in kept_off)
        )
    opened = drape.get("seams_open_before_weld") or []
    if opened:
        out.append(
            f"[fit] welding closed {len(opened)} seam(s) the drape left open by more than "
            f"{WELDED_OPEN_MM:g} mm: "
            + ", ".join(f"{r['seam']} {r['max_mm']:.0f} mm" for r in opened[:4])
            + (" ..." if len(opened) > 4 else "")
            + "; look there in fit_*.png"
        )
    inside, crossing = drape.get("penetrating_vertices", 0), drape.get("crossing_triangles", 0)
    if inside or crossing:
        where = drape.get("crossing_pieces") or []
        out.append(
            f"[fit] the garment still passes through the skin: {inside} vertices inside, {crossing} triangle(s) "
            "crossing" + (f" on {', '.join(where)}" if where else "") + "; look there in fit_*.png"
        )
    folded = drape.get("self_crossing_pieces") or {}
    if folded:
        most = sorted(folded.items(), key=lambda kv: -kv[1])
        out.append(
            f"[fit] the garment passes through itself in {sum(folded.values())} triangle(s), most on "
            + ", ".join(f"{piece} {n}" for piece, n in most[:3])
            + " (folds pushed through the cloth beside them); look there before simulating it further"
        )
    return out
