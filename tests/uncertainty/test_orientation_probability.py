"""P(overturn) per orientation of a block of unknown orientation, against closed forms.

A half-sine pulse polarized along one azimuth, in a two-component record: in a plane at angle phi to the
polarization the block feels the pulse scaled by |cos phi|. With only the amplitude uncertain (lognormal,
median 1, s = sqrt(ln(1 + cov^2))) and a block whose overturning is monotonic in amplitude around its
threshold a* (checked in tests/uncertainty/test_uncertainty.py), the block overturns in plane phi when
eps k |cos phi| > 1, so:

* the worst orientation is the polarization plane, with P = Phi(ln k / s);
* the average over orientations uniform on [0, 180) tends to (2/pi) arccos(1/k) as s -> 0 (0.373 for
  k = 1.2), which the scan's 5-degree grid resolves to within one grid step (13 of 36 planes).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from scipy.stats import norm

from pipeline.blocks import geometry
from pipeline.rocking.block import BlockShape
from pipeline.rocking.codes import Verdict
from pipeline.rocking.orientation import plane_grid
from pipeline.rocking.references.excitation import pulse
from pipeline.rocking.references.reference import rock_reference
from pipeline.uncertainty.orientations import orientation_probability
from pipeline.uncertainty.sampling import common_normals
from pipeline.uncertainty.scenes import motion, scene_probability
from pipeline.uncertainty.settings import UncertaintyConfig

G = 9.80665
HEIGHT, WIDTH, MU = 2.0, 0.3, 2.0          # slender, cannot slide
POLARIZATION_DEG = 30.0
OMEGA_OVER_P = 3.0
SAMPLES_PER_PERIOD = 200


def _block():
    geo = geometry(HEIGHT, WIDTH, g_ms2=G)
    return float(geo.p), float(geo.alpha), float(geo.e_housner)


def _unit_halfsine():
    p, _, _ = _block()
    return pulse("half-sine", amplitude_ms2=1.0, period_s=2 * math.pi / (OMEGA_OVER_P * p),
                 samples_per_period=SAMPLES_PER_PERIOD)


@pytest.fixture(scope="module")
def threshold() -> float:
    """The half-sine's smallest overturning amplitude a* [m s-2], by bisection on the independent solver."""
    p, alpha, e = _block()
    unit, dt = _unit_halfsine()
    lo, hi = G * math.tan(alpha), 20 * G * math.tan(alpha)
    for _ in range(40):
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if rock_reference(mid * unit, dt, p=p, alpha=alpha, e=e, g=G).overturned else (mid, hi)
    return hi


def _polarized(amplitude_ms2: float):
    """Two components (north, east) of a half-sine polarized along POLARIZATION_DEG."""
    unit, dt = _unit_halfsine()
    phi = math.radians(POLARIZATION_DEG)
    return np.vstack([amplitude_ms2 * math.cos(phi) * unit, amplitude_ms2 * math.sin(phi) * unit]), dt


def _settings(cov: float, samples: int) -> UncertaintyConfig:
    return UncertaintyConfig(samples=samples, batch=50, amplitude_cov=cov, restitution_cov=0.0, friction_cov=0.0,
                             size_cov=0.0, azimuth_sd_deg=0.0, seed=11, p_halfwidth=0.02)


def _orientation(k: float, threshold: float, settings: UncertaintyConfig):
    h, dt = _polarized(k * threshold)
    grid = plane_grid(5.0)
    m = motion(h, 0.0, None, dt, planes_deg=grid)
    return orientation_probability(m, common_normals(settings.seed, settings.samples),
                                   BlockShape(height_m=HEIGHT, width_m=WIDTH, mu=MU), grid_deg=grid,
                                   prefer_deg=math.nan, settings=settings, g_ms2=G)


def test_worst_orientation_is_the_polarization_plane_with_the_lognormal_probability(threshold):
    k, cov = 1.03, 0.05
    settings = _settings(cov, 400)
    out = _orientation(k, threshold, settings)
    expected = float(norm.cdf(math.log(k) / math.sqrt(math.log1p(cov * cov))))      # 0.72
    assert out.worst_azimuth_deg == pytest.approx(POLARIZATION_DEG)
    se = math.sqrt(expected * (1 - expected) / out.worst.drawn)
    assert out.worst.p == pytest.approx(expected, abs=4 * se)
    assert out.random <= out.worst.p + (out.random_high - out.random_low) / 2


def test_average_over_orientations_tends_to_the_arccos_closed_form(threshold):
    """One grid plane per draw, cycling permutations of the grid: after whole cycles (3 x 36 draws) of a nearly
    deterministic scene, the fraction is the grid's exactly; its interval covers the continuous value."""
    k = 1.2
    settings = dataclasses.replace(_settings(0.001, 100), orientation_average_samples=108,
                                   orientation_average_halfwidth=0.001)
    out = _orientation(k, threshold, settings)
    continuous = 2 / math.pi * math.acos(1 / k)                                        # 0.373
    assert out.random == pytest.approx(13 / 36, abs=1e-12)    # planes within 33.6 deg of the polarization
    assert out.random_low <= continuous <= out.random_high
    assert abs(out.random - continuous) < 1 / 36               # the grid resolves it to one step
    assert out.worst.p == 1.0 and out.worst_azimuth_deg == pytest.approx(POLARIZATION_DEG)


def test_worst_is_at_most_some_plane_and_the_average_at_most_the_worst_on_a_real_record(records_dir, config):
    """A chaotic case (the per-plane outcomes differ across draws): Rinaldi RSN1063 and a 20 m column. The old
    measure, 'overturns in some plane of the scan', is an upper bound of every single orientation's."""
    from pipeline.records.loader import iter_records

    rec = next(r for r in iter_records(records_dir / "peer-at2", config=config)
               if r.record_id.startswith("RSN1063"))
    settings = dataclasses.replace(UncertaintyConfig(), samples=40)
    grid = plane_grid(5.0)
    m = motion(rec.horizontal_ms2, rec.azimuths_deg[0], rec.vertical_ms2, rec.dt_s, planes_deg=grid)
    z = common_normals(settings.seed, settings.samples)
    block = BlockShape(height_m=20.0, width_m=2.2, mu=0.7)
    out = orientation_probability(m, z, block, grid_deg=grid, prefer_deg=math.nan, settings=settings, g_ms2=G)
    some = scene_probability(m, z, block, settings=settings, g_ms2=G)
    assert 0.0 < some.p
    assert out.worst.p <= some.p + (out.worst.high - out.worst.low) / 2
    assert out.random <= out.worst.p + (out.worst.high - out.worst.low) / 2
    assert out.random < some.p


def test_each_cycle_of_the_random_orientation_draws_every_grid_plane_once():
    from pipeline.uncertainty.orientations import plane_order

    order = plane_order(36, 120)
    for c in range(3):
        assert sorted(order[36 * c: 36 * (c + 1)].tolist()) == list(range(36))
    assert np.array_equal(order, plane_order(36, 120))           # the same for every scene
    assert not np.array_equal(order[:36], np.arange(36))         # a permutation, not the grid's order


def _scene_at(k: float, threshold: float):
    """The polarized half-sine at k times the threshold, in batches of 5 draws: settings, motion, draws, grid,
    block."""
    settings = dataclasses.replace(_settings(0.05, 40), batch=5)
    h, dt = _polarized(k * threshold)
    grid = plane_grid(5.0)
    m = motion(h, 0.0, None, dt, planes_deg=grid)
    z = common_normals(settings.seed, settings.samples)
    return settings, m, z, grid, BlockShape(height_m=HEIGHT, width_m=WIDTH, mu=MU)


@pytest.mark.parametrize("governing_deg", [30.0, 60.0, 120.0])
def test_the_worst_orientation_is_never_below_the_governing_planes_own_estimate(threshold, governing_deg):
    """Step 5: where the nominal overturned, the governing plane's estimate on the independent draws bounds the
    worst orientation's p from below, whichever plane the selection chose."""
    from pipeline.uncertainty.orientations import estimation_normals

    settings, m, z, grid, block = _scene_at(1.03, threshold)
    out = orientation_probability(m, z, block, grid_deg=grid, prefer_deg=governing_deg, settings=settings,
                                  g_ms2=G, nominal_overturned=True)
    own = scene_probability(dataclasses.replace(m, planes_deg=np.array([governing_deg])),
                            estimation_normals(settings, settings.samples), block, settings=settings, g_ms2=G)
    assert out.worst.p >= own.p
    assert out.worst_azimuth_deg == pytest.approx(POLARIZATION_DEG, abs=5.0) or out.worst.p == own.p


def test_a_standing_nominal_races_only_its_candidates(threshold):
    """Where the nominal stands, the candidates are the governing plane and the three planes of largest nominal
    rotation: the selection simulates those planes only, and the chosen plane is one of them."""
    settings, m, z, grid, block = _scene_at(1.03, threshold)
    ranked = [25.0, 35.0, 20.0, 40.0, 30.0]
    out = orientation_probability(m, z, block, grid_deg=grid, prefer_deg=45.0, settings=settings, g_ms2=G,
                                  nominal_overturned=False, ranked_deg=ranked)
    assert out.worst_azimuth_deg in (45.0, 25.0, 35.0, 20.0)
    assert out.worst_azimuth_deg in (25.0, 35.0)                  # the nearest the polarization among them


def _random_orientation_drawn(amplitude, settings, monkeypatch):
    """The random orientation of the module's block on the polarized record at ``amplitude`` [m s-2], on the 5-deg
    grid under ``settings``: its mean and bounds, and the draws it simulated."""
    from pipeline.rocking.settings import SimulationConfig
    from pipeline.uncertainty import orientations

    h, dt = _polarized(amplitude)
    grid = plane_grid(5.0)
    m = motion(h, 0.0, None, dt, planes_deg=grid)
    blk = orientations._Block(BlockShape(height_m=HEIGHT, width_m=WIDTH, mu=MU), settings, SimulationConfig(), G)
    drawn: list[int] = []
    simulate = orientations.simulate_cells
    monkeypatch.setattr(orientations, "simulate_cells", lambda m_, sb_, p_, b_: drawn.append(len(sb_.amplitude)) or
                        simulate(m_, sb_, p_, b_))
    mean, low, high, _ = orientations.random_orientation(m, orientations.average_normals(settings), blk,
                                                         grid_deg=grid)
    return mean, low, high, sum(drawn)


def test_the_random_orientation_stops_once_the_planes_decide_it(threshold, monkeypatch):
    """The nearly deterministic scene (13 of 36 planes overturn): the first two batches of 20 draws cover every
    plane, the stratified mean's interval is then about +-0.05 and stops the draws, where Wilson's (+-0.12 at
    p = 0.36) would have drawn on to the 120 allowed. The interval covers the grid's 13 / 36."""
    from pipeline.uncertainty.robust import wilson_interval

    settings = dataclasses.replace(_settings(0.001, 40), batch=20, orientation_average_samples=120,
                                   orientation_average_halfwidth=0.07)
    mean, low, high, drawn = _random_orientation_drawn(1.2 * threshold, settings, monkeypatch)
    assert drawn == 40
    assert (high - low) / 2 <= 0.07 and low <= 13 / 36 <= high
    w_low, w_high = wilson_interval(round(mean * 40), 40, confidence=settings.confidence)
    assert (w_high - w_low) / 2 > 0.07


def test_where_every_plane_agrees_the_random_orientation_keeps_wilsons_interval(threshold, monkeypatch):
    """Half the overturning amplitude, nothing overturns in any plane: the stratified estimate's variance is 0 and
    says nothing, so the draws go on to Wilson's half-width, 0 of n giving [0, z^2 / (n + z^2)]: 0.02 at n = 65."""
    from pipeline.uncertainty.robust import normal_quantile

    settings = dataclasses.replace(_settings(0.001, 40), batch=5, orientation_average_samples=120,
                                   orientation_average_halfwidth=0.02)
    mean, low, high, drawn = _random_orientation_drawn(0.5 * threshold, settings, monkeypatch)
    z2 = normal_quantile(0.95) ** 2
    assert drawn == 65 and mean == 0.0 and low == 0.0
    assert high == pytest.approx(z2 / (65 + z2), rel=1e-12)


OV, ST, UN = int(Verdict.overturns), int(Verdict.stands), int(Verdict.no_verdict)


@pytest.mark.parametrize(("columns", "kept"), [
    # 10 common draws per plane: the leader overturns in 9; one fewer stays, two fewer leaves
    (([OV] * 9 + [ST], [OV] * 8 + [ST] * 2, [OV] * 7 + [ST] * 3), [True, True, False]),
    # a plane's draws without a verdict count as overturning: 6 + 2 is one short of the leader's 9
    (([OV] * 9 + [ST], [OV] * 6 + [UN] * 2 + [ST] * 2), [True, True]),
    (([OV] * 9 + [ST], [OV] * 6 + [UN] + [ST] * 3), [True, False]),
    # every plane tied: none leaves
    (([OV] * 10, [OV] * 10, [OV] * 10), [True, True, True]),
    # far behind by Wilson's bounds too: 10 of 10 against 0 of 10
    (([OV] * 10, [ST] * 10), [True, False]),
])
def test_the_race_drops_a_plane_more_than_the_margin_behind_on_the_same_draws(columns, kept):
    """Which planes stay in the race: counted on the same draws, against the plane that overturned in most
    (RACE_MARGIN = 1), the planes' draws without a verdict taken as overturning; the leader always stays."""
    from pipeline.uncertainty.orientations import RACE_MARGIN, racing

    assert RACE_MARGIN == 1
    outcome = np.array(columns, dtype=np.int8).T
    assert racing(outcome, confidence=0.90).tolist() == kept
