"""The two-sided rocking model (pipeline.rocking.references.asymmetric): a rectangle reduces to Housner's block (the
event-driven reference solver and the compiled kernel, on pulses); the impact rule is Housner's for equal sides,
never adds energy, and is the angular momentum balance about the new pivot (by vectors, in
test_properties_asymmetric.py);
uplift happens toward each side at its own threshold, exactly; a mirrored body under a mirrored motion mirrors."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pipeline.rocking.references.asymmetric import rock_two_sided
from pipeline.rocking.references.reference import rock_reference
from pipeline.rocking.scanned.two_sided_body import TwoSided, rectangle

G = 9.80665
DT = 0.005


def _pulse(amp_g, period_s, n=1600):
    t = np.arange(n) * DT
    return np.where(t < period_s, amp_g * G * np.sin(2 * np.pi * t / period_s), 0.0)


@pytest.mark.parametrize("amp_g,period_s", [(0.25, 0.6), (0.22, 0.5), (0.28, 0.7), (0.3, 0.8), (0.5, 0.5)])
def test_a_rectangle_is_housners_block(amp_g, period_s):
    w, h = 0.3, 1.5
    alpha, R = math.atan2(w / 2, h / 2), math.hypot(w / 2, h / 2)
    a = _pulse(amp_g, period_s)
    ours = rock_two_sided(a, DT, rectangle(w, h))
    ref = rock_reference(a, DT, p=math.sqrt(0.75 * G / R), alpha=alpha, e=1 - 1.5 * math.sin(alpha) ** 2)
    assert ours.overturned == ref.overturned and ours.n_impacts == ref.n_impacts
    assert max(ours.theta_max_plus, ours.theta_max_minus) / alpha == pytest.approx(ref.theta_max_ratio, rel=1e-4)


def test_the_impact_rule_is_housners_for_equal_sides():
    for w, h in ((0.3, 1.5), (1.0, 1.0), (0.2, 3.0)):
        alpha = math.atan2(w, h)
        assert rectangle(w, h).impact_ratio(1.0) == pytest.approx(1 - 1.5 * math.sin(alpha) ** 2, rel=1e-12)


@pytest.mark.parametrize("side", [1.0, -1.0])
def test_uplift_toward_each_side_at_its_own_threshold_exactly(side):
    body = TwoSided(0.1, 0.3, 0.5, 0.05)
    alpha = body.side(side)[0]
    a = np.full(400, -side * G * math.tan(alpha))                 # pushes it toward side at its threshold
    at = rock_two_sided(a, DT, body)
    assert at.theta_max_plus == 0.0 and at.theta_max_minus == 0.0 and not at.overturned
    above = rock_two_sided(a * (1 + 1e-6), DT, body)
    assert (above.theta_max_plus if side > 0 else above.theta_max_minus) > 0.0


def test_a_mirrored_body_under_a_mirrored_motion_mirrors():
    body, mirror = TwoSided(0.12, 0.25, 0.5, 0.06), TwoSided(0.25, 0.12, 0.5, 0.06)
    a = _pulse(0.3, 0.7)
    one, two = rock_two_sided(a, DT, body), rock_two_sided(-a, DT, mirror)
    assert one.overturned == two.overturned and one.n_impacts == two.n_impacts
    assert one.theta_max_plus == pytest.approx(two.theta_max_minus, rel=1e-9)
    assert one.theta_max_minus == pytest.approx(two.theta_max_plus, rel=1e-9)


def test_the_easy_side_tips_first():
    """A body 15 deg to tip one way and 55 deg the other, like the granite rocks: a one-lobe pulse of 0.5 g toward
    the easy side overturns it; reversed, it cannot even lift it (tan 55 deg = 1.43)."""
    z = 0.3
    body = TwoSided(z * math.tan(math.radians(15.0)), z * math.tan(math.radians(55.0)), z, 0.04)
    t = np.arange(1600) * DT
    a = np.where(t < 0.8, 0.5 * G * np.sin(np.pi * t / 0.8), 0.0)
    easy, hard = rock_two_sided(-a, DT, body), rock_two_sided(a, DT, body)   # -a pushes it toward +x
    assert easy.overturned and not hard.overturned and hard.theta_max_minus == 0.0
