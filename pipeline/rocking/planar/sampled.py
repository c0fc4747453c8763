"""Many variants of one scene in one compiled call: the samples of the uncertainty analysis.

:func:`sample_verdicts` runs, for each sample, what the planner and the orientation scan
run for a nominal scene (:func:`~.planner.simulate_scene`, :func:`~.orientation.worst_plane`),
with the same kernels and the same decisions, but without Python between samples:

1. the record scaled by the sample's amplitude factor, vertical included;
2. the exact at-rest certificate: where the demand ratio max |a| / (g + a_v) of every
   candidate plane stays at or below min(tan alpha, mu), the sample rests (no integration);
   for several planes the horizontal vector's peak bounds every plane's demand first;
3. a sampled block that cannot rock (mu <= tan alpha, or too squat) cannot overturn: it is not
   integrated, and its verdict is free flight where a plane moves it and the ground's g + a_v reaches 0
   at some sample (exactly what the Coulomb integration of that plane would find), else 0;
4. otherwise the planes that move, strongest demand first, by rocking (with the vertical unless the
   ``vertical_fraction`` approximation drops it; at rest, the kernel passes over the chunks of samples that the
   record's vector quiet table, scaled by the sample's factor, shows cannot lift the block: the same verdict);
   the first plane that overturns decides;
5. verdict 1 (overturns in some plane), -1 (free flight in some plane and no overturn:
   undetermined), else 0.

The orientation refinement of the nominal scan (1-degree planes around the worst standing
plane) is not repeated per sample: a sample's worst plane is over the grid and the pulse axis.
With unit factors and the nominal block, a sample's verdict equals the nominal scene's
whenever the nominal verdict was decided on the grid (tested).
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable
from typing import NamedTuple

import numpy as np

from ...compiled import jit, rebound
from .. import models
from ..block import rigid_block
from ..codes import NO_VERDICT, OVERTURNS, STANDS
from ..contract import PlaneSample, SampleWorkspace, SceneFacts
from ..models import judge
from ..numerics.ground import NO_QUIET, QuietTable, scaled_demand_ratio
from ..rules import motion_threshold_compiled, rocks_compiled, vertical_kept_compiled
from ..simulate import step_control
from ..structures import RockingOutput, RockingState


class SampledMotion(NamedTuple):
    """The record the samples of a scene share (a numba namedtuple).

    Attributes
    ----------
    h1, h2 : ndarray
        The record's two horizontals [m s-2] (``h2`` zeros for a single component).
    av : ndarray
        Vertical [m s-2], empty without one.
    dt : float
        Sampling interval [s].
    quiet_peak, quiet_least : ndarray
        The record's :func:`~pipeline.rocking.numerics.ground.vector_quiet_table` (its peaks and least verticals,
        unscaled), which each sample scales by its factor so that its rocking kernel passes over the chunks that
        cannot lift its block; empty (the default): none, every sample tested.
    """

    h1: np.ndarray
    h2: np.ndarray
    av: np.ndarray
    dt: float
    quiet_peak: np.ndarray = NO_QUIET.peak_ah_ms2
    quiet_least: np.ndarray = NO_QUIET.least_av_ms2


class SampledBlocks(NamedTuple):
    """Each sample's amplitude factor and block (a numba namedtuple of arrays, shape (n_samples,)).

    Attributes
    ----------
    eps : ndarray
        Amplitude factor on the record [-].
    p, alpha, e, R, mu : ndarray
        Frequency parameter [rad s-1], slenderness [rad], restitution [-], half-diagonal [m], friction [-].
    """

    eps: np.ndarray
    p: np.ndarray
    alpha: np.ndarray
    e: np.ndarray
    R: np.ndarray
    mu: np.ndarray


class SampleRules(NamedTuple):
    """What decides a sample besides its motion and block (a numba namedtuple).

    Attributes
    ----------
    g : float
        Gravity [m s-2].
    vertical_fraction : float
        The planner's vertical approximation (0: the vertical is always simulated) [-].
    contact_model : bool
        Continue with the general contact model where pure rocking stops holding (without it, free flight gives
        no verdict).
    control : StepControl
        The simulator's step control (:func:`~pipeline.rocking.simulate.step_control`).
    """

    g: float
    vertical_fraction: float
    contact_model: bool
    control: object


def sample_rules(settings, g_ms2: float) -> SampleRules:
    """The :class:`SampleRules` of the simulator's settings (:class:`~..settings.SimulationConfig`) and gravity
    ``g_ms2`` [m s-2]."""
    return SampleRules(float(g_ms2), float(settings.vertical_fraction), bool(settings.contact_model),
                       step_control(settings))


def sampled_blocks(sb) -> SampledBlocks:
    """The :class:`SampledBlocks` of a :class:`~pipeline.uncertainty.sampling.SampledBlock`'s draws."""
    return SampledBlocks(sb.amplitude, sb.p, sb.alpha, sb.e, sb.R_m, sb.mu)


@jit
def _plane_demands(h1, h2, cosines, sines, k, eps, av, has_v, g, thr, ratios):
    """Fill ``ratios`` with sample k's demand in each of its planes
    (:func:`~pipeline.rocking.numerics.ground.scaled_demand_ratio`); True where some plane's
    exceeds ``thr`` (the sample moves)."""
    moves = False
    for j in range(ratios.size):
        ratios[j] = scaled_demand_ratio(h1, h2, cosines[k, j], sines[k, j], eps, av, has_v, g, bool(False))
        moves = moves or ratios[j] > thr
    return moves


@jit
def _scale_vertical(av_s, av, eps):
    """``av_s`` = eps ``av``, element by element (the sample's vertical; empty without one)."""
    for i in range(av_s.size):
        av_s[i] = eps * av[i]


@jit
def _scale_quiet(quiet, motion, eps):
    """Fill a sample's ``quiet`` table: the record's vector table (``motion.quiet_peak``, ``quiet_least``) times its
    factor ``eps``, what :func:`~..numerics.ground.vector_quiet_table` of the scaled record would hold: the values of
    :func:`~..numerics.ground.scaled_quiet_table`, written into the workspace's buffers (no array made per sample)."""
    for c in range(quiet.peak_ah_ms2.size):
        quiet.peak_ah_ms2[c] = eps * motion.quiet_peak[c]
        quiet.least_av_ms2[c] = eps * motion.quiet_least[c]


@jit
def _workspace(motion):
    """The :class:`~.contract.SampleWorkspace` of a :class:`SampledMotion`."""
    h1, av, dt = motion.h1, motion.av, motion.dt
    n = h1.size
    has_v = av.size == n
    chunks = motion.quiet_peak.size
    return SampleWorkspace(n=n, has_v=has_v, t_end=(n - 1) * dt, a=np.empty(n), av_s=np.empty(n if has_v else 0),
                           quiet=QuietTable(np.empty(chunks), np.empty(chunks)),
                           none=np.zeros(0), no_output=RockingOutput(theta=np.zeros(0), impacts=np.zeros((0, 3))),
                           at_rest=RockingState(theta=0.0, omega=0.0, t=0.0))


@jit
def _sample_block(p, alpha, e, R, mu, g, control, contact_model):
    """A sample's compiled block; the rocking kernel stops where the pivot's friction demand exceeds mu when the
    contact model continues (else never)."""
    return rigid_block(p, alpha, e, R, mu, g, control.rest_ratio, bool(False), mu if contact_model else math.inf)


@jit
def _judge(w, ratio, thr, rocks, use_v, flight, contact_model, h1, h2, c, s, eps, dt, alpha, mu, block, control):
    """One sample in one plane of weights (c, s), by the registered model whose certificate holds first
    (:func:`.models.judge`): ``(outcome, integrated)``, a :class:`~.codes.Verdict` and whether a plane was
    integrated."""
    facts = SceneFacts(ratio=ratio, threshold=thr, rocks=rocks, vertical=use_v, alpha=alpha, mu=mu)
    x = PlaneSample(a=w.a, h1=h1, h2=h2, c=c, s=s, eps=eps, av_s=w.av_s if use_v else w.none, dt=dt, t_end=w.t_end,
                    flight=flight, contact_model=contact_model)
    return judge(facts, x, block, control, w)


@jit
def _vertical_kept(av_s, g, vertical_fraction):
    """Whether a sample keeps its (scaled) vertical ``av_s`` (empty: none), by the planner's rule."""
    if av_s.size == 0:
        return False
    peak = 0.0
    for i in range(av_s.size):
        peak = max(peak, abs(av_s[i]))
    return vertical_kept_compiled(peak, g, vertical_fraction)


@jit
def _flight_at_some_sample(av_s, g):
    """True where the ground's g + a_v reaches 0 at some sample (``av_s`` empty: never)."""
    for i in range(av_s.size):
        if g + av_s[i] <= 0.0:
            return True
    return False


@jit
def sample_plane_outcomes(motion, cosines, sines, blocks, rules, outcome_out, planes_out):
    """Every sample's outcome in every candidate plane: what a block of each orientation would do.

    The same inputs as :func:`sample_verdicts`, and the same decisions per plane (the exact at-rest
    certificate, no integration for a block that cannot rock, rocking otherwise), but no plane is skipped
    once another overturns: ``outcome_out[k, j]`` is a :class:`~.codes.Verdict` (no_verdict: free flight before
    any overturning, no verdict) for sample k in plane j. ``planes_out[k]`` counts the planes integrated.
    """
    h1, h2, av, dt = motion.h1, motion.h2, motion.av, motion.dt
    eps, p, alpha, e, R, mu = blocks
    g, vertical_fraction, contact_model, control = rules
    w = _workspace(motion)
    av_s = w.av_s
    n_s, n_p = cosines.shape
    ratios = np.empty(n_p)
    for k in range(n_s):
        thr = motion_threshold_compiled(alpha[k], mu[k])
        planes_out[k] = 0
        if not _plane_demands(h1, h2, cosines, sines, k, eps[k], av, w.has_v, g, thr, ratios):
            for j in range(n_p):          # at rest in every plane: the at-rest certificate, nothing integrated
                outcome_out[k, j] = STANDS
            continue
        _scale_vertical(av_s, av, eps[k])
        _scale_quiet(w.quiet, motion, eps[k])
        use_v = _vertical_kept(av_s, g, vertical_fraction)
        rocks = rocks_compiled(alpha[k], mu[k])
        flight = use_v and _flight_at_some_sample(av_s, g)
        block = _sample_block(p[k], alpha[k], e[k], R[k], mu[k], g, control, contact_model)
        for j in range(n_p):
            outcome, integrated = _judge(w, ratios[j], thr, rocks, use_v, flight, contact_model, h1, h2, cosines[k, j],
                                         sines[k, j], eps[k], dt, alpha[k], mu[k], block, control)
            outcome_out[k, j] = outcome
            planes_out[k] += integrated


@jit
def sample_verdicts(motion, cosines, sines, blocks, rules, verdict_out, planes_out):
    """Verdicts of the samples of one scene.

    Parameters
    ----------
    motion : SampledMotion
        The record.
    cosines, sines : ndarray, shape (n_samples, n_planes)
        Projection weights of each sample's candidate planes: a = c h1 + s h2.
    blocks : SampledBlocks
        Amplitude factor and block of each sample.
    rules : SampleRules
        Gravity, the vertical approximation, the contact model's setting and the step control.
    verdict_out, planes_out : ndarray (int64)
        Filled with each sample's :class:`~.codes.Verdict` and planes integrated.
    """
    h1, h2, av, dt = motion.h1, motion.h2, motion.av, motion.dt
    eps, p, alpha, e, R, mu = blocks
    g, vertical_fraction, contact_model, control = rules
    w = _workspace(motion)
    has_v, av_s = w.has_v, w.av_s
    n_s, n_p = cosines.shape
    ratios = np.empty(n_p)
    for k in range(n_s):
        thr = motion_threshold_compiled(alpha[k], mu[k])
        verdict_out[k] = STANDS
        planes_out[k] = 0
        # the horizontal vector bounds every plane's demand; a sample no plane moves rests, nothing integrated
        if n_p > 1 and not scaled_demand_ratio(h1, h2, 0.0, 0.0, eps[k], av, has_v, g, bool(True)) > thr:
            continue
        if not _plane_demands(h1, h2, cosines, sines, k, eps[k], av, has_v, g, thr, ratios):
            continue
        _scale_vertical(av_s, av, eps[k])
        _scale_quiet(w.quiet, motion, eps[k])
        order = np.argsort(-ratios, kind="mergesort")
        use_v = _vertical_kept(av_s, g, vertical_fraction)
        rocks = rocks_compiled(alpha[k], mu[k])
        flight = use_v and _flight_at_some_sample(av_s, g)
        block = _sample_block(p[k], alpha[k], e[k], R[k], mu[k], g, control, contact_model)
        # the planes that move, strongest demand first; the first that overturns decides (a sample that cannot
        # rock is integrated only where the contact model takes a free flight: the sliding model's twin)
        seen_flight = False
        for jj in range(n_p):
            j = order[jj]
            if not ratios[j] > thr:
                break
            outcome, integrated = _judge(w, ratios[j], thr, rocks, use_v, flight, contact_model, h1, h2,
                                         cosines[k, j], sines[k, j], eps[k], dt, alpha[k], mu[k], block, control)
            planes_out[k] += integrated
            if outcome == OVERTURNS:
                verdict_out[k] = OVERTURNS
                break
            if outcome == NO_VERDICT:
                seen_flight = True
        if verdict_out[k] == STANDS and seen_flight:
            verdict_out[k] = NO_VERDICT


class SampledKernels(NamedTuple):
    """The sampled kernels of one registry of scene models."""

    sample_verdicts: Callable[..., None]
    sample_plane_outcomes: Callable[..., None]


def kernels() -> SampledKernels:
    """The sampled kernels for the planar registry as it stands now (:func:`.models.compiled_judge`): the compiled
    functions cached on disk where it is the registry imported, else copies built for it (compiled on their first
    call)."""
    current = models.compiled_judge()
    if current is judge:
        return SampledKernels(sample_verdicts, sample_plane_outcomes)
    return _kernels_for(current)


@functools.lru_cache(maxsize=4)
def _kernels_for(dispatch) -> SampledKernels:
    one = rebound(_judge, judge=dispatch)
    return SampledKernels(rebound(sample_verdicts, _judge=one), rebound(sample_plane_outcomes, _judge=one))
