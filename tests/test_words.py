"""Numbers in one notation down a column, and terms explained where they appear."""

from __future__ import annotations


def test_annual_rates_read_in_one_notation():
    from pipeline.report.fragility_html import rate_text

    got = [rate_text(x) for x in (1.92e-05, 0.000114, 0.0031, float("nan"))]
    assert got == ["1.92e-05", "1.14e-04", "3.10e-03", ""]


def test_the_event_page_explains_p_bounds_and_basis_where_they_appear():
    from pathlib import Path

    page = (Path(__file__).resolve().parents[1] / "pipeline" / "report" / "templates" / "event.html.j2").read_text()
    terms = page[page.index('id="terms"'):page.index('id="detail-table"')]
    for word in ("P bounds", "basis", "fitted", "extrapolated", "bounds only", "cannot rock", "no fragility"):
        assert word in terms, word
