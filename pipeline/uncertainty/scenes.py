"""The probability of overturning of one scene under the declared uncertainty.

Samples are drawn in batches (:attr:`UncertaintyConfig.batch`) and judged by one compiled
call per batch (:func:`pipeline.rocking.batch.sample_verdicts`); after each batch the Wilson
interval is tested and sampling stops once it decides the robustness class
(:mod:`.robust`). Samples proven at rest by the exact certificate are not integrated.

``p_overturn`` = k / n over the samples with a verdict; samples whose ground reached
g + a_v <= 0 before any overturning (free flight) have none and are counted apart. A scene
whose first batch holds no sample with a verdict stops there (p undetermined, robustness -1):
its ground leaves the contact model at every amplitude sampled.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Iterator
from dataclasses import dataclass
from statistics import NormalDist

import numpy as np

from ..constants import G
from ..rocking.batch import sample_plane_outcomes, sample_verdicts
from ..rocking.settings import SimulationConfig
from ..rocking.simulate import step_control
from .robust import Robustness, classify, final_class, wilson_interval
from .sampling import SampledBlock, common_normals, sample_block
from .settings import UncertaintyConfig


def _batches(z: np.ndarray, batch: int, **block) -> Iterator[tuple[slice, SampledBlock]]:
    """The draws of ``z`` in batches of ``batch``: each batch's rows and its sampled blocks."""
    done = 0
    while done < len(z):
        rows = z[done: done + max(1, batch)]
        yield slice(done, done + len(rows)), sample_block(rows, **block)
        done += len(rows)


@dataclass(frozen=True)
class Probability:
    """A scene's probability of overturning and how it was reached."""

    #: fraction of the samples with a verdict that overturn (NaN: none had a verdict)
    p: float
    low: float
    high: float
    #: :class:`~.robust.Robustness` code, -1 when no sample had a verdict
    robustness: int
    #: samples drawn, samples that overturned, samples in free flight (no verdict)
    drawn: int
    overturned: int
    free_flight: int
    #: rocking or sliding planes integrated over all samples
    simulations: int


NOT_EVALUATED = Probability(math.nan, math.nan, math.nan, -1, 0, 0, 0, 0)


@dataclass(frozen=True)
class SceneMotion:
    """What a scene's samples are simulated against: the record and the candidate planes.

    ``planes_deg``: the scanned planes (the pulse axis and the grid) shared by every sample;
    None for a block with a given rocking plane (``given_deg``, sampled per sample). One
    horizontal: ``h2`` is zeros and the one recorded plane is used.
    """

    h1: np.ndarray
    h2: np.ndarray
    vertical: np.ndarray
    dt_s: float
    azimuth0_deg: float
    planes_deg: np.ndarray | None
    single: bool


def motion(horizontal_ms2: np.ndarray, azimuth0_deg: float, vertical_ms2: np.ndarray | None, dt_s: float,
           planes_deg=None) -> SceneMotion:
    """The :class:`SceneMotion` of a record (planes: None for a given azimuth or one horizontal)."""
    h = np.ascontiguousarray(np.atleast_2d(horizontal_ms2), dtype=float)
    h2 = h[1] if h.shape[0] > 1 else np.zeros_like(h[0])
    v = np.zeros(0) if vertical_ms2 is None else np.ascontiguousarray(vertical_ms2, dtype=float)
    single = h.shape[0] == 1
    planes = None if planes_deg is None or single else np.asarray(planes_deg, dtype=float)
    return SceneMotion(h[0], np.ascontiguousarray(h2), v, float(dt_s), float(azimuth0_deg), planes, single)


def scene_probability(m: SceneMotion, z: np.ndarray, *, height_m: float, width_m: float, mu: float,
                      restitution: float, azimuth_deg: float, settings: UncertaintyConfig,
                      simulation: SimulationConfig = SimulationConfig(), g_ms2: float = G) -> Probability:
    """Sample one scene until its robustness class is decided (a sensitive one to ``settings.p_halfwidth``) or
    ``z`` is used up.

    Parameters
    ----------
    m : SceneMotion
        The record and the candidate planes.
    z : ndarray, shape (n, 6)
        Common random numbers (:func:`~.sampling.common_normals`); n is the largest number of samples.
    height_m, width_m, mu, restitution, azimuth_deg : float
        The nominal block (restitution NaN: Housner's; azimuth NaN: scanned).
    settings : UncertaintyConfig
        Spreads, batch size and thresholds.
    simulation : SimulationConfig
        The simulator's settings.
    g_ms2 : float
        Gravity [m s-2].
    """
    n_max = len(z)
    if n_max == 0:
        return NOT_EVALUATED
    verdicts = np.empty(n_max, dtype=np.int64)
    planes = np.zeros(n_max, dtype=np.int64)
    done = 0
    low = high = math.nan
    for sl, sb in _batches(z, settings.batch, height_m=height_m, width_m=width_m, mu=mu, restitution=restitution,
                           azimuth_deg=azimuth_deg, settings=settings, g_ms2=g_ms2):
        n_rows = sl.stop - sl.start
        if m.single:
            phi = np.zeros((n_rows, 1))
        elif m.planes_deg is None:
            phi = np.deg2rad(sb.azimuth_deg - m.azimuth0_deg)[:, None]
        else:
            phi = np.broadcast_to(np.deg2rad(m.planes_deg - m.azimuth0_deg), (n_rows, m.planes_deg.size))
        s = simulation
        sample_verdicts(m.h1, m.h2, m.vertical, m.dt_s, np.ascontiguousarray(np.cos(phi)),
                        np.ascontiguousarray(np.sin(phi)), sb.amplitude, sb.p, sb.alpha, sb.e, sb.R_m, sb.mu,
                        float(g_ms2), float(s.vertical_fraction), bool(s.contact_model), step_control(s), verdicts[sl],
                        planes[sl])
        done = sl.stop
        v = verdicts[:done]
        k, n = int(np.sum(v == 1)), int(np.sum(v >= 0))
        lo, hi = wilson_interval(k, n, confidence=settings.confidence)
        low, high = float(lo), float(hi)
        if n == 0:                    # every sample so far in free flight: no verdict to estimate p from
            break
        decided = classify(low, high, below=settings.robust_below, above=settings.robust_above)
        if decided is not None and (decided != Robustness.sensitive or (high - low) / 2.0 <= settings.p_halfwidth):
            break
    v = verdicts[:done]
    k, n = int(np.sum(v == 1)), int(np.sum(v >= 0))
    return Probability(k / n if n else math.nan, low, high,
                       final_class(low, high, below=settings.robust_below, above=settings.robust_above),
                       done, k, int(np.sum(v == -1)), int(planes[:done].sum()))


#: Offset of the seed of the independent draws that estimate the worst orientation's probability (the
#: orientation is chosen on the first draws; estimating it on the same draws would bias it upward).
ESTIMATION_SEED_OFFSET = 1
#: Batches of draws at least, before the worst orientation is chosen [-].
SELECTION_BATCHES = 2
#: Draws at least before the worst orientation is chosen among planes tied for the largest fraction: a tie
#: broken blind chose a plane 0.11 below the average on the bundled records with 10 draws; with 15 no plane
#: falls more than 0.05 below it (docs/validation.md) [-].
TIE_DRAWS = 15


@dataclass(frozen=True)
class OrientationProbability:
    """A scene's probability of overturning per orientation of the block.

    ``worst`` is the probability in the orientation found worst among the candidate planes (its robustness class
    is the scene's), estimated on draws independent of those that chose it; ``random`` the probability for a
    block whose orientation is unknown (uniform on [0, 180) deg): the average over the grid of planes, with the
    interval of :func:`average_interval`. For a given rocking plane or one recorded horizontal both are that
    plane's.
    """

    worst: Probability
    #: the plane ``worst`` is for [deg]; NaN when not evaluated
    worst_azimuth_deg: float
    random: float
    random_low: float
    random_high: float
    #: planes integrated in both stages
    simulations: int


NOT_EVALUATED_ORIENTATION = OrientationProbability(NOT_EVALUATED, math.nan, math.nan, math.nan, math.nan, 0)


def one_plane(prob: Probability, azimuth_deg: float) -> OrientationProbability:
    """A scene whose plane is known (given azimuth, one horizontal): both probabilities are that plane's."""
    if prob.drawn == 0:
        return NOT_EVALUATED_ORIENTATION
    return OrientationProbability(prob, azimuth_deg, prob.p, prob.low, prob.high, prob.simulations)


def orientation_probability(m: SceneMotion, z: np.ndarray, *, grid_deg: np.ndarray, height_m: float,
                            width_m: float, mu: float, restitution: float, prefer_deg: float,
                            settings: UncertaintyConfig, simulation: SimulationConfig = SimulationConfig(),
                            g_ms2: float = G, z_estimate: np.ndarray | None = None) -> OrientationProbability:
    """P(overturn) per orientation of a block whose rocking plane is unknown.

    Stage 1: draws of ``z`` in batches, each simulated in every plane of ``m.planes_deg`` (the same draws for
    every plane: common random numbers), at least :data:`SELECTION_BATCHES` batches and until the average over
    the ``grid_deg`` planes is known to ``settings.p_halfwidth`` (:func:`average_interval`) and one plane leads
    alone or :data:`TIE_DRAWS` draws are in, or ``z`` is used up. The worst plane is the one with the largest
    fraction overturning (on a tie, the middle of the plateau, then ``prefer_deg``, the nominal governing
    plane). Stage 2: that plane's probability on independent draws (:data:`ESTIMATION_SEED_OFFSET`),
    by :func:`scene_probability`, which also decides the scene's robustness class.

    Parameters
    ----------
    m : SceneMotion
        The record and the candidate planes (``m.planes_deg``: the pulse axis and the grid).
    z : ndarray, shape (n, 6)
        Common random numbers; n is the largest number of samples.
    grid_deg : ndarray
        The uniform grid of planes on [0, 180) the average over orientations is taken on [deg].
    height_m, width_m, mu, restitution : float
        The nominal block (restitution NaN: Housner's).
    prefer_deg : float
        The nominal governing plane [deg], chosen on a tie.
    settings, simulation, g_ms2
        As for :func:`scene_probability`.
    z_estimate : ndarray, optional
        The independent draws of stage 2, when the caller made them once for many scenes (default:
        :func:`estimation_normals` of ``settings``).
    """
    n_max = len(z)
    planes_deg = np.asarray(m.planes_deg, dtype=float)
    if n_max == 0 or planes_deg.size == 0:
        return NOT_EVALUATED_ORIENTATION
    on_grid = np.isin(np.round(planes_deg % 180.0, 9), np.round(np.asarray(grid_deg) % 180.0, 9))
    outcomes = np.zeros((n_max, planes_deg.size), dtype=np.int8)
    planes = np.zeros(n_max, dtype=np.int64)
    done = 0
    mean = low = high = math.nan
    control = step_control(simulation)
    cosines, sines = np.cos(np.deg2rad(planes_deg - m.azimuth0_deg)), np.sin(np.deg2rad(planes_deg - m.azimuth0_deg))
    for sl, sb in _batches(z, settings.batch, height_m=height_m, width_m=width_m, mu=mu, restitution=restitution,
                           azimuth_deg=math.nan, settings=settings, g_ms2=g_ms2):
        shape = (sl.stop - sl.start, planes_deg.size)
        sample_plane_outcomes(m.h1, m.h2, m.vertical, m.dt_s, np.ascontiguousarray(np.broadcast_to(cosines, shape)),
                              np.ascontiguousarray(np.broadcast_to(sines, shape)), sb.amplitude, sb.p, sb.alpha, sb.e,
                              sb.R_m, sb.mu, float(g_ms2), float(simulation.vertical_fraction),
                              bool(simulation.contact_model), control, outcomes[sl], planes[sl])
        done = sl.stop
        fractions = _grid_fractions(outcomes[:done], on_grid)
        if fractions.size == 0:       # no draw has a verdict in any grid plane (free flight)
            mean = low = high = math.nan
            break
        mean, low, high = average_interval(fractions, confidence=settings.confidence)
        if done >= SELECTION_BATCHES * settings.batch and (high - low) / 2.0 <= settings.p_halfwidth \
                and (done >= TIE_DRAWS or _top_is_unique(_plane_fractions(outcomes[:done]))):
            break
    worst_deg = _worst_plane(_plane_fractions(outcomes[:done]), planes_deg, prefer_deg)
    if math.isnan(worst_deg):
        return NOT_EVALUATED_ORIENTATION
    z2 = estimation_normals(settings, n_max) if z_estimate is None else z_estimate
    worst = scene_probability(dataclasses.replace(m, planes_deg=np.array([worst_deg])), z2, height_m=height_m,
                              width_m=width_m, mu=mu, restitution=restitution, azimuth_deg=math.nan,
                              settings=settings, simulation=simulation, g_ms2=g_ms2)
    return OrientationProbability(worst, worst_deg, mean, low, high, int(planes[:done].sum()) + worst.simulations)


def estimation_normals(settings: UncertaintyConfig, samples: int) -> np.ndarray:
    """The common random numbers of the draws that estimate a chosen orientation's probability: independent of
    the selection draws (seed + :data:`ESTIMATION_SEED_OFFSET`)."""
    return common_normals(settings.seed + ESTIMATION_SEED_OFFSET, samples)


def average_interval(fractions: np.ndarray, *, confidence: float) -> tuple[float, float, float]:
    """Mean of per-draw fractions in [0, 1] and its two-sided interval: normal on their spread, or, when every
    draw gives the same fraction (no spread to measure), Wilson's on their sum as k of n (a fraction's variance
    is at most a Bernoulli one's, so this is the conservative bound)."""
    n = fractions.size
    mean = float(fractions.mean())
    sd = float(fractions.std(ddof=1)) if n > 1 else 0.0
    if sd > 0.0:
        half = NormalDist().inv_cdf(0.5 + confidence / 2.0) * sd / math.sqrt(n)
        return mean, max(0.0, mean - half), min(1.0, mean + half)
    lo, hi = wilson_interval(float(fractions.sum()), n, confidence=confidence)
    return mean, float(lo), float(hi)


def _grid_fractions(outcomes: np.ndarray, on_grid: np.ndarray) -> np.ndarray:
    """Per draw with a verdict in some grid plane, the fraction of those planes that overturn."""
    grid = outcomes[:, on_grid]
    judged = (grid >= 0).sum(axis=1)
    over = (grid == 1).sum(axis=1)
    has = judged > 0
    return over[has] / judged[has]


def _plane_fractions(outcomes: np.ndarray) -> np.ndarray:
    """Per plane, the fraction of the draws with a verdict that overturn (NaN for a plane without one)."""
    judged = (outcomes >= 0).sum(axis=0)
    return np.where(judged > 0, (outcomes == 1).sum(axis=0) / np.maximum(judged, 1), np.nan)


def _top_is_unique(frac: np.ndarray) -> bool:
    """True when one plane alone has the largest fraction (``frac`` of :func:`_plane_fractions`)."""
    return bool(np.isfinite(frac).any()) and int(np.sum(frac == np.nanmax(frac))) == 1


def _worst_plane(frac: np.ndarray, planes_deg: np.ndarray, prefer_deg: float) -> float:
    """The plane with the largest fraction of draws overturning (``frac`` of :func:`_plane_fractions`); on a
    tie, the one farthest from any plane with a smaller fraction (the probability varies smoothly with the
    orientation, so the middle of a plateau is taken as the best guess of its maximum); then ``prefer_deg``,
    then the first.
    NaN when no plane has a draw with a verdict."""
    if not np.isfinite(frac).any():
        return math.nan
    best = np.flatnonzero(frac == np.nanmax(frac))
    lower = np.flatnonzero(~(frac == np.nanmax(frac)))
    if best.size > 1 and lower.size:
        gap = np.abs((planes_deg[best][:, None] - planes_deg[lower][None, :] + 90.0) % 180.0 - 90.0)
        depth = gap.min(axis=1)                       # angular distance to the plateau's edge [deg]
        best = best[np.isclose(depth, depth.max())]
    if np.isfinite(prefer_deg):
        preferred = best[np.isclose(planes_deg[best] % 180.0, prefer_deg % 180.0)]
        if preferred.size:
            return float(planes_deg[preferred[0]])
    return float(planes_deg[best[0]])
