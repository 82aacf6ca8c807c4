"""The size chart a tailor's file is graded in, chosen from its own size labels, and the body of its sample size.

A pattern's ease is its girth minus the body girth of the size it is drawn in.
The file says which size that is (its sample size) and, by its labels, which
system the sizes belong to; the body of that size comes from the system's
control dimension and a chart of body measurements:

- **European women's numeric sizes** (labels even numbers, the smallest below
  40, the sample at most 46: ``26 … 52`` with sample ``36``): the bust girth
  is 84 cm at size 36 and grows 4 cm per size (2 numbers), the German size
  table's normal sizes 32–46 (size 36: bust 84; 40: 92; 44: 100); the other
  dimensions are read off the library's women's chart at that bust
  (:data:`~patternbridge.library.sizes.WOMEN`: EN 13402-3 intervals,
  Aldrich's *Metric Pattern Cutting for Women's Wear* proportions).
- **European men's numeric sizes** (labels even numbers from 40 up, the
  sample 42–64: ``42 … 70`` with sample ``50``): the size is half the chest
  girth (size 50: chest 100 cm); the other dimensions are read off the
  library's men's chart at that chest (:data:`~patternbridge.library.sizes.MEN`).
- **Anything else** (one size, letters S/M/L whose chest ranges the file does
  not state, labels that are the girth itself as the library's own DXFs
  write them): the reference body, the library men's sample size (chest 96).

**Head girth.** Neither library chart gives it, and it hardly changes with
the size: every system's body gets its adult mean, ``HEAD_GIRTH_CM`` (men
57 cm, women 55 cm, rounded means of the large adult anthropometric
surveys such as ANSUR II), which says whether a pullover's neck opening
goes over the head without stretching (:mod:`.fabric`).

A chart read at a girth outside its five sizes is extended linearly with its
own steps. A dimension the women's chart lacks (the outside leg, the inside
leg, the ankle) is the men's sample value in proportion to the height
(168 / 176 cm).

**Leg girths.** Both library charts give the thigh and the knee girth (the
men's also the ankle); neither gives the **calf**, which every system here
gains from the knee of the same size: the calf girth is the knee girth less
``CALF_UNDER_KNEE_CM`` (men 0, women 1 cm), so it grows with the knee's
0.8 cm per size. Standard body tables put the adult calf within about 2 cm
of the knee, and so do the shared characters as ``patternbridge measure``
measures them (calf − knee: E_average_male +1.9, B_slim_female −1.5,
F_tall_thin_elder −2.9, D_cartoon_child +0.3 cm; ``docs/measurements.md``).
Where on the leg each girth lies is :data:`LEG_LEVELS`, read off the
measurement definitions (``patternbridge.measure``): the knee point 40 % of
the way from the crotch to the ankle (60 % of the height from ankle to
crotch), the calf's largest girth about 30 % of the way from the knee to the
ankle (the shared characters measure it at 25–35 %), the ankle girth just
above the ankle bones (80–87 %).
"""

from __future__ import annotations

import enum
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from types import MappingProxyType

import numpy as np

from ..library.sizes import MEN, WOMEN, SizeChart

__all__ = [
    "CALF_UNDER_KNEE_CM",
    "HEAD_GIRTH_CM",
    "LEG_LEVELS",
    "REFERENCE_BODY_CM",
    "ChartChoice",
    "SizeSystem",
    "choose_chart",
]


class SizeSystem(enum.Enum):
    """The size system a file's labels belong to."""

    WOMEN_EU = "women_eu"
    MEN_EU = "men_eu"
    REFERENCE = "reference"


#: the adult mean head girth of each size system (module docstring: no chart states it)
HEAD_GIRTH_CM = MappingProxyType({"women": 55.0, "men": 57.0})

#: the calf girth under the knee girth of the same size, per library chart (module docstring: no chart states it)
CALF_UNDER_KNEE_CM = MappingProxyType({"men": 0.0, "women": 1.0})

#: where each leg girth is measured: its share of the inside leg, from the crotch (0) down to the ankle (1); the
#: calf 30 % and the ankle girth 83 % of the way from the knee (0.40) to the ankle (module docstring)
LEG_LEVELS = MappingProxyType(
    {"knee_girth_right": 0.40, "calf_girth_right": 0.40 + 0.60 * 0.30, "ankle_girth_right": 0.40 + 0.60 * 0.83}
)


def with_leg_girths(body: Mapping[str, float], chart: SizeChart) -> dict[str, float]:
    """``body`` with the calf girth of :data:`CALF_UNDER_KNEE_CM` and the head girth added (it keeps those it has)."""
    out = dict(body)
    out.setdefault("head_girth", HEAD_GIRTH_CM[chart.name])
    if "knee_girth_right" in out:
        out.setdefault("calf_girth_right", out["knee_girth_right"] - CALF_UNDER_KNEE_CM[chart.name])
    return out


#: the body of the library men's sample size (chest 96): the body a file in no recognised size system is read against
REFERENCE_BODY_CM = MappingProxyType(with_leg_girths(MEN.body(MEN.sample_size), MEN))

#: women's European numeric sizes: bust girth at size 36 and per size step (2 numbers)
WOMEN_BUST_AT_36_CM = 84.0
WOMEN_BUST_PER_SIZE_CM = 4.0


@dataclass(frozen=True, slots=True, kw_only=True)
class ChartChoice:
    """The size system chosen for a file, its sample size and the body of that size (cm).

    why : the evidence, one line (written to the sidecar and the summary)
    """

    system: SizeSystem
    sample_size: str
    body_cm: Mapping[str, float] = field(default_factory=dict)
    why: str = ""

    def __post_init__(self) -> None:
        object.__setattr__(self, "body_cm", MappingProxyType(dict(self.body_cm)))

    def to_dict(self) -> dict:
        """The sidecar's ``size_chart`` entry."""
        return {
            "system": self.system.value,
            "sample_size": self.sample_size,
            "why": self.why,
            "body_cm": {k: round(float(v), 2) for k, v in sorted(self.body_cm.items())},
        }


def body_at(chart: SizeChart, key: str, value: float) -> dict[str, float]:
    """Every dimension of ``chart`` at ``chart.dims[key] == value``, linear in ``key`` (extended past its ends)."""
    x = chart.dims[key]
    lo = int(np.clip(np.searchsorted(x, value) - 1, 0, len(x) - 2))
    t = (value - x[lo]) / (x[lo + 1] - x[lo])
    return {k: float(v[lo] + t * (v[lo + 1] - v[lo])) for k, v in chart.dims.items()}


def _even_numbers(sizes: Sequence[str]) -> np.ndarray | None:
    try:
        values = np.array([float(s) for s in sizes])
    except ValueError:
        return None
    if not len(values) or np.any(values != np.round(values)) or np.any(values % 2):
        return None
    return values


def choose_chart(sizes: Sequence[str], sample_size: str) -> ChartChoice:
    """The size system of a file with size labels ``sizes`` and its sample size's body."""
    values = _even_numbers(tuple(sizes) or (sample_size,))
    sample = _even_numbers((sample_size,))
    label = f"sizes {sizes[0]} to {sizes[-1]}, sample {sample_size}" if len(sizes) > 1 else f"size {sample_size}"
    if values is not None and sample is not None and 20 <= values.min() and values.max() <= 80:
        s = float(sample[0])
        if values.min() < 40 and s <= 46:
            bust = WOMEN_BUST_AT_36_CM + WOMEN_BUST_PER_SIZE_CM * (s - 36) / 2
            body = body_at(WOMEN, "bust_girth", bust)
            ratio = WOMEN.body(WOMEN.sample_size)["height"] / MEN.body(MEN.sample_size)["height"]
            body = with_leg_girths(body, WOMEN)
            body.update({k: v * ratio for k, v in REFERENCE_BODY_CM.items() if k not in body})
            why = f"{label}: European women's numeric sizes (size 36 = bust 84 cm); bust {bust:g} cm"
            return ChartChoice(system=SizeSystem.WOMEN_EU, sample_size=sample_size, body_cm=body, why=why)
        if values.min() >= 40 and 42 <= s <= 64:
            chest = 2.0 * s
            body = with_leg_girths(body_at(MEN, "chest_girth", chest), MEN)
            why = f"{label}: European men's numeric sizes (half the chest girth); chest {chest:g} cm"
            return ChartChoice(system=SizeSystem.MEN_EU, sample_size=sample_size, body_cm=body, why=why)
    why = f"{label}: no size system recognised; the library men's sample body (chest 96 cm)"
    return ChartChoice(system=SizeSystem.REFERENCE, sample_size=sample_size, body_cm=REFERENCE_BODY_CM, why=why)
