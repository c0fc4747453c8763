"""The one ticker: no silence longer than its period, the first word after its own delay, and output from elsewhere
restarting the silence."""

from __future__ import annotations

import time

from pipeline.ticker import Ticker


def _run(seconds: float, **kw) -> list[float]:
    spoke: list[float] = []
    with Ticker(lambda _t: spoke.append(time.monotonic()), **kw):
        time.sleep(seconds)
    return spoke


def test_no_silence_exceeds_the_period():
    t0 = time.monotonic()
    spoke = _run(1.0, every_s=0.2)
    gaps = [b - a for a, b in zip([t0, *spoke], spoke)]
    assert len(spoke) >= 4 and max(gaps) <= 0.2 + 0.1, gaps        # a look's slack for a loaded machine


def test_the_first_word_waits_for_its_own_delay_and_zero_speaks_at_once():
    assert _run(0.3, every_s=0.2, first_after_s=10.0) == []
    t0 = time.monotonic()
    spoke = _run(0.05, every_s=1.0, first_after_s=0.0)
    assert spoke and spoke[0] - t0 < 0.5


def test_output_from_elsewhere_restarts_the_silence():
    spoke: list[float] = []
    ticker = Ticker(lambda _t: spoke.append(time.monotonic()), every_s=0.3)
    with ticker:
        for _ in range(8):                 # something else prints every 0.1 s: the ticker has nothing to add
            time.sleep(0.1)
            ticker.said()
    assert spoke == []
