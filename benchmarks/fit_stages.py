"""Benchmark: the CPU seconds of every stage of one ``patternbridge fit``, and whether its files kept their bytes.

Usage::

    .venv/bin/python benchmarks/fit_stages.py ../shared/characters/E_average_male.obj --garment shirt \\
        --seed 1 -o /tmp/fit [--compare OLD_OUT/] [--profile OUT.prof]

Runs :func:`patternbridge.workflow.fit` as the command does and prints one row per stage with its CPU seconds
(``time.process_time``: the process's own CPU, which does not depend on how many others share the machine;
the NumPy/BLAS threads count too), the calls and the wall seconds. A stage's time is its own: time spent in a
stage it calls is counted there (the table adds up to the total). ``--compare OLD_OUT/`` compares the bytes of
``garment.obj`` and the graded DXF/RUL files with those of an earlier run of the same case and seed (a pure
speed-up keeps them; the exit status is 1 when one differs). ``--profile`` also writes a cProfile of the run
(timed on CPU) for ``python -m pstats``.

Targets (issues 18 and 19): the drape (``place`` to ``finish``) ≤ 30 CPU s per garment on a 13K-vertex
character, grading a shirt ≤ 20 CPU s, the whole fit ≤ 60 CPU s.
"""

from __future__ import annotations

import argparse
import filecmp
import functools
import importlib
import sys
import time
from pathlib import Path

# (stage, module, function): the functions whose own time is the stage's; order is the table's
STAGES = (
    ("load+measure", "patternbridge.workflow.run", "load_subject"),
    ("grade", "patternbridge.grade.run", "fit_pattern"),
    ("export dxf", "patternbridge.workflow.outputs", "_write_dxf"),
    ("drape: prepare", "patternbridge.assemble.pipeline", "prepare"),
    ("drape: place", "patternbridge.assemble.pipeline", "_place_cloth"),
    ("drape: sew+settle", "patternbridge.assemble.phases", "_sew"),
    ("drape: pose keys", "patternbridge.assemble.phases", "_keyframe"),
    ("drape: settle", "patternbridge.assemble.phases", "_settle"),
    ("drape: finish", "patternbridge.assemble.pipeline", "finish"),
    ("drape: pictures", "patternbridge.assemble.pictures", "write_pictures"),
    ("drape: export", "patternbridge.assemble", "dress"),
    ("plots", "patternbridge.workflow.outputs", "_write_plots"),
)
DRAPE = ("drape: prepare", "drape: place", "drape: sew+settle", "drape: pose keys", "drape: settle", "drape: finish")
COMPARED = ("garment.obj", "*.dxf", "*.rul")


class StageClock:
    """Own CPU and wall seconds and calls per stage: a stage called inside another is taken out of the outer one."""

    def __init__(self) -> None:
        self.cpu: dict[str, float] = {}
        self.wall: dict[str, float] = {}
        self.calls: dict[str, int] = {}
        self._stack: list[str] = ["other"]
        self._mark = (time.process_time(), time.perf_counter())

    def _switch(self, to: str | None) -> None:
        cpu, wall = time.process_time(), time.perf_counter()
        top = self._stack[-1]
        self.cpu[top] = self.cpu.get(top, 0.0) + cpu - self._mark[0]
        self.wall[top] = self.wall.get(top, 0.0) + wall - self._mark[1]
        self._mark = (cpu, wall)
        if to is None:
            self._stack.pop()
        else:
            self._stack.append(to)
            self.calls[to] = self.calls.get(to, 0) + 1

    def wrap(self, stage: str, fn):
        @functools.wraps(fn)
        def timed(*args, **kwargs):
            self._switch(stage)
            try:
                return fn(*args, **kwargs)
            finally:
                self._switch(None)

        return timed

    def install(self) -> None:
        for stage, module, name in STAGES:
            mod = importlib.import_module(module)
            setattr(mod, name, self.wrap(stage, getattr(mod, name)))

    def close(self) -> None:
        self._switch(None)
        self._stack.append("other")


def compare(new: Path, old: Path) -> list[tuple[str, bool]]:
    """``(file, same bytes)`` for the compared outputs present in ``old``."""
    out = []
    for pattern in COMPARED:
        for f in sorted(old.glob(pattern)):
            out.append((f.name, (new / f.name).is_file() and filecmp.cmp(f, new / f.name, shallow=False)))
    return out


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("character")
    ap.add_argument("--garment", default="shirt")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("-o", "--out", required=True)
    ap.add_argument("--compare", help="an earlier output folder of the same case and seed")
    ap.add_argument("--profile", help="write a cProfile (CPU time) of the run here")
    args = ap.parse_args(argv)

    clock = StageClock()
    clock.install()
    from patternbridge.workflow import fit

    profiler = None
    if args.profile:
        import cProfile

        profiler = cProfile.Profile(time.process_time)
        profiler.enable()
    t0, w0 = time.process_time(), time.perf_counter()
    result = fit(args.character, args.garment, seed=args.seed, out_dir=args.out)
    total, wall = time.process_time() - t0, time.perf_counter() - w0
    clock.close()
    if profiler is not None:
        profiler.disable()
        profiler.dump_stats(args.profile)

    print(f"{Path(args.character).stem} x {args.garment}, seed {args.seed}: verdict {result.figures.verdict}")
    print("| stage | CPU s | calls | wall s |\n|---|---:|---:|---:|")
    for stage in [s for s, _, _ in STAGES] + ["other"]:
        if stage in clock.cpu:
            print(f"| {stage} | {clock.cpu[stage]:.1f} | {clock.calls.get(stage, 1)} | {clock.wall[stage]:.1f} |")
    drape = sum(clock.cpu.get(s, 0.0) for s in DRAPE)
    print(f"| **drape (prepare to finish)** | **{drape:.1f}** | | |")
    print(f"| **total** | **{total:.1f}** | | {wall:.1f} |")
    if args.compare:
        rows = compare(Path(args.out), Path(args.compare))
        for name, same in rows:
            print(f"{name}: {'same bytes' if same else 'DIFFERS'}")
        if not rows or not all(same for _, same in rows):
            return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
