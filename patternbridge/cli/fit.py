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
import dataclasses
import json
import re
import shutil
import sys
import tempfile
from pathlib import Path

HELP = "measure a character and grade a garment to it (NSGA-II), write pattern, DXF+RUL and report"

__all__ = ["HELP", "add_arguments", "run"]


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
    parser.add_argument(
        "--landmarks", metavar="FILE", help="landmarks JSON for the character"
    )
    parser.add_argument(
        "--units",
        help="character mesh units when the file does not say (cm, mm, m, in)",
    )
    parser.add_argument("--up", help="character up axis when not +Y (e.g. +Z)")
    parser.add_argument(
        "--seed", type=int, default=0, help="random seed (same seed, same result)"
    )
    parser.add_argument(
        "--pop-size", type=int, default=None, help="NSGA-II population size"
    )
    parser.add_argument(
        "--generations", type=int, default=None, help="NSGA-II generations"
    )
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
    parser.add_argument(
        "--no-drape", action="store_true", help="do not assemble/drape the garment"
    )
    parser.add_argument(
        "-o", "--output", required=True, metavar="OUT/", help="output folder"
    )


def _safe_name(text: str) -> str:
    return re.sub(r"[^A-Za-z0-9_.-]+", "_", text).strip("_") or "fit"


def _is_measurements_json(path: Path) -> bool:
    if path.suffix.lower() != ".json" or not path.is_file():
        return False
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return False
    if not isinstance(data, dict):
        return False
    return "measurements" in data or (
        bool(data) and all(isinstance(v, (int, float)) for v in data.values())
    )


def run(args: argparse.Namespace) -> int:
    from ..errors import InputError
    from ._common import print_findings, progress_printer

    quiet = args.quiet > 0
    progress = progress_printer(quiet=quiet)

    def stage(text: str) -> None:
        if not quiet:
            print(f"[fit] {text}", file=sys.stderr, flush=True)

    out_dir = Path(args.output)
    if out_dir.exists() and not out_dir.is_dir():
        raise InputError(f"{out_dir}: exists and is not a folder; give a folder for -o")

    # --- pattern (a DXF without a sidecar gets inferred bridge data, written into OUT/)
    stage(f"loading garment {args.garment}")
    from ..bridge.fit_input import pattern_for_fit

    fit_input = pattern_for_fit(args.garment, out_dir)
    pattern, report = fit_input.pattern, fit_input.report
    print_findings(report)
    if fit_input.summary:
        stage(f"inferred {fit_input.summary}; sidecar {fit_input.sidecar}, picture {fit_input.picture}")
    garment = pattern.style or Path(str(args.garment)).stem
    if not pattern.measurements:
        raise InputError(
            f"{args.garment}: the pattern has no landmark-to-measurement mapping (no measurement links); "
            "add them with `patternbridge seams infer` or in the pattern's bridge-data sidecar, then run fit again"
        )

    # --- measurements
    char_path = Path(args.character)
    character = None
    from ..measure.model import load_measurements

    if _is_measurements_json(char_path):
        stage(f"reading measurements {char_path}")
        meas = load_measurements(char_path)
        char_name = (
            meas.character
            if meas.character and meas.character != "character"
            else char_path.stem
        )
    else:
        if not char_path.is_file():
            raise InputError(
                f"{char_path}: no such character file; give a mesh (OBJ/PLY/STL/glTF) "
                "or a measurements JSON"
            )
        from ..measure.run import measure
        from ..mesh.load import load_character

        stage(f"loading character {char_path}")
        character, creport = load_character(
            char_path, units=args.units, up=args.up, landmarks=args.landmarks
        )
        print_findings(creport)
        stage("measuring")
        meas = measure(character, progress=progress, partial=True)
        char_name = getattr(character, "name", "") or char_path.stem
        # the landmarks measuring found (from the rig or the geometry) also
        # place the pattern: a bare mesh has none of its own
        character = dataclasses.replace(character, landmarks={**meas.landmarks, **character.landmarks})
    values = meas.values_cm()
    needed = sorted({lk.measurement for lk in pattern.measurements})
    lacking = [m for m in needed if m not in values]
    if lacking:
        reasons = getattr(meas, "missing", {}) or {}
        detail = ", ".join(
            f"{m} ({reasons[m]})" if m in reasons else m for m in lacking
        )
        raise InputError(
            f"{args.character}: the character lacks measurements {garment!r} needs: {detail}; "
            "add the landmarks they need (--landmarks) or give them in a measurements JSON"
        )
    size = _safe_name(char_name)
    if size in pattern.sizes:
        size = f"{size}_fit"

    # --- grade
    from ..grade.report import fit_report
    from ..grade.run import fit_pattern

    kwargs = {}
    if args.pop_size:
        kwargs["pop_size"] = int(args.pop_size)
    if args.generations:
        kwargs["n_gen"] = int(args.generations)
    stage(
        f"grading {garment} to {char_name} ({len(pattern.pieces)} pieces, "
        f"{len(pattern.measurements)} measurements, {len(pattern.seams)} seams)"
    )
    result = fit_pattern(
        pattern,
        values,
        seed=args.seed,
        size=size,
        source=str(args.garment),
        do_repair=not args.no_repair,
        deformation=args.deformation,
        progress=progress,
        **kwargs,
    )
    rep = fit_report(result, character=char_name, garment=garment)

    created = not out_dir.exists()
    out_dir.mkdir(parents=True, exist_ok=True)
    tmp_dir = Path(tempfile.mkdtemp(prefix=".fit-", dir=out_dir))
    try:
        written = _write_outputs(
            tmp_dir,
            args,
            pattern,
            result,
            rep,
            meas,
            character,
            size,
            garment,
            progress,
            stage,
            drape_sidecar=fit_input.sidecar,
        )
        final = []
        for name in written:
            src = tmp_dir / name
            dst = out_dir / name
            if src.is_dir():
                if dst.exists():
                    shutil.rmtree(dst)
                src.replace(dst)
            else:
                src.replace(dst)
            final.append(dst)
    except BaseException:
        shutil.rmtree(tmp_dir, ignore_errors=True)
        if created:  # nothing half-written: not even the folder
            shutil.rmtree(out_dir, ignore_errors=True)
        raise
    finally:
        shutil.rmtree(tmp_dir, ignore_errors=True)

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
    print(f"wrote {len(final)} files to {out_dir}: " + ", ".join(p.name for p in final))
    return 0


def drape_warnings(drape: dict) -> list[str]:
    """One line per thing in the ``drape`` report a user should look at in the pictures."""
    from ..assemble.pipeline import WELDED_OPEN_MM

    out = []
    opened = drape.get("seams_open_before_weld") or []
    if opened:
        out.append(
            f"[fit] welding closed {len(opened)} seam(s) the drape left open by more than "
            f"{WELDED_OPEN_MM:g} mm: " + ", ".join(f"{r['seam']} {r['max_mm']:.0f} mm" for r in opened[:4])
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


def _write_outputs(
    tmp: Path,
    args,
    pattern,
    result,
    rep,
    meas,
    character,
    size,
    garment,
    progress,
    stage,
    drape_sidecar: Path | None = None,
) -> list[str]:
    """Write every output into ``tmp``; return the names written (in order).

    ``drape_sidecar``: the bridge sidecar of a DXF; its recorded turns stand the
    pieces upright for draping (the DXF written back keeps the designer's drawing).
    """
    from ..io.pattern_json import save_pattern_json
    from ..io.plot_fit import plot_fit_overlay, plot_pareto
    from ..measure.model import write_measurements
    from ..pattern.grading import add_size, single_size
    from ..report import Report
    from ._common import print_findings

    names: list[str] = []
    write_measurements(tmp / "measurements.json", meas)
    names.append("measurements.json")

    graded = single_size(result.pattern, size)
    stem = _safe_name(garment)
    save_pattern_json(graded, tmp / f"{stem}_{size}.json")
    names.append(f"{stem}_{size}.json")

    # DXF + RUL: the character as one more size beside the original sizes
    stage("writing DXF-AAMA / DXF-ASTM with the character as one more size")
    from ..io.dxf_aama.write import write_dxf

    base = pattern
    if not base.sizes:
        sample = base.sample_size or "base"
        base = dataclasses.replace(base, sample_size=sample, sizes=(sample,))
    outlines = {p.name: p.outline for p in result.pattern.pieces}
    combined = add_size(base, size, outlines)
    dxf_report = Report()
    for flavor in ("aama", "astm"):
        dxf = f"{stem}_{flavor}.dxf"
        rul = f"{stem}_{flavor}.rul"
        write_dxf(
            combined,
            tmp / dxf,
            flavor=flavor,
            sizes="sample",
            rul_path=tmp / rul,
            report=dxf_report,
        )
        names += [dxf, rul]
    print_findings(dxf_report)

    drape_dict = None
    if not args.no_drape and character is not None:
        from ..assemble import dress

        stage("assembling and draping")
        drape_dir = tmp / "drape"
        drape_dir.mkdir()
        draped = result.pattern
        if drape_sidecar is not None:
            from ..bridge.upright import upright_pattern

            draped = upright_pattern(draped, drape_sidecar)
        drape_dict = dress(character, draped, drape_dir, seed=args.seed, progress=progress)
        moved = []
        for f in sorted(drape_dir.iterdir()):
            if not f.name.startswith("."):
                f.replace(tmp / f.name)
                names.append(f.name)
                moved.append(f.name)
        drape_dir.rmdir()
        # the assembler names the files where it wrote them (the temporary
        # folder); the report names them where they end up, relative to OUT/
        drape_dict = dict(drape_dict)
        drape_dict["files"] = _relative_files(drape_dict.get("files"), moved)
    elif character is None and not args.no_drape:
        rep["drape"] = {"skipped": "measurements given without a character mesh"}
    if drape_dict is not None:
        rep["drape"] = drape_dict

    stage("drawing pattern.png and pareto.png")
    plot_fit_overlay(
        pattern.pieces,
        result.pattern.pieces,
        tmp / "pattern.png",
        labels=(pattern.sample_size or "original", size),
        title=f"{garment}: original vs graded for {size}",
    )
    names.append("pattern.png")
    plot_pareto(
        result.front_F,
        tmp / "pareto.png",
        chosen=result.ga_choice.scores.F,
        final=result.chosen.scores.F,
        refined=result.front_refined,
        within=result.front_within,
        baselines={n: s.scores.F for n, s in result.baselines.items()},
        title=f"{garment} on {size}: final Pareto front",
    )
    names.append("pareto.png")

    from ..atomic import write_text

    write_text(
        tmp / "fit_report.json", json.dumps(rep, indent=1, default=_json_default) + "\n"
    )
    names.append("fit_report.json")
    return names


def _relative_files(files, moved: list[str]) -> list[str]:
    """File names of the drape outputs relative to OUT/ (they land at its top level)."""
    if not files:
        return sorted(moved)
    return [Path(str(f)).name for f in files if Path(str(f)).name in moved] or sorted(moved)


def _json_default(obj):
    import numpy as np

    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, (np.floating, np.integer)):
        return obj.item()
    if isinstance(obj, Path):
        return str(obj)
    raise TypeError(f"not JSON serialisable: {type(obj).__name__}")
