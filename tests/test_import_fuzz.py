"""The fuzz suite's importer kinds (Moving AI, PNG, TMX, Tiled JSON, LDtk), asserted: ``tests/test_fuzz.py``
counts them but leaves them to this file, since guardsim/importers/ is fixed apart.

Every generated input (``tests/fuzz_cases.py``: mutations of valid maps, nasty numbers and values,
special files, huge declared sizes) run through ``guardsim import`` must keep the rule: exit 0 with a
level that loads, or exit 2 with one stderr line naming the file; no traceback, no half-written file.
Derandomised; ``benchmarks/fuzz.py`` runs any number of cases.
"""

from __future__ import annotations

import tempfile
from collections import Counter
from pathlib import Path

import numpy as np
import pytest

# The generators are the fuzz suite's (another part of the project); without them there is nothing to run.
fuzz_cases = pytest.importorskip("tests.fuzz_cases", reason="tests/fuzz_cases.py (the fuzz generators) is absent")
IMPORTER_KINDS = sorted(getattr(fuzz_cases, "IMPORTER_KINDS", ()))

#: Cases per importer kind in CI.
CASES = 100
#: The seed of the CI cases (the same scheme as tests/test_fuzz.py, so a case is found by its index).
SEED = 16


@pytest.mark.parametrize(
    "kind",
    # tmx (6-7 s: XML through pytiled-parser) runs in the slow tier; tiled-json keeps the Tiled path in the fast one.
    [pytest.param(kind, marks=[pytest.mark.slow] if kind == "tmx" else []) for kind in IMPORTER_KINDS],
)
def test_generated_maps_keep_the_rule(kind: str) -> None:
    failures: Counter[str] = Counter()
    examples: dict[str, str] = {}
    for index in range(CASES):
        rng = np.random.default_rng([SEED, index, *map(ord, kind)])
        case = fuzz_cases.generate(kind, "import", rng, None)
        with tempfile.TemporaryDirectory() as folder:
            outcome = fuzz_cases.run_in_process(case, Path(folder))
        if outcome != "ok":
            failures[outcome] += 1
            examples.setdefault(outcome, f"case {index}: {case.note}")
    assert not failures, f"{dict(failures)}; first of each: {examples}"
