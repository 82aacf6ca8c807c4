"""Benchmark: the fabric ``bridge infer`` reads off every file of ``../shared/aama``, with its evidence.

Plain script. For every DXF in ``../shared/aama`` it reads the file, runs
:func:`patternbridge.bridge.infer_bridge` and the sidecar writer (which reads
the measurement links' ease against the file's size chart and infers the
fabric, :mod:`patternbridge.bridge.fabric`), and prints the file, the garment's
fabric class, the pieces of another fabric and the evidence; then the fabric
each library garment states.

    .venv/bin/python benchmarks/fabric.py [--markdown]
"""

from __future__ import annotations

import argparse
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
SHARED = REPO.parent / "shared"


def main() -> int:
    from patternbridge.bridge import infer_bridge
    from patternbridge.bridge.sidecar import inference_sidecar
    from patternbridge.io.dxf_aama import read_dxf
    from patternbridge.library import load_garment
    from patternbridge.library.catalogue import garment_names

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--markdown", action="store_true", help="print a markdown table")
    args = parser.parse_args()
    rows = []
    for path in sorted((SHARED / "aama").iterdir(), key=lambda p: p.name.lower()):
        if path.suffix.lower() != ".dxf":
            continue
        pattern, _ = read_dxf(path)
        sidecar = inference_sidecar(pattern, infer_bridge(pattern))
        own = ", ".join(f"{p['name']} {p['fabric_class']}" for p in sidecar["pieces"] if "fabric_class" in p)
        rows.append((path.name, sidecar["fabric_class"], own or "-", sidecar["fabric_why"]))
    for name in garment_names():
        g = load_garment(name)
        own = ", ".join(f"{p.name} {p.fabric_class}" for p in g.pieces if p.fabric_class is not None)
        rows.append((f"library {name}", str(g.fabric_class), own or "-", g.fabric_why))
    head = ("file", "fabric", "pieces of another fabric", "evidence")
    if args.markdown:
        print("| " + " | ".join(head) + " |")
        print("|" + "---|" * len(head))
        for row in rows:
            print("| " + " | ".join(row) + " |")
    else:
        for row in rows:
            print(f"{row[0]:28s} {row[1]:13s} {row[2]:40s} {row[3]}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
