"""Entry point: builds the sub-command parsers and maps errors to exit codes.

Each sub-command lives in ``patternbridge/cli/<module>.py`` and exposes
``add_arguments(parser)``, ``run(args) -> int`` and a one-line ``HELP``.
Heavy imports happen inside ``run`` so ``--help`` stays fast.
"""

from __future__ import annotations

import argparse
import contextlib
import importlib
import logging
import os
import signal
import sys
import threading
from collections.abc import Sequence

from .. import __version__
from ..errors import PatternBridgeError

__all__ = ["main"]

# command name -> module under patternbridge.cli, in the order --help lists them
COMMANDS: dict[str, str] = {
    "fit": "fit",
    "batch": "batch",
    "import": "import_",
    "info": "info",
    "export": "export",
    "grade": "grade",
    "plot": "plot",
    "check": "check",
    "seams": "seams",
    "bridge": "bridge",
    "library": "library",
    "measure": "measure",
    "geodesic": "geodesic",
}


def _load(module: str):
    name = f"{__package__}.{module}"
    try:
        return importlib.import_module(name)
    except ModuleNotFoundError as exc:  # a command not built yet is simply absent
        if exc.name == name:
            return None
        raise


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="patternbridge",
        description="Fit real tailoring patterns (DXF-AAMA/ASTM + RUL) to animation "
        "characters: import, measure, grade, drape, export.",
    )
    parser.add_argument(
        "--version", action="version", version=f"%(prog)s {__version__}"
    )
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True
    for command, module_name in COMMANDS.items():
        module = _load(module_name)
        if module is None:
            continue
        p = sub.add_parser(command, help=module.HELP, description=module.HELP)
        p.add_argument("-v", "--verbose", action="count", default=0, help="more output")
        p.add_argument("-q", "--quiet", action="count", default=0, help="less output")
        module.add_arguments(p)
        p.set_defaults(_run=module.run)
    return parser


def _configure_logging(verbosity: int) -> None:
    level = {-1: logging.ERROR, 0: logging.WARNING, 1: logging.INFO}.get(
        max(-1, min(verbosity, 2)), logging.DEBUG
    )
    logging.basicConfig(level=level, format="patternbridge: %(levelname)s: %(message)s")


class _Terminated(BaseException):
    """SIGTERM turned into an exception so ``finally`` blocks remove temporary files."""


def _raise_terminated(signum, frame) -> None:
    raise _Terminated


@contextlib.contextmanager
def _terminate_cleanly():
    """While running a command, SIGTERM unwinds the stack (the default would kill at once).

    Atomic writes delete their temporary file in ``finally``; a plain SIGTERM
    would skip that and leave a ``.name.XXXX`` file beside the target.
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.signal(signal.SIGTERM, _raise_terminated)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous)


def main(argv: Sequence[str] | None = None) -> int:
    """Run the CLI; return the process exit code (0 ok, 2 bad input, 130/143 interrupted)."""
    parser = build_parser()
    args = parser.parse_args(argv)
    _configure_logging(args.verbose - args.quiet)
    try:
        with _terminate_cleanly():
            code = int(args._run(args) or 0)
        sys.stdout.flush()  # surface a closed pipe here, not at interpreter exit
        return code
    except PatternBridgeError as exc:
        print(f"patternbridge: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("patternbridge: interrupted", file=sys.stderr)
        return 130
    except _Terminated:
        print("patternbridge: terminated", file=sys.stderr)
        return 143
    except BrokenPipeError:
        # the reader went away (`patternbridge info x.dxf | head`): not an error of ours
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
