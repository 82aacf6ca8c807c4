"""One line per garment: roles found, seams, alternatives chosen, lowest confidence."""

from __future__ import annotations

from collections import Counter

from ..pattern.model import Pattern
from .band_spans import split_bands
from .model import BridgeInference
from .size_chart import choose_chart

__all__ = ["summary_line"]


def summary_line(pattern: Pattern, inference: BridgeInference) -> str:
    """``style: 2 front, 2 back, … | 14 seams | alternatives: … | sizes: … | lowest confidence 0.42``.

    Seams are counted as the sidecar writes them (bands split by the opening's ranges).
    """
    pattern, inference, _ = split_bands(pattern, inference)
    roles = Counter(inference.roles[n].role.value for n in inference.chosen)
    role_text = ", ".join(f"{k} {r}" if k > 1 else r for r, k in sorted(roles.items()))
    kinds = Counter(j.kind for j in inference.joins)
    seam_text = f"{len(inference.joins)} seams (" + ", ".join(f"{v} {k}" for k, v in sorted(kinds.items())) + ")"
    alts = "; ".join(
        " | ".join("+".join(o) for o in group) + f" -> {'+'.join(group[0])}" for group in inference.alternatives
    )
    return (
        f"{pattern.style}: {role_text} | {seam_text} | alternatives: {alts or 'none'}"
        f" | {choose_chart(pattern.sizes, pattern.sample_size).why}"
        f" | lowest confidence {inference.lowest_confidence:.2f} | {inference.seconds:.2f} s"
    )
