"""The planar margin's scan on real records against the same scan with every factor's scene planned on the scaled
series themselves (the second algorithm): :func:`~pipeline.bodies.planar.overturn_scale_simulated` judges each
factor by the sampled kernel (one draw at that amplitude, the series checked once, not at every factor) and does
not judge the factors below the one that first lifts the block (they stand); the margins are the same, and so are
the scenes simulated, less those factors. Series that are not finite times some factor of the scan are planned at each
factor, which refuses a series that is not finite (with a gap, say)."""

from __future__ import annotations

import numpy as np
import pytest

from pipeline.bodies.factor_sweep import factor_sweep
from pipeline.bodies.planar import lift_factor, overturn_scale_simulated
from pipeline.config import Config
from pipeline.errors import ParameterError
from pipeline.records.loader import iter_records
from pipeline.rocking.block import BlockShape, dynamics
from pipeline.rocking.planner import simulate_scene
from pipeline.rocking.settings import SimulationConfig

SETTINGS = SimulationConfig()
#: (height, width, mu): blocks that rock (mu above tan alpha), slender and stocky, some slipping at their pivot, the
#: last lifted only by the record scaled above 1
SHAPES = [(1.2, 0.3, 0.7), (2.5, 0.8, 0.6), (0.8, 0.3, 0.45), (3.0, 0.6, 0.25), (1.0, 0.7, 0.9)]


def _direct(ah, av, dt, block, *, below_lift: bool):
    """The scan, each factor's scene planned on ``f ah`` and ``f av`` (its ratio and checks from them); with
    ``below_lift``, the factors below the one that first lifts the block planned too."""
    first = lift_factor(ah, av, alpha=block.alpha, g_ms2=block.g_ms2)
    return factor_sweep(first, lambda f: simulate_scene(f * ah, None if av is None else f * av, dt, block=block,
                                                        settings=SETTINGS).verdict, settings=SETTINGS,
                        stands_below=0.0 if below_lift else first)


@pytest.fixture(scope="module")
def yarimca(kocaeli):
    (rec,) = list(iter_records(kocaeli, config=Config()))
    return rec


@pytest.mark.parametrize("vertical", [True, False])
@pytest.mark.parametrize("azimuth_deg", [0.0, 65.0])
def test_the_scan_is_the_scan_of_the_scaled_scenes(yarimca, compiled_simulator, vertical, azimuth_deg):
    ah = np.ascontiguousarray(yarimca.along(azimuth_deg))
    av = yarimca.vertical_ms2 if vertical else None
    assert av is None or av.size == ah.size
    blocks = dynamics([BlockShape(height_m=h, width_m=w, mu=mu) for h, w, mu in SHAPES])
    found = [overturn_scale_simulated(ah, av, yarimca.dt_s, block=b, settings=SETTINGS) for b in blocks]
    assert found == [_direct(ah, av, yarimca.dt_s, b, below_lift=False) for b in blocks]
    every = [_direct(ah, av, yarimca.dt_s, b, below_lift=True) for b in blocks]
    assert [m for m, _ in found] == [m for m, _ in every]              # below the lift, every factor stands
    assert all(runs <= all_runs for (_, runs), (_, all_runs) in zip(found, every))
    assert found[-1][1] < every[-1][1]                                  # the stocky block's factors up to its lift
    assert sum(runs for _, runs in found) > 4 * len(SHAPES)            # the scans ran: every block lifted


def test_a_series_with_a_gap_is_refused_not_judged(compiled_simulator):
    t = np.arange(0.0, 4.0, 0.01)
    ah = 0.3 * 9.80665 * np.sin(2 * np.pi * t / 0.8)
    block = dynamics([BlockShape(height_m=1.2, width_m=0.3, mu=0.7)])[0]
    assert np.isfinite(overturn_scale_simulated(ah, None, 0.01, block=block, settings=SETTINGS)[0])
    ah[150] = np.nan                            # the sampled kernel checks nothing: the planner refuses it
    with pytest.raises(ParameterError, match="NaN or infinite values at sample 150"):
        overturn_scale_simulated(ah, None, 0.01, block=block, settings=SETTINGS)
