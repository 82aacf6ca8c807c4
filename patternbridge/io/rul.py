"""``.RUL`` grade-rule tables (ASTM D6673 / AAMA): reader and writer.

A ``.RUL`` file is a header (any version line, ``UNITS``, ``GRADE RULE TABLE``,
``NUMBER OF SIZES``, ``SIZE LIST``, ``SAMPLE SIZE`` in any order) followed by
``RULE: DELTA <id>`` blocks, each holding one cumulative ``dx, dy`` pair per
size in size-list order, wrapped over any number of lines, and ``END``.

The reader pairs the numbers after each ``RULE: DELTA`` two by two, so every
variant met in real files parses the same way: a comma between dx and dy or
none, one to four (or any number of) pairs per line, a whole rule on the
``RULE:`` line itself, CRLF or LF. It checks that each rule has one pair per
size and that the sample-size column is zero. Values are converted to cm
(METRIC files are mm, ENGLISH files inches).
"""

from __future__ import annotations

import datetime as _dt
import os
import re
from pathlib import Path

import numpy as np

from ..atomic import write_text
from ..errors import InputError, RULFormatError, UnitsError
from ..pattern.model import Flavor, GradeRuleTable, Units
from ..report import Report
from ..units import from_cm, to_cm

__all__ = ["creation_time", "declared_units", "format_rul", "parse_rul", "read_rul", "rule_sort_key", "write_rul"]

_NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")
_RULE = re.compile(r"RULE\s*:\s*DELTA\s+([^\s,]+)", re.IGNORECASE)
_END = re.compile(r"^\s*END\s*$", re.IGNORECASE | re.MULTILINE)
_HEADER = re.compile(r"^\s*([A-Za-z][A-Za-z /]*?)\s*:(.*)$")
_VERSION_LINE = {
    Flavor.ASTM: "ASTM/D13Proposal 1 Version: D 6673-04",  # AccuMark 17.1, Richpeace, Boke
    Flavor.AAMA: "ANSI/AAMA VERSION: 1.0.0",  # AccuMark AAMA and Optitex
}
_MAX_DELTA = 1.0e7  # file units, as for DXF coordinates
_SAMPLE_ZERO_TOL = 1e-6  # file units; the sample column is written as 0.0000


def _decode(data: bytes) -> str:
    for enc in ("utf-8", "cp1252"):
        try:
            return data.decode(enc)
        except UnicodeDecodeError:
            continue
    return data.decode("latin-1")


def _units(value: str | Units | None) -> Units | None:
    if value is None:
        return None
    if isinstance(value, Units):
        return value
    v = str(value).strip().upper()
    return {"METRIC": Units.METRIC, "MM": Units.METRIC, "ENGLISH": Units.ENGLISH, "IN": Units.ENGLISH,
            "INCH": Units.ENGLISH}.get(v)


FIXED_DATE = _dt.datetime(1980, 1, 1, 0, 0)
"""The creation date written when neither ``SOURCE_DATE_EPOCH`` nor the source gives one."""
_SOURCE_DATE = re.compile(r"^\s*(\d{1,2})[-/.](\d{1,2})[-/.](\d{4})(?:\s+(\d{1,2}):(\d{1,2}))?")


def creation_time(source_created: str = "") -> _dt.datetime:
    """The creation date and time to write into a DXF or RUL: never the clock.

    ``SOURCE_DATE_EPOCH`` (seconds since 1970, UTC) when set, as reproducible
    builds define it; otherwise the source file's own ``dd-mm-yyyy hh:mm``;
    otherwise :data:`FIXED_DATE`. The same inputs give the same bytes.

    Examples
    --------
    >>> creation_time("12-12-2017 14:33") if "SOURCE_DATE_EPOCH" not in os.environ else None
    datetime.datetime(2017, 12, 12, 14, 33)
    """
    epoch = os.environ.get("SOURCE_DATE_EPOCH", "").strip()
    if epoch:
        try:
            return _dt.datetime.fromtimestamp(int(epoch), _dt.timezone.utc).replace(tzinfo=None)
        except (ValueError, OverflowError, OSError):
            raise InputError(f"SOURCE_DATE_EPOCH={epoch[:30]!r} is not a number of seconds since "
                                      "1970; unset it or give an integer") from None
    m = _SOURCE_DATE.match(source_created or "")
    if m:
        day, month, year, hour, minute = (int(g) if g else 0 for g in m.groups())
        try:
            return _dt.datetime(year, month, day, hour, minute)
        except ValueError:
            pass
    return FIXED_DATE


def declared_units(path: str | os.PathLike) -> Units | None:
    """The units a ``.RUL`` file's ``UNITS:`` line declares (``None`` when absent or unknown)."""
    try:
        text = _decode(Path(path).read_bytes()[:4096])
    except OSError:
        return None
    m = re.search(r"^\s*UNITS\s*:(.*)$", text, re.IGNORECASE | re.MULTILINE)
    return _units(m.group(1)) if m else None


def rule_sort_key(rule: str) -> tuple:
    """Sort key putting integer ids in numeric order, then the others by name."""
    try:
        return (0, int(rule), "")
    except ValueError:
        return (1, 0, rule)


def parse_rul(
    text: str, *, source: str = "<rul>", units: str | Units | None = None
) -> tuple[GradeRuleTable, Report]:
    """Parse the text of a ``.RUL`` file.

    Parameters
    ----------
    text : the file's text (CRLF or LF)
    source : file name used in messages
    units : override the file's ``UNITS:`` line (``METRIC``/``ENGLISH``)

    Returns
    -------
    (GradeRuleTable, Report)
        Deltas in cm, one ``(n_sizes, 2)`` array per rule id, sample row zero.

    Raises
    ------
    RULFormatError
        No ``RULE: DELTA`` block, no size list, a size count that disagrees with
        ``NUMBER OF SIZES``, a sample size outside the size list, a rule with the
        wrong number of values, a duplicate rule id, a non-zero sample column.
    UnitsError
        Unknown ``UNITS:`` and no override.
    """
    report = Report()
    text = text.replace("\r\n", "\n").replace("\r", "\n").lstrip("\ufeff")
    first = _RULE.search(text)
    if first is None:
        end = _END.search(text)
        if end is None or not re.search(r"^\s*SIZE LIST\s*:", text[: end.start()], re.IGNORECASE | re.MULTILINE):
            raise RULFormatError(f"{source}: no 'RULE: DELTA' block found (not a .RUL grade-rule table); "
                                 "give the .RUL exported with the DXF")
        first = end  # a header and END: a table without rules (a pattern that does not grade)
        report.add("rul-no-rules", "the table holds no rules; every point keeps its sample position", source)
    header, sizes, sample = _header(text[: first.start()], source, report)
    unit = _units(units)
    if unit is None:
        if units is not None:
            raise UnitsError(f"{source}: unknown units override {units!r}; use METRIC or ENGLISH")
        declared = header.get("UNITS")
        unit = _units(declared) if declared is not None else None
        if unit is None:
            if declared is None:
                raise UnitsError(f"{source}: no 'UNITS:' line; give the units (METRIC or ENGLISH)")
            raise UnitsError(f"{source}: unknown units {declared!r}; expected METRIC or ENGLISH")
    body = text[first.start():]
    end = _END.search(body)
    if end is None:
        report.add("rul-no-end", "no END line (file may be truncated); read up to the end of the file", source)
    else:
        tail = body[end.end():].strip()
        body = body[: end.start()]
        if tail:
            report.add("rul-after-end", "text after END ignored", source)
    deltas = _deltas(body, sizes, sample, unit, source)
    table = GradeRuleTable(name=header.get("GRADE RULE TABLE", ""), sizes=sizes, sample_size=sample,
                           deltas=deltas)
    return table, report


def _header(text: str, source: str, report: Report) -> tuple[dict[str, str], tuple[str, ...], str]:
    """Header keys, size list and sample size of the text before the first rule (checked)."""
    header: dict[str, str] = {}
    version = ""
    for line in text.split("\n"):
        if not line.strip():
            continue
        m = _HEADER.match(line)
        key = " ".join(m.group(1).upper().split()) if m else ""
        if m and key in {"AUTHOR", "PRODUCT", "VERSION", "CREATION DATE", "CREATION TIME", "UNITS",
                         "GRADE RULE TABLE", "NUMBER OF SIZES", "SIZE LIST", "SAMPLE SIZE"}:
            header.setdefault(key, m.group(2).strip())
        elif not version:
            version = line.strip()
    sizes = tuple(header.get("SIZE LIST", "").split())
    if not sizes:
        raise RULFormatError(f"{source}: no 'SIZE LIST:' line before the first rule; the table is unusable")
    twice = sorted({s for s in sizes if sizes.count(s) > 1})
    if twice:
        raise RULFormatError(f"{source}: SIZE LIST names size {' '.join(twice)[:60]} more than once "
                             f"({' '.join(sizes)[:120]}); each column must be a different size")
    n_declared = header.get("NUMBER OF SIZES")
    if n_declared is not None:
        try:
            n_decl = int(n_declared)
        except ValueError:
            raise RULFormatError(f"{source}: 'NUMBER OF SIZES: {n_declared}' is not a number") from None
        if n_decl != len(sizes):
            raise RULFormatError(
                f"{source}: NUMBER OF SIZES says {n_decl} but SIZE LIST has {len(sizes)} sizes "
                f"({' '.join(sizes)}); fix the header"
            )
    else:
        report.add("rul-no-size-count", "no 'NUMBER OF SIZES:' line; using the size list", source)
    sample = header.get("SAMPLE SIZE", "").strip()
    if not sample:
        raise RULFormatError(f"{source}: no 'SAMPLE SIZE:' line; cannot tell which column is the sample")
    if sample not in sizes:
        raise RULFormatError(f"{source}: sample size {sample!r} is not in the size list ({' '.join(sizes)})")
    return header, sizes, sample


def _deltas(body: str, sizes: tuple[str, ...], sample: str, unit: Units, source: str) -> dict[str, np.ndarray]:
    """Each rule's (n_sizes, 2) cumulative deltas in cm, checked against the size list and the sample column."""
    matches = list(_RULE.finditer(body))
    n = len(sizes)
    k_sample = sizes.index(sample)
    deltas: dict[str, np.ndarray] = {}
    for j, m in enumerate(matches):
        rid = m.group(1)
        chunk = body[m.end(): matches[j + 1].start() if j + 1 < len(matches) else len(body)]
        values = [float(v) for v in _NUMBER.findall(chunk)]
        if len(values) != 2 * n:
            raise RULFormatError(
                f"{source}: rule {rid} has {len(values)} values, expected {2 * n} "
                f"({n} sizes x dx,dy); the file is truncated or misaligned"
            )
        if rid in deltas:
            raise RULFormatError(f"{source}: rule {rid} is defined twice; remove the duplicate")
        arr = np.array(values, dtype=np.float64).reshape(n, 2)
        if not np.all(np.isfinite(arr)) or np.max(np.abs(arr)) > _MAX_DELTA:
            raise RULFormatError(f"{source}: rule {rid} holds a value that is not a finite number of sane size "
                                 f"(at most {_MAX_DELTA:g} file units); the file is damaged")
        if np.max(np.abs(arr[k_sample])) > _SAMPLE_ZERO_TOL:
            raise RULFormatError(
                f"{source}: rule {rid} moves the sample size {sample} by "
                f"({arr[k_sample, 0]:g}, {arr[k_sample, 1]:g}), expected 0, 0; the columns are misaligned"
            )
        arr[k_sample] = 0.0
        deltas[rid] = to_cm(arr, unit.value)
    return deltas


def read_rul(path: str | os.PathLike, *, units: str | Units | None = None) -> tuple[GradeRuleTable, Report]:
    """Read a ``.RUL`` file (see :func:`parse_rul`); deltas in cm.

    Raises
    ------
    RULFormatError
        When the file cannot be read or is malformed.
    """
    path = Path(path)
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise RULFormatError(f"{path}: cannot read the grade-rule table ({exc.strerror})") from None
    return parse_rul(_decode(data), source=str(path), units=units)


def _ascii(text: str) -> str:
    return text.encode("ascii", "replace").decode("ascii").replace("\n", " ").replace("\r", " ")


def format_rul(
    table: GradeRuleTable,
    units: str | Units = Units.METRIC,
    *,
    decimals: int = 4,
    pairs_per_line: int = 4,
    author: str = "PATTERNBRIDGE",
    created: _dt.datetime | None = None,
    newline: str = "\r\n",
    flavor: Flavor | str = Flavor.ASTM,
) -> str:
    """Text of a ``.RUL`` file for ``table`` (deltas in cm, written in ``units``).

    Writes the layout AccuMark uses: the flavour's version line (ASTM
    ``ASTM/D13Proposal 1 Version: D 6673-04``, AAMA ``ANSI/AAMA VERSION:
    1.0.0``), header, ``RULE: DELTA id`` with comma-separated pairs,
    ``pairs_per_line`` per line, rules in numeric id order, ``END``; 7-bit
    ASCII, CRLF by default. ``created`` defaults to :func:`creation_time`
    (``SOURCE_DATE_EPOCH`` or a fixed date, never the clock).

    Raises
    ------
    ValueError
        Empty size list, sample size outside it, a rule id with spaces, or a
        delta that is not a finite number.
    """
    unit = _units(units)
    if unit is None:
        raise UnitsError(f"format_rul: unknown units {units!r}; use METRIC or ENGLISH")
    if not table.sizes:
        raise ValueError("format_rul: the rule table has no sizes")
    if table.sample_size not in table.sizes:
        raise ValueError(f"format_rul: sample size {table.sample_size!r} not in {list(table.sizes)}")
    created = created or creation_time()
    flavor = Flavor(str(flavor.value if isinstance(flavor, Flavor) else flavor).lower())
    lines = [
        _VERSION_LINE[flavor],
        f"AUTHOR: {_ascii(author)}",
        f"CREATION DATE: {created:%d-%m-%Y}",
        f"CREATION TIME: {created:%H:%M}",
        f"UNITS: {unit.value}",
        f"GRADE RULE TABLE: {_ascii(table.name)}",
        f"NUMBER OF SIZES: {len(table.sizes)}",
        "SIZE LIST:  " + " ".join(_ascii(s) for s in table.sizes),
        f"SAMPLE SIZE: {_ascii(table.sample_size)}",
    ]
    width = decimals + 6
    for rid in sorted(table.deltas, key=rule_sort_key):
        if not rid or any(c.isspace() for c in rid) or "," in rid:
            raise ValueError(f"format_rul: rule id {rid!r} cannot be written (spaces or commas)")
        with np.errstate(over="ignore"):
            vals = from_cm(np.asarray(table.deltas[rid], dtype=np.float64), unit.value)
        if not np.all(np.isfinite(vals)):
            raise ValueError(f"format_rul: rule {rid} has a delta that is not a finite number")
        vals = np.where(np.abs(vals) < 0.5 * 10.0 ** -decimals, 0.0, vals)  # no "-0.0000"
        lines.append(f"RULE: DELTA {_ascii(rid)}")
        pairs = [f"{dx:{width}.{decimals}f},{dy:{width}.{decimals}f}" for dx, dy in vals]
        for i in range(0, len(pairs), pairs_per_line):
            lines.append("".join(pairs[i: i + pairs_per_line]))
    lines.append("END")
    return newline.join(lines) + newline


def write_rul(
    table: GradeRuleTable,
    path: str | os.PathLike,
    units: str | Units = Units.METRIC,
    **kwargs,
) -> Path:
    """Write ``table`` as a ``.RUL`` file atomically (see :func:`format_rul`)."""
    text = format_rul(table, units, **kwargs)
    return write_text(path, text, encoding="ascii", newline="")
