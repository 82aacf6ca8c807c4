"""RUL grade-rule tables: every syntax variant of real files, round trips, malformed input."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from patternbridge.errors import InputError, RULFormatError, UnitsError
from patternbridge.io.rul import format_rul, parse_rul, read_rul, write_rul
from patternbridge.pattern.model import GradeRuleTable, Units

ACCUMARK = (
    "ASTM/D13Proposal 1 Version: D 6673-04\r\n"
    "AUTHOR: GERBER TECHNOLOGY\r\nPRODUCT: ACCUMARK\r\nVERSION: 17.1.0\r\n"
    "CREATION DATE: 3-14-2024\r\nCREATION TIME: 10:3\r\nUNITS: ENGLISH\r\n"
    "GRADE RULE TABLE: CAP-RULES-A\r\nNUMBER OF SIZES: 9\r\nSIZE LIST:  2 4 6 8 10 12 14 16 18\r\n"
    "SAMPLE SIZE: 8\r\n"
    "RULE: DELTA 1\r\n"
    "   -0.2361,   0.1179   -0.1968,   0.0983   -0.1181,   0.0590    0.0000,   0.0000\r\n"
    "    0.1574,  -0.0787    0.3542,  -0.1771    0.5904,  -0.2952    0.8659,  -0.4329\r\n"
    "    1.1808,  -0.5903\r\n"
    "END\r\n"
)

CLO = """ASTM/D13 Proposal 1 Version: D 6673-04
AUTHOR: CLO Virtual Fashion Inc.
SAMPLE SIZE: XS
UNITS: METRIC
GRADE RULE TABLE: W SS
NUMBER OF SIZES: 6
SIZE LIST: XS S M L XL 2XL{space}
RULE: DELTA 1
     0.00     0.00     10.00     -14.29     20.00     -28.57     30.00     -31.75
     40.00     -35.56     50.00     -41.11
RULE: DELTA 2
     0.00     0.00     0.00     0.00     0.00     0.00     0.00     0.00
     0.00     0.00     0.00     0.00
END
""".format(space=" ")  # CLO writes a trailing space after the size list

ONE_PAIR = "\r\n".join(
    ["version ANSI/AAMA-292-B", "UNITS: METRIC", "NUMBER OF SIZES: 3", "SIZE LIST: 30 32 34",
     "SAMPLE SIZE: 32", "RULE: DELTA 7", "      -10.395,      19.458", "      0.000,      -0.000",
     "      4.000,      1.500", "END", ""]
)

SAME_LINE = """ANSI/AAMA VERSION: 1.0.0
UNITS: METRIC
NUMBER OF SIZES: 3
SIZE LIST: S M L
SAMPLE SIZE: M
RULE: DELTA 1  -1.00, 2.00  0.00, 0.00  1.00, -2.00
RULE: DELTA 2  0.50, 0.50  0.00, 0.00  -0.50, -0.50
END
"""


def test_accumark_english_four_pairs_per_line_crlf():
    table, report = parse_rul(ACCUMARK, source="cap.rul")
    assert table.sizes == ("2", "4", "6", "8", "10", "12", "14", "16", "18")
    assert table.sample_size == "8" and table.name == "CAP-RULES-A"
    d = table.deltas["1"]
    assert d.shape == (9, 2)
    np.testing.assert_allclose(d[0], [-0.2361 * 2.54, 0.1179 * 2.54])  # inches -> cm
    np.testing.assert_allclose(d[-1], [1.1808 * 2.54, -0.5903 * 2.54])
    np.testing.assert_array_equal(d[3], [0, 0])
    assert not report


def test_clo_no_comma_sample_first_trailing_space():
    table, _ = parse_rul(CLO)
    assert table.sizes == ("XS", "S", "M", "L", "XL", "2XL") and table.sample_size == "XS"
    np.testing.assert_allclose(table.deltas["1"][1], [1.0, -1.429])  # mm -> cm
    np.testing.assert_allclose(table.deltas["1"][5], [5.0, -4.111])
    np.testing.assert_array_equal(table.deltas["2"], np.zeros((6, 2)))


def test_one_pair_per_line_and_any_version_line():
    table, _ = parse_rul(ONE_PAIR)
    np.testing.assert_allclose(table.deltas["7"], [[-1.0395, 1.9458], [0, 0], [0.4, 0.15]])


def test_whole_rule_on_the_rule_line():
    table, _ = parse_rul(SAME_LINE)
    np.testing.assert_allclose(table.deltas["1"], [[-0.1, 0.2], [0, 0], [0.1, -0.2]])
    np.testing.assert_allclose(table.deltas["2"], [[0.05, 0.05], [0, 0], [-0.05, -0.05]])


def test_units_override_and_file(tmp_path):
    path = tmp_path / "style.RUL"
    path.write_bytes(SAME_LINE.encode())
    table, _ = read_rul(path, units="ENGLISH")
    np.testing.assert_allclose(table.deltas["1"][0], [-2.54, 5.08])
    table, _ = read_rul(path)
    np.testing.assert_allclose(table.deltas["1"][0], [-0.1, 0.2])


@pytest.mark.parametrize(
    ("text", "fragment"),
    [
        ("UNITS: METRIC\nSIZE LIST: S M\nSAMPLE SIZE: S\n", "no 'RULE: DELTA'"),
        ("UNITS: METRIC\nSIZE LIST: S M\nSAMPLE SIZE: S\nRULE: DELTA 1\n0,0 1e400,1\nEND\n", "not a finite"),
        ("UNITS: METRIC\nSIZE LIST: S M\nSAMPLE SIZE: S\nRULE: DELTA 1\n0,0 3e300,1\nEND\n", "sane size"),
        ("UNITS: METRIC\nSIZE LIST: S M L M\nSAMPLE SIZE: S\nRULE: DELTA 1\n0,0 1,1 2,2 3,3\nEND\n",
         "size M more than once"),
        ("UNITS: METRIC\nSAMPLE SIZE: S\nRULE: DELTA 1\n0,0 1,1\nEND\n", "no 'SIZE LIST:'"),
        ("UNITS: METRIC\nNUMBER OF SIZES: 3\nSIZE LIST: S M\nSAMPLE SIZE: S\nRULE: DELTA 1\n0,0 1,1\nEND\n",
         "NUMBER OF SIZES says 3"),
        ("UNITS: METRIC\nSIZE LIST: S M\nSAMPLE SIZE: L\nRULE: DELTA 1\n0,0 1,1\nEND\n", "not in the size list"),
        ("UNITS: METRIC\nSIZE LIST: S M\nRULE: DELTA 1\n0,0 1,1\nEND\n", "no 'SAMPLE SIZE:'"),
        ("UNITS: METRIC\nSIZE LIST: S M\nSAMPLE SIZE: S\nRULE: DELTA 1\n0,0 1\nEND\n", "has 3 values, expected 4"),
        ("UNITS: METRIC\nSIZE LIST: S M\nSAMPLE SIZE: S\nRULE: DELTA 1\n0,0 1,1\nRULE: DELTA 1\n0,0 2,2\nEND\n",
         "defined twice"),
        ("UNITS: METRIC\nSIZE LIST: S M\nSAMPLE SIZE: S\nRULE: DELTA 4\n0.5,0 1,1\nEND\n",
         "moves the sample size S"),
        ("UNITS: METRIC\nNUMBER OF SIZES: two\nSIZE LIST: S M\nSAMPLE SIZE: S\nRULE: DELTA 1\n0,0 1,1\nEND\n",
         "is not a number"),
    ],
)
def test_malformed_rul_raises_one_line(text, fragment):
    with pytest.raises(RULFormatError) as err:
        parse_rul(text, source="bad.rul")
    msg = str(err.value)
    assert msg.startswith("bad.rul: ") and fragment in msg and "\n" not in msg


@pytest.mark.parametrize(
    ("text", "fragment"),
    [
        ("SIZE LIST: S M\nSAMPLE SIZE: S\nRULE: DELTA 1\n0,0 1,1\nEND\n", "no 'UNITS:'"),
        ("UNITS: FURLONGS\nSIZE LIST: S M\nSAMPLE SIZE: S\nRULE: DELTA 1\n0,0 1,1\nEND\n", "unknown units"),
    ],
)
def test_units_errors(text, fragment):
    with pytest.raises(UnitsError, match=fragment):
        parse_rul(text, source="u.rul")


def test_missing_end_is_a_finding_and_unreadable_file_an_error(tmp_path):
    table, report = parse_rul("UNITS: METRIC\nSIZE LIST: S M\nSAMPLE SIZE: S\nRULE: DELTA 1\n0,0 1,1\n")
    assert "rul-no-end" in report.codes()
    np.testing.assert_allclose(table.deltas["1"][1], [0.1, 0.1])
    with pytest.raises(RULFormatError, match="cannot read"):
        read_rul(tmp_path / "absent.rul")


def test_write_rul_is_ascii_crlf_and_round_trips(tmp_path):
    table = GradeRuleTable(name="Bluse größe", sizes=("S", "M", "L"), sample_size="M",
                           deltas={"10": [[-0.5, 0.25], [0, 0], [0.5, -0.25]], "2": np.zeros((3, 2))})
    path = write_rul(table, tmp_path / "out.rul", units="ENGLISH")
    raw = path.read_bytes()
    assert raw.isascii() and b"\r\n" in raw and b"\n" not in raw.replace(b"\r\n", b"")
    text = raw.decode()
    assert text.index("RULE: DELTA 2") < text.index("RULE: DELTA 10")  # numeric order
    back, _ = read_rul(path)
    assert back.sizes == table.sizes and back.sample_size == "M"
    for rid in table.deltas:
        np.testing.assert_allclose(back.deltas[rid], table.deltas[rid], atol=0.5e-4 * 2.54)


sizes_st = st.lists(st.from_regex(r"[A-Z0-9]{1,4}", fullmatch=True), min_size=1, max_size=8, unique=True)


@st.composite
def rul_variants(draw):
    """A rule table and a .RUL text for it written in one of the real syntax variants."""
    sizes = draw(sizes_st)
    k = draw(st.integers(0, len(sizes) - 1))
    n_rules = draw(st.integers(1, 5))
    ids = draw(st.lists(st.integers(0, 9999), min_size=n_rules, max_size=n_rules, unique=True))
    vals = draw(st.lists(st.integers(-99999, 99999), min_size=2 * len(sizes) * n_rules,
                         max_size=2 * len(sizes) * n_rules))
    arr = np.array(vals, dtype=float).reshape(n_rules, len(sizes), 2) / 100.0  # two decimals, mm
    arr[:, k] = 0.0
    comma = draw(st.booleans())
    per_line = draw(st.integers(1, 4))
    same_line = draw(st.booleans())
    crlf = draw(st.booleans())
    version = draw(st.sampled_from(["ASTM/D13Proposal 1 Version: D 6673-04", "ASTM/D13 Proposal 1 Version: D 6673-04",
                                    "ANSI/AAMA VERSION: 1.0.0", "version ANSI/AAMA-292-B", ""]))
    header = [version, "UNITS: METRIC", f"NUMBER OF SIZES: {len(sizes)}", "SIZE LIST:  " + " ".join(sizes) + " ",
              f"SAMPLE SIZE: {sizes[k]}"]
    header = [header[0], *draw(st.permutations(header[1:]))]
    lines = header
    for rid, d in zip(ids, arr, strict=True):
        pairs = [f"{dx:10.2f}{',' if comma else ' '}{dy:10.2f}" for dx, dy in d]
        rows = ["  ".join(pairs[i:i + per_line]) for i in range(0, len(pairs), per_line)]
        if same_line:
            lines.append(f"RULE: DELTA {rid}  " + "  ".join(rows))
        else:
            lines += [f"RULE: DELTA {rid}", *rows]
    lines.append("END")
    text = ("\r\n" if crlf else "\n").join(lines) + "\n"
    return sizes, sizes[k], {str(r): d for r, d in zip(ids, arr, strict=True)}, text


@settings(max_examples=60, deadline=None)
@given(rul_variants())
def test_hypothesis_every_syntax_variant_parses(case):
    sizes, sample, deltas, text = case
    table, _ = parse_rul(text)
    assert table.sizes == tuple(sizes) and table.sample_size == sample
    assert set(table.deltas) == set(deltas)
    for rid, d in deltas.items():
        np.testing.assert_allclose(table.deltas[rid], d / 10.0, atol=1e-12)  # mm -> cm


@settings(max_examples=40, deadline=None)
@given(rul_variants(), st.sampled_from([Units.METRIC, Units.ENGLISH]), st.integers(1, 4))
def test_hypothesis_format_parse_round_trip(case, units, per_line):
    _, _, _, text = case
    table, _ = parse_rul(text)
    back, _ = parse_rul(format_rul(table, units, pairs_per_line=per_line))
    assert back.sizes == table.sizes and back.sample_size == table.sample_size
    step = 0.5e-4 * (0.1 if units is Units.METRIC else 2.54)
    for rid, d in table.deltas.items():
        np.testing.assert_allclose(back.deltas[rid], d, atol=step * 1.01)


def test_header_only_table_has_no_rules():
    """What we write for a pattern that does not grade (one size) reads back as an empty table."""
    table, report = parse_rul("UNITS: METRIC\nSIZE LIST: M\nSAMPLE SIZE: M\nEND\n", source="one.rul")
    assert table.sizes == ("M",) and not table.deltas and "rul-no-rules" in report.codes()


@pytest.mark.parametrize("flavor, first", [("aama", "ANSI/AAMA VERSION: 1.0.0"),
                                           ("astm", "ASTM/D13Proposal 1 Version: D 6673-04")])
def test_each_flavour_has_its_own_version_line(flavor, first):
    table = GradeRuleTable(sizes=("S", "M"), sample_size="M", deltas={"1": [[1.0, 0.0], [0.0, 0.0]]})
    text = format_rul(table, flavor=flavor)
    assert text.split("\r\n")[0] == first
    back, _ = parse_rul(text)
    assert back == table


def test_dates_from_source_date_epoch_never_the_clock(monkeypatch):
    table = GradeRuleTable(sizes=("S", "M"), sample_size="M", deltas={"1": [[1.0, 0.0], [0.0, 0.0]]})
    monkeypatch.delenv("SOURCE_DATE_EPOCH", raising=False)
    fixed = format_rul(table)
    assert "CREATION DATE: 01-01-1980" in fixed and format_rul(table) == fixed
    monkeypatch.setenv("SOURCE_DATE_EPOCH", "1700000000")  # 2023-11-14 22:13:20 UTC
    text = format_rul(table)
    assert "CREATION DATE: 14-11-2023" in text and "CREATION TIME: 22:13" in text
    monkeypatch.setenv("SOURCE_DATE_EPOCH", "soon")
    with pytest.raises(InputError, match="SOURCE_DATE_EPOCH"):
        format_rul(table)


def test_delta_overflowing_in_file_units_refused():
    # 1e308 cm is a finite model value but infinite in millimetres
    table = GradeRuleTable(sizes=("S", "M"), sample_size="M", deltas={"1": [[1e308, 0.0], [0.0, 0.0]]})
    with pytest.raises(ValueError, match="not a finite number"):
        format_rul(table)
