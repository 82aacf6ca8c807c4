"""Benchmark: ``patternbridge batch`` on a LocalCluster against the serial loop, in the same run.

Usage: ``python benchmarks/batch.py [--characters A_superhero,B_slim_female,...] [--garments shirt,trousers]
[--workers 2] [--pop-size 16] [--generations 10] [--drape] [--seed 0]``

The serial loop is what a script without the batch does: in one process,
measure each character once and call :func:`patternbridge.fit` for each of
its garments. The batch runs the same cases with
:func:`patternbridge.batch.run_batch` on a new ``LocalCluster`` (one
single-threaded worker process per core); its time includes starting the
cluster. The table gives the wall time, throughput (cases per minute), the
speed-up over the serial loop and the peak RSS of the serial process and of
each worker, the CPU time each run used (the serial process's threads, the
workers' summed) and the 1-minute load average at the start and end of each
run: on a machine busy with other work the wall times compare shares of the
cores, and the CPU times show what the batch itself costs. The last line
says whether every case's results are the same in both (reports without
timings, pattern/DXF/RUL bytes).

Target (issue 21): ≥ 1.8× the serial throughput with 2 workers on a 2-core
machine. The exit status is 1 when a case fails or the results differ.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import resource
import sys
import tempfile
import time
from pathlib import Path

from patternbridge import __version__
from patternbridge.testing import timeless, without_stamps

SHARED = Path(__file__).resolve().parents[1] / ".." / "shared" / "characters"


def peak_rss_mb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def cpu_seconds() -> float:
    """User + system CPU time of this process so far (all its threads)."""
    usage = resource.getrusage(resource.RUSAGE_SELF)
    return usage.ru_utime + usage.ru_stime


def serial(characters: list[Path], garments: list[str], out: Path, seed: int, options) -> tuple[float, dict]:
    """The serial loop's wall time and each step's CPU seconds (``character`` measuring, ``character/garment``)."""
    from patternbridge.workflow import fit, load_subject

    t0 = time.perf_counter()
    steps: dict[str, float] = {}
    for path in characters:
        c0 = cpu_seconds()
        subject, _ = load_subject(path)
        steps[path.stem] = cpu_seconds() - c0
        for garment in garments:
            c0 = cpu_seconds()
            fit(subject, garment, seed=seed, options=options, out_dir=out / path.stem / garment)
            steps[f"{path.stem}/{garment}"] = cpu_seconds() - c0
    return time.perf_counter() - t0, steps


def batch(characters: list[Path], garments: list[str], out: Path, seed: int, options, n_workers: int):
    """Run the batch on a new LocalCluster; its wall time counts from before the cluster starts."""
    from distributed import Client, get_task_stream

    from patternbridge.batch import run_batch
    from patternbridge.batch.cluster import local_cluster

    t0, cpu0 = time.perf_counter(), cpu_seconds()
    wall0 = time.time()
    with local_cluster(n_workers, dashboard_address=None) as cluster, Client(cluster) as client:
        with get_task_stream(client) as stream:
            result = run_batch([str(c) for c in characters], garments, out, client=client, seed=seed, options=options)
        seconds, wall1 = time.perf_counter() - t0, time.time()
        rss = client.run(peak_rss_mb)
        cpu = client.run(cpu_seconds)
        client_cpu = cpu_seconds() - cpu0  # scheduler, nannies, client: all run in this process
    return result, seconds, sorted(rss.values()), sum(cpu.values()), client_cpu, timeline(stream.data, wall0, wall1)


def timeline(tasks: list[dict], wall0: float, wall1: float) -> dict[str, float]:
    """Worker-seconds of the batch split into: before a worker's first task, in tasks, between tasks, after its last."""
    spans: dict[str, list[tuple[float, float]]] = {}
    for task in tasks:
        for ss in task["startstops"]:
            if ss["action"] == "compute":
                spans.setdefault(task["worker"], []).append((ss["start"], ss["stop"]))
    split = {"start": 0.0, "tasks": 0.0, "gaps": 0.0, "tail": 0.0}
    for worker_spans in spans.values():
        worker_spans.sort()
        busy = sum(b - a for a, b in worker_spans)
        split["start"] += worker_spans[0][0] - wall0
        split["tasks"] += busy
        split["tail"] += wall1 - worker_spans[-1][1]
        split["gaps"] += (worker_spans[-1][1] - worker_spans[0][0]) - busy
    return split


def same_results(a: Path, b: Path) -> bool:
    for report in a.rglob("fit_report.json"):
        other = b / report.relative_to(a)
        if not other.is_file():
            return False
        if timeless(json.loads(report.read_text())) != timeless(json.loads(other.read_text())):
            return False
        for f in report.parent.iterdir():
            if f.suffix in (".json", ".dxf", ".rul") and f.name != "fit_report.json":
                if without_stamps(f.read_bytes()) != without_stamps((other.parent / f.name).read_bytes()):
                    return False
    return True


def main() -> int:
    from patternbridge.batch import CaseStatus
    from patternbridge.workflow import FitOptions

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument(
        "--characters",
        default=",".join(sorted(p.stem for p in SHARED.glob("*.obj"))),
        help="character mesh stems in ../shared/characters (default: all six)",
    )
    ap.add_argument("--garments", default="shirt,trousers")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--pop-size", type=int, default=16)
    ap.add_argument("--generations", type=int, default=10)
    ap.add_argument("--drape", action="store_true", help="drape every case too (minutes per case)")
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args()
    if not SHARED.is_dir():
        print(f"benchmark needs {SHARED}", file=sys.stderr)
        return 1
    characters = [SHARED / f"{name}.obj" for name in args.characters.split(",")]
    garments = args.garments.split(",")
    options = FitOptions(pop_size=args.pop_size, n_gen=args.generations, drape=args.drape)
    n = len(characters) * len(garments)
    import dask
    import numpy as np

    print(
        f"# batch benchmark — patternbridge {__version__}, dask {dask.__version__}, numpy {np.__version__}, "
        f"python {platform.python_version()}, {platform.machine()}, {os.cpu_count()} cores, "
        f"load {os.getloadavg()[0]:.1f}, seed {args.seed}"
    )
    print(
        f"# {len(characters)} characters × {len(garments)} garments = {n} cases, pop {args.pop_size}, "
        f"{args.generations} generations, drape {'on' if args.drape else 'off'}"
    )
    with tempfile.TemporaryDirectory(prefix="pb-bench-batch-") as tmp:
        tmp = Path(tmp)
        load0, cpu0 = os.getloadavg()[0], cpu_seconds()
        t_serial, steps = serial(characters, garments, tmp / "serial", args.seed, options)
        cpu_serial, load1 = cpu_seconds() - cpu0, os.getloadavg()[0]
        rss_serial = peak_rss_mb()
        result, t_batch, rss_workers, cpu_batch, cpu_client, split = batch(
            characters, garments, tmp / "batch", args.seed, options, args.workers
        )
        load2 = os.getloadavg()[0]
        same = same_results(tmp / "serial", tmp / "batch")
    header = (
        f"{'run':<22} {'cases':>5} {'wall s':>8} {'CPU s':>7} {'load':>10} {'cases/min':>10} "
        f"{'speed-up':>9}  peak RSS MB"
    )
    print(header)
    print("-" * len(header))
    print(
        f"{'serial loop':<22} {n:5d} {t_serial:8.1f} {cpu_serial:7.1f} {f'{load0:.1f}→{load1:.1f}':>10} "
        f"{60 * n / t_serial:10.2f} {1.0:9.2f}  {rss_serial:.0f}"
    )
    workers = ", ".join(f"{r:.0f}" for r in rss_workers)
    print(
        f"{f'batch, {args.workers} workers':<22} {n:5d} {t_batch:8.1f} {cpu_batch:7.1f} "
        f"{f'{load1:.1f}→{load2:.1f}':>10} {60 * n / t_batch:10.2f} "
        f"{t_serial / t_batch:9.2f}  {workers} (per worker)"
    )
    print("# serial CPU s per step: " + ", ".join(f"{k} {v:.1f}" for k, v in steps.items()))
    print(f"# batch CPU s: workers {cpu_batch:.1f} + client process (scheduler, nannies, client) {cpu_client:.1f}")
    print(
        f"# worker-seconds of the batch ({args.workers} × {t_batch:.1f} s): before the first task (cluster start) "
        f"{split['start']:.1f}, in tasks {split['tasks']:.1f}, between tasks {split['gaps']:.1f}, "
        f"after the last (tail) {split['tail']:.1f}"
    )
    busy = split["tasks"] / max(args.workers * t_batch, 1e-9)
    print(
        f"# the speed-up these imply on an otherwise idle machine (workers busy {100 * busy:.0f} % of the time, "
        f"at the CPU cost of their tasks): {args.workers} × {busy:.2f} × {cpu_serial:.1f} / {cpu_batch:.1f} = "
        f"{args.workers * busy * cpu_serial / cpu_batch:.2f}"
    )
    done = result.count(CaseStatus.DONE)
    print(
        f"# {done}/{n} batch cases done; same results as the serial loop: {'yes' if same else 'NO'}; "
        f"target speed-up ≥ 1.8 with 2 workers: {'met' if t_serial / t_batch >= 1.8 else 'missed'}"
    )
    return 0 if done == n and same else 1


if __name__ == "__main__":
    sys.exit(main())
