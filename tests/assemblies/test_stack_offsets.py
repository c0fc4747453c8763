"""A stack's residual offsets (:attr:`pipeline.assemblies.n_block_verdicts.StackVerdicts.offset_m`): a squat top block
that slides on a base that holds ends where the Coulomb sliding block ends (a second model: the exact sliding
integration of :func:`pipeline.rocking.simulate.slide`); joints that hold leave no offset; a stack whose joints slipped
under a short pulse comes to rest after it, with a verdict."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pipeline.assemblies.stack import StackBody, StackPlace
from pipeline.assemblies.stack_scene import AT_REST, stack_run
from pipeline.constants import G
from pipeline.rocking.codes import STATUS_TAIL_CAP, Verdict
from pipeline.rocking.references.excitation import pulse
from pipeline.rocking.simulate import slide

STONE_KG_M3 = 2500.0


def _body(width_m: float, height_m: float, mu: float) -> StackBody:
    return StackBody(width_m, height_m, STONE_KG_M3 * width_m * width_m * height_m, mu)


def _half_sine(ap_g: float, tp_s: float, samples_per_period: int = 400) -> tuple[np.ndarray, float]:
    unit, dt = pulse("half-sine", amplitude_ms2=1.0, period_s=2.0 * tp_s, samples_per_period=samples_per_period)
    return np.concatenate([ap_g * G * unit, np.zeros(200)]), dt


@pytest.mark.parametrize("mu_top, ap_g, tp_s", [(0.2, 0.4, 0.5), (0.25, 0.45, 1.0), (0.3, 0.5, 0.8)])
def test_a_squat_top_block_slides_as_the_coulomb_block(mu_top, ap_g, tp_s):
    """A 1.0 x 0.3 m slab (it would tip only beyond 3.3 g) on a 1.2 x 0.6 m base of friction 0.8: the base holds,
    the slab slides on it as a block on the ground does."""
    a, dt = _half_sine(ap_g, tp_s)
    place = StackPlace((_body(1.2, 0.6, 0.8), _body(1.0, 0.3, mu_top)), 1, ("base", "slab"))
    judged = stack_run(place, a, None, dt)
    assert judged is not AT_REST and judged.verdicts == (Verdict.stands, Verdict.stands)
    alone = slide(a, dt, mu=mu_top)
    assert abs(alone.sliding_end_m) > 0.05
    assert abs(judged.offset_m[0]) < 1e-9                         # the base holds on the ground
    assert judged.offset_m[1] == pytest.approx(alone.sliding_end_m, rel=1e-3)


def test_a_slab_that_slides_off_its_base_falls_without_an_offset():
    a, dt = _half_sine(0.3, 1.5)
    place = StackPlace((_body(1.2, 0.6, 0.8), _body(1.0, 0.3, 0.15)), 1, ("base", "slab"))
    assert abs(slide(a, dt, mu=0.15).sliding_end_m) > 0.5        # farther than the slab's half width
    judged = stack_run(place, a, None, dt)
    assert judged.verdicts[1] == Verdict.overturns and math.isnan(judged.offset_m[1])


def test_joints_that_hold_leave_no_offset():
    """Three drums of friction 0.7 under a pulse that rocks them without a slip: every offset 0."""
    a, dt = _half_sine(0.5, 0.4)
    place = StackPlace(tuple(_body(0.85, h, 0.7) for h in (0.9, 0.85, 0.75)), 2, ("D1", "D2", "D3"))
    judged = stack_run(place, a, None, dt)
    assert judged is not AT_REST and judged.opened
    assert judged.verdicts == (Verdict.stands,) * 3 and judged.offset_m == (0.0, 0.0, 0.0)


@pytest.mark.parametrize("ap_g, tp_s", [(0.4, 0.4), (0.5, 0.4), (0.4, 1.0), (0.4, 1.4)])
def test_drums_whose_joints_slipped_come_to_rest_after_the_pulse(ap_g, tp_s):
    """Three drums with joints of friction 0.4 above the lowest: the upper joints slip under the pulse. After it the
    stack is still; the contact model hands it back at rest (a joint whose two ends press is shut when the joint's
    total friction is within the cone, however the two ends share it), so every body has a verdict and an offset
    well before the tail's cap (a step whose sweeps reach their cap may still be flagged, STATUS_STEP_CAP)."""
    a, dt = _half_sine(ap_g, tp_s, samples_per_period=200)
    place = StackPlace(tuple(_body(0.85, h, m) for h, m in ((0.9, 0.7), (0.85, 0.4), (0.75, 0.4))), 2,
                       ("D1", "D2", "D3"))
    judged = stack_run(place, a, None, dt)
    assert not judged.status & STATUS_TAIL_CAP
    assert all(v in (Verdict.stands, Verdict.overturns) for v in judged.verdicts)
    assert any(s > 1e-4 for s in judged.slide_m)
    assert all(math.isfinite(x) for x, v in zip(judged.offset_m, judged.verdicts) if v == Verdict.stands)
