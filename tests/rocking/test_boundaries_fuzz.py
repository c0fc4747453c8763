"""A fuzz run of 10,000 boundary scenes (slow; CI runs it): none over its wall-clock budget, every verdict
decided, the nominal and sampled paths agreeing; the slowest scene is printed.

Scenes: blocks from 2 cm to 30 m and slenderness from 1 deg to the 54.7 deg limit (exactly, and a double
either side), friction on and around the tie mu = tan(alpha), and the excitation families of
:func:`boundary_scenes.motions` with their peak demand at a threshold, a few doubles off it, or well above.
"""

from __future__ import annotations

import math
import time

import numpy as np
import pytest
from boundary_scenes import ALPHA_MAX, SCENE_BUDGET_S, G, block, motions, mu_ties, run_scene, sampled_verdict

#: slow; every scene here is timed against its budget: the simulator is compiled first
pytestmark = [pytest.mark.slow, pytest.mark.usefixtures("compiled_simulator")]

SCENES = 10_000


def _draws(rng: np.random.Generator):
    """Endless (block, motion) draws on the boundaries."""
    alphas = [math.radians(1.0), math.atan(0.5), math.nextafter(ALPHA_MAX, 0.0), ALPHA_MAX,
              math.nextafter(ALPHA_MAX, 1.0)]
    while True:
        alpha = alphas[rng.integers(len(alphas))] if rng.random() < 0.3 else rng.uniform(math.radians(1.0),
                                                                                          ALPHA_MAX)
        height = float(np.exp(rng.uniform(math.log(0.02), math.log(30.0))))
        mu = list(mu_ties(alpha).values())[rng.integers(5)] if rng.random() < 0.7 else rng.uniform(0.1, 1.2)
        thr = mu if rng.random() < 0.5 else math.tan(alpha)
        factor = [1.0, 1.0, 1.2, 3.0, 10.0][rng.integers(5)]
        ulps = [-3, -1, 0, 0, 1, 3][rng.integers(6)]
        n = [2, 3, 20, 200, 800][rng.integers(5)]
        dt = [0.005, 0.01, 0.02][rng.integers(3)]
        for m in motions(factor * thr * G, ulps=ulps, n=n, dt=dt, rng=rng):
            yield block(height, alpha, mu), m


def test_ten_thousand_boundary_scenes_end_within_their_budget():
    rng = np.random.default_rng(20261125)
    slowest = (0.0, "")
    t0 = time.perf_counter()
    draws = _draws(rng)
    for k in range(SCENES):
        blk, m = next(draws)
        timed = run_scene(m, blk)
        what = (f"{m.name}, n = {m.ah.size}, dt = {m.dt} s, peak {np.max(np.abs(m.ah)):.17g} m/s2, height "
                f"{2 * blk.R_m * math.cos(blk.alpha):.3g} m, alpha {blk.alpha!r}, mu {blk.mu!r}")
        assert timed.seconds < SCENE_BUDGET_S, what
        assert timed.scene.verdict in (0, 1), what
        assert math.isfinite(timed.scene.theta_max), what
        if k % 10 == 0:                                   # the sampled path on one scene in ten
            assert sampled_verdict(m, blk) == timed.scene.verdict, what
        slowest = max(slowest, (timed.seconds, what))
    print(f"\n{SCENES} boundary scenes in {time.perf_counter() - t0:.1f} s; the slowest took "
          f"{slowest[0] * 1e3:.1f} ms: {slowest[1]}")
