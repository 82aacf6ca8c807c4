"""Benchmark: seam gaps right after placement, before any simulation, for every garment on every character.

Plain script (no asv). For every character and library garment it runs
``patternbridge.assemble.pipeline.prepare`` (pose, segment, mesh, place) and
prints one line: the CPU seconds of ``prepare``, the dressing strategy, the
largest and the 95th-percentile gap between sewn vertex pairs as placed (mm),
the share of seams placed within 10 mm and 50 mm, the 99th percentile of the
placed edges' stretch (3D length / pattern length; the simulation must undo
it; edges as the drape report measures them), the vertices left inside the body,
and the worst seam. The
garment is the library's sample size, or the graded pattern found in
``--graded-cache`` (as ``benchmarks/assemble.py`` writes it). A last line sums
the table.

    .venv/bin/python benchmarks/placement.py [--characters A_superhero ...] [--variants] [--garments all]
"""

from __future__ import annotations

import argparse
import os
import platform
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from assemble import CHARACTERS, _character_path, _variant_names


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--characters", nargs="*", default=list(CHARACTERS))
    ap.add_argument("--variants", action="store_true", help="also every mesh of ../shared/characters/variants")
    ap.add_argument("--garments", nargs="*", default=["all"], help="library garments, or 'all'")
    ap.add_argument("--graded-cache", metavar="DIR", help="graded patterns <garment>_<character>.json to use")
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args(argv)

    import numpy as np

    from patternbridge.assemble.defects import edge_stretch
    from patternbridge.assemble.drape import seam_gaps
    from patternbridge.assemble.pipeline import prepare, seam_gap_table, with_anchor_landmarks
    from patternbridge.errors import PatternBridgeError
    from patternbridge.io.pattern_json import load_pattern_json
    from patternbridge.library import garment_names, load_garment
    from patternbridge.mesh.load import load_character

    names = list(args.characters) + (_variant_names() if args.variants else [])
    garments = garment_names() if args.garments == ["all"] else args.garments
    print(f"# placement benchmark  python {platform.python_version()}  numpy {np.__version__}  cores {os.cpu_count()}")
    print(
        f"{'case':44s} {'cpu s':>6s} {'strategy':10s} {'max mm':>7s} {'p95 mm':>7s} {'<10mm':>6s} {'<50mm':>6s}  worst"
    )
    maxima, stretches, within10, within50, n_seams = [], [], 0, 0, 0
    for cname in names:
        path = _character_path(cname)
        cname = path.stem
        character, _ = load_character(path)
        for gname in garments:
            cached = Path(args.graded_cache) / f"{gname}_{cname}.json" if args.graded_cache else None
            pattern = load_pattern_json(cached) if cached is not None and cached.exists() else load_garment(gname)
            tag = "graded" if cached is not None and cached.exists() else "sample"
            case = f"{gname} on {cname} ({tag})"
            t = time.process_time()
            try:
                dressed, _ = with_anchor_landmarks(character, pattern)
                sim = prepare(dressed, pattern, seed=args.seed)
            except PatternBridgeError as exc:
                print(f"{case:44s} not placed: {exc}", flush=True)
                continue
            secs = time.process_time() - t
            g = seam_gaps(sim.cloth.x, sim.cloth.seams) * 10.0
            table = seam_gap_table(sim)
            worst = max(table, key=lambda r: r["max_mm"]) if table else {"seam": "-", "max_mm": 0.0}
            per_seam = np.array([r["max_mm"] for r in table])
            c = sim.cloth
            stretch, _ = edge_stretch(c.x, c.edges, c.rest)
            inside = int(np.count_nonzero(sim.collider.inside(c.x)))
            stretches.append(float(np.percentile(stretch, 99)))
            strategy = str(sim.strategy.kind) if hasattr(sim, "strategy") else "-"
            print(
                f"{case:44s} {secs:6.1f} {strategy:10s} {g.max(initial=0):7.1f} "
                f"{np.percentile(g, 95) if len(g) else 0:7.1f} {np.mean(per_seam <= 10):6.0%} "
                f"{np.mean(per_seam <= 50):6.0%} {stretches[-1]:5.2f} {inside:4d}  "
                f"{worst['seam']} {worst['max_mm']:.0f}",
                flush=True,
            )
            maxima.append(float(g.max(initial=0)))
            within10 += int(np.count_nonzero(per_seam <= 10))
            within50 += int(np.count_nonzero(per_seam <= 50))
            n_seams += len(per_seam)
    if maxima:
        print(
            f"# {len(maxima)} cases: median of the largest gaps {np.median(maxima):.0f} mm, "
            f"largest {max(maxima):.0f} mm; "
            f"seams placed within 10 mm {within10}/{n_seams}, within 50 mm {within50}/{n_seams}; "
            f"median p99 stretch {np.median(stretches):.2f}, largest {max(stretches):.2f}"
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
