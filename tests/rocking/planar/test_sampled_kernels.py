"""The sampled kernels against the planner, draw by draw and plane by plane.

Each draw of the declared uncertainty is a block and a factor on the record; the planner
(:func:`~pipeline.rocking.planner.simulate_scene`, its own at-rest certificate and models) judges that block on the
record scaled by that factor and projected on each plane. The sampled kernels must give the same outcome in every
cell (:func:`~pipeline.rocking.planar.sampled.sample_plane_outcomes`) and the same verdict over the planes
(:func:`~pipeline.rocking.planar.sampled.sample_verdicts`), the draws that no plane moves (passed over before the
sample's vertical is scaled) as well as those that move.
"""

from __future__ import annotations

import numpy as np
import pytest

from pipeline.constants import G
from pipeline.rocking.block import BlockShape
from pipeline.rocking.codes import Verdict
from pipeline.rocking.planar.sampled import SampledMotion, SampleRules, kernels, sampled_blocks
from pipeline.rocking.planner import Physics, simulate_scene
from pipeline.rocking.scene import Scene
from pipeline.rocking.settings import SimulationConfig
from pipeline.rocking.simulate import step_control
from pipeline.uncertainty.sampling import common_normals, sample_block
from pipeline.uncertainty.settings import UncertaintyConfig

DT_S = 0.01
#: The planes' azimuths from the first horizontal [deg].
PLANES_DEG = np.array([0.0, 40.0, 95.0, 150.0])
#: A spread wide enough that the draws straddle the block's at-rest threshold on these records.
SPREAD = UncertaintyConfig(amplitude_cov=0.35, restitution_cov=0.05, friction_cov=0.10, size_cov=0.02)


def _record(vertical: str) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
    """Two horizontals (a pulse polarised at 30 deg and a weaker cross component) and a vertical: none, mild, or
    one whose ground falls faster than gravity for a moment."""
    t = np.arange(0.0, 4.0, DT_S)
    pulse = 0.30 * G * np.sin(2 * np.pi * t / 0.8) * (t < 1.6)
    cross = 0.08 * G * np.sin(2 * np.pi * t / 0.3)
    h1 = pulse * np.cos(np.radians(30.0)) + cross
    h2 = pulse * np.sin(np.radians(30.0))
    av = {"none": None, "mild": 0.1 * G * np.sin(2 * np.pi * t / 0.25),
          "falling": np.where((t > 2.0) & (t < 2.2), -1.2 * G, 0.0)}[vertical]
    return h1, h2, av


def _planner_scene(h1, h2, av, eps: float, c: float, s: float, block) -> Scene:
    """The planner's scene of one draw's block on the record scaled by ``eps``, projected on the plane (c, s)."""
    return simulate_scene(eps * (c * h1 + s * h2), None if av is None else eps * av, DT_S, block=block)


@pytest.mark.parametrize("vertical", ["none", "mild", "falling"])
@pytest.mark.parametrize("shape", [BlockShape(height_m=1.6, width_m=0.4, mu=0.7),      # rocks
                                   BlockShape(height_m=0.6, width_m=1.0, mu=0.25)],    # too squat: slides
                         ids=["slender", "squat"])
def test_every_cell_and_verdict_is_the_planners(vertical, shape):
    h1, h2, av = _record(vertical)
    draws = sample_block(common_normals(7, 24), shape, settings=SPREAD)
    n = draws.amplitude.size
    phi = np.radians(np.broadcast_to(PLANES_DEG, (n, PLANES_DEG.size)))
    cos, sin = np.ascontiguousarray(np.cos(phi)), np.ascontiguousarray(np.sin(phi))
    motion = SampledMotion(h1, h2, np.zeros(0) if av is None else av, DT_S)
    rules = SampleRules(G, 0.0, True, step_control(SimulationConfig()))
    outcome = np.empty((n, PLANES_DEG.size), dtype=np.int8)
    verdict, planes = np.empty(n, dtype=np.int64), np.zeros(n, dtype=np.int64)
    sample_verdicts, sample_plane_outcomes = kernels()
    sample_plane_outcomes(motion, cos, sin, sampled_blocks(draws), rules, outcome, np.zeros(n, dtype=np.int64))
    sample_verdicts(motion, cos, sin, sampled_blocks(draws), rules, verdict, planes)
    rests = 0
    for k in range(n):
        scenes = [_planner_scene(h1, h2, av, float(draws.amplitude[k]), float(cos[k, j]), float(sin[k, j]),
                                 draws.block(k)) for j in range(PLANES_DEG.size)]
        expected = [int(sc.verdict) for sc in scenes]
        assert outcome[k].tolist() == expected, k
        over = Verdict.overturns in expected
        assert verdict[k] == (Verdict.overturns if over else Verdict.no_verdict if Verdict.no_verdict in expected
                              else Verdict.stands), k
        at_rest = all(sc.physics == Physics.none for sc in scenes)
        assert not (at_rest and planes[k]), k
        rests += at_rest
    assert 0 < rests < n          # the draws straddle the threshold: no plane moves some, some plane moves others
