"""Benchmark: dress the shared characters and their variants in the library garments, with the drape's verdict.

Plain script (no asv). For every character and garment it runs
``patternbridge.assemble.dress`` with the garment graded to the character as
``patternbridge fit`` grades it (measure + ``fit_pattern``, its default
NSGA-II budget or ``--grade-budget POP GEN``, not timed; ``--sample`` keeps
the sample size; ``--graded-cache DIR`` grades each case once) and prints
one line: seconds, peak RSS, penetrating vertices, triangles crossing the
skin, triangles where the garment passes through itself (``self``), seam gap
before and after welding, stretch percentiles, the verdict (``ok`` /
``flawed`` / ``failed``) and the worst piece, then one line per reason of
the verdict. Pictures, meshes and ``drape.json`` go to ``--out`` (default
``bench_out/assemble``), one folder per case; ``--contact-sheet PNG`` tiles
the front and back pictures of every case folder there.

``--characters`` takes shared characters or variants by name, or paths;
``--variants`` adds every mesh of ``../shared/characters/variants`` (glTF,
remeshed Z-up, millimetres, T-poses); ``--garments all`` every library
garment. A case that cannot be graded or dressed (an ``InputError``) is a
row, not a crash.

    .venv/bin/python benchmarks/assemble.py [--characters A_superhero ...] [--variants] [--garments all] [--seeds 0 1 2]

The gap before welding is chaotic (it moves by tens of millimetres with the
seed of the start's jitter); ``--seeds`` dresses every case once per seed
and prints the median and the largest per case.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
SHARED = REPO.parent / "shared" / "characters"
VARIANTS = SHARED / "variants"
CHARACTERS = (
    "A_superhero",
    "B_slim_female",
    "C_heavy_male",
    "D_cartoon_child",
    "E_average_male",
    "F_tall_thin_elder",
)


def _character_path(name: str) -> Path:
    """A shared character by name (``A_superhero``), a variant by name, or a path to any mesh the loader reads."""
    path = Path(name)
    if path.suffix:
        return path
    if (SHARED / f"{name}.obj").exists():
        return SHARED / f"{name}.obj"
    found = sorted(p for p in VARIANTS.glob(f"{name}.*") if p.suffix in (".obj", ".glb", ".gltf", ".ply"))
    if not found:
        raise SystemExit(f"{name}: no such character in {SHARED} or {VARIANTS}")
    return found[0]


def _variant_names() -> list[str]:
    """The meshes of ``../shared/characters/variants`` (every format the loader reads)."""
    return sorted(p.stem for p in VARIANTS.iterdir() if p.suffix in (".obj", ".glb", ".gltf", ".ply"))


def contact_sheet(out_dirs: list[Path], path: Path, views: tuple[str, ...] = ("front", "back")) -> int:
    """Tile the ``fit_<view>.png`` pictures of every case folder under ``out_dirs`` into one PNG; return the count.

    Each case takes one cell per view, scaled to 180 px wide, with its folder
    name (garment_character) and its verdict (``drape.json``) above.
    """
    from PIL import Image, ImageDraw

    cases = sorted(d for out in out_dirs for d in Path(out).iterdir() if (d / "fit_front.png").exists())
    if not cases:
        return 0
    w, h, label = 180, 257, 14
    cols = 4  # cases per row
    rows = (len(cases) + cols - 1) // cols
    sheet = Image.new("RGB", (cols * len(views) * w, rows * (h + label)), "white")
    draw = ImageDraw.Draw(sheet)
    for i, case in enumerate(cases):
        r, c = divmod(i, cols)
        for j, view in enumerate(views):
            img = Image.open(case / f"fit_{view}.png").convert("RGB").resize((w, h))
            x, y = (c * len(views) + j) * w, r * (h + label)
            sheet.paste(img, (x, y + label))
        report = case / "drape.json"
        verdict = json.loads(report.read_text()).get("verdict", "?") if report.exists() else "?"
        draw.text((c * len(views) * w + 4, r * (h + label)), f"{case.name}: {verdict}", fill="black")
    path.parent.mkdir(parents=True, exist_ok=True)
    sheet.quantize(colors=128).save(path, optimize=True)  # a palette keeps the sheet small for the docs
    return len(cases)


def _rss_mb() -> float:
    try:
        import psutil

        return psutil.Process().memory_info().rss / 2**20
    except ImportError:
        import resource

        return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def _graded(pattern, character, cname: str, gname: str, cache: str | None, budget: tuple[int, int] | None = None):
    """The garment graded to the character as ``patternbridge fit`` does (measure + ``fit_pattern``'s defaults).

    Cached as JSON in ``cache``: a cache filled by an older run (a smaller
    budget) is reused as it is.
    """
    from patternbridge.io.pattern_json import load_pattern_json, save_pattern_json

    path = Path(cache) / f"{gname}_{cname}.json" if cache else None
    if path is not None and path.exists():
        return load_pattern_json(path)
    from patternbridge.grade.run import fit_pattern
    from patternbridge.measure.run import measure

    values = measure(character, partial=True).values_cm()
    kw = {"pop_size": budget[0], "n_gen": budget[1]} if budget else {}
    graded = fit_pattern(pattern, values, size=cname, **kw).pattern
    if path is not None:
        path.parent.mkdir(parents=True, exist_ok=True)
        save_pattern_json(graded, path)
    return graded


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument(
        "--characters",
        nargs="*",
        default=list(CHARACTERS),
        help="shared characters or variants by name, or paths to meshes",
    )
    ap.add_argument("--variants", action="store_true", help="also every mesh of ../shared/characters/variants")
    ap.add_argument("--garments", nargs="*", default=["shirt", "trousers"], help="library garments, or 'all'")
    ap.add_argument(
        "--grade-budget",
        nargs=2,
        type=int,
        metavar=("POP", "GEN"),
        help="grade with this NSGA-II population and generations instead of fit_pattern's defaults",
    )
    ap.add_argument(
        "--contact-sheet",
        metavar="PNG",
        help="at the end, tile the front and back pictures of every case under --out (and --sheet-from) into PNG",
    )
    ap.add_argument("--sheet-from", nargs="*", default=[], help="more output folders for the contact sheet")
    ap.add_argument("--grade-only", action="store_true", help="only fill --graded-cache, no drape")
    ap.add_argument("--out", default=str(REPO / "bench_out" / "assemble"))
    ap.add_argument("--json", help="also write the rows to this JSON file")
    ap.add_argument(
        "--sample",
        action="store_true",
        help="dress the sample size instead of grading each garment to the character first",
    )
    ap.add_argument(
        "--graded-cache",
        metavar="DIR",
        help="keep the graded patterns in DIR (pattern JSON) and reuse them on the next run",
    )
    ap.add_argument(
        "--graded",
        action="store_true",
        help="grade each garment to the character first (the default; kept for old command lines)",
    )
    ap.add_argument(
        "--seeds",
        nargs="*",
        type=int,
        default=[0],
        help="dress each case once per seed (the start's jitter); with more than one, a summary line per case "
        "gives the median and the largest gap before welding: a single run does not rank two schedules",
    )
    args = ap.parse_args(argv)

    import numpy as np

    from patternbridge.assemble import dress
    from patternbridge.errors import PatternBridgeError
    from patternbridge.library import garment_names, load_garment
    from patternbridge.mesh.load import load_character

    names = list(args.characters) + (_variant_names() if args.variants else [])
    garments = garment_names() if args.garments == ["all"] else args.garments
    print(
        f"# assemble benchmark  python {platform.python_version()}  numpy {np.__version__}  "
        f"cores {os.cpu_count()}  {platform.machine()}"
    )
    print(
        f"{'case':44s} {'s':>6s} {'RSS MB':>7s} {'pen':>4s} {'tri':>4s} {'self':>5s} {'gap0 mm':>8s} {'gap mm':>7s} "
        f"{'p5':>5s} {'p50':>5s} {'p95':>5s} {'p99':>5s}  {'verdict':8s} worst"
    )
    rows = []
    missed: list[str] = []  # cases off target, and why
    sewn = True  # the simulation closes every seam to 5 mm before welding
    for cname in names:
        path = _character_path(cname)
        cname = path.stem
        character, _ = load_character(path)
        for gname in garments:
            pattern = load_garment(gname)
            if not args.sample:
                try:
                    pattern = _graded(pattern, character, cname, gname, args.graded_cache, args.grade_budget)
                except PatternBridgeError as exc:  # a body the measuring cannot read: a row, not a crash
                    print(f"{gname + ' on ' + cname:44s} not graded: {exc}", flush=True)
                    missed.append(f"{gname} on {cname}: not graded")
                    rows.append({"character": cname, "garment": gname, "error": f"grade: {exc}"})
                    continue
            if args.grade_only:
                print(f"{gname + ' on ' + cname:44s} graded", flush=True)
                continue
            gaps0 = []
            for seed in args.seeds:
                case = f"{gname} on {cname}" + (f" s{seed}" if len(args.seeds) > 1 else "")
                out = Path(args.out) / (f"{gname}_{cname}" + (f"_s{seed}" if len(args.seeds) > 1 else ""))
                t = time.perf_counter()
                try:
                    r = dress(character, pattern, out, seed=seed)
                except PatternBridgeError as exc:
                    print(f"{case:44s} not dressed: {exc}", flush=True)
                    missed.append(f"{case}: not dressed")
                    rows.append({"character": cname, "garment": gname, "seed": seed, "error": f"dress: {exc}"})
                    continue
                secs = time.perf_counter() - t
                (out / "drape.json").write_text(json.dumps(r, indent=1))
                st = r["stretch"]["percentiles"]
                worst = r["stretch"]["worst_pieces"][0] if r["stretch"]["worst_pieces"] else {"piece": "-", "p95": 0}
                verdict = r.get("verdict", "-")
                print(
                    f"{case:44s} {secs:6.1f} {_rss_mb():7.0f} {r['penetrating_vertices']:4d} "
                    f"{r['crossing_triangles']:4d} {r['self_crossing_triangles']:5d} "
                    f"{r['max_seam_gap_before_weld_mm']:8.1f} {r['max_seam_gap_mm']:7.2f} "
                    f"{st['p5']:5.2f} {st['p50']:5.2f} {st['p95']:5.2f} {st['p99']:5.2f}  {verdict:8s} "
                    f"{worst['piece']} {worst['p95']:.2f}"
                    f"  (gap0 at {r.get('worst_seam_before_weld', '-')})",
                    flush=True,
                )
                for reason in r.get("verdict_reasons", []):
                    print(f"#     {reason['verdict']}: {reason['message']}", flush=True)
                gaps0.append(r["max_seam_gap_before_weld_mm"])
                sewn &= r["max_seam_gap_before_weld_mm"] <= 5.0
                why = [
                    reason
                    for reason, failed in (
                        (f"{secs:.0f} s", secs > 90),
                        (f"verdict {verdict}", verdict != "ok"),
                        (f"{r['penetrating_vertices']} vertices inside", r["penetrating_vertices"] > 0),
                        (f"{r['crossing_triangles']} triangles through the skin", r["crossing_triangles"] > 0),
                        (f"seams {r['max_seam_gap_mm']:.1f} mm open", r["max_seam_gap_mm"] > 1.0),
                    )
                    if failed
                ]
                if why:
                    missed.append(f"{case}: {', '.join(why)}")
                rows.append({"character": cname, "garment": gname, "seed": seed, "seconds": secs, **r})
            if len(gaps0) > 1:
                print(f"#   {gname} on {cname}: gap0 median {np.median(gaps0):.1f} mm, largest {max(gaps0):.1f} mm")
    if args.json:
        Path(args.json).write_text(json.dumps(rows, indent=1))
    if args.contact_sheet:
        folders = [Path(p) for p in (args.out, *args.sheet_from) if Path(p).is_dir()]
        n = contact_sheet(folders, Path(args.contact_sheet))
        print(f"# contact sheet of {n} cases: {args.contact_sheet}")
    if not rows:
        return 0
    verdicts = [r.get("verdict", "error") for r in rows]
    print("# verdicts: " + ", ".join(f"{v} {verdicts.count(v)}" for v in ("ok", "flawed", "failed", "error")))
    print("# all targets met" if not missed else "# some targets missed: " + "; ".join(missed))
    print("# every seam within 5 mm before welding" if sewn else "# some seams wider than 5 mm before welding")
    return 0 if not missed else 1


if __name__ == "__main__":
    sys.exit(main())
