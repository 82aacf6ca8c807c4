"""Benchmark: ``patternbridge batch`` on a LocalCluster against the serial loop, in the same run.

Usage: ``python benchmarks/batch.py [--characters A_superhero,B_slim_female,...] [--garments shirt,trousers]
[--workers 2] [--pop-size 16] [--generations 10] [--drape] [--seed 0]``

The serial loop is what a script without the batch does: in one new
interpreter, measure each character once and call :func:`patternbridge.fit`
for each of its garments. The batch runs the same cases with
:func:`patternbridge.batch.run_batch` on a new ``LocalCluster`` (one
single-threaded worker process per core) from this process, which has not
run a fit before; its time includes starting the cluster. Each run pays its
own imports. The table gives the wall time, throughput (cases per minute), the
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
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
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


@dataclass(frozen=True)
class SerialRun:
    """What the serial loop measured: wall and CPU seconds, peak RSS, each step's CPU seconds."""

    seconds: float
    cpu: float
    rss_mb: float
    steps: dict[str, float]


def serial_process(args: argparse.Namespace, out: Path) -> SerialRun:
    """Run the serial loop in a new interpreter (it pays its own imports, as the batch's client does)."""
    record = out / "serial.json"
    argv = [
        sys.executable,
        __file__,
        "--serial-into",
        str(out),
        *(
            f"--{k.replace('_', '-')}={v}"
            for k, v in (
                ("characters", args.characters),
                ("garments", args.garments),
                ("pop_size", args.pop_size),
                ("generations", args.generations),
                ("seed", args.seed),
            )
        ),
    ]
    subprocess.run([*argv, *(["--drape"] if args.drape else [])], check=True)
    return SerialRun(**json.loads(record.read_text()))


def serial_main(args: argparse.Namespace, characters: list[Path], garments: list[str], options) -> int:
    """``--serial-into OUT``: the serial loop alone, its files in OUT/ and its measures in OUT/serial.json."""
    out = Path(args.serial_into)
    cpu0 = cpu_seconds()
    seconds, steps = serial(characters, garments, out, args.seed, options)
    run = {"seconds": seconds, "cpu": cpu_seconds() - cpu0, "rss_mb": peak_rss_mb(), "steps": steps}
    (out / "serial.json").write_text(json.dumps(run))
    return 0


def batch(characters: list[Path], garments: list[str], out: Path, seed: int, options, n_workers: int):
    """Run the batch on a new LocalCluster; its wall time counts from before the cluster starts."""
    from distributed import Client, get_task_stream

    from patternbridge.batch import run_batch
    from patternbridge.batch.cluster import DRAPE_MODULES, FIT_MODULES, local_cluster

    t0, cpu0 = time.perf_counter(), cpu_seconds()
    wall0 = time.time()
    modules = FIT_MODULES + (DRAPE_MODULES if options.drape else ())
    with local_cluster(n_workers, dashboard_address=None, modules=modules) as cluster, Client(cluster) as client:
        started = sum(client.run(cpu_seconds).values())  # the workers' CPU before any task: starting up
        client_start = cpu_seconds() - cpu0  # the client's imports and the cluster's start
        with get_task_stream(client) as stream:
            result = run_batch([str(c) for c in characters], garments, out, client=client, seed=seed, options=options)
        seconds, wall1 = time.perf_counter() - t0, time.time()
        rss = client.run(peak_rss_mb)
        cpu = client.run(cpu_seconds)
        client_cpu = cpu_seconds() - cpu0  # scheduler, nannies, client: all run in this process
    return BatchRun(
        result=result,
        seconds=seconds,
        rss_mb=sorted(rss.values()),
        cpu=sum(cpu.values()),
        worker_cpu=sorted(cpu.values()),
        start_cpu=started,
        client_start_cpu=client_start,
        client_cpu=client_cpu,
        split=timeline(stream.data, wall0, wall1),
        starts=case_starts(stream.data, wall0),
    )


@dataclass(frozen=True)
class BatchRun:
    """What the batch run measured: wall and CPU seconds, peak RSS per worker, the worker-seconds split."""

    result: object
    seconds: float
    rss_mb: list[float]
    cpu: float
    worker_cpu: list[float]
    start_cpu: float
    client_start_cpu: float
    client_cpu: float
    split: dict[str, float]
    starts: dict[str, float]


def case_starts(tasks: list[dict], wall0: float) -> dict[str, float]:
    """When each case's task started (seconds after the batch began), by case key (task ``fit-<key>-<stamp>``)."""
    starts = {}
    for task in tasks:
        key = str(task["key"])
        if key.startswith("fit-"):
            for ss in task["startstops"]:
                if ss["action"] == "compute":
                    starts[key[4 : key.rindex("-")]] = ss["start"] - wall0
    return starts


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
    ap.add_argument("--serial-into", help=argparse.SUPPRESS)  # the serial loop's own process
    args = ap.parse_args()
    if not SHARED.is_dir():
        print(f"benchmark needs {SHARED}", file=sys.stderr)
        return 1
    characters = [SHARED / f"{name}.obj" for name in args.characters.split(",")]
    garments = args.garments.split(",")
    options = FitOptions(pop_size=args.pop_size, n_gen=args.generations, drape=args.drape)
    n = len(characters) * len(garments)
    if args.serial_into:
        return serial_main(args, characters, garments, options)
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
        load0 = os.getloadavg()[0]
        (tmp / "serial").mkdir()
        serial_run = serial_process(args, tmp / "serial")
        load1 = os.getloadavg()[0]
        run = batch(characters, garments, tmp / "batch", args.seed, options, args.workers)
        load2 = os.getloadavg()[0]
        same = same_results(tmp / "serial", tmp / "batch")
    print_table(serial_run, run, n, args.workers, (load0, load1, load2))
    done = run.result.count(CaseStatus.DONE)
    speedup = serial_run.seconds / run.seconds
    print(
        f"# {done}/{n} batch cases done; same results as the serial loop: {'yes' if same else 'NO'}; "
        f"target speed-up ≥ 1.8 with 2 workers: {'met' if speedup >= 1.8 else 'missed'} ({speedup:.2f})"
    )
    return 0 if done == n and same else 1


def print_table(serial_run: SerialRun, run: BatchRun, n: int, n_workers: int, loads: tuple[float, ...]) -> None:
    """The two runs side by side, then where the batch's worker-seconds and CPU seconds went."""
    header = (
        f"{'run':<22} {'cases':>5} {'wall s':>8} {'CPU s':>7} {'load':>10} {'cases/min':>10} "
        f"{'speed-up':>9}  peak RSS MB"
    )
    print(header)
    print("-" * len(header))
    print(
        f"{'serial loop':<22} {n:5d} {serial_run.seconds:8.1f} {serial_run.cpu:7.1f} "
        f"{f'{loads[0]:.1f}→{loads[1]:.1f}':>10} {60 * n / serial_run.seconds:10.2f} {1.0:9.2f}  "
        f"{serial_run.rss_mb:.0f}"
    )
    workers = ", ".join(f"{r:.0f}" for r in run.rss_mb)
    print(
        f"{f'batch, {n_workers} workers':<22} {n:5d} {run.seconds:8.1f} {run.cpu:7.1f} "
        f"{f'{loads[1]:.1f}→{loads[2]:.1f}':>10} {60 * n / run.seconds:10.2f} "
        f"{serial_run.seconds / run.seconds:9.2f}  {workers} (per worker)"
    )
    print_cases(serial_run, run)
    case_cpu = sum(o.cpu_seconds for o in run.result.outcomes)
    print(
        f"# batch CPU s: workers {run.cpu:.1f} = starting up {run.start_cpu:.1f} + cases {case_cpu:.1f} + "
        f"measuring and between tasks {run.cpu - run.start_cpu - case_cpu:.1f}; "
        f"client process (scheduler, nannies, client) {run.client_cpu:.1f}"
    )
    split = run.split
    print(
        f"# worker-seconds of the batch ({n_workers} × {run.seconds:.1f} s): before the first task (cluster start) "
        f"{split['start']:.1f}, in tasks {split['tasks']:.1f}, between tasks {split['gaps']:.1f}, "
        f"after the last (tail) {split['tail']:.1f}"
    )
    idle = run.client_start_cpu + max(run.worker_cpu)
    print(
        f"# on an otherwise idle machine (estimate from CPU times: the client starts the cluster, then the busiest "
        f"worker runs without waiting): serial CPU {serial_run.cpu:.1f} / (client start {run.client_start_cpu:.1f} "
        f"+ busiest worker {max(run.worker_cpu):.1f}; workers {', '.join(f'{c:.1f}' for c in run.worker_cpu)}) "
        f"= {serial_run.cpu / idle:.2f}"
    )


def print_cases(serial_run: SerialRun, run: BatchRun) -> None:
    """Each case's CPU seconds in the serial loop and in its worker, in the order the batch started them."""
    measured = ", ".join(f"{k} {v:.1f}" for k, v in serial_run.steps.items() if "/" not in k)
    print(f"# serial CPU s measuring each character: {measured}")
    print(
        f"# {'case':<26} {'start s':>7} {'wall s':>7} {'worker':>6} {'serial CPU s':>12} {'batch CPU s':>11} "
        f"{'ratio':>6} {'worker peak RSS MB':>18}"
    )
    workers = sorted({o.worker for o in run.result.outcomes})
    for o in sorted(run.result.outcomes, key=lambda o: run.starts.get(o.case.key, 0.0)):
        s = serial_run.steps.get(o.case.key, float("nan"))
        print(
            f"# {o.case.key:<26} {run.starts.get(o.case.key, float('nan')):7.1f} {o.seconds:7.1f} "
            f"{workers.index(o.worker):6d} {s:12.1f} {o.cpu_seconds:11.1f} {o.cpu_seconds / max(s, 1e-9):6.2f} "
            f"{o.peak_rss_mb:18.0f}"
        )


if __name__ == "__main__":
    sys.exit(main())
