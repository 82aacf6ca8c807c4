"""Import time of the real DXF-AAMA/ASTM exports, with ezdxf's own ``readfile`` as reference.

Usage: ``python benchmarks/dxf_import.py [--repeat N] [FILE ...]``

For each file: blocks, pieces, sizes, the best-of-N time of
``patternbridge.io.dxf_aama.read_dxf`` (parse, pieces, grade-rule derivation
from the nest) and of ``ezdxf.readfile`` (parse only) in the same run, and the
process's peak RSS. Target: under 0.5 s for the 42-block AccuMark file.
"""

from __future__ import annotations

import argparse
import platform
import resource
import sys
import time
from pathlib import Path

import ezdxf
import numpy as np

from patternbridge import __version__
from patternbridge.io.dxf_aama import read_dxf

SHARED = Path(__file__).resolve().parents[1] / ".." / "shared" / "aama"
TARGET_S = 0.5


def best_of(fn, repeat: int) -> float:
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times)


def peak_rss_mb() -> float:
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return rss / 1024.0 if sys.platform != "darwin" else rss / 1024.0 / 1024.0


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("files", nargs="*", type=Path)
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args(argv)
    files = args.files or sorted(p for p in SHARED.glob("*") if p.suffix.lower() == ".dxf")
    if not files:
        print(f"no DXF files found in {SHARED}", file=sys.stderr)
        return 1
    print(f"# patternbridge {__version__}, ezdxf {ezdxf.__version__}, numpy {np.__version__}, "
          f"python {platform.python_version()}, {platform.machine()}, best of {args.repeat}")
    header = f"{'file':24s} {'KiB':>6s} {'blocks':>6s} {'pieces':>6s} {'sizes':>5s} " \
             f"{'read_dxf s':>10s} {'ezdxf s':>8s} {'peak MiB':>8s}"
    print(header)
    print("-" * len(header))
    worst_42 = None
    for path in files:
        pattern, _ = read_dxf(path)
        ours = best_of(lambda path=path: read_dxf(path), args.repeat)
        ref = best_of(lambda path=path: ezdxf.readfile(path), args.repeat)
        n_blocks = len([b for b in ezdxf.readfile(path).blocks if not b.name.startswith("*")])
        print(f"{path.name:24s} {path.stat().st_size / 1024:6.0f} {n_blocks:6d} {len(pattern.pieces):6d} "
              f"{len(pattern.sizes):5d} {ours:10.3f} {ref:8.3f} {peak_rss_mb():8.0f}")
        if n_blocks == 42:
            worst_42 = max(worst_42 or 0.0, ours)
    if worst_42 is not None:
        verdict = "ok" if worst_42 < TARGET_S else "TOO SLOW"
        print(f"42-block AccuMark file: {worst_42:.3f} s (target < {TARGET_S} s): {verdict}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
