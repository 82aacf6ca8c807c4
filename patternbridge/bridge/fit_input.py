"""The pattern ``fit`` grades, from whatever garment argument the user gives.

A library name or a canonical JSON is used as it is. A DXF uses the bridge
sidecar beside it (``<stem>.seams.json``) when there is one; otherwise the
bridge data are inferred (:func:`~.infer.infer_bridge`), and the inferred
sidecar and its review picture are written into the output folder so the user
can correct the sidecar and run again. When the sidecar names the pieces of
its default garment (``garment_pieces``), only those are fitted and draped:
a file holding alternatives (three leg lengths, two sleeves) is one garment on
the body, and the graded DXF sent back holds that garment.
"""

from __future__ import annotations

import dataclasses
import json
import os
from dataclasses import dataclass
from pathlib import Path

from ..atomic import write_bytes, write_text
from ..io.json_file import read_json
from ..io.load import load_pattern
from ..library.sidecar import apply_sidecar, sidecar_beside
from ..pattern.model import Pattern
from ..report import Report
from .infer import infer_bridge
from .picture import review_png
from .sidecar import inference_sidecar
from .summary import summary_line

__all__ = ["FitInput", "garment_only", "pattern_for_fit"]

_SIDECAR_HINT = "give a sidecar written by 'patternbridge seams infer' or 'library export'"


@dataclass(frozen=True, slots=True, kw_only=True)
class FitInput:
    """The pattern to fit and where its bridge data came from.

    sidecar : the sidecar applied (beside the DXF, or the inferred one in the
        output folder), None for a library garment or JSON
    picture : the review picture written for an inferred sidecar
    summary : one line (roles, seams, alternatives, lowest confidence) when inferred
    """

    pattern: Pattern
    report: Report
    sidecar: Path | None = None
    picture: Path | None = None
    summary: str | None = None


def garment_only(pattern: Pattern, sidecar: str | os.PathLike) -> Pattern:
    """``pattern`` cut down to the sidecar's ``garment_pieces``, with the seams and links among them."""
    names = read_json(sidecar, hint=_SIDECAR_HINT, what="sidecar file").get("garment_pieces")
    if not names:
        return pattern
    keep = set(names)
    return dataclasses.replace(
        pattern,
        pieces=tuple(p for p in pattern.pieces if p.name in keep),
        seams=tuple(s for s in pattern.seams if s.a.piece in keep and s.b.piece in keep),
        measurements=tuple(m for m in pattern.measurements if all(g.piece in keep for g in m.legs)),
    )


def pattern_for_fit(
    garment: str | os.PathLike,
    out_dir: str | os.PathLike,
    *,
    rul: str | os.PathLike | None = None,
    units: str | None = None,
) -> FitInput:
    """Load ``garment`` with its bridge data, inferring them for a DXF without a sidecar.

    Parameters
    ----------
    garment : library name, canonical ``.json`` or DXF-AAMA/ASTM file
    out_dir : folder where an inferred ``<stem>.seams.json`` and
        ``<stem>.bridge.png`` are written (created if needed)

    Raises
    ------
    InputError
        Unreadable garment or sidecar.
    """
    pattern, report = load_pattern(garment, rul=rul, units=units)
    path = Path(garment)
    if not (path.is_file() and path.suffix.lower() == ".dxf"):
        return FitInput(pattern=pattern, report=report)
    beside = sidecar_beside(path)
    if beside is not None:
        return FitInput(pattern=garment_only(apply_sidecar(pattern, beside), beside), report=report, sidecar=beside)
    inference = infer_bridge(pattern)
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    sidecar = out / f"{path.stem}.seams.json"
    picture = out / f"{path.stem}.bridge.png"
    write_text(sidecar, json.dumps(inference_sidecar(pattern, inference), indent=1, ensure_ascii=False) + "\n")
    write_bytes(picture, review_png(pattern, inference))
    return FitInput(
        pattern=garment_only(apply_sidecar(pattern, sidecar), sidecar),
        report=report,
        sidecar=sidecar,
        picture=picture,
        summary=summary_line(pattern, inference),
    )
