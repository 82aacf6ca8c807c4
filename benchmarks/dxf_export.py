"""Export time of the real DXF-AAMA/ASTM files and the library garments, both flavours.

Usage: ``python benchmarks/dxf_export.py [--repeat N] [--no-library] [FILE ...]``

Each pattern is read once (not timed), then written four ways into a temporary
directory: AAMA and ASTM, each as the sample size + ``.RUL`` (``sizes="sample"``)
and as a graded nest (``sizes="all"``). The table gives the best-of-N time of
``patternbridge.io.dxf_aama.write_dxf`` (format, atomic write of the DXF and the
``.RUL``), the written size, the time of ezdxf's ``readfile`` of the same
file as a reference for what a DXF of that size costs to parse, and the
round-trip error: the largest distance, over every size, between a point of
the pattern (boundary, notches, internal lines, cutouts, sew lines, grain
line, drill holes) and the same point read back from what was written.
"""

from __future__ import annotations

import argparse
import platform
import sys
import tempfile
from pathlib import Path

import ezdxf
import numpy as np

from patternbridge import __version__
from patternbridge.io.dxf_aama import read_dxf, write_dxf
from patternbridge.report import Report

sys.path.insert(0, str(Path(__file__).resolve().parent))
from dxf_import import best_of, peak_rss_mb

SHARED = Path(__file__).resolve().parents[1] / ".." / "shared" / "aama"
LIBRARY = ("shirt", "trousers", "skirt", "dress", "tshirt", "shorts")


def _patterns(files: list[Path], library: bool):
    for path in files:
        yield path.name, read_dxf(path)[0]
    if library:
        from patternbridge.library import load_garment

        for name in LIBRARY:
            yield f"library:{name}", load_garment(name)


def _points(pattern) -> dict:
    from patternbridge.pattern.grading import grade

    out = {}
    for size in pattern.sizes or (pattern.sample_size,):
        for piece in grade(pattern, size).pieces:
            pts = [piece.outline, piece.outline[[n.vertex for n in piece.notches]].reshape(-1, 2)]
            pts += [pl.points for pl in (*piece.internal_lines, *piece.cutouts, *piece.sew_lines)]
            pts += [piece.grain_line.points] if piece.grain_line is not None else []
            pts += [np.array([h.position for h in piece.drill_holes]).reshape(-1, 2)]
            out[size, piece.name] = np.vstack(pts)
    return out


def round_trip_mm(before: dict, dxf: Path) -> float:
    """Largest distance (mm) between a point of the pattern and the same point read back."""
    after = _points(read_dxf(dxf)[0])
    return 10.0 * max(float(np.max(np.linalg.norm(pts - after[key], axis=1), initial=0.0))
                      for key, pts in before.items())


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("files", nargs="*", type=Path)
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument(
        "--no-library", action="store_true", help="only the DXF files, not the garments"
    )
    args = parser.parse_args(argv)
    files = args.files or sorted(
        p for p in SHARED.glob("*") if p.suffix.lower() == ".dxf"
    )
    print(
        f"# patternbridge {__version__}, ezdxf {ezdxf.__version__}, numpy "
        f"{np.__version__}, python {platform.python_version()}, {platform.machine()}, "
        f"best of {args.repeat}"
    )
    header = (
        f"{'pattern':24s} {'pieces':>6s} {'sizes':>5s} {'flavour':>7s} {'form':>6s} "
        f"{'KiB':>6s} {'write_dxf s':>11s} {'ezdxf read s':>12s} {'round trip mm':>13s}"
    )
    print(header)
    print("-" * len(header))
    worst = 0.0
    with tempfile.TemporaryDirectory() as tmp:
        for name, pattern in _patterns(files, not args.no_library):
            graded = bool(pattern.rules.deltas) and len(pattern.rules.sizes) > 1
            before = _points(pattern)
            for flavor in ("aama", "astm"):
                for sizes in ("sample", "all"):
                    folder = Path(tmp) / name.replace(":", "_") / f"{flavor}_{sizes}"
                    folder.mkdir(parents=True, exist_ok=True)
                    dxf = folder / "out.dxf"
                    rul = (
                        dxf.with_suffix(".rul")
                        if sizes == "sample" and graded
                        else None
                    )

                    def run(dxf=dxf, rul=rul, flavor=flavor, sizes=sizes, p=pattern):
                        write_dxf(
                            p,
                            dxf,
                            flavor=flavor,
                            sizes=sizes,
                            rul_path=rul,
                            report=Report(),
                        )

                    ours = best_of(run, args.repeat)
                    ref = best_of(lambda dxf=dxf: ezdxf.readfile(dxf), 1)
                    error = round_trip_mm(before, dxf)
                    form = "s+RUL" if rul is not None else sizes
                    worst = max(worst, ours)
                    print(
                        f"{name:24s} {len(pattern.pieces):6d} "
                        f"{len(pattern.sizes) or 1:5d} {flavor:>7s} {form:>6s} "
                        f"{dxf.stat().st_size / 1024:6.0f} {ours:11.3f} {ref:12.3f} {error:13.4f}"
                    )
    print(f"slowest export {worst:.3f} s; peak RSS {peak_rss_mb():.0f} MiB")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
