"""The probability of overturning of a cylinder's scene on two horizontals: each draw of the declared uncertainty
(amplitude, sizes, friction, restitution; :func:`~.sampling.sample_block`) runs the 3D model once
(:mod:`pipeline.rocking.cylinder_scene`), with the sampling and stopping rule of every other scene
(:func:`~.scenes.sample_until_decided`). A draw whose base would slide or lift off has no verdict and is counted
apart, as a planar draw in free flight is. No orientation is drawn: the cylinder is axisymmetric.
"""

from __future__ import annotations

import numpy as np

from ..constants import G
from ..rocking.block import BlockShape
from ..rocking.codes import Verdict
from ..rocking.cylinder3d import FLAG_FLIGHT, FLAG_SLIDE, cylinder_from_corner
from ..rocking.cylinder_scene import run_on_record
from ..rocking.settings import SimulationConfig
from .sampling import sample_block
from .scenes import Probability, SceneMotion, sample_until_decided
from .settings import UncertaintyConfig


def cylinder_probability(m: SceneMotion, z: np.ndarray, shape: BlockShape, *, settings: UncertaintyConfig,
                         simulation: SimulationConfig = SimulationConfig(), g_ms2: float = G) -> Probability:
    """Sample a cylinder's 3D scene until its robustness class is decided or ``z`` is used up (parameters as
    :func:`~.scenes.scene_probability`; ``m`` must hold two horizontals)."""
    def judge(sl: slice, verdicts: np.ndarray, runs: np.ndarray) -> None:
        sb = sample_block(z[sl], shape, settings=settings, g_ms2=g_ms2)
        for r in range(sl.stop - sl.start):
            drawn = cylinder_from_corner(float(sb.R_m[r]), float(sb.alpha[r]), mu=float(sb.mu[r]),
                                         restitution=float(sb.e[r]))
            out = run_on_record(m.h1, m.h2, m.vertical, m.dt_s, drawn, settings=simulation, g_ms2=g_ms2,
                                amplitude=float(sb.amplitude[r]))
            verdicts[sl.start + r] = (Verdict.overturns if out.overturned else Verdict.no_verdict
                                      if out.flag in (FLAG_SLIDE, FLAG_FLIGHT) else Verdict.stands)
            runs[sl.start + r] = 1 if out.theta_max_rad > 0 else 0

    return sample_until_decided(len(z), judge, settings=settings)
