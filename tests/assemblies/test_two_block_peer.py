"""Two stacked blocks against an independent rigid-body engine (PyBullet, tests only) on the bundled records of at
most 60 s, each first horizontal scaled to 0.5 g: a statue on its plinth and two drums, friction 2 (no joint slides).
What falls first (nothing, the top, the stack) agrees in at least 90 % of each family's scenes, and every scene where
they differ is one the engine does not decide robustly (its verdict changes with its step halved or the record
scaled by 0.98 or 1.02). Slow."""

from __future__ import annotations

from functools import partial

import pytest
from rigid_body_peer import bullet_stack_falls, perturbed_verdicts, short_records

from pipeline.assemblies.stack import StackBody
from pipeline.assemblies.two_block import two_block
from pipeline.assemblies.two_block_run import simulate_two_block
from pipeline.constants import G

MU, RHO, PGA_G, MAX_DURATION_S = 2.0, 2500.0, 0.5, 60.0
#: family -> ((width, height) of the lower block, of the upper) [m]
STACKS = {"statue on plinth": ((0.6, 1.0), (0.3, 1.2)), "two drums": ((0.5, 1.5), (0.5, 1.0))}


@pytest.mark.slow
@pytest.mark.parametrize("family", list(STACKS))
def test_what_falls_first_agrees_with_pybullet(records_dir, family):
    lower, upper = STACKS[family]
    tb = two_block(StackBody(lower[0], lower[1], RHO * lower[0] * lower[1], MU),
                   StackBody(upper[0], upper[1], RHO * upper[0] * upper[1], MU))
    records = short_records(records_dir, MAX_DURATION_S)[::2]
    agree, differ = 0, []
    for rec in records:
        a = rec.horizontal_ms2[0] * (PGA_G * G / abs(rec.horizontal_ms2[0]).max())
        ours = simulate_two_block(tb, a, rec.dt_s).falls
        engine = bullet_stack_falls(a, rec.dt_s, lower, upper, mu=MU, density=RHO)
        if ours == engine:
            agree += 1
            continue
        checks = perturbed_verdicts(partial(bullet_stack_falls, a, rec.dt_s, lower, upper, mu=MU, density=RHO))
        differ.append((rec.record_id, ours, engine, checks))
    assert len(records) >= 10
    assert agree >= 0.9 * len(records), differ
    assert all(checks != {engine} for _, _, engine, checks in differ), differ
