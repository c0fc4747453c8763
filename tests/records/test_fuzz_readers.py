"""A fuzz of the readers (tables plain and gzip, AT2, COSMOS, DMG, meshes, inventories) under a 3 GB address-space
cap, in a process of its own (tests/support/fuzz_readers.py): every mutated or random input is read or refused by a
named error; no traceback, no MemoryError."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

FUZZ = Path(__file__).resolve().parents[1] / "support" / "fuzz_readers.py"


@pytest.mark.slow
@pytest.mark.parametrize("seed", [7, 11])
def test_fuzzed_inputs_are_read_or_refused_by_name_in_bounded_memory(seed):
    proc = subprocess.run([sys.executable, str(FUZZ), "3", "3000", str(seed)], capture_output=True, text=True,
                          timeout=900)
    assert proc.returncode == 0, proc.stderr[-4000:]
    assert "3000 inputs, 0 not read nor refused by a named error" in proc.stdout
