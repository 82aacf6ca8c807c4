"""docs/cli.md's exit-code table says what every sub-command's code can return.

The codes a sub-command returns are read from its source: every ``return`` of
its ``run`` (following calls into functions of ``patternbridge.cli`` and names
assigned from them) must be a whole-number literal or a conditional of them, so
a new code, or a code computed some other way, fails here until the table says
what it means. ``main`` adds 2 (bad input, argparse errors) to every command.
"""

from __future__ import annotations

import ast
import re
from pathlib import Path

import pytest

from patternbridge.cli.main import COMMANDS, main

CLI = Path(__file__).resolve().parents[2] / "patternbridge" / "cli"
DOC = Path(__file__).resolve().parents[2] / "docs" / "cli.md"
CODES = (0, 1, 2, 3)
NONE = "—"


def _functions(module: str) -> dict[str, ast.FunctionDef]:
    tree = ast.parse((CLI / f"{module}.py").read_text(encoding="utf-8"))
    return {n.name: n for n in tree.body if isinstance(n, ast.FunctionDef)}


def _imports(module: str) -> dict[str, str]:
    """Names a cli module imports from a sibling module (``from .export import f``): name -> module."""
    tree = ast.parse((CLI / f"{module}.py").read_text(encoding="utf-8"))
    return {
        alias.asname or alias.name: node.module
        for node in ast.walk(tree)
        if isinstance(node, ast.ImportFrom) and node.level == 1 and node.module
        for alias in node.names
    }


def _own_nodes(func: ast.FunctionDef):
    """The nodes of ``func``'s body, not those of functions defined inside it."""
    todo = list(func.body)
    while todo:
        node = todo.pop()
        yield node
        todo.extend(c for c in ast.iter_child_nodes(node) if not isinstance(c, ast.FunctionDef | ast.Lambda))


def _codes(module: str, name: str, seen: frozenset[tuple[str, str]] = frozenset()) -> set[int]:
    """Every exit code ``module.name`` can return (raises when one cannot be read from the source)."""
    func = _functions(module)[name]
    assigned = {
        t.id: n.value
        for n in _own_nodes(func)
        if isinstance(n, ast.Assign)
        for t in n.targets
        if isinstance(t, ast.Name)
    }

    def value(expr: ast.expr) -> set[int]:
        if isinstance(expr, ast.Constant) and type(expr.value) is int:
            return {expr.value}
        if isinstance(expr, ast.IfExp):
            return value(expr.body) | value(expr.orelse)
        if isinstance(expr, ast.Name) and expr.id in assigned:
            return value(assigned[expr.id])
        if isinstance(expr, ast.Call) and isinstance(expr.func, ast.Name):
            callee = expr.func.id
            where = module if callee in _functions(module) else _imports(module).get(callee)
            if where is not None and (where, callee) not in seen:
                return _codes(where, callee, seen | {(module, name)})
        raise AssertionError(f"cli/{module}.py {name}: cannot tell the exit code of `return {ast.unparse(expr)}`")

    returns = [n for n in _own_nodes(func) if isinstance(n, ast.Return)]
    assert returns, f"cli/{module}.py {name} has no return"
    return set().union(*(value(r.value) if r.value is not None else {0} for r in returns))


def _table() -> dict[str, dict[int, str]]:
    """docs/cli.md's exit-code table: command -> {code: meaning} (cells saying — left out)."""
    text = DOC.read_text(encoding="utf-8")
    section = text.split("## Exit codes", 1)[1].split("\n## ", 1)[0]
    rows = [line for line in section.splitlines() if line.startswith("| `")]
    table = {}
    for line in rows:
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        command = re.fullmatch(r"`(\w+)`", cells[0]).group(1)
        table[command] = {code: cell for code, cell in zip(CODES, cells[1:], strict=True) if cell != NONE}
    return table


def test_table_has_one_row_per_command():
    assert sorted(_table()) == sorted(COMMANDS)


@pytest.mark.parametrize("command", sorted(COMMANDS))
def test_documented_codes_are_the_codes_run_returns(command):
    documented = _table()[command]
    returned = _codes(COMMANDS[command], "run") | {2}  # main: PatternBridgeError and argparse errors
    assert set(documented) == returned, f"{command}: documented {sorted(documented)}, returned {sorted(returned)}"
    assert all(documented.values())


def test_reader_follows_calls_and_names():
    # library's export action returns export.py's export_pattern(...) through a name
    assert _codes("library", "run") == {0}
    assert _codes("check", "run") == {0, 1}
    assert _codes("batch", "run") == {0, 1, 3}


def test_bad_arguments_exit_2_as_the_table_says(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["check", "--no-such-option"])
    assert exc.value.code == 2
    assert main(["info", str(DOC.with_suffix(".nothing.dxf"))]) == 2
    assert "patternbridge: error:" in capsys.readouterr().err
