"""Benchmark: the garment right after placement, before any simulation, for every garment on every character.

Plain script (no asv). For every character and garment it runs
``patternbridge.assemble.pipeline.prepare`` (pose, segment, mesh, place) and
prints one line:

- ``cpu s``: CPU seconds of ``prepare``; the dressing strategy;
- ``max mm`` / ``p95 mm``: the largest and the 95th-percentile gap between
  sewn vertex pairs as placed; ``<10mm`` / ``<50mm``: the share of seams
  placed within 10 and 50 mm;
- ``p99``: the 99th percentile of the placed edges' stretch (3D length /
  pattern length, the edges the drape report measures; the simulation must
  undo it);
- ``in``: vertices inside the body (the solver's collider);
- ``self``: triangles passing through the cloth as placed — a piece through
  itself or through another piece (:func:`~patternbridge.assemble.selfcross.self_crossing`
  over the whole garment as one group, the two sides of a seam counting as one
  vertex although they are still apart);
- ``skin``: triangles through the skin of the dressing-pose body, by the
  independent check (:mod:`~patternbridge.assemble.skin_check`: signed
  distances of 15 points on every triangle, deeper than 1 mm);
- ``anch cm``: the largest vertical distance between a piece's anchor mark and
  its landmark, in the dressing pose (``defects.anchor_levels_cm``, what the
  verdict's ``level`` check measures after the drape);
- the worst seam.

The garment is the library's sample size, or the graded pattern found in
``--graded-cache`` (as ``benchmarks/assemble.py`` writes it). ``--aama``
adds the garments ``bridge infer`` makes from real files of ``../shared/aama``
(sample size, ``pattern_for_fit`` exactly as ``patternbridge fit`` loads a DXF
without a sidecar). A last line sums the table.

    .venv/bin/python benchmarks/placement.py [--characters A_superhero ...] [--variants] [--garments all] [--aama]
"""

from __future__ import annotations

import argparse
import os
import platform
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from assemble import CHARACTERS, _character_path, _variant_names

AAMA = Path(__file__).resolve().parents[1].parent / "shared" / "aama"
AAMA_GARMENTS = {
    "tank": "WM LOOSE SHAPE TANK.DXF",
    "tee": "MEN CLASSIC TEE.DXF",
    "leggings": "GLX4802S19_AAMA.DXF",
}


def placed_crossings(sim) -> tuple[int, int]:
    """(triangles through the cloth, triangles through the skin deeper than 1 mm) of the placed garment."""
    import numpy as np

    from patternbridge.assemble.drape import weld_groups
    from patternbridge.assemble.selfcross import self_crossing
    from patternbridge.assemble.skin_check import skin_check

    c = sim.cloth
    same = weld_groups(len(c.x), c.seams)
    folded = self_crossing(c.x, c.faces, np.zeros(len(c.faces), np.int64), same)
    skin = skin_check(sim.body, sim.character.faces, c.x, c.faces)
    return int(np.count_nonzero(folded)), int(np.count_nonzero(skin.inside(0.1)))


def _patterns(args, cname: str, tmp: Path):
    """(garment name, pattern, tag) of every garment to place on ``cname``."""
    from patternbridge.bridge.fit_input import pattern_for_fit
    from patternbridge.io.pattern_json import load_pattern_json
    from patternbridge.library import garment_names, load_garment

    garments = garment_names() if args.garments == ["all"] else args.garments
    for gname in garments:
        cached = Path(args.graded_cache) / f"{gname}_{cname}.json" if args.graded_cache else None
        if cached is not None and cached.exists():
            yield gname, load_pattern_json(cached), "graded"
        else:
            yield gname, load_garment(gname), "sample"
    if args.aama:
        for gname, fname in AAMA_GARMENTS.items():
            yield gname, pattern_for_fit(AAMA / fname, tmp / gname).pattern, "inferred"


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--characters", nargs="*", default=list(CHARACTERS))
    ap.add_argument("--variants", action="store_true", help="also every mesh of ../shared/characters/variants")
    ap.add_argument("--garments", nargs="*", default=["all"], help="library garments, 'all', or none")
    ap.add_argument("--aama", action="store_true", help="also the inferred tank, tee and leggings")
    ap.add_argument("--graded-cache", metavar="DIR", help="graded patterns <garment>_<character>.json to use")
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args(argv)

    import numpy as np

    from patternbridge.assemble.defects import anchor_levels_cm, edge_stretch
    from patternbridge.assemble.drape import seam_gaps
    from patternbridge.assemble.pipeline import prepare, seam_gap_table, with_anchor_landmarks
    from patternbridge.errors import PatternBridgeError
    from patternbridge.mesh.load import load_character

    names = list(args.characters) + (_variant_names() if args.variants else [])
    print(f"# placement benchmark  python {platform.python_version()}  numpy {np.__version__}  cores {os.cpu_count()}")
    print(
        f"{'case':48s} {'cpu s':>6s} {'strategy':8s} {'max mm':>7s} {'p95 mm':>7s} {'<10mm':>6s} {'<50mm':>6s} "
        f"{'p99':>5s} {'in':>4s} {'self':>5s} {'skin':>5s} {'anch cm':>7s}  worst"
    )
    maxima, stretches, within10, within50, n_seams = [], [], 0, 0, 0
    selfs, skins, anchors = [], [], []
    tmp = Path(tempfile.mkdtemp(prefix="placement-"))
    for cname in names:
        path = _character_path(cname)
        cname = path.stem
        character, _ = load_character(path)
        for gname, pattern, tag in _patterns(args, cname, tmp):
            case = f"{gname} on {cname} ({tag})"
            t = time.process_time()
            try:
                dressed, _ = with_anchor_landmarks(character, pattern)
                sim = prepare(dressed, pattern, seed=args.seed)
            except PatternBridgeError as exc:
                print(f"{case:48s} not placed: {exc}", flush=True)
                continue
            secs = time.process_time() - t
            c = sim.cloth
            g = seam_gaps(c.x, c.seams) * 10.0
            table = seam_gap_table(sim)
            worst = max(table, key=lambda r: r.max_mm) if table else None
            per_seam = np.array([r.max_mm for r in table])
            stretch, _ = edge_stretch(c.x, c.edges, c.rest)
            inside = int(np.count_nonzero(sim.collider.inside(c.x)))
            n_self, n_skin = placed_crossings(sim)
            levels = anchor_levels_cm(sim.character, sim.body, pattern, sim.pmesh, c.x, c.group)
            anchor = max(levels.values(), default=0.0)
            stretches.append(float(np.percentile(stretch, 99)))
            print(
                f"{case:48s} {secs:6.1f} {sim.strategy.kind!s:8s} {g.max(initial=0):7.1f} "
                f"{np.percentile(g, 95) if len(g) else 0:7.1f} {np.mean(per_seam <= 10):6.0%} "
                f"{np.mean(per_seam <= 50):6.0%} {stretches[-1]:5.2f} {inside:4d} {n_self:5d} {n_skin:5d} "
                f"{anchor:7.1f}  {worst.seam if worst else '-'} {worst.max_mm if worst else 0.0:.0f}",
                flush=True,
            )
            maxima.append(float(g.max(initial=0)))
            selfs.append(n_self)
            skins.append(n_skin)
            anchors.append(anchor)
            within10 += int(np.count_nonzero(per_seam <= 10))
            within50 += int(np.count_nonzero(per_seam <= 50))
            n_seams += len(per_seam)
    if maxima:
        selfs_a, skins_a = np.array(selfs), np.array(skins)
        print(
            f"# {len(maxima)} cases: median of the largest gaps {np.median(maxima):.0f} mm, "
            f"largest {max(maxima):.0f} mm; "
            f"seams placed within 10 mm {within10}/{n_seams}, within 50 mm {within50}/{n_seams}; "
            f"median p99 stretch {np.median(stretches):.2f}, largest {max(stretches):.2f}; "
            f"self-crossing triangles 0 in {np.mean(selfs_a == 0):.0%} of the cases, median {np.median(selfs_a):.0f}, "
            f"largest {selfs_a.max()}; skin triangles 0 in {np.mean(skins_a == 0):.0%}, largest {skins_a.max()}; "
            f"anchor level median {np.median(anchors):.1f} cm, largest {max(anchors):.1f} cm"
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
