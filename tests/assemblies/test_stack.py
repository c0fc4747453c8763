"""A stack's statics and the certificate that its interfaces stay shut, against closed forms: Housner's uplift
bound for one block, a statue on its plinth worked by hand, and a column of equal drums against the single block of
its outline."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pipeline.assemblies.stack import StackBody, interfaces, opening_ratio, stays_shut, uplift_ratios
from pipeline.errors import BlockParameterError

G = 9.80665
STATUE, PLINTH = StackBody(0.4, 1.6, 100.0, 0.6), StackBody(1.0, 1.0, 500.0, 0.6)


@pytest.mark.parametrize("width, height, mu", [(0.4, 1.6, 0.6), (0.5, 1.0, 0.3), (0.3, 2.7, 0.9)])
def test_one_block_opens_at_housners_bound_and_slips_at_coulombs(width, height, mu):
    """One block: the interface's bounds are -/+ tan alpha = b / h (Housner 1963); at rest exactly at
    min(tan alpha, mu) g, moving a rounding above it (tie rule 2: motion only where the demand exceeds)."""
    block = [StackBody(width, height, 10.0, mu)]
    low, high = uplift_ratios(interfaces(block)[0])
    assert (low, high) == pytest.approx((-width / height, width / height), rel=1e-15)
    limit = min(width / height, mu) * G
    for sign in (1.0, -1.0):
        assert stays_shut(block, np.array([0.0, sign * limit, 0.0]))
        assert not stays_shut(block, np.array([0.0, sign * limit * (1 + 1e-12), 0.0]))


def test_a_statue_on_its_plinth_worked_by_hand():
    """A 0.4 x 1.6 m statue of 100 kg centred on a 1.0 x 1.0 m plinth of 500 kg: the statue's joint opens at
    a_h = 0.2 / 0.8 g = 0.25 g; the plinth's base carries G at (500 x 0.5 + 100 x 1.8) / 600 = 0.7167 m, opening at
    0.5 / 0.7167 g = 0.698 g; so the joint governs, and with mu 0.2 at the joint the slip does."""
    base, joint = interfaces([PLINTH, STATUE])
    assert uplift_ratios(joint) == pytest.approx((-0.25, 0.25), rel=1e-15)
    assert base.z_m == pytest.approx(430.0 / 600.0, rel=1e-15)
    assert uplift_ratios(base)[1] == pytest.approx(0.5 / (430.0 / 600.0), rel=1e-15)
    ramp = np.linspace(0.0, 1.0, 11)
    assert stays_shut([PLINTH, STATUE], 0.249 * G * ramp)
    assert not stays_shut([PLINTH, STATUE], 0.251 * G * ramp)
    slippery = [PLINTH, STATUE._replace(mu=0.2)]
    assert stays_shut(slippery, 0.199 * G * ramp) and not stays_shut(slippery, 0.201 * G * ramp)
    # where each joint starts to open, either way: the nearer of its support's two ends
    assert opening_ratio(joint) == pytest.approx(0.25, rel=1e-15)
    assert opening_ratio(base) == pytest.approx(0.5 / (430.0 / 600.0), rel=1e-15)
    # the statue 0.4 m off centre overhangs the plinth: its support is [0.2, 0.5] m, G at 0.4 m, 0.1 m from its end
    overhung = interfaces([PLINTH, STATUE._replace(offset_m=0.4)])[1]
    assert opening_ratio(overhung) == pytest.approx(0.1 / 0.8, rel=1e-14)


def test_an_offset_statue_on_a_narrow_pedestal_is_bound_by_the_overlap():
    """A 0.6 m wide statue 0.15 m off the centre of a 0.4 m pedestal rests on the overlap [-0.15, 0.2] m: its
    centre of mass 0.15 m out, 0.5 m up tips toward +x at (0.15 - 0.2) / 0.5 and toward -x at (0.15 + 0.15) / 0.5."""
    pedestal, statue = StackBody(0.4, 1.0, 300.0, 0.7), StackBody(0.6, 1.0, 80.0, 0.7, offset_m=0.15)
    joint = interfaces([pedestal, statue])[1]
    assert (joint.left_m, joint.right_m) == pytest.approx((-0.15, 0.2), abs=1e-15)
    assert uplift_ratios(joint) == pytest.approx((-0.1, 0.6), rel=1e-12)


@pytest.mark.parametrize("drums", [2, 3, 5])
def test_a_column_of_equal_drums_stays_shut_where_the_block_of_its_outline_stays_at_rest(drums):
    """Equal drums with the same friction: each joint's part is less slender than the whole, so the stack stays shut
    exactly where the single block of its outline stays at rest (Housner's bound and Coulomb's, a_v included), on
    a real-looking random ground scaled through the bound."""
    rng = np.random.default_rng(drums)
    width, height, mu = 0.8, 4.0, 0.5
    column = [StackBody(width, height / drums, 200.0, mu) for _ in range(drums)]
    outline = [StackBody(width, height, 200.0 * drums, mu)]
    ah, av = rng.normal(0.0, 1.0, 400), rng.normal(0.0, 0.3, 400)
    for scale in np.linspace(0.1, 2.0, 40):
        demand = np.max(np.abs(scale * ah) / (G + scale * av))
        assert stays_shut(column, scale * ah, scale * av) == stays_shut(outline, scale * ah, scale * av)
        assert stays_shut(outline, scale * ah, scale * av) == (demand <= min(width / height, mu))


def test_the_bounds_are_unchanged_by_scale_and_by_the_masses_scaled_together():
    """Similitude: lengths times 3.7 and every mass times 0.01 leave the bounds of every interface unchanged."""
    stack = [PLINTH, STATUE._replace(offset_m=0.05)]
    scaled = [b._replace(width_m=3.7 * b.width_m, height_m=3.7 * b.height_m, offset_m=3.7 * b.offset_m,
                         mass_kg=0.01 * b.mass_kg) for b in stack]
    for a, b in zip(interfaces(stack), interfaces(scaled), strict=True):
        assert uplift_ratios(a) == pytest.approx(uplift_ratios(b), rel=1e-12)


def test_the_ground_falling_faster_than_gravity_is_not_certified():
    assert not stays_shut([STATUE], np.zeros(3), np.array([0.0, -G, 0.0]))


@pytest.mark.parametrize("stack, words", [
    ([PLINTH, STATUE._replace(offset_m=0.7)], r"body 1 \(0 = bottom\) on body 0 cannot stand at rest"),
    # a heavy slab off the axis of a light post: the whole leans out of the post's base
    ([StackBody(0.4, 1.0, 10.0, 0.5), StackBody(2.0, 0.2, 500.0, 0.5, offset_m=0.3)],
     r"body 0 \(0 = bottom\) on the ground"),
    ([STATUE._replace(height_m=math.nan)], "height_m = nan"),
    ([STATUE._replace(mu=0.0)], "mu = 0.0"),
    ([], "no bodies"),
])
def test_a_stack_that_cannot_stand_is_a_named_error(stack, words):
    with pytest.raises(BlockParameterError, match=words):
        interfaces(stack, label="inventory line 4 (S-1)")
