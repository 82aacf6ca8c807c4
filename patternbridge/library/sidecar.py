"""Bridge-data sidecars: the seams, marks, landmarks, measurements and placement
that a DXF-AAMA file cannot carry, as a small JSON file beside it.

``write_sidecar`` writes it (``patternbridge library export`` and ``seams
infer`` do); a user confirms or edits it; ``apply_sidecar`` puts it back onto
a pattern read from the DXF. Marks are stored as vertex indices *and* the
sample-size coordinates of the outline vertex, so a file whose outline starts
at another vertex or was re-saved by a CAD system is re-matched by position.
The format is documented in ``formats/bridge.md``.
"""

from __future__ import annotations

import json
import os
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np

from ..atomic import write_text
from ..errors import InputError
from ..pattern.insert import insert_vertices, segment_at
from ..pattern.json import (
    fabric_to_dict,
    measurement_link_from_dict,
    measurement_link_to_dict,
    placement_to_dict,
    seam_from_dict,
    seam_to_dict,
)
from ..pattern.json_check import check_sidecar_dict
from ..pattern.model import FabricClass, Pattern, Placement

__all__ = [
    "SIDECAR_FORMAT",
    "apply_sidecar",
    "insert_marked_vertices",
    "read_sidecar",
    "sidecar_beside",
    "sidecar_dict",
    "write_sidecar",
]

SIDECAR_FORMAT = "patternbridge.bridge"
SIDECAR_VERSION = "1.0"
#: how far (cm) a mark's stored position may be from the outline vertex it names
MATCH_TOL_CM = 0.05


def sidecar_dict(pattern: Pattern, *, proposals: list[dict[str, Any]] | None = None) -> dict[str, Any]:
    """The sidecar content of ``pattern`` as a JSON-ready dict.

    proposals : extra seam proposals (from ``seams infer``) written with their
        confidence and ``"status": "proposed"``.
    """
    pieces = []
    for p in pattern.pieces:
        entry: dict[str, Any] = {
            "name": p.name,
            "n_vertices": p.n_vertices,
            **({"role": str(p.role)} if p.role is not None else {}),
            **({"fabric_class": str(p.fabric_class)} if p.fabric_class is not None else {}),
            "marks": {m: {"vertex": i, "xy": [round(float(v), 4) for v in p.outline[i]]} for m, i in p.marks.items()},
            "landmarks": dict(p.landmarks),
            "placement": placement_to_dict(p.placement),
        }
        pieces.append(entry)
    seams = [{**seam_to_dict(s), "status": "confirmed"} for s in pattern.seams]
    seams.extend(proposals or [])
    return {
        "format": SIDECAR_FORMAT,
        "format_version": SIDECAR_VERSION,
        "length_unit": "cm",
        "style": pattern.style,
        "description": pattern.description,
        "sample_size": pattern.sample_size,
        "pieces": pieces,
        "seams": seams,
        "measurements": [measurement_link_to_dict(m) for m in pattern.measurements],
        **fabric_to_dict(pattern),
    }


def write_sidecar(
    pattern: Pattern,
    path: str | os.PathLike,
    *,
    proposals: list[dict[str, Any]] | None = None,
) -> Path:
    """Write the bridge-data sidecar of ``pattern`` to ``path`` atomically."""
    text = json.dumps(sidecar_dict(pattern, proposals=proposals), indent=1, ensure_ascii=False) + "\n"
    return write_text(path, text)


def sidecar_beside(dxf: str | os.PathLike) -> Path | None:
    """The bridge-data sidecar that goes with a DXF, or None.

    Looks for ``<stem>.seams.json`` (any case of ``.seams``) beside the DXF, then
    the same without an ``_aama``/``_astm`` flavour suffix on the stem (the
    library ships ``shirt_aama.dxf`` and ``shirt_astm.dxf`` with one
    ``shirt.seams.json``).
    """
    dxf = Path(dxf)
    stems = [dxf.stem]
    for flavour in ("_aama", "_astm"):
        if dxf.stem.lower().endswith(flavour):
            stems.append(dxf.stem[: -len(flavour)])
    for stem in stems:
        for name in (f"{stem}.seams.json", f"{stem}.SEAMS.json"):
            if (dxf.parent / name).is_file():
                return dxf.parent / name
    return None


def read_sidecar(path: str | os.PathLike) -> dict[str, Any]:
    """Read a sidecar file as a dict.

    Raises
    ------
    InputError
        Missing file, invalid JSON, or not a PatternBridge bridge sidecar.
    """
    from ..io.json_file import read_json

    path = Path(path)
    data = read_json(
        path, hint="give a sidecar written by 'patternbridge seams infer' or 'library export'", what="sidecar file"
    )
    if not isinstance(data, dict) or data.get("format") != SIDECAR_FORMAT:
        got = data.get("format") if isinstance(data, dict) else type(data).__name__
        raise InputError(
            f"{path}: not a bridge-data sidecar (format {got!r}, expected {SIDECAR_FORMAT!r}); "
            "give a *.seams.json sidecar"
        )
    try:
        check_sidecar_dict(data)
    except ValueError as exc:
        raise InputError(f"{path}: malformed sidecar ({exc}); see formats/bridge.md") from None
    return data


def insert_marked_vertices(piece, entry: dict[str, Any]):
    """``piece`` with a vertex at each mark of ``entry`` flagged ``insert`` that is not a vertex yet.

    A band's joints placed in proportion to its opening fall between the band's
    vertices; the sidecar stores them with ``"insert": true`` and their
    cut-line position, and they become vertices here (:mod:`..pattern.insert`).
    """
    for m in entry.get("marks", {}).values():
        if isinstance(m, dict) and m.get("insert") and m.get("xy") is not None:
            at = segment_at(piece.outline, np.asarray(m["xy"], dtype=np.float64), MATCH_TOL_CM)
            if at is not None:
                piece, _ = insert_vertices(piece, [at])
    return piece


def _match_marks(path: Path, piece, entry: dict[str, Any]) -> dict[str, int]:
    marks = {}
    outline = piece.outline
    for name, m in entry.get("marks", {}).items():
        if isinstance(m, int):
            m = {"vertex": m}
        vertex = int(m["vertex"])
        xy = m.get("xy")
        if xy is not None:
            xy = np.asarray(xy, dtype=np.float64)
            if not (0 <= vertex < len(outline)) or np.hypot(*(outline[vertex] - xy)) > MATCH_TOL_CM:
                dist = np.hypot(*(outline - xy).T)
                vertex = int(np.argmin(dist))
                if dist[vertex] > MATCH_TOL_CM:
                    raise InputError(
                        f"{path}: mark {name!r} of piece {piece.name!r} at {xy.tolist()} is "
                        f"{dist[vertex]:.2f} cm from the nearest outline vertex; the sidecar belongs to "
                        "another version of the pattern, re-run 'patternbridge seams infer'"
                    )
        if not 0 <= vertex < len(outline):
            raise InputError(
                f"{path}: mark {name!r} of piece {piece.name!r} is vertex {vertex}, the outline "
                f"has {len(outline)}; fix the sidecar"
            )
        marks[name] = vertex
    return marks


def _piece_entries(path: Path, data: dict[str, Any], names: set[str]) -> dict[str, dict[str, Any]]:
    """The sidecar's piece entries by name; each must name a piece of the pattern."""
    entries = {}
    for entry in data.get("pieces", []):
        if entry.get("name") not in names:
            raise InputError(
                f"{path}: piece {entry.get('name')!r} is not in the pattern (pieces: {sorted(names)}); fix the sidecar"
            )
        entries[entry["name"]] = entry
    return entries


def _with_entry(path: Path, piece, entry: dict[str, Any]):
    """``piece`` with the marks, landmarks, placement, role and fabric class of its sidecar entry."""
    piece = insert_marked_vertices(piece, entry)
    marks = _match_marks(path, piece, entry)
    pl = entry.get("placement")
    return replace(
        piece,
        marks=marks,
        landmarks=entry.get("landmarks", {}),
        placement=None if pl is None else Placement(**pl),
        role=entry.get("role", piece.role),
        role_confidence=entry.get("role_confidence", piece.role_confidence),
        fabric_class=entry.get("fabric_class", piece.fabric_class),
    )


def _applied_seams(data: dict[str, Any], confirmed_only: bool) -> list:
    """The sidecar's seams to apply: not bands, and only confirmed ones when ``confirmed_only``."""
    seams = []
    for s in data.get("seams", []):
        status = s.get("status", "confirmed")
        if status == "band" or (confirmed_only and status != "confirmed"):
            continue
        seams.append(seam_from_dict(s))
    return seams


def _check_seams(path: Path, seams: list, pattern: Pattern) -> None:
    """Every seam end must name a piece of ``pattern`` and marks that piece has."""
    names = set(pattern.piece_names)
    for s in seams:
        for e in (s.a, s.b):
            if e.piece not in names:
                raise InputError(f"{path}: seam {s.id!r} names piece {e.piece!r}, not in the pattern; fix the sidecar")
            piece = pattern.piece(e.piece)
            for m in (e.start, e.end):
                if m not in piece.marks:
                    raise InputError(
                        f"{path}: seam {s.id!r} names mark {m!r} that piece {e.piece!r} does not "
                        "have; add it under the piece's marks"
                    )


def _check_links(path: Path, links: tuple, pattern: Pattern) -> None:
    """Every leg of every measurement link must name a piece of ``pattern`` and two of its marks."""
    names = set(pattern.piece_names)
    for m in links:
        for g in m.legs:
            if (
                g.piece not in names
                or g.start not in pattern.piece(g.piece).marks
                or g.end not in pattern.piece(g.piece).marks
            ):
                raise InputError(
                    f"{path}: measurement {m.id!r} leg {g.piece}:{g.start}-{g.end} names an "
                    "unknown piece or mark; fix the sidecar"
                )


def _fabric_class(path: Path, data: dict[str, Any], default: FabricClass) -> FabricClass:
    try:
        return FabricClass(data.get("fabric_class", default))
    except ValueError:
        raise InputError(
            f"{path}: fabric_class {data.get('fabric_class')!r} is none of "
            f"{[str(f) for f in FabricClass]}; fix the sidecar"
        ) from None


def apply_sidecar(pattern: Pattern, path: str | os.PathLike, *, confirmed_only: bool = False) -> Pattern:
    """Return ``pattern`` with the bridge data of the sidecar at ``path``.

    Marks, landmarks, placement and role replace the pieces' own; seams and
    measurement links replace the pattern's. Seams with ``"status":
    "proposed"`` are applied too unless ``confirmed_only``; ``"status": "band"``
    entries (a band along an opening of several ranges) are not applied.

    Raises
    ------
    InputError
        When the sidecar names a piece or mark the pattern does not have, or
        its marks do not sit on the outline.
    """
    path = Path(path)
    data = read_sidecar(path)
    entries = _piece_entries(path, data, set(pattern.piece_names))
    try:
        pieces = [p if p.name not in entries else _with_entry(path, p, entries[p.name]) for p in pattern.pieces]
        out = replace(pattern, pieces=tuple(pieces))
        seams = _applied_seams(data, confirmed_only)
        links = tuple(measurement_link_from_dict(m) for m in data.get("measurements", []))
    except (KeyError, TypeError, ValueError) as exc:
        raise InputError(f"{path}: malformed sidecar ({exc}); see formats/bridge.md") from None
    _check_seams(path, seams, out)
    _check_links(path, links, out)
    return replace(
        out,
        seams=tuple(seams),
        measurements=links,
        description=data.get("description") or out.description,
        fabric_class=_fabric_class(path, data, out.fabric_class),
        fabric_why=data.get("fabric_why", out.fabric_why) if "fabric_class" in data else out.fabric_why,
    )
