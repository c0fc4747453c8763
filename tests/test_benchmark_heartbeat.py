"""The benchmarks' heartbeat (benchmarks/heartbeat.py): a benchmark run as a script that waits in silence says every
2 s that it runs, its own output restarts the silence, and a benchmark imported by a test starts nothing."""

from __future__ import annotations

import subprocess
import sys
import time
from pathlib import Path

import pytest

BENCHMARKS = Path(__file__).resolve().parents[1] / "benchmarks"
pytestmark = pytest.mark.slow       # about 6 s of waiting; the developers' tooling, not the product


def _lines_with_times(code: str) -> list[tuple[float, str]]:
    """Run ``code`` in a child interpreter with the benchmarks' folder on its path; every line it prints (stdout and
    stderr together) with when it came [s]."""
    prelude = f"import sys, time; sys.path.insert(0, {str(BENCHMARKS)!r}); "
    proc = subprocess.Popen([sys.executable, "-u", "-c", prelude + code], stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True)
    t0 = time.monotonic()
    assert proc.stdout is not None
    lines = [(time.monotonic() - t0, line.rstrip("\n")) for line in proc.stdout]
    assert proc.wait() == 0
    return lines


def test_a_silent_benchmark_says_every_2_s_that_it_runs_and_its_own_output_restarts_the_silence():
    lines = _lines_with_times("import heartbeat; heartbeat.start('probe'); time.sleep(2.1); print('half'); "
                              "time.sleep(1.0); print('done')")
    texts = [text for _, text in lines]
    assert texts[-1] == "done" and "half" in texts
    beats = [text for text in texts if text.startswith("  ... probe: ")]
    assert len(beats) == 1, texts                          # within the 2.1 s silence; none in the 1.0 s one
    half = texts.index("half")
    assert all(not text.startswith("  ... ") for text in texts[half + 1:-1]), texts
    times = [0.0] + [t for t, _ in lines]
    assert max(b - a for a, b in zip(times, times[1:])) < 2.5, lines   # 2 s, and the child's start


def test_a_benchmark_imported_rather_than_run_starts_no_heartbeat():
    lines = _lines_with_times("import heartbeat; time.sleep(2.2); print('done')")
    assert [text for _, text in lines] == ["done"]
