"""The exact rest check of the 3D scenes (pipeline.rocking.solids.solid3d.stays_at_rest), which lets the screening skip
a 3D run where nothing moves: wherever it says at rest, the 3D models themselves (a second algorithm) do not move, on
random two-component records scaled around their thresholds; it holds at its exact boundaries. (Just above the
threshold a box may lift by less than the samples show: the check then runs the model, which is exact too.)"""

from __future__ import annotations

import math

import numpy as np
import pytest

from pipeline.rocking.settings import SimulationConfig
from pipeline.rocking.solids.box3d import Box
from pipeline.rocking.solids.cylinder3d import Cylinder
from pipeline.rocking.solids.solid3d import Solid, judge_solid, lift_factor, run, stays_at_rest

G = 9.80665
DT = 0.01

SOLIDS = {
    "cylinder": Solid(Cylinder(radius_m=0.15, half_height_m=0.6, mu=0.7, restitution=0.9), 0.0, math.atan2(0.15, 0.6)),
    "square box at 30 deg": Solid(Box(half_width_m=0.15, half_depth_m=0.15, half_height_m=0.6, mu=0.7), 30.0,
                                  math.atan2(0.15, 0.6)),
    "cabinet at 110 deg": Solid(Box(half_width_m=0.2, half_depth_m=0.45, half_height_m=1.0, mu=0.8), 110.0,
                                math.atan2(0.2, 1.0)),
}


def _record(seed: int, n: int = 600):
    rng = np.random.default_rng(seed)
    t = np.arange(n) * DT
    h = [sum(rng.uniform(0.5, 2.0) * np.sin(2 * np.pi * rng.uniform(0.5, 4.0) * t + rng.uniform(0, 6.3))
             for _ in range(3)) * np.exp(-((t - 3.0) / 1.5) ** 2) for _ in range(3)]
    return h[0], h[1], 0.4 * h[2]


@pytest.mark.parametrize("name", list(SOLIDS))
@pytest.mark.parametrize("seed", range(6))
def test_the_rest_check_agrees_with_the_3d_model(name, seed):
    solid = SOLIDS[name]
    h1, h2, v = _record(seed)
    f = lift_factor(h1, h2, v, solid)
    for amplitude in (0.5 * f, 0.999 * f, 1.001 * f, 1.5 * f):
        out = run(h1, h2, v, DT, solid, settings=SimulationConfig(), amplitude=amplitude)
        quiet = stays_at_rest(h1, h2, v, solid, amplitude=amplitude)
        moved = out.theta_max_rad > 0.0 or out.flag != 0
        assert quiet == (amplitude <= f)                    # the factor at which it first lifts (or slides)
        if quiet:                                           # the shortcut is exact: the model does not move either
            assert not moved, (amplitude / f, out.theta_max_rad, out.flag)
        if amplitude > 1.2 * f:                             # and it is not vacuous
            assert moved


@pytest.mark.parametrize("solid", [
    Solid(Cylinder(radius_m=0.15, half_height_m=0.6, mu=0.7, restitution=0.9), 0.0, math.atan2(0.15, 0.6)),
    Solid(Box(half_width_m=0.2, half_depth_m=0.45, half_height_m=1.0, mu=0.8), 0.0, math.atan2(0.2, 1.0)),
], ids=["cylinder", "box"])
def test_the_rest_check_holds_at_the_exact_uplift_boundary(solid):
    """|a_h| = g tan alpha exactly (along the width for the box): at rest, in the check and in the 3D model."""
    n = 50
    tan_a = (solid.body.radius_m if isinstance(solid.body, Cylinder) else solid.body.half_width_m) / \
        solid.body.half_height_m
    a = np.full(n, G * tan_a)
    assert stays_at_rest(a, np.zeros(n), None, solid)
    assert run(a, np.zeros(n), None, DT, solid, settings=SimulationConfig()).theta_max_rad == 0.0
    assert not stays_at_rest(a * (1 + 1e-9), np.zeros(n), None, solid)


def test_the_rest_check_holds_at_mu_g_and_stops_at_free_fall():
    box = Solid(Box(half_width_m=0.5, half_depth_m=0.5, half_height_m=0.4, mu=0.5), 0.0, math.atan2(0.5, 0.4))
    n = 50
    a = np.full(n, 0.5 * G / math.sqrt(2.0))               # |a_h| = mu g along the diagonal
    assert stays_at_rest(a, -a, None, box)
    assert not stays_at_rest(a * (1 + 1e-9), -a, None, box)
    assert not stays_at_rest(np.zeros(n), np.zeros(n), np.full(n, -G), box)   # g + a_v = 0


def test_a_scene_left_at_rest_is_judged_without_a_run():
    solid = SOLIDS["cylinder"]
    h1, h2, v = _record(3)
    f = lift_factor(h1, h2, v, solid)
    got = judge_solid(h1, h2, v, DT, solid, amplitude=0.9 * f, history=True)
    assert got.scene.theta_max == 0.0 and not got.scene.overturned and got.scene.physics == 0
    assert got.scene.theta_over_alpha is not None and not np.any(got.scene.theta_over_alpha)


def _moves_somewhere(h1, h2, v, solid: Solid, amplitude: float, g_ms2: float = G) -> bool:
    """The rest check's conditions stated on whole arrays: some sample where the ground falls away, slides the base
    or pushes the solid past a tipping tan (a cylinder: |a_h| over tan alpha; a box: along or across its width)."""
    x, y = amplitude * h1, -amplitude * h2
    gv = g_ms2 + (amplitude * v if v is not None else 0.0)
    radial = np.hypot(x, y)
    if np.any(gv <= 0.0) or np.any(radial > solid.body.mu * gv):
        return True
    if isinstance(solid.body, Cylinder):
        return bool(np.any(radial > gv * solid.body.radius_m / solid.body.half_height_m))
    b = solid.body
    c, s = math.cos(math.radians(solid.azimuth_deg)), math.sin(math.radians(solid.azimuth_deg))
    along, across = c * x + s * y, -s * x + c * y
    return bool(np.any(np.abs(along) > gv * b.half_width_m / b.half_height_m)
                or np.any(np.abs(across) > gv * b.half_depth_m / b.half_height_m))


@pytest.mark.parametrize("name", list(SOLIDS))
@pytest.mark.parametrize("vertical", [True, False])
def test_the_compiled_rest_check_is_its_conditions_on_whole_arrays(name, vertical):
    """The check stops at the first sample that moves the solid: it says at rest exactly where no sample moves it,
    on records scaled from well below to well above their thresholds (lift, slide, and a vertical reaching -g)."""
    solid = SOLIDS[name]
    for seed in range(4):
        h1, h2, v = _record(seed)
        v = (3.0 * v if vertical else None)
        f = lift_factor(h1, h2, v, solid)
        for amplitude in (0.3 * f, 0.9 * f, 0.999 * f, 1.001 * f, 2.0 * f, 8.0 * f):
            assert stays_at_rest(h1, h2, v, solid, amplitude=amplitude) is not _moves_somewhere(h1, h2, v, solid,
                                                                                                  amplitude)
