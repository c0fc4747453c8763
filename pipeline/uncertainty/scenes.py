"""The probability of overturning of one scene under the declared uncertainty.

Samples are drawn in batches (:attr:`UncertaintyConfig.batch`) and judged by one compiled
call per batch (:func:`pipeline.rocking.planar.sampled.sample_verdicts`); after each batch the Wilson
interval is tested and sampling stops once it decides the robustness class
(:mod:`.robust`). Samples proven at rest by the exact certificate are not integrated.

``p_overturn`` = k / n over the samples with a verdict. A sample without one (the ground fell
faster than gravity with the contact model off, a 3D or scanned model stopped where the base would
slide, twist or lift off, a cap) is unknown: it is counted apart, and the interval spans it
(:func:`~.robust.spanning_interval`: the lower bound counts it as standing, the upper as
overturning), so a scene with unknown samples is never reported safer than they allow. A scene
whose first batch holds no sample with a verdict stops there: p undetermined, its interval
[0, 1] and its class ``sensitive``.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Iterator
from dataclasses import dataclass

import numpy as np

from ..constants import G
from ..rocking.block import BlockShape
from ..rocking.codes import Verdict
from ..rocking.numerics.ground import QuietTable, vector_quiet_table
from ..rocking.planar.sampled import SampledBlocks, SampledMotion, kernels, sample_rules, sampled_blocks
from ..rocking.settings import SimulationConfig
from .robust import Robustness, classify, final_class, spanning_interval
from .sampling import sample_block
from .settings import UncertaintyConfig


def _batches(n: int, batch: int) -> Iterator[slice]:
    """The rows of ``n`` draws in batches of ``batch``."""
    for start in range(0, n, max(1, batch)):
        yield slice(start, min(start + max(1, batch), n))


@dataclass(frozen=True)
class Probability:
    """A scene's probability of overturning and how it was reached."""

    #: fraction of the samples with a verdict that overturn (NaN: none had a verdict)
    p: float
    low: float
    high: float
    #: :class:`~.robust.Robustness` code, -1 when no sample had a verdict
    robustness: int
    #: samples drawn, samples that overturned, samples without a verdict (unknown)
    drawn: int
    overturned: int
    without_verdict: int
    #: rocking or sliding planes integrated over all samples
    simulations: int


NOT_EVALUATED = Probability(math.nan, math.nan, math.nan, -1, 0, 0, 0, 0)


@dataclass(frozen=True)
class SceneMotion:
    """What a scene's samples are simulated against: the record and the candidate planes.

    ``planes_deg``: the scanned planes (the pulse axis and the grid) shared by every sample;
    None for a block with a given rocking plane (``given_deg``, sampled per sample). One
    horizontal: ``h2`` is zeros and the one recorded plane is used. ``quiet``: the record's
    :func:`~pipeline.rocking.numerics.ground.vector_quiet_table`, which holds in every plane.
    """

    h1: np.ndarray
    h2: np.ndarray
    vertical: np.ndarray
    dt_s: float
    azimuth0_deg: float
    planes_deg: np.ndarray | None
    single: bool
    quiet: QuietTable

    @functools.cached_property
    def sampled(self) -> SampledMotion:
        """The record as the sampled kernels take it (:class:`~pipeline.rocking.planar.sampled.SampledMotion`), made
        once."""
        return SampledMotion(self.h1, self.h2, self.vertical, self.dt_s, self.quiet.peak_ah_ms2,
                             self.quiet.least_av_ms2)


def motion(horizontal_ms2: np.ndarray, azimuth0_deg: float, vertical_ms2: np.ndarray | None, dt_s: float,
           planes_deg=None) -> SceneMotion:
    """The :class:`SceneMotion` of a record (planes: None for a given azimuth or one horizontal)."""
    h = np.ascontiguousarray(np.atleast_2d(horizontal_ms2), dtype=float)
    h2 = h[1] if h.shape[0] > 1 else np.zeros_like(h[0])
    v = np.zeros(0) if vertical_ms2 is None else np.ascontiguousarray(vertical_ms2, dtype=float)
    single = h.shape[0] == 1
    planes = None if planes_deg is None or single else np.asarray(planes_deg, dtype=float)
    h2 = np.ascontiguousarray(h2)
    quiet = vector_quiet_table(h[0], h2, v if v.size else None)
    return SceneMotion(h[0], h2, v, float(dt_s), float(azimuth0_deg), planes, single, quiet)


def scene_probability(m: SceneMotion, z: np.ndarray, shape: BlockShape, *, settings: UncertaintyConfig,
                      simulation: SimulationConfig = SimulationConfig(), g_ms2: float = G) -> Probability:
    """Sample one scene until its robustness class is decided (a sensitive one to ``settings.p_halfwidth``) or
    ``z`` is used up.

    Parameters
    ----------
    m : SceneMotion
        The record and the candidate planes.
    z : ndarray, shape (n, 6)
        Common random numbers (:func:`~.sampling.common_normals`); n is the largest number of samples.
    shape : BlockShape
        The nominal block (restitution NaN: Housner's; azimuth NaN: scanned, else the given plane, sampled).
    settings : UncertaintyConfig
        Spreads, batch size and thresholds.
    simulation : SimulationConfig
        The simulator's settings.
    g_ms2 : float
        Gravity [m s-2].
    """
    draws = sample_block(z, shape, settings=settings, g_ms2=g_ms2)     # every draw's block, made once
    # every draw's planes and the kernel's arguments, made once: each batch takes its rows
    n = len(z)
    if m.single:
        phi = np.zeros((n, 1))
    elif m.planes_deg is None:
        phi = np.deg2rad(draws.azimuth_deg - m.azimuth0_deg)[:, None]
    else:
        phi = np.broadcast_to(np.deg2rad(m.planes_deg - m.azimuth0_deg), (n, m.planes_deg.size))
    cosines, sines = np.ascontiguousarray(np.cos(phi)), np.ascontiguousarray(np.sin(phi))
    blocks = sampled_blocks(draws)
    rules = sample_rules(simulation, g_ms2)
    sample_verdicts = kernels().sample_verdicts

    def judge(sl: slice, verdicts: np.ndarray, planes: np.ndarray) -> None:
        sample_verdicts(m.sampled, cosines[sl], sines[sl], SampledBlocks(*(column[sl] for column in blocks)), rules,
                        verdicts[sl], planes[sl])

    return sample_until_decided(len(z), judge, settings=settings)


def sample_until_decided(n_max: int, judge, *, settings: UncertaintyConfig) -> Probability:
    """Judge draws in batches (``judge(rows, verdicts, simulations)`` fills the :class:`~pipeline.rocking.codes.Verdict`
    and the simulations of the rows ``rows``) until the Wilson interval decides the robustness class (a sensitive
    one to ``settings.p_halfwidth``) or the ``n_max`` draws are used up."""
    if n_max == 0:
        return NOT_EVALUATED
    verdicts = np.empty(n_max, dtype=np.int64)
    planes = np.zeros(n_max, dtype=np.int64)
    done = 0
    low = high = math.nan
    for sl in _batches(n_max, settings.batch):
        judge(sl, verdicts, planes)
        done = sl.stop
        k, unknown, judged = _counts(verdicts[:done])
        low, high = spanning_interval(k, unknown, done, confidence=settings.confidence)
        if judged == 0:               # no sample so far has a verdict: nothing to estimate p from
            break
        decided = classify(low, high, below=settings.robust_below, above=settings.robust_above)
        # the unknown draws' share of the width is no sampling error: more draws keep it, so it is not waited on
        if decided is not None and (decided != Robustness.sensitive
                                    or (high - low - unknown / done) / 2.0 <= settings.p_halfwidth):
            break
    k, unknown, judged = _counts(verdicts[:done])
    return Probability(k / judged if judged else math.nan, low, high,
                       final_class(low, high, below=settings.robust_below, above=settings.robust_above,
                                   unknown_fraction=unknown / done),
                       done, k, unknown, int(planes[:done].sum()))


def _counts(verdicts: np.ndarray) -> tuple[int, int, int]:
    """Draws that overturn, draws without a verdict and draws with one, of :class:`~pipeline.rocking.codes.Verdict`
    codes (a scene's few dozen codes counted as a list: three array reductions cost more than the counting)."""
    codes = verdicts.tolist()
    overturned, unknown = codes.count(Verdict.overturns), codes.count(Verdict.no_verdict)
    return overturned, unknown, overturned + codes.count(Verdict.stands)
