"""Words on the pages: numbers in one notation down a column (the terms of the event page: tests/event/test_event.py),
and the decisions of the report's first screen."""

from __future__ import annotations

import math


def test_annual_rates_read_in_one_notation():
    from pipeline.report.fragility_html import rate_text

    got = [rate_text(x) for x in (1.92e-05, 0.000114, 0.0031, float("nan"))]
    assert got == ["1.92e-05", "1.14e-04", "3.10e-03", ""]


def test_the_first_screen_names_the_assets_that_call_for_action_in_words():
    """The decision first: the assets whose decision calls for something, riskiest first, each with its decision
    (the recommendation's action) and why in words; the tally counts every asset once."""
    from pipeline.report.decisions import FIRST_SCREEN_ASSETS, first_screen, tally

    def row(block, recommendation, over, margin, p):
        return {"block": block, "block_name": f"name of {block}", "recommendation": recommendation,
                "stations_overturning": over, "stations_screened": 31, "overturn_scale_simulated": margin,
                "p_overturn": p, "governing_record": "RSN1063"}

    assets = [row("A", "restrain or anchor: p = 1.00 under RSN1063", 24, 0.24, 1.0),
              row("B", "restrain: p = 0.12 under RSN1063", 0, 1.08, 0.12),
              row("C", "limit sliding (friction pads or a restraint): it slides 0.35 m under RSN1063", 0, math.inf,
                  0.0),
              row("D", "no action: p = 0.00", 0, math.inf, 0.0)]
    first = first_screen(assets)
    assert [d["block"] for d in first] == ["A", "B", "C"]                  # "no action" is in the tally only
    assert first[0]["decision"] == "restrain or anchor"
    assert first[0]["reason"] == ("24 of the 31 stations' records overturn it; RSN1063 overturns it at 0.24 times "
                                  "its shaking; its highest chance of overturning over the records is 100 %.")
    assert first[1]["reason"].startswith("none of the 31 stations' records overturns it; RSN1063 overturns it at "
                                         "1.08 times its shaking")
    assert first[2]["reason"] == "it slides 0.35 m under RSN1063."
    assert dict(tally(assets)) == {"restrain or anchor": 1, "restrain": 1,
                                   "limit sliding (friction pads or a restraint)": 1, "no action": 1}
    many = [row(f"X{i}", "restrain or anchor: p = 1.00", 3, 0.5, 1.0) for i in range(FIRST_SCREEN_ASSETS + 3)]
    assert len(first_screen(many)) == FIRST_SCREEN_ASSETS
    assert [d["block"] for d in first_screen([assets[3]])] == ["D"]          # nothing to do: the riskiest still shown


def test_the_first_screen_says_why_two_records_are_named():
    """Where the record of the highest chance is not the governing one (the smallest overturning factor), the
    sentence names both and says which is which."""
    from pipeline.report.decisions import reason_of

    row = {"block": "S", "recommendation": "restrain or anchor: p = 1.00 under NGA", "stations_overturning": 13,
           "stations_screened": 31, "overturn_scale_simulated": 0.96, "p_overturn": 1.0, "p_record": "NGA",
           "governing_record": "RSN723"}
    assert reason_of(row) == ("13 of the 31 stations' records overturn it; RSN723 overturns it at 0.96 times its "
                              "shaking; its highest chance of overturning over the records is 100 %, under NGA: "
                              "the record with the highest chance is not the one that overturns it at the smallest "
                              "factor, RSN723.")
    assert "not the one" not in reason_of(dict(row, p_record="RSN723"))

