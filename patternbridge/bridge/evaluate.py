"""Compare an inference with a hand label: piece roles and seams at the edge level.

A label (``tests/bridge/labels/*.json``, format in ``docs/bridge.md``) names
each piece's role, its fold edge and the seams as pairs of boundary ranges
``[piece, start vertex, end vertex]`` on the imported sample-size outline; a
side may list alternative ranges (either long edge of a symmetric band); seams
the geometry cannot settle (a piece that does not grade, so its lengths agree in
the sample size only) are listed under ``uncertain`` and not scored: an
inferred seam that matches one counts neither as found nor as extra. An
inferred seam matches a labelled one when each of its two ranges covers the
labelled range's arc length with an overlap of at least ``MIN_OVERLAP`` of the
longer of the two (so a 2 cm step at the end of a seam does not count against
it). Folds count as seams of an edge with itself.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..library.seams import sew_line
from ..pattern.model import Pattern
from .model import BridgeInference

__all__ = ["LABELS_DIR", "Score", "label_pairs", "load_labelled", "score", "sidecar_pairs"]

MIN_OVERLAP = 0.7
#: the hand labels, relative to the repository
LABELS_DIR = Path(__file__).resolve().parents[2] / "tests" / "bridge" / "labels"


@dataclass(frozen=True, slots=True, kw_only=True)
class Score:
    """Roles right out of labelled, seams found / labelled / inferred."""

    roles_right: int
    roles_total: int
    seams_matched: int
    seams_labelled: int
    seams_inferred: int
    wrong_roles: tuple[str, ...] = ()
    missed: tuple[str, ...] = ()
    extra: tuple[str, ...] = ()

    @property
    def recall(self) -> float:
        return self.seams_matched / self.seams_labelled if self.seams_labelled else 1.0

    @property
    def precision(self) -> float:
        return self.seams_matched / self.seams_inferred if self.seams_inferred else 1.0


def _mask(n: int, s: int, e: int) -> np.ndarray:
    m = np.zeros(n, dtype=bool)  # segment k runs from vertex k to k+1
    k = s
    while k != e:
        m[k] = True
        k = (k + 1) % n
    return m


def _overlap(seg: np.ndarray, a: tuple, b: tuple) -> float:
    n = len(seg)
    ma, mb = _mask(n, a[1], a[2]), _mask(n, b[1], b[2])
    inter = seg[ma & mb].sum()
    return float(inter / max(seg[ma].sum(), seg[mb].sum(), 1e-9))


def label_pairs(label: dict) -> list[tuple[list, list]]:
    """The labelled seams and folds as (side options, side options) pairs."""

    def opts(side):
        return [tuple(x) for x in side] if isinstance(side[0], list) else [tuple(side)]

    out = [(opts(a), opts(b)) for a, b in label["seams"]]
    out += [([tuple(f)], [tuple(f)]) for f in label.get("folds", [])]
    return out


def score(pattern: Pattern, inference: BridgeInference, label: dict, pairs=None) -> Score:
    """Score ``inference`` against ``label`` (``pairs`` overrides the label's seams)."""
    truth_roles = {k: v["role"] for k, v in label["pieces"].items()}
    wrong = tuple(
        f"{n}: {inference.roles[n].role.value} (label {r})"
        for n, r in truth_roles.items()
        if n in inference.roles and inference.roles[n].role.value != r
    )
    seg = {p.name: np.linalg.norm(np.roll(sew_line(p)[0], -1, axis=0) - sew_line(p)[0], axis=1) for p in pattern.pieces}
    pairs = label_pairs(label) if pairs is None else pairs

    def side_ok(x, options):
        return any(o[0] == x[0] and _overlap(seg[x[0]], x, o) >= MIN_OVERLAP for o in options)

    unsure = label_pairs({"seams": label.get("uncertain", [])})
    inferred = [
        (j.a.key, j.b.key, j.id)
        for j in inference.joins
        if not any((side_ok(j.a.key, oa) and side_ok(j.b.key, ob)) or (side_ok(j.a.key, ob) and side_ok(j.b.key, oa))
                   for oa, ob in unsure)
    ]

    matched, used = 0, set()
    missed = []
    for oa, ob in pairs:
        hit = None
        for k, (a, b, _) in enumerate(inferred):
            if k in used:
                continue
            if (side_ok(a, oa) and side_ok(b, ob)) or (side_ok(a, ob) and side_ok(b, oa)):
                hit = k
                break
        if hit is None:
            missed.append(f"{oa[0]} ~ {ob[0]}")
        else:
            used.add(hit)
            matched += 1
    extra = tuple(f"{a} ~ {b}" for k, (a, b, _) in enumerate(inferred) if k not in used)
    return Score(
        roles_right=len(truth_roles) - len(wrong),
        roles_total=len(truth_roles),
        seams_matched=matched,
        seams_labelled=len(pairs),
        seams_inferred=len(inferred),
        wrong_roles=wrong,
        missed=tuple(missed),
        extra=extra,
    )


def sidecar_pairs(path: str | Path) -> list[tuple[list, list]]:
    """The seams of a library sidecar projected onto the drawn pieces (copies merged)."""
    data = json.loads(Path(path).read_text(encoding="utf-8"))
    marks = {e["name"]: {m: v["vertex"] for m, v in e["marks"].items()} for e in data["pieces"]}
    pairs = set()
    for s in data["seams"]:
        ka, kb = ((e["piece"], marks[e["piece"]][e["start"]], marks[e["piece"]][e["end"]]) for e in (s["a"], s["b"]))
        pairs.add(tuple(sorted([ka, kb])))
    return [([a], [b]) for a, b in sorted(pairs)]


def load_labelled(label_path: str | Path, shared_dir: str | Path) -> tuple[Pattern, dict, list]:
    """``(pattern, label, pairs)`` of one label file; the pattern is read without any sidecar."""
    from ..io.dxf_aama import read_dxf

    label_path = Path(label_path)
    label = json.loads(label_path.read_text(encoding="utf-8"))
    repo = LABELS_DIR.parents[2]
    name = label["file"]
    path = repo / name if "/" in name else Path(shared_dir) / "aama" / name
    pattern, _ = read_dxf(path)
    if label.get("seams_from_sidecar"):
        pairs = sidecar_pairs(repo / label["seams_from_sidecar"])
    else:
        pairs = label_pairs(label)
    return pattern, label, pairs


def label_inference(pattern: Pattern, label: dict, pairs: list) -> BridgeInference:
    """The label as an inference (certain roles, the labelled seams), to draw it for review."""
    from ..pattern.model import Role
    from .model import Join, RoleGuess, Side
    from .orient import orient_piece

    joins = []
    for k, (oa, ob) in enumerate(pairs, start=1):
        (pa, sa, ea), (pb, sb, eb) = oa[0], ob[0]
        kind = "fold" if (pa, sa, ea) == (pb, sb, eb) and [pa, sa, ea] in label.get("folds", []) else "seam"
        joins.append(
            Join(id=f"label_{k}", a=Side(piece=pa, start=sa, end=ea), b=Side(piece=pb, start=sb, end=eb), kind=kind)
        )
    roles = {n: RoleGuess(role=Role(v["role"]), confidence=1.0) for n, v in label["pieces"].items()}
    return BridgeInference(
        roles=roles,
        orientations={p.name: orient_piece(p) for p in pattern.pieces},
        joins=tuple(joins),
        chosen=tuple(pattern.piece_names),
    )
