"""Benchmark: ``fit`` on real tailor's files with no hand-written bridge data.

Usage: ``python benchmarks/bridge_fit.py [--characters E_average_male,B_slim_female,...]
[--files "simple.DXF,MEN CLASSIC TEE.DXF"] [--no-drape] [--grade-budget POPxGEN|default] [--seed 0]
[--out DIR] [--markdown]``

For every file of ``../shared/aama`` (or ``--files``) × character: the
character is measured once, then :func:`patternbridge.fit` runs on the DXF
without a sidecar beside it (the bridge data are inferred), exactly what
``patternbridge fit CHARACTER --garment FILE -o OUT`` does. One row per case:

- ``exit``: the CLI's exit status (0; 2 for a ``PatternBridgeError``, 3 for a
  failed drape verdict, 1 for any other exception);
- ``meas``: mean measurement error of the graded pattern, cm (target ≤ 0.5);
- ``seam``: worst seam length or notch mismatch, mm (target ≤ 1);
- ``links``: the measurement links inferred;
- ``reimport``: the graded DXF-AAMA + RUL written back, read again with its
  RUL, holds the character as one more size and graded to it gives the fitted
  outlines within 0.1 mm, in the designer's layout (``ok``);
- ``design``: the grader's design checks (``fit_report.json`` ``checks``,
  :mod:`patternbridge.grade.checks`): pieces collapsed, stretched or
  ``piece-turned`` (the longest edge, a fold, centre line or band's long
  edge, turned by over 2° against proportional scaling), curves flattened,
  symmetry lost, ``share-moved`` (a girth over several pieces whose share
  on one moved by over 3 %: a front narrowed while the back widened);
  ``kept`` when silent;
- ``drape``: the drape's verdict (``-`` with ``--no-drape``);
- ``verdict``: ``pass`` when all of the above hold, else what failed;
- ``CPU s``: process CPU seconds of the case (the machine is shared: wall time
  is not a measure).

The exit status is 1 when any row does not pass.
"""

from __future__ import annotations

import argparse
import platform
import resource
import sys
import tempfile
from pathlib import Path

import numpy as np

from patternbridge import __version__

ROOT = Path(__file__).resolve().parents[1]
SHARED = ROOT / ".." / "shared"
CHARACTERS = ("E_average_male", "B_slim_female", "D_cartoon_child")
TARGET = {"mean_cm": 0.5, "seam_mm": 1.0, "reimport_mm": 0.1}


def _budget(text: str) -> tuple[int | None, int | None]:
    if text == "default":
        return None, None
    pop, _, gen = text.lower().partition("x")
    return int(pop), int(gen)


def _character_path(name: str) -> Path:
    for folder in (SHARED / "characters", SHARED / "characters" / "variants"):
        for ext in (".obj", ".glb", ".ply"):
            if (folder / f"{name}{ext}").is_file():
                return folder / f"{name}{ext}"
    raise SystemExit(f"bridge_fit: no character {name!r} in {SHARED / 'characters'}; give a name without extension")


def _files(arg: str | None) -> list[Path]:
    folder = SHARED / "aama"
    if arg:
        return [folder / f.strip() for f in arg.split(",") if f.strip()]
    return sorted(p for p in folder.iterdir() if p.suffix.lower() == ".dxf")


def reimport_error_mm(out: Path, result) -> float:
    """Largest distance (mm) between the re-imported DXF+RUL graded to the character and the fitted outlines."""
    from patternbridge.io.load import load_pattern
    from patternbridge.pattern.grading import grade

    dxf = next(out.glob("*_aama.dxf"))
    back, _ = load_pattern(dxf, rul=dxf.with_suffix(".rul"))
    fitted = {p.name: p.outline for p in result.grading.pattern.pieces}
    extra = [s for s in back.sizes if s not in result.grading.original.sizes]
    if len(back.sizes) != len(result.grading.original.sizes or (1,)) + 1 or len(extra) != 1:
        return float("inf")
    graded = grade(back, extra[0])
    worst = 0.0
    for piece in graded.pieces:
        if piece.name not in fitted or piece.outline.shape != fitted[piece.name].shape:
            return float("inf")
        worst = max(worst, float(np.abs(piece.outline - fitted[piece.name]).max()) * 10.0)
    return worst if len(graded.pieces) == len(fitted) else float("inf")


#: length links of the body (in proportion to a body length); any other ``*_length`` is a band's
BODY_LENGTHS = ("body_length", "sleeve_length", "leg_length")


def _links(measurements: list[dict]) -> str:
    """Short names of the links: girths and body lengths by name; band widths, straps and band lengths counted."""
    ids = [m["id"] for m in measurements]
    widths = sum(i.endswith("_width") for i in ids)
    straps = sum(i.endswith("_strap") for i in ids)
    bands = sum(i.endswith("_length") and i not in BODY_LENGTHS for i in ids)
    counted_ends = ("_width", "_length", "_strap")
    names = [i.removesuffix("_girth") for i in ids if not i.endswith(counted_ends) or i in BODY_LENGTHS]
    counted = [f"{widths} width{'s' * (widths != 1)}"] * bool(widths)
    counted += [f"{straps} strap{'s' * (straps != 1)}"] * bool(straps)
    counted += [f"{bands} band length{'s' * (bands != 1)}"] * bool(bands)
    return ", ".join(names + counted)


def _cpu() -> float:
    """CPU seconds of this process and its finished children."""
    own, kids = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + kids.ru_utime + kids.ru_stime


def run_case(subject, garment: Path, out: Path, options, seed: int) -> dict:
    from patternbridge import fit
    from patternbridge.errors import PatternBridgeError
    from patternbridge.workflow import Verdict

    t0 = _cpu()
    row = {"file": garment.name, "character": subject.name}
    try:
        result = fit(subject, garment, seed=seed, options=options, out_dir=out)
    except PatternBridgeError as exc:
        row.update(exit=2, why=str(exc).splitlines()[0][:120], cpu=_cpu() - t0)
        return row
    except Exception as exc:  # a bug: keep going, say which
        row.update(exit=1, why=f"{type(exc).__name__}: {exc}"[:120], cpu=_cpu() - t0)
        return row
    rep, fig = result.report, result.figures
    row.update(
        exit=3 if fig.verdict is Verdict.FAILED else 0,
        mean=fig.mean_error_cm,
        seam=fig.max_seam_mm,
        links=_links(rep["measurements"]),
        checks=[c["code"] for c in rep.get("checks", [])],
        drape=fig.verdict.value if fig.verdict else "-",
    )
    try:
        row["reimport_mm"] = reimport_error_mm(out, result)
    except Exception as exc:
        row["reimport_mm"], row["why"] = float("inf"), f"re-import: {exc}"[:120]
    row["cpu"] = _cpu() - t0
    return row


def verdict(row: dict) -> str:
    if row["exit"] not in (0,):
        return f"exit {row['exit']}"
    bad = []
    if row["mean"] > TARGET["mean_cm"]:
        bad.append("meas")
    if row["seam"] > TARGET["seam_mm"]:
        bad.append("seam")
    if not row["reimport_mm"] <= TARGET["reimport_mm"]:
        bad.append("reimport")
    bad += sorted(set(row["checks"]))
    if row["drape"] not in ("-", "ok"):
        bad.append(f"drape {row['drape']}")
    return "pass" if not bad else ", ".join(bad)


def _cells(row: dict) -> list[str]:
    if "mean" not in row:
        return [
            row["file"],
            row["character"],
            str(row["exit"]),
            "-",
            "-",
            "-",
            "-",
            "-",
            "-",
            f"{verdict(row)}: {row.get('why', '')}",
            f"{row['cpu']:.1f}",
        ]
    design = "kept" if not row["checks"] else ",".join(sorted(set(row["checks"])))
    reimport = "ok" if row["reimport_mm"] <= TARGET["reimport_mm"] else f"{row['reimport_mm']:.2f} mm"
    return [
        row["file"],
        row["character"],
        str(row["exit"]),
        f"{row['mean']:.2f}",
        f"{row['seam']:.2f}",
        row["links"],
        reimport,
        design,
        row["drape"],
        verdict(row),
        f"{row['cpu']:.1f}",
    ]


HEADER = [
    "file",
    "character",
    "exit",
    "meas cm",
    "seam mm",
    "links",
    "re-import",
    "design",
    "drape",
    "verdict",
    "CPU s",
]


def _print_row(cells: list[str], markdown: bool) -> None:
    if markdown:
        print("| " + " | ".join(cells) + " |", flush=True)
    else:
        widths = (24, 16, 4, 7, 7, 62, 9, 16, 7, 24, 6)
        print("  ".join(c.ljust(w) for c, w in zip(cells, widths, strict=True)), flush=True)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--characters", default=",".join(CHARACTERS))
    ap.add_argument("--files", default=None, help="comma-separated file names in ../shared/aama (default: all)")
    ap.add_argument("--no-drape", action="store_true")
    ap.add_argument("--grade-budget", default="16x4", help="NSGA-II POPxGEN, or 'default' (the grader's own)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--out", default=None, help="keep every case's outputs under this folder")
    ap.add_argument("--markdown", action="store_true")
    args = ap.parse_args(argv)

    from patternbridge.workflow import FitOptions, load_subject

    pop, gen = _budget(args.grade_budget)
    options = FitOptions(pop_size=pop, n_gen=gen, drape=not args.no_drape)
    out_root = Path(args.out) if args.out else Path(tempfile.mkdtemp(prefix="bridge-fit-"))
    print(
        f"# patternbridge {__version__}, Python {platform.python_version()}, numpy {np.__version__}, "
        f"{platform.machine()}; budget {args.grade_budget}, seed {args.seed}, "
        f"drape {'off' if args.no_drape else 'on'}; outputs in {out_root}"
    )
    _print_row(HEADER, args.markdown)
    if args.markdown:
        print("|" + "---|" * len(HEADER))
    rows = []
    for name in [c.strip() for c in args.characters.split(",") if c.strip()]:
        t0 = _cpu()
        subject, _ = load_subject(_character_path(name))
        print(f"# {name} measured in {_cpu() - t0:.1f} CPU s", file=sys.stderr, flush=True)
        for garment in _files(args.files):
            out = out_root / name / garment.stem.replace(" ", "_")
            row = run_case(subject, garment, out, options, args.seed)
            rows.append(row)
            _print_row(_cells(row), args.markdown)
    n_pass = sum(verdict(r) == "pass" for r in rows)
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
    print(f"# {n_pass}/{len(rows)} pass; CPU {sum(r['cpu'] for r in rows):.0f} s; peak RSS {rss:.0f} MB")
    return 0 if n_pass == len(rows) else 1


if __name__ == "__main__":
    raise SystemExit(main())
