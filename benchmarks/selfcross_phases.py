"""Benchmark: self-crossing triangles after placement and after every phase of the drape.

Plain script (no asv). For every character, garment and seed it places the
garment (``pipeline.prepare``), counts the triangles where the garment passes
through itself (``selfcross.self_crossing`` on the seams averaged, as the
report counts them before the skin clean-up), then runs the planned phases
(``phases.run_phases``) and counts again after each one: ``place``,
``sew`` (the last sewing step), ``key1``.. (each pose keyframe), ``settle``.
The last column is the report's count after ``finish`` (welded, skin
cleared). It prints one line per case with the counts, the widest seam gap
before welding (mm) and the CPU seconds of the simulation (``time.process_time``,
the measuring left out), and ``--json`` writes the rows.

    .venv/bin/python benchmarks/selfcross_phases.py --graded-cache G [--shard 0/2] [--seeds 0 1]
        [--untangle sew key settle]

``--shard K/N`` runs every N-th case from the K-th, so N processes share a
grid.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from assemble import CHARACTERS, _character_path, _graded, _variant_names


def _welded_count(sim) -> int:
    """Self-crossing triangles of the whole cloth, as the report counts them, with the sewn vertices averaged."""
    import numpy as np

    from patternbridge.assemble.drape import weld_groups
    from patternbridge.assemble.selfcross import self_crossing

    cloth = sim.cloth
    weld = weld_groups(len(cloth.x), cloth.seams)
    ids, inv = np.unique(weld, return_inverse=True)
    wx = np.zeros((len(ids), 3))
    np.add.at(wx, inv, cloth.x)
    wx /= np.bincount(inv, minlength=len(ids))[:, None]
    return int(np.count_nonzero(self_crossing(wx, inv[cloth.faces])))


def run_case(character, pattern, seed: int, *, untangle: list[str] | None = None, out: Path | None = None) -> dict:
    """Counts after each phase, CPU seconds of the simulation and the report of the finished garment.

    ``untangle`` (phase kinds ``sew``, ``key``, ``settle``) untangles in those phases instead of the plan's;
    ``out`` receives the pictures of the finished garment.
    """
    from dataclasses import replace

    from patternbridge.assemble.phases import PoseKeyframe, Settle, Sew, run_phases
    from patternbridge.assemble.pipeline import finish, prepare, with_anchor_landmarks
    from patternbridge.assemble.strategy import choose_strategy

    character, _ = with_anchor_landmarks(character, pattern)
    posing = character
    if (character.skeleton is None or character.skin is None) and choose_strategy(pattern).raise_arms:
        from patternbridge.assemble.landmark_rig import landmark_rig

        posing = landmark_rig(character) or character
    measured = 0.0  # CPU seconds spent measuring, left out of the simulation's time
    counts: dict[str, int] = {}
    keys = 0
    t0 = time.process_time()
    sim = prepare(posing, pattern, seed=seed)
    if untangle is not None:  # the plan's untangling replaced: on in the phases of these kinds only
        kinds = {"sew": Sew, "key": PoseKeyframe, "settle": Settle}
        on = tuple(kinds[u] for u in untangle)
        sim.phases = tuple(replace(p, untangle=isinstance(p, on)) for p in sim.phases)

    def observe(phase) -> None:
        nonlocal measured, keys
        t = time.process_time()
        if isinstance(phase, PoseKeyframe):
            keys += 1
            name = f"key{keys}"
        else:
            name = "sew" if isinstance(phase, Sew) and "sew" not in counts else "settle"
        counts[name] = _welded_count(sim)
        measured += time.process_time() - t

    observe_place = time.process_time()
    counts["place"] = _welded_count(sim)
    measured += time.process_time() - observe_place
    run_phases(sim, sim.phases, None, observe)
    cpu = time.process_time() - t0 - measured
    garment = finish(sim)
    report = garment.report
    if out is not None:
        from patternbridge.assemble.export_obj import write_obj
        from patternbridge.assemble.pictures import write_pictures

        out.mkdir(parents=True, exist_ok=True)
        write_pictures(out, garment, character)
        write_obj(out / "garment.obj", garment)
    return {
        "counts": counts,
        "final": report.self_crossing_triangles,
        "pieces": dict(report.self_crossing_pieces),
        "gap0_mm": round(report.max_seam_gap_before_weld_mm, 2),
        "skin_triangles": report.skin_triangles,
        "verdict": str(report.verdict),
        "reasons": [r.check.value for r in report.reasons],
        "turned_cm2": {k: round(v, 1) for k, v in report.turned_cm2.items()},
        "cpu_s": round(cpu, 1),
        "vertices": len(sim.cloth.x),
    }


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--characters", nargs="*", default=list(CHARACTERS))
    ap.add_argument("--variants", action="store_true", help="also every mesh of ../shared/characters/variants")
    ap.add_argument("--garments", nargs="*", default=["all"])
    ap.add_argument("--graded-cache", metavar="DIR")
    ap.add_argument("--grade-budget", nargs=2, type=int, default=(40, 40), metavar=("POP", "GEN"))
    ap.add_argument("--seeds", nargs="*", type=int, default=[0])
    ap.add_argument("--shard", default="0/1", help="K/N: run every N-th case from the K-th")
    ap.add_argument("--json", help="write the rows to this JSON file")
    ap.add_argument(
        "--untangle",
        nargs="*",
        choices=["sew", "key", "settle"],
        help="untangle in the phases of these kinds instead of the plan's (none given: nowhere)",
    )
    ap.add_argument("--out", help="write the fit_*.png pictures of every case to OUT/<garment>_<character>_s<seed>")
    args = ap.parse_args(argv)

    from patternbridge.library import garment_names, load_garment
    from patternbridge.mesh.load import load_character

    k, n = (int(v) for v in args.shard.split("/"))
    names = list(args.characters) + (_variant_names() if args.variants else [])
    garments = garment_names() if args.garments == ["all"] else args.garments
    cases = [(c, g, s) for c in names for g in garments for s in args.seeds][k::n]
    rows = []
    loaded: dict = {}
    for cname, gname, seed in cases:
        path = _character_path(cname)
        if path not in loaded:
            loaded[path] = load_character(path)[0]
        character = loaded[path]
        pattern = _graded(load_garment(gname), character, path.stem, gname, args.graded_cache, args.grade_budget)
        out = Path(args.out) / f"{gname}_{path.stem}_s{seed}" if args.out else None
        row = {
            "character": path.stem,
            "garment": gname,
            "seed": seed,
            "untangle": args.untangle,
            **run_case(character, pattern, seed, untangle=args.untangle, out=out),
        }
        rows.append(row)
        phases = " ".join(f"{key}={v}" for key, v in row["counts"].items())
        print(
            f"{gname + ' on ' + path.stem + f' s{seed}':44s} {phases}  final={row['final']}  "
            f"gap0={row['gap0_mm']:.1f}mm  skin={row['skin_triangles']}  cpu={row['cpu_s']:.1f}s  "
            f"V={row['vertices']}  {row['verdict']}",
            flush=True,
        )
        if args.json:
            Path(args.json).write_text(json.dumps(rows, indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
