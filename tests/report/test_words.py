"""Numbers in one notation down a column (the terms of the event page: tests/event/test_event.py)."""

from __future__ import annotations


def test_annual_rates_read_in_one_notation():
    from pipeline.report.fragility_html import rate_text

    got = [rate_text(x) for x in (1.92e-05, 0.000114, 0.0031, float("nan"))]
    assert got == ["1.92e-05", "1.14e-04", "3.10e-03", ""]
