"""The simulator against an independent rigid-body engine (PyBullet), on scenes of the bundled records.

Every scene the general contact model decides (friction exceeded, lift-off, free flight) and 36 drawn
pure-rocking scenes, each along its governing plane with its vertical, ``--samples 0``: the verdicts must
agree, except the disagreements listed here and explained in docs/validation.md ("The general contact
model against PyBullet").
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from rigid_body_peer import bullet_overturns, pybullet

from pipeline.blocks import read_inventory
from pipeline.constants import G
from pipeline.records.listing import find_records
from pipeline.records.record import project
from pipeline.records.side_files import read_declared_units
from pipeline.records.side_files import read_inventory as read_stations
from pipeline.rocking.planner import Physics, simulate_scene
from pipeline.rocking.simulate import rock
from pipeline.run.screening import Context, screen_record

#: (record, block): where PyBullet stands and rockscreen overturns, explained in docs/validation.md. Each is a
#: knife-edge in rockscreen itself (the verdict flips within 5 % of the horizontal or 10 % of the vertical,
#: checked below), three of them in the plane the orientation scan chose because it overturns there.
KNOWN_DISAGREEMENTS = {
    ("RSN1086_NORTHR_SYL", "CAB-02"),
    ("RSN181_IMPVALL.H_H-E06", "PBR-01"),
    ("CI.CCC..HN", "TOMB-02"),
    ("CI.CCC..HN", "CAB-03"),
}
PURE_ROCKING_DRAWN = 36


#: Sampling [s] and duration [s] of the half-sine cases (a 2 m x 0.3 m block at omega/p = 3).
DT_S, DURATION_S = 0.002, 8.0


def half_sine_threshold(av_ms2: np.ndarray | None):
    """The half-sine case's time axis, its pulse as a function of amplitude, and the rocking kernel's threshold
    amplitude [m s-2] (upward scan in steps of 0.25 % of g tan alpha) with the vertical ``av_ms2``."""
    b, h = 0.15, 1.0
    R, alpha = math.hypot(b, h), math.atan(b / h)
    p = math.sqrt(3 * G / (4 * R))
    e = 1 - 1.5 * math.sin(alpha) ** 2
    w = 3 * p
    t = np.arange(0.0, DURATION_S, DT_S)

    def pulse(amplitude):
        return np.where(t < math.pi / w, amplitude * np.sin(w * t), 0.0)

    levels = np.arange(1.0, 4.0, 0.0025) * G * math.tan(alpha)
    return pulse, next(A for A in levels if rock(pulse(A), DT_S, p=p, alpha=alpha, e=e, R_m=R,
                                                 av_ms2=av_ms2).overturned)


def test_bullet_reproduces_the_half_sine_threshold():
    """The peer's calibration: a 2 m x 0.3 m block under a half-sine at omega/p = 3 stands at 0.97 and overturns
    at 1.03 times the threshold amplitude found by the rocking kernel."""
    pybullet()
    pulse, threshold = half_sine_threshold(None)
    assert not bullet_overturns(pulse(0.97 * threshold), None, DT_S, height_m=2.0, width_m=0.3, mu=10.0)[0]
    assert bullet_overturns(pulse(1.03 * threshold), None, DT_S, height_m=2.0, width_m=0.3, mu=10.0)[0]


@pytest.mark.slow
def test_verdicts_agree_with_pybullet_on_bundled_scenes(records_dir, data_dir, config):
    pybullet()
    cfg = dataclasses.replace(config, uncertainty=dataclasses.replace(config.uncertainty, samples=0))
    # the planar model against Bullet's box: the bundled inventory as it was when this comparison was drawn and
    # analysed (docs/validation.md), every block a box (the vase too, rocking plane 0 deg)
    inv = read_inventory(data_dir / "blocks-planar-peer.csv", default_mu=config.blocks.default_mu)
    blocks = dict(zip(inv.ids, inv.rocking_blocks(g_ms2=config.records.g_ms2)))
    ctx = Context(str(records_dir), cfg, inv, read_declared_units(records_dir, cfg), read_stations(records_dir))
    sources, _ = find_records(records_dir, config=cfg)
    rng = np.random.default_rng(1)
    general, pure = [], []
    for src in sources:
        res = screen_record(src, ctx)
        if not res.ok:
            continue
        rec = ctx.load(src)
        for j, bid in enumerate(res.block_ids):
            physics = int(res.blocks["physics"][j])
            scene = (src.record_id, bid, rec, float(res.blocks["governing_azimuth"][j]))
            if physics == Physics.general:
                general.append(scene)
            elif physics in (Physics.rocking, Physics.rocking_vertical):
                pure.append(scene)
    drawn = [pure[i] for i in rng.choice(len(pure), PURE_ROCKING_DRAWN, replace=False)]
    rows, disagree = [], set()
    for record_id, bid, rec, azimuth in general + drawn:
        ah = project(rec.horizontal_ms2, rec.azimuths_deg[0], azimuth)
        k = inv.ids.index(bid)
        ours = simulate_scene(ah, rec.vertical_ms2, rec.dt_s, block=blocks[bid], settings=cfg.simulation_settings())
        peer, tilt = bullet_overturns(ah, rec.vertical_ms2, rec.dt_s, height_m=float(inv.height_m[k]),
                                      width_m=float(inv.width_m[k]), mu=float(inv.mu[k]))
        rows.append(f"{record_id} {bid} physics {ours.physics} rockscreen {ours.verdict} bullet {int(peer)} "
                    f"(tilt {tilt / blocks[bid].alpha:.2f} alpha)")
        if ours.verdict != int(peer):
            disagree.add((record_id, bid))
            nearby = {simulate_scene(fa * ah, None if rec.vertical_ms2 is None else fv * rec.vertical_ms2, rec.dt_s,
                                     block=blocks[bid], settings=cfg.simulation_settings()).verdict
                      for fa in (0.95, 1.0, 1.05) for fv in (0.9, 1.0, 1.1)}
            assert nearby == {0, 1}, f"{record_id} x {bid}: a disagreement that is not a knife-edge"
    print("\n".join(rows))
    assert len(general) >= 30 and len(rows) >= 60
    assert disagree == KNOWN_DISAGREEMENTS, rows


@pytest.mark.slow
@pytest.mark.parametrize("vertical", ["constant", "harmonic 5 Hz", "harmonic 8 Hz"])
def test_bullet_with_a_vertical_brackets_the_kernels_threshold(vertical):
    """The peer under a vertical ground motion: a half-sine at omega/p = 3 on a 2 m x 0.3 m block, with a constant
    -0.2 g or a harmonic vertical; Bullet stands at 0.95 and overturns at 1.05 times the rocking kernel's threshold
    amplitude (measured: within 1 % for the constant vertical, between 1 % and 5 % above it for the harmonic
    ones, the direction of the four disagreements, which all have a vertical)."""
    pybullet()
    t = np.arange(0.0, DURATION_S, DT_S)
    av = {"constant": np.full(t.size, -0.2 * G), "harmonic 5 Hz": 0.3 * G * np.sin(2 * np.pi * 5 * t),
          "harmonic 8 Hz": 0.5 * G * np.sin(2 * np.pi * 8 * t + 0.3)}[vertical]
    pulse, threshold = half_sine_threshold(av)
    assert not bullet_overturns(pulse(0.95 * threshold), av, DT_S, height_m=2.0, width_m=0.3, mu=10.0)[0]
    assert bullet_overturns(pulse(1.05 * threshold), av, DT_S, height_m=2.0, width_m=0.3, mu=10.0)[0]
