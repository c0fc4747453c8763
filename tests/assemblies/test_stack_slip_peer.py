"""Stacks whose joints slip against an independent rigid-body engine (PyBullet, tests only): the stack's contact model
(pipeline.assemblies.stack_contact) where a joint needs more friction than it has, on the bundled records of at most
60 s, each first horizontal scaled to 0.5 g, no vertical (no flight); a statue on its plinth and a column of three
drums (tests/support/stack_flights.py), friction 0.5 on the floor and 0.25 between the boxes in both engines, so that
a joint slips where the ground passes 0.25 g; rockscreen judges the stacks as ``screen`` does. In at least 80 % of
the scenes a joint slips by more than 1 mm; every scene has a verdict; every box's verdict (fallen or not by the end
of the engine's run) and whether any box falls agree in at least 90 % of each family's scenes; where rockscreen has
every box standing and the engine overturns one robustly (its first fall the same with its step halved and the
record scaled by 0.98 and 1.02), that box is not robust_stand in rockscreen under the default draws.
benchmarks/stack_slip_peer.py runs every record and the two other families. Slow."""

from __future__ import annotations

from functools import partial

import pytest
from rigid_body_peer import NONE_FALLS, bullet_first_fall, bullet_stack_fallen, perturbed_verdicts, short_records
from stack_flights import RHO, STACKS, drawn_class, screen_verdicts

from pipeline.constants import G
from pipeline.rocking.codes import Verdict
from pipeline.uncertainty.robust import Robustness

MU, PGA_G, MAX_DURATION_S = 0.5, 0.5, 60.0
#: shares of the scenes (measured on every record: 21 and 20 of 21 slip; every box's verdict, docs/validation.md)
SLIP, AGREE = 0.8, 0.9


@pytest.mark.slow
@pytest.mark.parametrize("family", ["statue", "three"])
def test_stacks_whose_joints_slip_agree_with_pybullet(records_dir, family):
    boxes = STACKS[family]
    records = short_records(records_dir, MAX_DURATION_S)[::2]
    slipped, bodies_agree, any_agree, differ = 0, 0, 0, []
    for rec in records:
        a = rec.horizontal_ms2[0] * (PGA_G * G / abs(rec.horizontal_ms2[0]).max())
        judged = screen_verdicts(family, a, rec.dt_s, mu=MU)
        assert all(v != Verdict.no_verdict for v in judged.verdicts), (rec.record_id, judged)
        slipped += bool(judged.slide_m) and max(judged.slide_m) > 1e-3
        ours_fallen = tuple(v == Verdict.overturns for v in judged.verdicts)
        engine_fallen = bullet_stack_fallen(a, rec.dt_s, boxes, mu=MU, density=RHO)
        bodies_agree += ours_fallen == engine_fallen
        any_agree += any(ours_fallen) == any(engine_fallen)
        if any(ours_fallen) or not any(engine_fallen):
            continue
        judge = partial(bullet_first_fall, a, rec.dt_s, boxes, mu=MU, density=RHO)
        engine = judge()
        drawn = None
        if engine != NONE_FALLS and perturbed_verdicts(judge) == {engine}:
            drawn = drawn_class(family, engine, a[None, :], None, 0.0, rec.dt_s, 0.0, MU).robustness
        differ.append((rec.record_id, ours_fallen, engine_fallen, drawn))
    n = len(records)
    assert n >= 10
    assert slipped >= SLIP * n, slipped
    assert bodies_agree >= AGREE * n, (bodies_agree, differ)
    assert any_agree >= AGREE * n, (any_agree, differ)
    assert not [d for d in differ if d[3] == Robustness.robust_stand], differ
