"""The Examples in the pure modules' docstrings run and hold."""

from __future__ import annotations

import doctest
import importlib
import pkgutil

import pytest

import patternbridge

PURE_PACKAGES = ("patternbridge.pattern", "patternbridge.measure", "patternbridge.library")
PURE_MODULES = ("patternbridge.units", "patternbridge.report", "patternbridge.atomic", "patternbridge.geodesic.tape")
#: I/O modules whose pure helpers carry Examples (notch ticks, label size, line ends)
IO_MODULES = ("patternbridge.io.plot", "patternbridge.io.dxf_aama.write")


def _modules() -> list[str]:
    names = [*PURE_MODULES, *IO_MODULES]
    for pkg_name in PURE_PACKAGES:
        pkg = importlib.import_module(pkg_name)
        names += [m.name for m in pkgutil.iter_modules(pkg.__path__, pkg_name + ".")]
    return names


@pytest.mark.parametrize("name", _modules())
def test_docstring_examples(name):
    module = importlib.import_module(name)
    result = doctest.testmod(module, optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    assert result.failed == 0, f"{result.failed} of {result.attempted} examples failed in {name}"


def test_package_import_is_light():
    import subprocess
    import sys

    code = (
        "import sys, patternbridge, patternbridge.cli.main as m; m.build_parser();"
        "heavy = [n for n in ('open3d', 'pymoo', 'ezdxf', 'matplotlib') if n in sys.modules];"
        "print(','.join(heavy))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "", f"--help imports heavy modules: {out.stdout.strip()}"
    assert patternbridge.__version__
