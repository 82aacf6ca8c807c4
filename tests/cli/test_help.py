"""Every command answers --help with exit 0 and names its options."""

from __future__ import annotations

import pytest

from patternbridge.cli.main import main


@pytest.mark.parametrize(
    "command, options",
    [
        ("import", ["--rul", "--units", "--unfold", "--strict", "--seams", "-o"]),
        ("info", ["--json"]),
        ("export", ["--flavor", "--sizes", "--rul", "-o"]),
        ("grade", ["--size", "-o"]),
        ("plot", ["--sizes", "-o"]),
    ],
)
def test_help(command, options, capsys):
    with pytest.raises(SystemExit) as exc:
        main([command, "--help"])
    assert exc.value.code == 0
    text = capsys.readouterr().out
    assert f"usage: patternbridge {command}" in text
    for option in options:
        assert option in text


def test_top_level_help_lists_our_commands(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["--help"])
    assert exc.value.code == 0
    text = capsys.readouterr().out
    for command in ("import", "info", "export", "grade", "plot"):
        assert command in text


def test_missing_required_option_is_a_usage_error(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["export", "x.json"])
    assert exc.value.code == 2
    assert "-o/--output" in capsys.readouterr().err
