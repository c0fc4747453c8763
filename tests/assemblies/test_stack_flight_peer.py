"""Stacks whose ground falls faster than gravity against an independent rigid-body engine (PyBullet, tests only): the
flights the stack's contact model follows (tests/support/stack_flights.py: the bundled records whose vertical
reaches 1.2 g below gravity at a scale of at most 2.2, in four planes each; friction mu on the floor and mu^2
between the boxes in both engines). The lowest box fallen at the first fall (none, or the box) agrees in at least 80
% of each family's scenes (90 % is not met in flight: docs/validation.md), whether any box falls (the stack's verdict
under ``screen``'s default rule) in at least 90 %, every scene has a
verdict, and no scene the engine overturns robustly (its verdict the same with its step halved and the record scaled
by 0.98 and 1.02) stands in rockscreen at 1, 0.98 and 1.02 of the record, nor, where the first falls differ, is the
box the engine overturns robustly robust_stand under the default draws (the class ``screen`` reports). Slow."""

from __future__ import annotations

from functools import partial

import pytest
from rigid_body_peer import NONE_FALLS, bullet_first_fall, perturbed_verdicts
from stack_flights import MU, RHO, STACKS, drawn_class, first_fall, flight_records, stack

from pipeline.assemblies.n_block_verdicts import judge_n_block
from pipeline.records.record import project
from pipeline.rocking.codes import Verdict
from pipeline.uncertainty.robust import Robustness

PLANES_DEG = (0.0, 45.0, 90.0, 135.0)
#: the share of scenes that agree at least (measured: 19 and 16 of 20, benchmarks/stack_flight_peer.py; the 90 %
#: asked of stacks is not met in flight)
AGREE = 0.8
#: ... and on whether any box falls (measured: 20 and 18 of 20)
ANY_AGREE = 0.9


@pytest.mark.slow
@pytest.mark.parametrize("family", ["statue", "three"])
def test_the_first_fall_in_a_flight_agrees_with_pybullet(records_dir, family):
    nb, mu = stack(family)
    agree, any_agree, differ, n = 0, 0, [], 0
    for rid, hz, av, az0, dt, _scale in flight_records(records_dir):
        for az in PLANES_DEG:
            a = project(hz, az0, az)
            judged = judge_n_block(nb, a, dt, av_ms2=av, mu=mu)
            assert all(v != Verdict.no_verdict for v in judged.verdicts), (rid, az)
            ours = first_fall(judged)
            engine = bullet_first_fall(a, dt, STACKS[family], mu=MU, density=RHO, av_ms2=av)
            n += 1
            any_agree += (ours == NONE_FALLS) == (engine == NONE_FALLS)
            if ours == engine:
                agree += 1
                continue
            robust = engine != NONE_FALLS and perturbed_verdicts(partial(
                bullet_first_fall, a, dt, STACKS[family], mu=MU, density=RHO, av_ms2=av)) == {engine}
            missed = robust and ours == NONE_FALLS
            if missed:          # the engine falls robustly where rockscreen stands: robustly so at 0.98 and 1.02?
                missed = all(first_fall(judge_n_block(nb, s * a, dt, av_ms2=s * av, mu=mu)) == NONE_FALLS
                             for s in (0.98, 1.02))
            drawn = drawn_class(family, engine, hz, av, az0, dt, az).robustness if robust else None
            differ.append((rid, az, ours, engine, missed, drawn))
    assert n >= 8
    assert agree >= AGREE * n, differ
    assert any_agree >= ANY_AGREE * n, differ
    assert not [d for d in differ if d[4]], differ
    assert not [d for d in differ if d[5] == Robustness.robust_stand], differ
    assert any(d[5] is not None for d in differ) or family == "statue", differ   # three drums: the draws were run
