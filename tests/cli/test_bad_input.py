"""Malformed input (issue section 7): one line naming the file and exit 2.

Or a warning when the file is still usable; nothing is written on error.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from patternbridge.io.dxf_aama.write import write_dxf

CRLF = "\r\n"


@pytest.fixture()
def good(tee, tmp_path) -> tuple[str, str]:
    dxf, rul = tmp_path / "good.dxf", tmp_path / "good.rul"
    write_dxf(tee, dxf, rul_path=rul)
    return dxf.read_bytes().decode("ascii"), rul.read_bytes().decode("ascii")


def _write(tmp_path: Path, name: str, text: str | bytes) -> Path:
    d = tmp_path / "in"
    d.mkdir(exist_ok=True)
    path = d / name
    if isinstance(text, bytes):
        path.write_bytes(text)
    else:
        path.write_text(text, encoding="ascii", newline="")
    return path


def _assert_error(result, path: Path, out: Path, *needles: str) -> None:
    code, _stdout, err = result
    assert code == 2, err
    lines = err.splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith("patternbridge: error: ") and path.name in lines[0]
    assert "Traceback" not in err
    for needle in needles:
        assert needle.lower() in lines[0].lower()
    assert not out.exists()
    assert not list(out.parent.glob(f".{out.stem}.*")), "temporary file left behind"


def _assert_warning(result, out: Path, *codes: str) -> None:
    code, _, err = result
    assert code == 0, err
    lines = err.splitlines()
    for c in codes:
        assert any(line.startswith("patternbridge: warning: ") and f"[{c}]" in line for line in lines), err
    # everything else is a warning or an informational note, never a traceback
    assert all(line.startswith(("patternbridge: warning: ", "patternbridge: note: ")) for line in lines)
    assert out.is_file()


def _dxf_mutants(good_dxf: str) -> dict[str, str | bytes]:
    back = good_dxf.index("BACK_M")
    head = (
        "POLYLINE"
        + CRLF
        + "  8"
        + CRLF
        + "1"
        + CRLF
        + " 66"
        + CRLF
        + "1"
        + CRLF
        + " 70"
        + CRLF
    )
    j = good_dxf.index(head + "1", back)
    unclosed = good_dxf[:j] + head + "0" + good_dxf[j + len(head) + 1 :]

    def swap(text: str, a: str, b: str) -> str:
        return text.replace(a, "@@").replace(b, a).replace("@@", b)

    corner = " 10" + CRLF + "{}" + CRLF + " 20" + CRLF + "{}"
    body = swap(
        good_dxf[back:],
        corner.format("250.0000", "400.0000"),
        corner.format("170.0000", "600.0000"),
    )
    insert = CRLF.join(
        ["  0", "INSERT", "  8", "1", "  2", "GHOST_M", " 10", "0.0", " 20", "0.0", ""]
    )
    end = f"  0{CRLF}ENDSEC{CRLF}  0{CRLF}EOF{CRLF}"
    return {
        "truncated": good_dxf[: len(good_dxf) // 2],
        "garbage": b"\x00\x01\x02\xff binary junk" * 50,
        "empty": "",
        "units": good_dxf.replace("Units: METRIC", "Units: FURLONGS"),
        "undefined_insert": good_dxf[: -len(end)] + insert + end,
        "unclosed": unclosed,
        "selfx": good_dxf[:back] + body,
        "no_units": good_dxf.replace("Units: METRIC", "Remark: none"),
    }


@pytest.mark.parametrize(
    "case, needles",
    [
        ("truncated", ["truncated"]),
        ("garbage", ["not a text DXF"]),
        ("empty", ["no DXF entities"]),
        ("units", ["units", "FURLONGS"]),
    ],
)
@pytest.mark.parametrize("command", ["import", "info", "export", "plot"])
def test_unusable_dxf_is_one_line_exit_2(cli, good, tmp_path, case, needles, command):
    bad = _write(tmp_path, f"{case}.dxf", _dxf_mutants(good[0])[case])
    suffix = {"import": ".json", "info": ".json", "export": ".dxf", "plot": ".png"}[
        command
    ]
    out = tmp_path / f"out{suffix}"
    argv = [command, bad] + ([] if command == "info" else ["-o", out])
    _assert_error(cli(*argv), bad, out, *needles)


@pytest.mark.parametrize(
    "case, codes",
    [
        ("undefined_insert", ["insert-undefined-block"]),
        ("unclosed", ["boundary-not-closed"]),
        ("selfx", ["boundary-self-intersects"]),
        ("no_units", ["units-assumed"]),
    ],
)
def test_usable_dxf_warns_and_strict_refuses(cli, good, tmp_path, case, codes):
    bad = _write(tmp_path, f"{case}.dxf", _dxf_mutants(good[0])[case])
    _write(tmp_path, f"{case}.rul", good[1])
    out = tmp_path / "out.json"
    _assert_warning(cli("import", bad, "-o", out), out, *codes)
    out.unlink()
    code, _, err = cli("import", bad, "--strict", "-o", out)
    assert code == 2 and "strict" in err.splitlines()[-1] and not out.exists()


def _rul_with(
    good_rul: str,
    *,
    sample_dx: str | None = None,
    count: str | None = None,
    sizes: str | None = None,
) -> str:
    lines = good_rul.split(CRLF)
    if sample_dx is not None:  # rule 2: the M column (2nd pair) made non-zero
        i = lines.index("RULE: DELTA 2") + 1
        nums = re.findall(r"-?\d+\.\d+", lines[i])
        nums[2] = sample_dx
        lines[i] = "  ".join(
            f"{nums[k]}, {nums[k + 1]}" for k in range(0, len(nums), 2)
        )
    if count is not None:
        lines = [
            f"NUMBER OF SIZES: {count}" if ln.startswith("NUMBER OF SIZES") else ln
            for ln in lines
        ]
    if sizes is not None:
        lines = [
            f"SIZE LIST: {sizes}" if ln.startswith("SIZE LIST") else ln for ln in lines
        ]
    return CRLF.join(lines)


@pytest.mark.parametrize(
    "mutation, needles",
    [
        ({"sample_dx": "5.0000"}, ["sample"]),
        ({"count": "5"}, ["5"]),
        ({"sizes": "S M L XL XXL", "count": "5"}, []),
    ],
)
def test_bad_rul_is_one_line_exit_2(cli, good, tmp_path, mutation, needles):
    dxf = _write(tmp_path, "tee.dxf", good[0])
    rul = _write(tmp_path, "bad.rul", _rul_with(good[1], **mutation))
    out = tmp_path / "out.json"
    _assert_error(cli("import", dxf, "--rul", rul, "-o", out), rul, out, *needles)


def test_rul_sizes_must_hold_the_dxf_sample_size(cli, good, tmp_path):
    dxf = _write(tmp_path, "tee.dxf", good[0])
    rul = _write(tmp_path, "other.rul", _rul_with(good[1], sizes="XS S L XL"))
    out = tmp_path / "out.json"
    code, _, err = cli("import", dxf, "--rul", rul, "-o", out)
    assert code == 2 and len(err.splitlines()) == 1 and not out.exists()


def test_missing_rul_and_missing_dxf(cli, good, tmp_path):
    dxf = _write(tmp_path, "tee.dxf", good[0])
    out = tmp_path / "out.json"
    _assert_error(
        cli("import", dxf, "--rul", tmp_path / "nope.rul", "-o", out),
        Path("nope.rul"),
        out,
    )
    _assert_error(
        cli("import", tmp_path / "nope.dxf", "-o", out), Path("nope.dxf"), out
    )


def test_existing_output_survives_an_error(cli, good, tmp_path):
    bad = _write(tmp_path, "truncated.dxf", _dxf_mutants(good[0])["truncated"])
    out = tmp_path / "keep.json"
    out.write_text("precious", encoding="utf-8")
    code, _, _ = cli("import", bad, "-o", out)
    assert code == 2 and out.read_text(encoding="utf-8") == "precious"
