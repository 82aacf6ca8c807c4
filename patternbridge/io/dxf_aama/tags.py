"""The DXF tag stream: group codes and values, checked, grouped into blocks and entities.

This is the lowest layer of the reader (ezdxf's ``lldxf``): it knows nothing of
pattern pieces. It decodes the bytes, pairs group codes with values and checks
every tag once, so the layers above only meet well-formed numbers:

- a group code is an integer and every code has its value (no truncation);
- every value of a floating-point group (10-59, 110-149, 210-239, 1010-1059)
  is a finite number, and in BLOCKS and ENTITIES of sane magnitude (at most
  ``MAX_ABS_VALUE`` file units, 10 km in millimetres; HEADER may hold
  AutoCAD's 1e20 "no extents" markers): ``nan``, ``inf`` and numbers that
  overflow a double are refused with the line they are on;
- no value is longer than ``MAX_VALUE_CHARS`` characters (DXF R12 limits
  strings to 255; a longer one is a damaged or hostile file);
- sections and blocks are closed.

Bad input raises :class:`~patternbridge.errors.DXFFormatError` with one line
naming the file and the line of the file.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

from ...errors import DXFFormatError
from ...report import Report
from .layers import layer_number
from .text import decode

__all__ = ["MAX_ABS_VALUE", "MAX_BLOCKS", "MAX_VALUE_CHARS", "Block", "Entity", "parse_tags"]

MAX_ABS_VALUE = 1.0e7
"""Largest magnitude (file units) of a coordinate, height, angle or depth we accept."""
MAX_VALUE_CHARS = 1024
"""Longest tag value (characters) we accept; DXF R12 itself allows 255."""
MAX_BLOCKS = 20_000
"""Most BLOCK definitions in one file (the largest real nest has 255)."""


def _is_float_code(code: int) -> bool:
    return 10 <= code <= 59 or 110 <= code <= 149 or 210 <= code <= 239 or 1010 <= code <= 1059


@dataclass(slots=True)
class Entity:
    """One DXF entity: its type, layer, first value per group code and line."""

    type: str
    layer: int | None
    layer_name: str
    tags: dict[int, str]
    line: int  # 1-based line number of the entity's "0" tag
    vertices: list = field(default_factory=list)  # POLYLINE: [(x, y), ...]

    def f(self, code: int, default: float | None = 0.0) -> float | None:
        """Group ``code`` as a float (already checked finite by :func:`parse_tags`)."""
        v = self.tags.get(code)
        return default if v is None else float(v)

    @property
    def closed(self) -> bool:
        """POLYLINE flag 70 bit 1."""
        try:
            return bool(int(float(self.tags.get(70, "0"))) & 1)
        except ValueError:
            return False


@dataclass(slots=True)
class Block:
    """A BLOCK definition: its name, entities in file order and line."""

    name: str
    entities: list[Entity]
    line: int


def _tag_stream(path: Path, data: bytes) -> tuple[list[int], list[str]]:
    if data.startswith(b"AutoCAD Binary DXF"):
        raise DXFFormatError(f"{path}: binary DXF is not supported; export DXF-AAMA/ASTM as text (R12)")
    if b"\x00" in data[:4096]:
        raise DXFFormatError(f"{path}: not a text DXF (binary content near the start); export it again as text")
    lines = decode(data).replace("\r\n", "\n").replace("\r", "\n").split("\n")
    while lines and not lines[-1].strip():
        lines.pop()
    if len(lines) % 2:
        raise DXFFormatError(
            f"{path}: truncated DXF (ends after group code {lines[-1].strip()[:30]!r} on line {len(lines)} "
            "without its value); export the file again"
        )
    raw_codes = lines[0::2]
    codes: list[int] = []
    for k, c in enumerate(raw_codes):
        try:
            codes.append(int(c))
        except ValueError:
            raise DXFFormatError(
                f"{path}: corrupted DXF (line {2 * k + 1}: group code {c.strip()[:30]!r} is not an integer); "
                "export the file again"
            ) from None
    values = [v.strip() for v in lines[1::2]]
    _check_values(path, codes, values)
    return codes, values


def _check_values(path: Path, codes: list[int], values: list[str]) -> None:
    """Refuse over-long values and non-finite or absurd numbers, naming the line."""
    longest = max(range(len(values)), key=lambda k: len(values[k]), default=None)
    if longest is not None and len(values[longest]) > MAX_VALUE_CHARS:
        raise DXFFormatError(
            f"{path}: line {2 * longest + 2}: group {codes[longest]} value is {len(values[longest]):,} "
            f"characters long (at most {MAX_VALUE_CHARS}); the file is damaged, export it again"
        )
    section = ""
    for k, code in enumerate(codes):
        if code == 2 and k and codes[k - 1] == 0 and values[k - 1].upper() == "SECTION":
            section = values[k].upper()
        if not _is_float_code(code):
            continue
        try:
            x = float(values[k])
        except ValueError:
            raise DXFFormatError(
                f"{path}: corrupted DXF (line {2 * k + 2}: group {code} value {values[k][:30]!r} is not a "
                "number); export the file again"
            ) from None
        # HEADER and TABLES may hold AutoCAD's 1e20 "no extents" markers; only geometry must be of garment size
        if not math.isfinite(x) or (abs(x) > MAX_ABS_VALUE and section in ("BLOCKS", "ENTITIES")):
            what = "is not a finite number" if not math.isfinite(x) else f"exceeds {MAX_ABS_VALUE:g} file units"
            raise DXFFormatError(
                f"{path}: line {2 * k + 2}: group {code} value {values[k][:30]!r} {what}; the file is damaged, "
                "export it again"
            )


@dataclass(slots=True)
class _State:
    section: str | None = None
    sections_seen: list[str] = field(default_factory=list)
    block: Block | None = None
    poly: Entity | None = None
    saw_eof: bool = False


def parse_tags(path: Path, data: bytes, report: Report) -> tuple[list[Block], list[Entity]]:
    """Blocks (with their entities) and the ENTITIES section of a text DXF.

    POLYLINE vertices are attached to their POLYLINE, LWPOLYLINEs become
    POLYLINEs; HEADER, TABLES and other sections are skipped.

    Raises
    ------
    DXFFormatError
        Binary or truncated file, a bad group code, a non-finite, absurd or
        unreadable number, an over-long value, unclosed sections or blocks.
    """
    codes, values = _tag_stream(path, data)
    n = len(codes)
    starts = [k for k in range(n) if codes[k] == 0]
    if not starts:
        raise DXFFormatError(f"{path}: no DXF entities found (empty or not a DXF file)")
    blocks: list[Block] = []
    entities: list[Entity] = []
    st = _State()
    starts.append(n)
    for j in range(len(starts) - 1):
        s, e = starts[j], starts[j + 1]
        tags: dict[int, str] = {}
        for k in range(s + 1, e):
            tags.setdefault(codes[k], values[k])
        if _structure(path, st, values[s].upper(), tags, 2 * s + 1, blocks):
            if st.saw_eof:
                break
            continue
        if st.section not in ("BLOCKS", "ENTITIES"):
            continue
        _entity(st, values[s].upper(), tags, 2 * s + 1, codes[s + 1: e], values[s + 1: e],
                st.block.entities if st.block is not None else entities)
    _check_end(path, st, report, len(blocks))
    return blocks, entities


def _structure(path: Path, st: _State, kind: str, tags: dict[int, str], line: int, blocks: list[Block]) -> bool:
    """Handle SECTION/ENDSEC/EOF/BLOCK/ENDBLK; True when ``kind`` was one of them."""
    if kind == "SECTION":
        if st.section is not None:
            raise DXFFormatError(f"{path}: truncated or corrupted DXF (section {st.section} not closed before "
                                 f"the SECTION on line {line}); export the file again")
        st.section = tags.get(2, "").upper()
        st.sections_seen.append(st.section)
    elif kind == "ENDSEC":
        if st.block is not None:
            raise DXFFormatError(f"{path}: corrupted DXF (BLOCK {st.block.name[:60]!r} not closed by ENDBLK); "
                                 "export the file again")
        st.section, st.poly = None, None
    elif kind == "EOF":
        st.saw_eof = True
    elif kind == "BLOCK" and st.section in ("BLOCKS", "ENTITIES"):
        st.block, st.poly = Block(name=tags.get(2, ""), entities=[], line=line), None
    elif kind == "ENDBLK" and st.section in ("BLOCKS", "ENTITIES"):
        if st.block is not None:
            blocks.append(st.block)
            if len(blocks) > MAX_BLOCKS:
                raise DXFFormatError(f"{path}: more than {MAX_BLOCKS:,} BLOCKs (line {line}); not a pattern "
                                     "file a CAD system writes")
        st.block, st.poly = None, None
    else:
        return False
    return True


def _entity(st: _State, kind: str, tags: dict[int, str], line: int, codes: list[int], values: list[str],
            target: list[Entity]) -> None:
    if kind == "VERTEX":
        if st.poly is not None:
            st.poly.vertices.append((float(tags.get(10, "0")), float(tags.get(20, "0"))))
        return
    if kind == "SEQEND":
        st.poly = None
        return
    layer_name = tags.get(8, "")
    ent = Entity(type=kind, layer=layer_number(layer_name), layer_name=layer_name, tags=tags, line=line)
    st.poly = ent if kind == "POLYLINE" else None
    if kind == "LWPOLYLINE":
        xs = [float(v) for c, v in zip(codes, values, strict=True) if c == 10]
        ys = [float(v) for c, v in zip(codes, values, strict=True) if c == 20]
        ent.vertices = list(zip(xs, ys, strict=False))
        ent.type = "POLYLINE"
    target.append(ent)


def _check_end(path: Path, st: _State, report: Report, n_blocks: int) -> None:
    if st.section is not None or st.block is not None:
        what = f"section {st.section}" if st.section else "a BLOCK"
        raise DXFFormatError(f"{path}: truncated DXF ({what} not closed, no EOF); export the file again")
    if not st.saw_eof:
        if "ENTITIES" not in st.sections_seen:
            raise DXFFormatError(f"{path}: truncated DXF (no ENTITIES section and no EOF); export the file again")
        report.add("no-eof", "no EOF marker at the end of the file (sections are complete)", str(path.name))
    if "BLOCKS" not in st.sections_seen and "ENTITIES" not in st.sections_seen:
        raise DXFFormatError(f"{path}: no BLOCKS or ENTITIES section (empty or not a DXF-AAMA/ASTM file)")
