"""Body-size charts the library garments are drafted from (cm).

Two charts, five sizes each, keyed by the measurement ids of
``formats/measurements.md`` (plus a few drafting-only dimensions such as
``scye_depth`` and ``body_rise``). The control dimensions (chest/bust, waist,
hip, height) follow the EN 13402-3 body-dimension intervals (4 cm girth steps
for chest/bust and hip); the secondary dimensions and their per-size
increments follow the standard body measurement tables in Aldrich, *Metric
Pattern Cutting for Menswear* and *Metric Pattern Cutting for Women's Wear*.
Sources and the full table are in ``docs/library.md``.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType

import numpy as np

__all__ = ["MEN", "WOMEN", "SizeChart"]


@dataclass(frozen=True, slots=True, kw_only=True, eq=False)
class SizeChart:
    """A body-size chart: one row of body dimensions per size.

    sizes : size labels in grading order
    sample_size : the size the pattern is drafted and shown in
    dims : measurement id -> (n_sizes,) float64, cm
    source : citation
    """

    name: str
    sizes: tuple[str, ...]
    sample_size: str
    dims: Mapping[str, np.ndarray] = field(default_factory=dict)
    source: str = ""

    def __post_init__(self) -> None:
        table = {}
        for k, v in dict(self.dims).items():
            arr = np.asarray(v, dtype=np.float64)
            if arr.shape != (len(self.sizes),):
                raise ValueError(
                    f"size chart {self.name}: {k} has shape {arr.shape}, expected ({len(self.sizes)},)"
                )
            arr.flags.writeable = False
            table[k] = arr
        object.__setattr__(self, "dims", MappingProxyType(table))

    def body(self, size: str) -> dict[str, float]:
        """Body dimensions (cm) of one size."""
        i = self.sizes.index(size)
        return {k: float(v[i]) for k, v in self.dims.items()}

    def relabel(self, key: str, fmt: str = "{:g}") -> SizeChart:
        """The same chart with sizes labelled by dimension ``key`` (e.g. waist girth)."""
        labels = tuple(fmt.format(v) for v in self.dims[key])
        sample = labels[self.sizes.index(self.sample_size)]
        return SizeChart(
            name=self.name,
            sizes=labels,
            sample_size=sample,
            dims=self.dims,
            source=self.source,
        )


def _steps(
    sample: float, step: float, n_below: int = 2, n_above: int = 2
) -> np.ndarray:
    return sample + step * np.arange(-n_below, n_above + 1, dtype=np.float64)


MEN = SizeChart(
    name="men",
    sizes=("88", "92", "96", "100", "104"),
    sample_size="96",
    source="EN 13402-3:2017 control dimensions (chest girth, 4 cm steps, height 176); "
    "secondary dimensions after Aldrich, Metric Pattern Cutting for Menswear (5th ed., 2011), "
    "standard body measurements",
    dims={
        "height": _steps(176.0, 0.0),
        "stature": _steps(176.0, 0.0),
        "chest_girth": _steps(96.0, 4.0),
        "waist_girth": _steps(84.0, 4.0),
        "hip_girth": _steps(100.0, 4.0),
        "neck_girth": _steps(39.0, 1.0),
        "back_width": _steps(39.0, 1.0),
        "shoulder_width": _steps(45.0, 1.0),
        "shoulder_length_right": _steps(15.6, 0.3),
        "back_length": _steps(45.0, 0.4),
        "front_length": _steps(37.5, 0.4),
        "scye_depth": _steps(22.6, 0.4),
        # the armhole line to the waist down the side: back length − scye depth
        "side_length": _steps(22.4, 0.0),
        "arm_length_right": _steps(64.0, 0.6),
        "upper_arm_girth_right": _steps(31.8, 1.2),
        "wrist_girth_right": _steps(17.4, 0.4),
        "waist_to_hip": _steps(20.4, 0.2),
        "body_rise": _steps(27.0, 0.4),
        "crotch_length": _steps(70.0, 2.0),
        "inside_leg_right": _steps(78.0, 0.0),
        "outside_leg_right": _steps(105.0, 0.4),
        "thigh_girth_right": _steps(57.0, 2.0),
        "knee_girth_right": _steps(38.0, 0.8),
        "ankle_girth_right": _steps(23.6, 0.6),
    },
)

WOMEN = SizeChart(
    name="women",
    sizes=("80", "84", "88", "92", "96"),
    sample_size="88",
    source="EN 13402-3:2017 control dimensions (bust girth, 4 cm steps, height 168); "
    "secondary dimensions after Aldrich, Metric Pattern Cutting for Women's Wear (6th ed., 2015), "
    "standard body measurements",
    dims={
        "height": _steps(168.0, 0.0),
        "stature": _steps(168.0, 0.0),
        "bust_girth": _steps(88.0, 4.0),
        "chest_girth": _steps(88.0, 4.0),
        "waist_girth": _steps(70.0, 4.0),
        "hip_girth": _steps(96.0, 4.0),
        "neck_girth": _steps(36.0, 0.6),
        "back_width": _steps(34.4, 0.6),
        "shoulder_width": _steps(39.0, 0.8),
        "shoulder_length_right": _steps(12.2, 0.2),
        "back_length": _steps(41.0, 0.4),
        "front_length": _steps(35.0, 0.5),
        "scye_depth": _steps(21.0, 0.4),
        "bust_span": _steps(18.5, 0.5),
        "arm_length_right": _steps(58.4, 0.4),
        "upper_arm_girth_right": _steps(28.4, 1.2),
        "wrist_girth_right": _steps(16.0, 0.5),
        "waist_to_hip": _steps(20.6, 0.0),
        "waist_to_knee": _steps(58.5, 0.0),
        "body_rise": _steps(28.0, 0.4),
        "thigh_girth_right": _steps(55.0, 2.4),
        "knee_girth_right": _steps(36.0, 0.8),
    },
)
