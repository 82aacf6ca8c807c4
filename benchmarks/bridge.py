"""Benchmark: ``bridge infer`` against the hand labels, one line per file, with its time.

Plain script. For every label in ``tests/bridge/labels`` (the files of
``../shared/aama`` and the six library garments read from their DXF without
the sidecar) it runs :func:`patternbridge.bridge.infer_bridge`, scores it with
:mod:`patternbridge.bridge.evaluate` and prints the file, its pieces, roles
right, seam recall and precision at the edge level and the CPU seconds taken.
Totals count the files labelled as garments (``"garment": true``): a style
exported in both flavours (AAMA and ASTM twins) counts once.

Targets (issue 17): roles >= 95 %, seams >= 95 % recall and precision, <= 2 s a file.

    .venv/bin/python benchmarks/bridge.py [--markdown] [--only TEXT]
"""

from __future__ import annotations

import argparse
import platform
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
SHARED = REPO.parent / "shared"


def main() -> int:
    from patternbridge import __version__
    from patternbridge.bridge import infer_bridge
    from patternbridge.bridge.evaluate import LABELS_DIR, load_labelled, score

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--markdown", action="store_true", help="print a markdown table")
    parser.add_argument("--only", default="", help="only label files whose name contains this")
    parser.add_argument("-v", "--verbose", action="store_true", help="list wrong roles, missed and extra seams")
    args = parser.parse_args()
    print(f"# patternbridge {__version__}, Python {platform.python_version()}, {platform.machine()}")
    head = ("file", "pieces", "roles", "seams found", "recall", "precision", "cpu s")
    if args.markdown:
        print("| " + " | ".join(head) + " |")
        print("|" + "---|" * len(head))
    else:
        print(f"{head[0]:32s} {head[1]:>6s} {head[2]:>7s} {head[3]:>11s} {head[4]:>7s} {head[5]:>9s} {head[6]:>7s}")
    tot = [0, 0, 0, 0, 0]
    worst = 0.0
    for path in sorted(LABELS_DIR.glob("*.json")):
        if args.only not in path.name:
            continue
        pattern, label, pairs = load_labelled(path, SHARED)
        t0 = time.process_time()  # CPU seconds: the machine is shared, wall time is not the code's
        inference = infer_bridge(pattern)
        seconds = time.process_time() - t0
        sc = score(pattern, inference, label, pairs)
        twin = f" (twin of {label['twin_of']}, not counted)" if "twin_of" in label else " (not counted)"
        name = label["file"].split("/")[-1] + ("" if label["garment"] else twin)
        if label["garment"]:
            for k, v in enumerate(
                (sc.roles_right, sc.roles_total, sc.seams_matched, sc.seams_labelled, sc.seams_inferred)
            ):
                tot[k] += v
        worst = max(worst, seconds)
        row = (
            name,
            str(len(pattern.pieces)),
            f"{sc.roles_right}/{sc.roles_total}",
            f"{sc.seams_matched}/{sc.seams_labelled}",
            f"{100 * sc.recall:.0f} %",
            f"{100 * sc.precision:.0f} %",
            f"{seconds:.2f}",
        )
        if args.markdown:
            print("| " + " | ".join(row) + " |")
        else:
            print(f"{row[0]:32s} {row[1]:>6s} {row[2]:>7s} {row[3]:>11s} {row[4]:>7s} {row[5]:>9s} {row[6]:>7s}")
        if args.verbose:
            for line in (
                sc.wrong_roles + tuple("missed " + m for m in sc.missed) + tuple("extra " + e for e in sc.extra)
            ):
                print("    " + line)
    roles = 100 * tot[0] / max(tot[1], 1)
    recall, precision = 100 * tot[2] / max(tot[3], 1), 100 * tot[2] / max(tot[4], 1)
    print(
        f"garments: roles {tot[0]}/{tot[1]} ({roles:.1f} %), seams recall {tot[2]}/{tot[3]} ({recall:.1f} %), "
        f"precision {tot[2]}/{tot[4]} ({precision:.1f} %), slowest {worst:.2f} CPU s"
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
