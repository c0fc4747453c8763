"""make's installs and warm-up speak while pip or numba is silent (tools/ticking.py): the command's output passes
through, a line comes at least every 2 s of silence, and the command's exit code is kept."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

TICKING = Path(__file__).resolve().parents[1] / "tools" / "ticking.py"


# make test keeps under 5 min from a fresh clone; CI runs it in make test-slow
@pytest.mark.slow
def test_a_silent_command_is_announced_and_its_output_and_exit_code_kept():
    out = subprocess.run([sys.executable, str(TICKING), "installing", "--", "sh", "-c",
                          "echo first; sleep 2.6; echo last; exit 3"], capture_output=True, text=True, timeout=30)
    lines = out.stdout.splitlines()
    assert out.returncode == 3
    assert lines[0] == "first" and lines[-1] == "last"
    assert any(line.startswith("  ... installing: ") for line in lines[1:-1]), lines


def test_a_call_without_its_separator_is_refused_with_the_usage():
    out = subprocess.run([sys.executable, str(TICKING), "installing", "pip"], capture_output=True, text=True,
                         timeout=30)
    assert out.returncode == 2 and "usage: python tools/ticking.py LABEL -- COMMAND" in out.stderr
