"""The probability of overturning of a 3D scene on two horizontals (a cylinder, or a box with a depth at its
azimuth; :mod:`pipeline.rocking.solids.solid3d`): each draw of the declared uncertainty (amplitude, sizes, friction,
restitution, and a box's azimuth; :func:`~.sampling.sample_block`) is judged once
(:func:`~pipeline.rocking.solids.solid3d.judge_solid`: a box's planar scene where that draw's other axis is certified,
else the 3D model), with the sampling and stopping rule of every other scene
(:func:`~.scenes.sample_until_decided`). A draw whose base would slide or lift off, or that reached the step cap,
has no verdict and is counted apart, as a planar draw in free flight is. A draw that cannot tip while the ground
pushes it up (:func:`~pipeline.rocking.solids.solid3d.stays_flat`: its drawn mu below the tan of its drawn smallest
tipping angle) stands without a run. A cylinder draws no orientation: it is axisymmetric.
"""

from __future__ import annotations

import numpy as np

from ..constants import G
from ..rocking.block import BlockShape
from ..rocking.codes import Verdict
from ..rocking.settings import SimulationConfig
from ..rocking.solids.solid3d import Solid, drawn, judge_solid
from .sampling import sample_block
from .scenes import Probability, SceneMotion, sample_until_decided
from .settings import UncertaintyConfig


def solid_probability(m: SceneMotion, z: np.ndarray, shape: BlockShape, solid: Solid, *, record_azimuth_deg: float,
                      settings: UncertaintyConfig, simulation: SimulationConfig = SimulationConfig(),
                      g_ms2: float = G) -> Probability:
    """Sample a solid's 3D scene until its robustness class is decided or ``z`` is used up (parameters as
    :func:`~.scenes.scene_probability`; ``m`` must hold two horizontals, the first at compass
    ``record_azimuth_deg``)."""
    draws = sample_block(z, shape, settings=settings, g_ms2=g_ms2)     # every draw's block, made once

    def judge(sl: slice, verdicts: np.ndarray, runs: np.ndarray) -> None:
        sb = draws.rows(sl)
        for r in range(sl.stop - sl.start):
            az = None if np.isnan(sb.azimuth_deg[r]) else float(sb.azimuth_deg[r])
            body = drawn(solid, R_m=float(sb.R_m[r]), alpha=float(sb.alpha[r]), mu=float(sb.mu[r]),
                         restitution=float(sb.e[r]), azimuth_deg=az, record_azimuth_deg=record_azimuth_deg)
            sc = judge_solid(m.h1, m.h2, m.vertical, m.dt_s, body, settings=simulation, g_ms2=g_ms2,
                             amplitude=float(sb.amplitude[r]), verdict_only=True).scene
            verdicts[sl.start + r] = (Verdict.overturns if sc.overturned else Verdict.no_verdict
                                      if sc.verdict < 0 else Verdict.stands)
            runs[sl.start + r] = 1 if sc.theta_max > 0 else 0

    return sample_until_decided(len(z), judge, settings=settings)
