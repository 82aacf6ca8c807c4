"""A deterministic sample of the 1,132-case mutation run (``benchmarks/fuzz.py``) in every CI run.

Every 37th case of the full list from the 11th (31: every input kind and command),
each in a forked child with a 60 s timeout. A case passes when it ends in a
clean one-line error or in an exit 0 whose files read back (see ``fuzz_run``).
"""

from __future__ import annotations

import pytest
from fuzz_run import SHARED, Outcome, build_cases, preload, run_case

STEP = 37
CASES = build_cases()[10::STEP] if SHARED.is_dir() else []


@pytest.fixture(scope="module")
def warm(measurements_json):
    preload()
    return measurements_json


@pytest.mark.parametrize("case", CASES, ids=[c.id for c in CASES])
def test_mutated_input(case, warm, tmp_path):
    result = run_case(case, tmp_path, warm, timeout_s=60.0)
    assert result.outcome in (Outcome.ERROR, Outcome.OK), f"{result.outcome}: {result.detail}"
