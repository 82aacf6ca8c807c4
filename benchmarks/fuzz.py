"""Malformed-input run: mutations of the real files through every command, a table of outcomes.

Re-creates issue 20's run: 1,132 cases derived from the DXF and RUL files, the
garment-library pattern JSON, the characters (OBJ, PLY, GLB), their sidecars,
the landmark table and a measured character's measurements JSON, each through
``import``, ``info``, ``export``, ``plot``, ``check``, ``seams infer``,
``measure``, ``geodesic`` or ``fit`` (tiny budget, ``--no-drape``), with a
timeout per case (CPU seconds of the case's process, so a busy machine does
not turn slow cases into hangs). Prints a machine/versions header, the table command ×
outcome, and one line per case that is not a clean error or a checked ok.

Usage::

    python benchmarks/fuzz.py [--cases 1132] [--seed 0] [--timeout 60] [--jobs 1] [--only CMD] [--json OUT]
"""

from __future__ import annotations

import argparse
import collections
import json
import os
import platform
import sys
import tempfile
import threading
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "tests" / "fuzz"))
sys.path.insert(0, str(REPO))

from fuzz_run import Outcome, build_cases, measurements_file, preload, run_case  # noqa: E402

COMMANDS = ["import", "info", "export", "plot", "check", "seams", "measure", "geodesic", "fit"]


def _header() -> str:
    import numpy

    import patternbridge

    return (
        f"# {platform.node()} {platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}, "
        f"numpy {numpy.__version__}, patternbridge {patternbridge.__version__}"
    )


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", type=int, default=1132)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument(
        "--timeout", type=float, default=60.0, help="CPU seconds per case before it counts as a hang (5x in wall time)"
    )
    parser.add_argument("--jobs", type=int, default=1, help="cases run at the same time")
    parser.add_argument("--only", help="run only the cases of this command")
    parser.add_argument("--json", help="also write every result to this JSON file")
    args = parser.parse_args(argv)

    preload()
    cases = build_cases(args.cases, seed=args.seed)
    if args.only:
        cases = [c for c in cases if c.command == args.only]
    print(_header())
    print(f"# {len(cases)} cases, seed {args.seed}, timeout {args.timeout:g} s CPU ({5 * args.timeout:g} s wall)")
    with tempfile.TemporaryDirectory(prefix="pb-fuzz-") as tmp:
        work = Path(tmp)
        meas = measurements_file(work)
        t0 = time.perf_counter()
        lock, done = threading.Lock(), [0]

        def one(case):
            result = run_case(case, work, meas, timeout_s=args.timeout)
            with lock:
                done[0] += 1
                if done[0] % 50 == 0 or done[0] == len(cases):
                    print(f"# {done[0]}/{len(cases)} cases, {time.perf_counter() - t0:.0f} s", file=sys.stderr)
            return result

        with ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
            results = list(pool.map(one, cases))
        total = time.perf_counter() - t0
    table: dict[str, collections.Counter] = collections.defaultdict(collections.Counter)
    for r in results:
        table[r.case.command][r.outcome] += 1
    outcomes = list(Outcome)
    width = max(len(str(o)) for o in outcomes) + 2
    print(f"\n{'command':<10}" + "".join(f"{o!s:>{width}}" for o in outcomes) + f"{'total':>8}")
    for cmd in [*COMMANDS, *sorted(set(table) - set(COMMANDS))]:
        if cmd in table:
            row = table[cmd]
            print(f"{cmd:<10}" + "".join(f"{row[o]:>{width}}" for o in outcomes) + f"{sum(row.values()):>8}")
    sums = collections.Counter(r.outcome for r in results)
    print(f"{'all':<10}" + "".join(f"{sums[o]:>{width}}" for o in outcomes) + f"{len(results):>8}")
    slowest = max(results, key=lambda r: r.seconds)
    print(f"\n# {total:.0f} s in all; slowest case {slowest.seconds:.1f} s ({slowest.case.id})")
    bad = [r for r in results if r.outcome not in (Outcome.ERROR, Outcome.OK)]
    for r in bad:
        print(f"{r.outcome!s:>16}  {r.case.id}  {r.detail[:240]}")
    if args.json:
        Path(args.json).write_text(
            json.dumps(
                [{"case": r.case.id, "outcome": str(r.outcome), "detail": r.detail, "seconds": round(r.seconds, 2)}
                 for r in results],
                indent=1,
            )
            + "\n"
        )
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
