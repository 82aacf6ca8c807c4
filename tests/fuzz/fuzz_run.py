"""Run one malformed-input case through the CLI in a forked child and classify the outcome.

A case is (input kind, real source file, mutation, seed, command). The child
process writes the mutated input into its own folder, calls
``patternbridge.cli.main.main(argv)`` in-process (the parent imported the heavy
modules once, so a fork costs milliseconds), then checks what it wrote. The
parent kills it after a timeout of CPU time (five times that in wall time at
the latest), so a loaded machine does not turn slow cases into hangs. Outcomes:

- ``error``: exit 2, one ``patternbridge: error:`` line, no traceback, no output
  and no temporary file left behind;
- ``ok``: exit 0 and every written file reads back cleanly (see :func:`check_outputs`);
- ``traceback``: any exception that is not a ``PatternBridgeError``;
- ``hang``: still running at the timeout (a loop, or a file that makes work explode);
- ``nonsense``: exit 0 with output that fails a check, or an error that left
  output or temporary files behind, or an error message that is not one line.
"""

from __future__ import annotations

import contextlib
import json
import math
import os
import shutil
import signal
import sys
import time
import traceback
import zlib
from dataclasses import dataclass
from enum import Enum
from pathlib import Path

import numpy as np
from fuzz_mutate import mutate

__all__ = ["Case", "Outcome", "Result", "assert_clean_error", "build_cases", "run_case"]

REPO = Path(__file__).resolve().parents[2]
SHARED = (REPO.parent / "shared").resolve()
LIBRARY = REPO / "garment_library"

STATURE_CM = (40.0, 300.0)
"""A measured stature outside this range is nonsense for a character."""


class Outcome(str, Enum):
    ERROR = "clean error"
    OK = "ok"
    TRACEBACK = "traceback"
    HANG = "hang"
    NONSENSE = "exit-0 nonsense"

    def __str__(self) -> str:
        return self.value


@dataclass(frozen=True, slots=True)
class Case:
    """One malformed input through one command; the id names it for a re-run."""

    kind: str  # dxf | rul | pattern | mesh | sidecar | landmarks | measurements | args
    source: str  # real file the input derives from (or the argv template for "args")
    mutation: str
    seed: int
    command: str

    @property
    def id(self) -> str:
        return f"{self.command}:{self.kind}:{Path(self.source).name}:{self.mutation}:{self.seed}"


@dataclass(frozen=True, slots=True)
class Result:
    case: Case
    outcome: Outcome
    detail: str
    seconds: float


# ------------------------------------------------------------------ inputs
def _library(suffix: str) -> list[Path]:
    return sorted(LIBRARY.glob(f"*/*{suffix}"))


def sources() -> dict[str, list[Path]]:
    """Real files of each input kind (``../shared`` and ``garment_library``)."""
    chars = SHARED / "characters"
    return {
        "dxf": sorted((SHARED / "aama").glob("*.[dD][xX][fF]")) + _library("_aama.dxf") + _library("_astm.dxf"),
        "rul": _library(".rul"),
        "pattern": [p for p in _library(".json") if not p.name.endswith(".seams.json")],
        "mesh": sorted(chars.glob("*.obj"))
        + sorted((chars / "variants").glob("*.obj"))
        + sorted((chars / "variants").glob("*.glb"))
        + sorted(chars.glob("*.ply")),
        "sidecar": [chars / "E_average_male.json", chars / "B_slim_female.json"],
        "landmarks": [chars / "landmarks.json"],
        "measurements": [],  # measured once per run, see measurements_source()
    }


MUTATIONS_OF = {
    "dxf": ["truncate", "garble", "delete-lines", "duplicate-lines", "huge-name"]
    + [f"number-{v}" for v in ("nan", "NaN", "inf", "-inf", "1e308", "-1e308", "1e400", "99999999999999999999", "0")],
    "rul": ["truncate", "garble", "delete-lines", "duplicate-lines", "number-nan", "number-inf", "number-1e308",
            "number-99999999999999999999", "number-0"],
    "pattern": ["json-type-swap", "json-delete-key", "json-top-level", "json-deep", "json-huge-string",
                "json-no-pieces", "json-bad-number", "truncate", "garble", "duplicate-lines"],
    "obj": ["truncate", "garble", "delete-lines", "duplicate-lines", "number-nan", "number-inf", "number-1e308",
            "number-99999999999999999999", "scale-obj-1e300", "stray-triangle"],
    "glb": ["glb-truncate", "glb-drop-bin", "glb-accessor-count", "glb-accessor-field", "glb-structure",
            "glb-nan-position", "glb-scale-positions", "garble"],
    "ply": ["truncate", "garble", "number-99999999999999999999", "number-0"],
    "json": ["json-type-swap", "json-delete-key", "json-top-level", "json-deep", "json-huge-string",
             "json-no-pieces", "json-bad-number", "truncate"],
}
COMMANDS_OF = {
    "dxf": ["import", "info", "export", "plot", "check", "seams"],
    "rul": ["import", "info"],
    "pattern": ["info", "export", "plot", "check", "seams", "info", "export", "plot", "check", "seams", "fit"],
    "mesh": ["measure", "geodesic", "measure", "geodesic", "measure", "geodesic", "fit"],
    "sidecar": ["measure"],
    "landmarks": ["measure", "geodesic"],
    "measurements": ["fit"],
}
# argv templates: {IN} a real pattern, {MESH} a real mesh, {OUT} the output folder
BAD_ARGS = [
    ["fit", "{MEAS}", "--garment", "shorts", "--pop-size", "-3", "-o", "{OUT}/fit"],
    ["fit", "{MEAS}", "--garment", "shorts", "--generations", "-1", "-o", "{OUT}/fit"],
    ["fit", "{MEAS}", "--garment", "shorts", "--pop-size", "1", "--generations", "1", "--no-drape", "-o", "{OUT}/f"],
    ["fit", "{MEAS}", "--garment", "shorts", "--seed", "-5", "--pop-size", "4", "--generations", "1", "--no-drape",
     "--no-repair", "-o", "{OUT}/fit"],
    ["fit", "{MEAS}", "--garment", "shorts", "--seed", str(2**70), "-o", "{OUT}/fit"],
    ["fit", "{MEAS}", "--garment", "no_such_garment", "-o", "{OUT}/fit"],
    ["fit", "{MESH}", "--garment", "shorts", "--units", "furlong", "-o", "{OUT}/fit"],
    ["fit", "{MESH}", "--garment", "shorts", "--up", "sideways", "-o", "{OUT}/fit"],
    ["fit", "{MEAS}", "--garment", "shorts", "-o", "{IN}"],
    ["measure", "{MESH}", "--units", "nan", "-o", "{OUT}/m.json"],
    ["measure", "{MESH}", "--units", "km", "-o", "{OUT}/m.json"],
    ["measure", "{MESH}", "--up", "W", "-o", "{OUT}/m.json"],
    ["measure", "{MESH}", "-o", "{OUT}"],
    ["geodesic", "{MESH}", "--from", "0", "--to", "99999999999", "--json"],
    ["geodesic", "{MESH}", "--from", "-1", "--to", "5", "--json"],
    ["geodesic", "{MESH}", "--from", "nope", "--to", "5", "--json"],
    ["check", "{IN}", "--tol-mm", "nan", "--json"],
    ["check", "{IN}", "--tol-mm", "-1", "--notch-tol-mm", "inf", "--json"],
    ["export", "{IN}", "--sizes", "XXL,,", "-o", "{OUT}/e.dxf"],
    ["plot", "{IN}", "--sizes", ",", "-o", "{OUT}/p.svg"],
    ["plot", "{IN}", "--title", "T" * (2 * 2**20), "-o", "{OUT}/p.png"],
    ["seams", "infer", "{IN}", "--min-confidence", "nan", "-o", "{OUT}/s.seams.json"],
]

FIT_BUDGET = ["--pop-size", "8", "--generations", "2", "--no-drape", "--no-repair"]


def _mesh_family(path: Path) -> str:
    return {".glb": "glb", ".ply": "ply"}.get(path.suffix.lower(), "obj")


def build_cases(total: int = 1132, seed: int = 0, quotas: dict[str, int] | None = None) -> list[Case]:
    """The deterministic case list: ``quotas[kind]`` cases per input kind, round robin
    over files, mutations and commands, each with its own seed."""
    quotas = quotas or {
        "dxf": 420, "rul": 80, "pattern": 300, "mesh": 200, "sidecar": 30, "landmarks": 40, "measurements": 40,
    }
    found = sources()
    found["measurements"] = [Path("measurements.json")]
    rng = np.random.default_rng(seed)
    cases: list[Case] = []
    for kind, quota in quotas.items():
        files = found[kind]
        if not files:
            continue
        commands = COMMANDS_OF[kind]
        for k in range(quota):
            src = files[k % len(files)]
            family = _mesh_family(src) if kind == "mesh" else kind
            family = "json" if kind in ("sidecar", "landmarks", "measurements") else family
            mutations = MUTATIONS_OF[family]
            mutation = mutations[(k // len(files)) % len(mutations)]
            command = commands[(k // (len(files) * len(mutations)) + k) % len(commands)]
            cases.append(Case(kind, str(src), mutation, int(rng.integers(0, 2**31)), command))
    for k, argv in enumerate(BAD_ARGS[: max(0, total - len(cases))]):
        cases.append(Case("args", json.dumps(argv), "argv", k, argv[0]))
    return cases[:total]


# ------------------------------------------------------------------ one case
def _companions(case: Case, src: Path, where: Path) -> Path:
    """Write the mutated input (and the unchanged files it needs beside it) into ``where``."""
    where.mkdir(parents=True, exist_ok=True)
    data = mutate(src.read_bytes(), case.mutation, case.seed)
    if case.kind == "rul":
        dxf = next(iter(sorted(src.parent.glob("*_aama.dxf"))))
        shutil.copy(dxf, where / "pattern.dxf")
        (where / "pattern.rul").write_bytes(data)
        return where / "pattern.dxf"
    target = where / src.name
    target.write_bytes(data)
    if case.kind == "dxf":
        rul = src.parent / (src.name.split("_")[0] + ".rul")
        if rul.is_file() and src.parent.parent == LIBRARY:
            shutil.copy(rul, where / (src.stem + ".rul"))
    elif case.kind == "mesh":
        sidecar = src.with_suffix(".json")
        if sidecar.is_file():
            shutil.copy(sidecar, where / sidecar.name)
    elif case.kind == "sidecar":
        shutil.copy(src.with_suffix(".obj"), where / src.with_suffix(".obj").name)
        return where / src.with_suffix(".obj").name
    return target


def argv_for(case: Case, ws: Path, measurements: Path) -> list[str]:
    """The command line of ``case`` inside the work folder ``ws``."""
    out = ws / "out"
    mesh = SHARED / "characters" / "E_average_male.obj"
    shorts = LIBRARY / "shorts" / "shorts.json"
    if case.kind == "args":
        subs = {"{IN}": str(shorts), "{MESH}": str(mesh), "{MEAS}": str(measurements), "{OUT}": str(out)}
        argv = json.loads(case.source)
        return [_sub(a, subs) for a in argv]
    src = Path(case.source)
    if case.kind == "measurements":
        src = measurements
    inp = _companions(case, src, ws / "in")
    if case.kind == "landmarks":
        extra, inp = ["--landmarks", str(inp)], mesh
    else:
        extra = []
    picture = "p.svg" if case.seed % 2 else "p.png"
    pattern_cmds = {
        "import": ["import", str(inp), "-o", str(out / "p.json")],
        "info": ["info", str(inp), "--json"],
        "export": ["export", str(inp), "-o", str(out / "e.dxf")],
        "plot": ["plot", str(inp), "-o", str(out / picture)],
        "check": ["check", str(inp), "--json"],
        "seams": ["seams", "infer", str(inp), "-o", str(out / "s.seams.json")],
    }
    if case.command in pattern_cmds:
        return pattern_cmds[case.command]
    if case.command == "measure":
        return ["measure", str(inp), "-o", str(out / "m.json"), *extra]
    if case.command == "geodesic":
        return ["geodesic", str(inp), "--from", "0", "--to", "881", "--json", *extra]
    if case.kind == "pattern":
        return ["fit", str(measurements), "--garment", str(inp), *FIT_BUDGET, "-o", str(out / "fit")]
    return ["fit", str(inp), "--garment", "shorts", *FIT_BUDGET, "-o", str(out / "fit")]


def _sub(arg: str, subs: dict[str, str]) -> str:
    for key, value in subs.items():
        arg = arg.replace(key, value)
    return arg


# ------------------------------------------------------------------ checks of what was written
def _strict_json(text: str):
    def refuse(name):
        raise ValueError(f"{name} in JSON output")

    return json.loads(text, parse_constant=refuse)


def _finite_numbers(obj, where: str) -> None:
    """Raise when any number in a parsed JSON value is not finite (strict parse already refuses NaN)."""
    stack = [obj]
    while stack:
        item = stack.pop()
        if isinstance(item, dict):
            stack.extend(item.values())
        elif isinstance(item, list):
            stack.extend(item)
        elif isinstance(item, float) and not math.isfinite(item):
            raise ValueError(f"{where}: non-finite number {item}")


def _check_pattern(pattern, where: str) -> None:
    from patternbridge.pattern.geometry import area as polygon_area

    if not pattern.pieces:
        raise ValueError(f"{where}: pattern without pieces")
    for piece in pattern.pieces:
        area = polygon_area(piece.outline)
        if not math.isfinite(area) or abs(area) <= 0:
            raise ValueError(f"{where}: piece {piece.name[:40]!r} has area {area}")


def check_file(path: Path) -> None:
    """Read a written file back the way a user would; raise on anything wrong."""
    suffix = path.suffix.lower()
    name = path.name
    if suffix == ".json":
        data = _strict_json(path.read_text(encoding="utf-8"))
        _finite_numbers(data, name)
        if name.endswith(".seams.json"):
            return
        if isinstance(data, dict) and data.get("format") == "patternbridge.pattern":
            from patternbridge.io.pattern_json import load_pattern_json

            _check_pattern(load_pattern_json(path), name)
        elif isinstance(data, dict) and data.get("format") == "patternbridge-measurements":
            from patternbridge.measure.model import load_measurements

            values = load_measurements(path).values_cm()
            stature = values.get("stature")
            if stature is not None and not STATURE_CM[0] <= stature <= STATURE_CM[1]:
                raise ValueError(f"{name}: stature {stature:.4g} cm is not a body")
    elif suffix == ".dxf":
        from patternbridge.io.dxf_aama import read_dxf

        rul = path.with_suffix(".rul")
        pattern, _ = read_dxf(path, rul=rul if rul.is_file() else None)
        _check_pattern(pattern, name)
    elif suffix == ".png":
        data = path.read_bytes()
        if not data.startswith(b"\x89PNG\r\n\x1a\n") or len(data) < 200:
            raise ValueError(f"{name}: not a PNG")
    elif suffix == ".svg":
        import xml.etree.ElementTree as ET

        ET.parse(path)
    elif suffix == ".rul":
        if not path.read_bytes().strip():
            raise ValueError(f"{name}: empty RUL")


def check_outputs(case: Case, argv: list[str], out: Path, stdout: str) -> None:
    """The exit-0 checks: every written file re-reads, stdout JSON is finite, nothing stray."""
    for path in sorted(p for p in out.rglob("*") if p.is_file()) if out.is_dir() else []:
        if path.name.startswith("."):
            raise ValueError(f"temporary file {path.name} left behind")
        check_file(path)
    if "--json" in argv:
        data = _strict_json(stdout)
        _finite_numbers(data, "stdout")
        if case.command == "geodesic" and not 0 < data.get("length_cm", -1) < 1e4:
            raise ValueError(f"geodesic length {data.get('length_cm')} cm")
    elif any(tok in stdout.lower().split() for tok in ("nan", "inf", "-inf")):
        raise ValueError("NaN or inf printed")


# ------------------------------------------------------------------ the child process
def _child(case: Case, ws: Path, measurements: Path) -> int:
    from patternbridge.cli.main import main

    report = ws / "result.json"
    argv: list[str] = []
    try:
        argv = argv_for(case, ws, measurements)
        (ws / "out").mkdir(parents=True, exist_ok=True)
        try:
            code = main(argv)
        except SystemExit as exc:  # argparse rejects bad arguments with exit 2
            code = exc.code if isinstance(exc.code, int) else 2
        sys.stdout.flush()
        sys.stderr.flush()
        detail = ""
        if code == 0 or (code == 1 and case.command == "check"):  # check: 1 = seams do not match
            try:
                check_outputs(case, argv, ws / "out", (ws / "stdout").read_text(encoding="utf-8", errors="replace"))
            except Exception as exc:  # a check failing is the finding, whatever it raised
                detail = f"{type(exc).__name__}: {str(exc)[:300]}"
        outcome = {"code": code, "detail": detail}
    except BaseException as exc:  # the fuzz target: anything escaping main is a traceback
        tb = traceback.extract_tb(exc.__traceback__)
        frame = tb[-1] if tb else None
        where = f" at {Path(frame.filename).name}:{frame.lineno}" if frame else ""
        outcome = {"code": "traceback", "detail": f"{type(exc).__name__}: {str(exc)[:200]}{where}"}
    report.write_text(json.dumps(outcome))
    return 0


def _classify(case: Case, ws: Path, result: dict | None, seconds: float) -> Result:
    if result is None:
        return Result(case, Outcome.TRACEBACK, "child died without a result (crash or signal)", seconds)
    code, detail = result["code"], result["detail"]
    if code == "traceback":
        return Result(case, Outcome.TRACEBACK, detail, seconds)
    err = (ws / "stderr").read_text(encoding="utf-8", errors="replace")
    if code == 0 or (code == 1 and case.command == "check"):
        return Result(case, Outcome.NONSENSE if detail else Outcome.OK, detail, seconds)
    lines = [line for line in err.splitlines() if line.startswith("patternbridge: error:") or "Error" in line]
    out = ws / "out"
    left = [p.name for p in out.rglob("*")] if out.is_dir() else []
    if code != 2 or "Traceback" in err:
        return Result(case, Outcome.TRACEBACK, f"exit {code}: {err.strip()[-200:]}", seconds)
    if left:
        return Result(case, Outcome.NONSENSE, f"error left files behind: {left[:3]}", seconds)
    error_lines = [line for line in err.splitlines() if line.startswith("patternbridge: error:")]
    usage = err.lstrip().startswith("usage:")
    if len(error_lines) != 1 and not usage:
        return Result(case, Outcome.NONSENSE, f"error is not one line: {lines[:2]}", seconds)
    return Result(case, Outcome.ERROR, (error_lines or [err.strip().splitlines()[-1]])[0][:300], seconds)


WALL_FACTOR = 5.0
"""A case is also killed after this many times its CPU limit in wall time (a child stuck waiting)."""


def _cpu_seconds(pid: int) -> float:
    """CPU time (user + system) used so far by process ``pid``; 0 once it has ended."""
    try:
        fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    except (OSError, IndexError):
        return 0.0
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def run_case(case: Case, work: Path, measurements: Path, timeout_s: float = 60.0, keep: bool = False) -> Result:
    """Run ``case`` in a forked child under ``work``; classify it (see the module docstring).

    ``timeout_s`` counts the child's CPU time, so a case is not called a hang
    because the machine is shared; ``WALL_FACTOR`` times it in wall time is the
    hard stop.
    """
    ws = work / f"case-{zlib.crc32(case.id.encode()):010d}"
    shutil.rmtree(ws, ignore_errors=True)
    ws.mkdir(parents=True)
    t0 = time.perf_counter()
    pid = os.fork()
    if pid == 0:  # pragma: no cover - runs in the child
        code = 1
        try:
            os.setpgid(0, 0)
            out = os.open(ws / "stdout", os.O_WRONLY | os.O_CREAT | os.O_TRUNC)
            err = os.open(ws / "stderr", os.O_WRONLY | os.O_CREAT | os.O_TRUNC)
            os.dup2(out, 1)
            os.dup2(err, 2)
            # under pytest sys.stdout/sys.stderr are capture objects, not fds 1 and 2
            sys.stdout = open(1, "w", encoding="utf-8", closefd=False)
            sys.stderr = open(2, "w", encoding="utf-8", closefd=False)
            signal.signal(signal.SIGINT, signal.SIG_DFL)
            code = _child(case, ws, measurements)
        finally:
            os._exit(code)
    while _cpu_seconds(pid) < timeout_s and time.perf_counter() - t0 < WALL_FACTOR * timeout_s:
        done, _ = os.waitpid(pid, os.WNOHANG)
        if done:
            break
        time.sleep(0.02)
    else:
        cpu = _cpu_seconds(pid)
        with contextlib.suppress(ProcessLookupError):
            os.killpg(pid, signal.SIGKILL)
        os.waitpid(pid, 0)
        wall = time.perf_counter() - t0
        result = Result(case, Outcome.HANG, f"killed after {cpu:.0f} s CPU, {wall:.0f} s wall", wall)
        if not keep:
            shutil.rmtree(ws, ignore_errors=True)
        return result
    seconds = time.perf_counter() - t0
    report = ws / "result.json"
    data = json.loads(report.read_text()) if report.is_file() else None
    result = _classify(case, ws, data, seconds)
    if not keep:
        shutil.rmtree(ws, ignore_errors=True)
    return result


def preload() -> None:
    """Import what the commands import, once, so forked children start warm."""
    import matplotlib

    matplotlib.use("Agg")
    import ezdxf  # noqa: F401
    import shapely  # noqa: F401
    import trimesh  # noqa: F401

    import patternbridge.cli.main
    import patternbridge.io.dxf_aama
    import patternbridge.io.load
    import patternbridge.io.pattern_json
    import patternbridge.io.plot
    import patternbridge.io.plot_fit
    import patternbridge.library.seams
    import patternbridge.library.sidecar
    import patternbridge.measure.run
    import patternbridge.mesh.gltf
    import patternbridge.mesh.load

    with contextlib.suppress(ImportError):
        import patternbridge.grade.run  # noqa: F401


def measurements_file(work: Path) -> Path:
    """A real measurements JSON (the E character measured once), the source of the measurements cases."""
    path = work / "measurements.json"
    if not path.is_file():
        from patternbridge.measure.model import write_measurements
        from patternbridge.measure.run import measure
        from patternbridge.mesh.load import load_character

        character, _ = load_character(SHARED / "characters" / "E_average_male.obj")
        write_measurements(path, measure(character, partial=True))
    return path


def assert_clean_error(result, *needles: str, outputs: tuple[Path, ...] = ()) -> str:
    """Exit 2, one ``patternbridge: error:`` line containing ``needles``, nothing written."""
    code, _out, err = result
    assert code == 2, err[-2000:]
    assert "Traceback" not in err
    lines = [line for line in err.splitlines() if line.startswith("patternbridge: error:")]
    assert len(lines) == 1, err[-2000:]
    assert len(lines[0]) < 1000, "the error line carries the whole bad value"
    for needle in needles:
        assert needle.lower() in lines[0].lower(), lines[0]
    for out in outputs:
        assert not out.exists(), f"{out} written after an error"
        assert not list(out.parent.glob(f".{out.stem}.*")), "temporary file left behind"
    return lines[0]
