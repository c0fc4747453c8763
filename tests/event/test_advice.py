"""The words of an event's recommendations: each inspection level an action with the probability it rests on;
an asset with only bounds, without a fragility or too wide to rock said so, never "stands"; a natural rock never
told to be inspected as an asset; a scenario worded as a plan."""

from __future__ import annotations

import math

import pytest

from pipeline.event.advice import recommendation
from pipeline.event.assets import Basis, Level

NAN = math.nan


@pytest.mark.parametrize("level, p, start, reason", [
    (Level.high, 0.62, "inspect first", "it probably overturned (P = 0.62)"),
    (Level.medium, 0.22, "inspect:", "it may have overturned (P = 0.22)"),
    (Level.low, 0.08, "inspect after the high and medium ones", "unlikely to have overturned (P = 0.08)"),
    (Level.none, 0.004, "no inspection for overturning", "it very probably stands (P = <0.01)"),
])
def test_each_level_is_an_action_with_its_probability(level, p, start, reason):
    text = recommendation(level, Basis.fitted, p, p / 2, min(2 * p, 1.0), slides=False, scenario=False)
    assert text.startswith(start) and text.endswith(reason), text


@pytest.mark.parametrize("basis", [Basis.bounds_only, Basis.unjudged])
def test_only_bounds_are_said_as_bounds_never_as_a_verdict(basis):
    text = recommendation(Level.high, basis, NAN if basis == Basis.bounds_only else 0.3, 0.1, 0.7, slides=False,
                          scenario=False)
    assert text == "inspect first: only bounds of its chance of overturning are known (P 0.10 to 0.70)"


def test_no_fragility_is_unknown_and_too_wide_cannot_overturn():
    unknown = recommendation(Level.high, Basis.no_fragility, NAN, NAN, NAN, slides=False, scenario=False)
    assert unknown.startswith("inspect") and "not known" in unknown and "stand" not in unknown
    wide = recommendation(Level.none, Basis.cannot_rock, 0.0, 0.0, 0.0, slides=True, scenario=False)
    assert wide.startswith("no inspection for overturning: too wide to rock")
    assert wide.endswith("check it for sliding: it slides at this shaking")


def test_a_scenario_is_a_plan_and_a_natural_rock_is_checked_not_inspected():
    plan = recommendation(Level.medium, Basis.fitted, 0.22, 0.1, 0.3, slides=False, scenario=True)
    assert plan == "inspect: it may overturn (P = 0.22)"
    rock = recommendation(Level.low, Basis.fitted, 0.16, 0.1, 0.2, slides=False, scenario=False, natural=True)
    assert rock.startswith("check whether it still stands (a natural rock")
    assert rock.endswith("P = 0.16 that it toppled")
    planned = recommendation(Level.low, Basis.fitted, 0.16, 0.1, 0.2, slides=False, scenario=True, natural=True)
    assert planned.startswith("no action (a natural rock, never restrained)")
