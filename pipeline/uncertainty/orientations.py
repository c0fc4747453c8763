"""P(overturn) of a block whose rocking plane is unknown: the worst orientation, and a random one.

Samples are spent only where they decide something.

**The worst orientation** (:func:`worst_orientation`), on a record of two horizontals:

1. Where the nominal scan overturned the block, its governing plane is estimated first, on draws independent
   of any selection (:func:`estimation_normals`). If that is ``robust_overturn`` it is the answer: a worse plane
   can only be higher.
2. Otherwise the candidates are the governing plane and the three planes with the largest nominal peak
   rotation; where the nominal overturned (most planes then overturn nominally, and their peak rotation cannot
   tell them apart), every :data:`PILOT_STRIDE`-th plane in azimuth order and the governing plane, the chosen
   plane's neighbours being simulated on the race's draws at the end (:func:`_refine`).
3. A pilot of one batch of draws in every candidate (common random numbers: the same draws in every plane).
   The leader, the plane with the largest fraction overturning, is estimated on the independent draws; it is the
   answer when that decides ``robust_overturn``, or ``robust_stand`` with no overturning in any pilot cell.
4. Otherwise a race, batch by batch, on the surviving planes only: a plane whose Wilson upper bound falls below
   the leader's lower bound is dropped, and so is one that overturned in more than :data:`RACE_MARGIN` fewer of
   the same draws than the plane that overturned in most (:func:`racing`). The race ends when one plane is left,
   when one plane leads alone after :data:`SELECTION_BATCHES` batches, or at :data:`TIE_DRAWS` draws; the plane
   with the largest fraction is chosen (on a tie the middle of the plateau, then the governing plane) and
   estimated on the independent draws.
5. The answer is never below the governing plane's own estimate where one was made (step 1): a scene whose
   nominal run overturns is ``robust_stand`` only when that estimate says so.

**A random orientation** (:func:`random_orientation`): each draw is simulated in one plane of the grid, taken by
cycling random permutations of the grid (a fixed seed, the same for every scene), so that the fraction of draws
that overturn is an unbiased estimate of the average over orientations uniform on [0, 180); cells already
simulated by the worst orientation's selection are reused. Its interval stops the draws at a half-width of
``orientation_average_halfwidth`` or ``orientation_average_samples`` draws: Wilson's, or, once every plane of the
grid has a draw and every draw a verdict, the stratified mean's by successive differences over the planes
(:mod:`.stratified`) where that is narrower and not of zero width (the draws are a sample stratified by plane:
where the probability changes with the orientation, their mean varies less than a binomial's; below half of it in
``tests/uncertainty/test_stratified.py``).

References
----------
Wilson, E. B. (1927). Probable inference, the law of succession, and statistical inference. JASA 22(158),
209-212. Even-Dar, E., Mannor, S. & Mansour, Y. (2006). Action elimination and stopping conditions for the
multi-armed bandit and reinforcement learning problems. JMLR 7, 1079-1105 (successive elimination: an arm is
dropped once its upper confidence bound falls below the leader's lower one).
"""

from __future__ import annotations

import dataclasses
import functools
import math
from dataclasses import dataclass

import numpy as np

from ..constants import G
from ..rocking.block import BlockShape
from ..rocking.codes import Verdict
from ..rocking.planar.sampled import SampleRules, kernels, sample_rules, sampled_blocks
from ..rocking.settings import SimulationConfig
from .robust import Robustness, spanning_interval, wilson_interval
from .sampling import SampledBlock, common_normals, sample_block
from .scenes import NOT_EVALUATED, Probability, SceneMotion, scene_probability
from .settings import UncertaintyConfig
from .stratified import StratifiedMean, successive_difference_interval

#: Offset of the seed of the independent draws that estimate the worst orientation's probability (the
#: orientation is chosen on the first draws; estimating it on the same draws would bias it upward).
ESTIMATION_SEED_OFFSET = 1
#: Batches of draws at least before one plane leading alone ends the race [-].
SELECTION_BATCHES = 2
#: Draws at most in the race: planes still tied then are chosen by the plateau rule (with 15 draws no plane fell
#: more than 0.05 below the orientation average on the bundled records, docs/validation.md) [-].
TIE_DRAWS = 15
#: Planes with the largest nominal peak rotation among the candidates, besides the governing plane [-].
NOMINAL_CANDIDATES = 3
#: Seed of the permutations of the grid that give each draw of the random orientation its plane [-].
PERMUTATION_SEED = 20261125
#: Where every plane is a candidate, the pilot and the race take every PILOT_STRIDE-th plane in azimuth order (and
#: the governing plane); the chosen plane's neighbours are then raced with it [-].
PILOT_STRIDE = 2
#: In the race, a plane that overturned in more than this many fewer of the same draws than the plane that overturned
#: in most, its draws without a verdict counted as overturning, is dropped (:func:`racing`) [-]. With Wilson's rule
#: alone, 99 of the 151 scenes of 20 records x 200 blocks that raced the whole grid kept 20-22 planes to the 15th
#: draw; with this, the bundled records' scanned scenes integrated 19,461 sampled planes against 21,042, their
#: classes, worst-orientation and random-orientation errors against the 200-draw reference as before
#: (docs/validation.md).
RACE_MARGIN = 1
#: A cell (draw, plane) not simulated.
NOT_SIMULATED = -2


@dataclass(frozen=True)
class OrientationProbability:
    """A scene's probability of overturning per orientation of the block.

    ``worst`` is the probability in the orientation found worst (its robustness class is the scene's), estimated
    on draws independent of those that chose it; ``random`` the probability for a block whose orientation is
    unknown (uniform on [0, 180) deg) with its Wilson interval. For a given rocking plane or one recorded
    horizontal both are that plane's.
    """

    worst: Probability
    #: the plane ``worst`` is for [deg]; NaN when not evaluated
    worst_azimuth_deg: float
    random: float
    random_low: float
    random_high: float
    #: planes integrated for both
    simulations: int


NOT_EVALUATED_ORIENTATION = OrientationProbability(NOT_EVALUATED, math.nan, math.nan, math.nan, math.nan, 0)


def one_plane(prob: Probability, azimuth_deg: float) -> OrientationProbability:
    """A scene whose plane is known (given azimuth, one horizontal): both probabilities are that plane's."""
    if prob.drawn == 0:
        return NOT_EVALUATED_ORIENTATION
    return OrientationProbability(prob, azimuth_deg, prob.p, prob.low, prob.high, prob.simulations)


def estimation_normals(settings: UncertaintyConfig, samples: int) -> np.ndarray:
    """The common random numbers of the draws that estimate a chosen orientation's probability: independent of
    the selection draws (seed + :data:`ESTIMATION_SEED_OFFSET`)."""
    return common_normals(settings.seed + ESTIMATION_SEED_OFFSET, samples)


def average_normals(settings: UncertaintyConfig) -> np.ndarray:
    """The draws of the random orientation: the selection draws' seed, so that its first rows are theirs."""
    return common_normals(settings.seed, max(settings.orientation_average_samples, settings.samples))


@dataclass(frozen=True)
class _Block:
    """The nominal block and what its samples are simulated with."""

    #: the nominal block, its azimuth blank (each plane is given by the caller)
    shape: BlockShape
    settings: UncertaintyConfig
    simulation: SimulationConfig
    g_ms2: float

    def sample(self, z: np.ndarray) -> SampledBlock:
        """The blocks of the draws ``z`` (:func:`~.sampling.sample_block`)."""
        return sample_block(z, self.shape, settings=self.settings, g_ms2=self.g_ms2)

    @functools.cached_property
    def rules(self) -> SampleRules:
        """The sampled kernels' :class:`~pipeline.rocking.planar.sampled.SampleRules`, made once."""
        return sample_rules(self.simulation, self.g_ms2)


class _Cells:
    """Outcomes of (draw, plane) cells on the selection draws: 1 overturns, 0 stands, -1 no verdict (free flight),
    :data:`NOT_SIMULATED`; simulated on demand, each once."""

    def __init__(self, m: SceneMotion, z: np.ndarray, planes_deg: np.ndarray, blk: _Block) -> None:
        self.m, self.z, self.planes_deg, self.blk = m, z, planes_deg, blk
        self.outcome = np.full((len(z), planes_deg.size), NOT_SIMULATED, dtype=np.int8)
        self.simulations = 0

    @functools.cached_property
    def draws(self) -> SampledBlock:
        """Every selection draw's block, made once (at the first cells simulated)."""
        return self.blk.sample(self.z)

    def index(self, azimuth_deg: float) -> int:
        """The column of a plane, or -1."""
        return int(self.columns([azimuth_deg])[0])

    def columns(self, azimuths_deg) -> np.ndarray:
        """The column of each plane (the first of equal ones), -1 where none."""
        az = np.asarray(azimuths_deg, dtype=float)
        if self.planes_deg.size == 0:
            return np.full(az.size, -1)
        near = np.abs((self.planes_deg[None, :] - az[:, None] + 90.0) % 180.0 - 90.0) <= 1e-6    # isclose to 0
        return np.where(near.any(axis=1), near.argmax(axis=1), -1)

    def fill(self, rows: np.ndarray, columns: np.ndarray) -> None:
        """Simulate the cells of ``rows`` x ``columns`` not simulated yet."""
        cols = np.asarray(columns)
        rows = np.asarray([r for r in rows if np.any(self.outcome[r, cols] == NOT_SIMULATED)], dtype=int)
        if rows.size == 0 or cols.size == 0:
            return
        outcome, integrated = simulate_cells(self.m, self.draws.rows(rows),
                                             np.broadcast_to(self.planes_deg[cols], (rows.size, cols.size)), self.blk)
        self.outcome[np.ix_(rows, cols)] = outcome
        self.simulations += integrated


def simulate_cells(m: SceneMotion, sb: SampledBlock, planes_deg: np.ndarray,
                   blk: _Block) -> tuple[np.ndarray, int]:
    """Outcomes (1, 0, -1) of each draw's block of ``sb`` (:meth:`_Block.sample`) in each plane of its row of
    ``planes_deg`` [deg], and the planes integrated."""
    phi = np.deg2rad(np.asarray(planes_deg, dtype=float) - m.azimuth0_deg)
    out = np.zeros(phi.shape, dtype=np.int8)
    planes = np.zeros(phi.shape[0], dtype=np.int64)
    kernels().sample_plane_outcomes(m.sampled, np.ascontiguousarray(np.cos(phi)), np.ascontiguousarray(np.sin(phi)),
                                    sampled_blocks(sb), blk.rules, out, planes)
    return out, int(planes.sum())


def _fractions(outcome: np.ndarray) -> np.ndarray:
    """Per column, the fraction of the simulated draws with a verdict that overturn (NaN without one)."""
    judged = (outcome >= Verdict.stands).sum(axis=0)
    return np.where(judged > 0, (outcome == Verdict.overturns).sum(axis=0) / np.maximum(judged, 1), np.nan)


def _worst_plane(frac: np.ndarray, planes_deg: np.ndarray, prefer_deg: float, *, plateau: bool = True) -> float:
    """The plane with the largest fraction of draws overturning; on a tie, with ``plateau`` (the planes are the
    whole grid), the one farthest from any plane with a smaller fraction (the probability varies smoothly with the
    orientation, so the middle of a plateau is the best guess of its maximum); then ``prefer_deg``, then the first
    in the given order. NaN when no plane has a verdict."""
    if not np.isfinite(frac).any():
        return math.nan
    best = np.flatnonzero(frac == np.nanmax(frac))
    lower = np.flatnonzero(~(frac == np.nanmax(frac)))
    if plateau and best.size > 1 and lower.size:
        gap = np.abs((planes_deg[best][:, None] - planes_deg[lower][None, :] + 90.0) % 180.0 - 90.0)
        depth = gap.min(axis=1)                       # angular distance to the plateau's edge [deg]
        best = best[np.isclose(depth, depth.max())]
    if np.isfinite(prefer_deg):
        preferred = best[np.isclose(planes_deg[best] % 180.0, prefer_deg % 180.0)]
        if preferred.size:
            return float(planes_deg[preferred[0]])
    return float(planes_deg[best[0]])


@dataclass(frozen=True)
class WorstOrientation:
    """The worst orientation's probability, its plane, and the selection cells (reused by the average)."""

    prob: Probability
    azimuth_deg: float
    cells: _Cells
    simulations: int


def worst_orientation(m: SceneMotion, z: np.ndarray, z_estimate: np.ndarray, blk: _Block, *, governing_deg: float,
                      nominal_overturned: bool, ranked_deg) -> WorstOrientation:
    """The worst orientation by the module's steps 1-5 (``ranked_deg``: the planes by decreasing nominal peak
    rotation, None: every plane is a candidate)."""
    planes_deg = np.asarray(m.planes_deg, dtype=float)
    cells = _Cells(m, z, planes_deg, blk)
    u = blk.settings
    estimates: dict[float, Probability] = {}
    sims = 0

    def estimate(az: float) -> Probability:
        nonlocal sims
        if az not in estimates:
            estimates[az] = scene_probability(dataclasses.replace(m, planes_deg=np.array([az])), z_estimate,
                                              blk.shape, settings=u, simulation=blk.simulation,
                                              g_ms2=blk.g_ms2)
            sims += estimates[az].simulations
        return estimates[az]

    def done(prob: Probability, az: float) -> WorstOrientation:
        gov = estimates.get(governing_deg)
        if gov is not None and gov.drawn and (math.isnan(prob.p) or gov.p > prob.p):
            prob, az = gov, governing_deg                      # step 5: never below the governing plane's estimate
        return WorstOrientation(prob, az, cells, sims + cells.simulations)

    gov_known = math.isfinite(governing_deg) and cells.index(governing_deg) >= 0
    if nominal_overturned and gov_known:                       # step 1
        gov = estimate(governing_deg)
        if gov.robustness == Robustness.robust_overturn:
            return done(gov, governing_deg)
    whole = nominal_overturned or ranked_deg is None
    if whole:                                                  # step 2
        by_azimuth = np.argsort(planes_deg % 180.0, kind="stable")
        coarse = by_azimuth[::PILOT_STRIDE]
        gov_column = cells.index(governing_deg) if gov_known else -1
        cand = np.array(sorted(set(coarse.tolist()) | ({gov_column} if gov_column >= 0 else set())), dtype=int)
    else:
        first = [governing_deg] if gov_known else []
        picks = [c for c in dict.fromkeys(cells.columns([*first, *ranked_deg]).tolist()) if c >= 0]
        cand = np.array(picks[:NOMINAL_CANDIDATES + len(first)] or [0], dtype=int)
    n_max, batch = len(z), max(1, u.batch)
    drawn = min(batch, n_max)
    cells.fill(np.arange(drawn), cand)                        # step 3: the pilot
    frac = _fractions(cells.outcome[:drawn][:, cand])
    leader = _worst_plane(frac, planes_deg[cand], governing_deg, plateau=whole)
    if math.isnan(leader):
        return WorstOrientation(NOT_EVALUATED, math.nan, cells, sims + cells.simulations)
    lead = estimate(leader)
    pilot_overturns = bool(np.any(cells.outcome[:drawn][:, cand] == Verdict.overturns))
    if lead.robustness == Robustness.robust_overturn or (lead.robustness == Robustness.robust_stand
                                                        and not pilot_overturns):
        return done(lead, leader)
    alive = cand                                               # step 4: the race
    while True:
        outcome = cells.outcome[:drawn][:, alive]
        frac = _fractions(outcome)
        keep = racing(outcome, confidence=u.confidence)
        alive = alive[keep]
        unique = int(np.sum(frac[keep] == np.nanmax(frac[keep]))) == 1 if np.isfinite(frac[keep]).any() else False
        if alive.size <= 1 or drawn >= n_max or drawn >= TIE_DRAWS or (unique and drawn >= SELECTION_BATCHES * batch):
            break
        more = min(batch, n_max - drawn)
        cells.fill(np.arange(drawn, drawn + more), alive)
        drawn += more
    # the plateau rule sees the planes dropped from the race as lower ones
    frac = np.where(np.isin(cand, alive), _fractions(cells.outcome[:drawn][:, cand]), -1.0)
    chosen = _worst_plane(frac, planes_deg[cand], governing_deg, plateau=whole)
    if whole and PILOT_STRIDE > 1 and math.isfinite(chosen):
        chosen = _refine(cells, chosen, drawn, alive, governing_deg)
    if math.isnan(chosen):
        chosen = leader
    return done(estimate(chosen), chosen)


def racing(outcome: np.ndarray, *, confidence: float) -> np.ndarray:
    """Which planes stay in the race, given their outcomes on the same draws (``outcome``: one column per plane,
    :class:`~pipeline.rocking.codes.Verdict` codes, every cell simulated). A plane leaves it where its Wilson upper
    bound is below the leader's lower bound (successive elimination, Even-Dar et al. 2006), or where it overturned in
    more than :data:`RACE_MARGIN` fewer of those draws than the plane that overturned in most, its draws without a
    verdict counted as overturning. The leader (the largest fraction) always stays: its upper bound is not below its
    own lower bound, and a plane dropped by the margin overturned in fewer of the draws and stood in more of them
    than the plane that overturned in most, so that its fraction is the smaller."""
    k = (outcome == Verdict.overturns).sum(axis=0)
    n = (outcome >= Verdict.stands).sum(axis=0)
    unknown = (outcome == Verdict.no_verdict).sum(axis=0)
    frac = _fractions(outcome)
    low, high = wilson_interval(k, n, confidence=confidence)
    top = int(np.nanargmax(np.where(np.isfinite(frac), frac, -1.0)))
    return ~(np.nan_to_num(high, nan=1.0) < np.nan_to_num(low[top], nan=0.0)) & (k + unknown >= k.max() - RACE_MARGIN)


def _refine(cells: _Cells, chosen_deg: float, drawn: int, alive: np.ndarray, governing_deg: float) -> float:
    """The chosen plane or one of its neighbours left out of a strided race, whichever overturns most often on the
    race's draws (the neighbours are simulated on those draws)."""
    planes_deg = cells.planes_deg
    order = np.argsort(planes_deg % 180.0, kind="stable")
    at = int(np.flatnonzero(order == cells.index(chosen_deg))[0])
    side = [int(order[(at + d) % order.size]) for d in range(-PILOT_STRIDE + 1, PILOT_STRIDE) if d]
    near = np.array(sorted(set(side) - set(alive.tolist())), dtype=int)
    if near.size == 0:
        return chosen_deg
    cells.fill(np.arange(drawn), near)
    cols = np.concatenate([[cells.index(chosen_deg)], near])
    return _worst_plane(_fractions(cells.outcome[:drawn][:, cols]), planes_deg[cols], chosen_deg, plateau=False)


def random_orientation(m: SceneMotion, z_average: np.ndarray, blk: _Block, *, grid_deg: np.ndarray,
                       cells: _Cells | None = None) -> tuple[float, float, float, int]:
    """P(overturn) for a uniformly random orientation, its interval (the module's: Wilson's, or the stratified
    mean's where that is narrower and not of zero width) and the planes integrated: draw k in grid plane ``order[k]``
    (:func:`plane_order`), reusing the selection ``cells`` where they hold that cell."""
    u = blk.settings
    grid = np.asarray(grid_deg, dtype=float)
    n_max = len(z_average)
    order = plane_order(grid.size, n_max)
    outcome = np.full(n_max, NOT_SIMULATED, dtype=np.int8)
    if cells is not None:
        columns = cells.columns(grid)
        for k in range(min(n_max, len(cells.z))):
            c = columns[order[k]]
            if c >= 0 and cells.outcome[k, c] != NOT_SIMULATED:
                outcome[k] = cells.outcome[k, c]
    sims, drawn, batch = 0, 0, max(1, u.batch)
    mean = low = high = math.nan
    draws = blk.sample(z_average)                      # every draw's block, made once
    while drawn < n_max:
        rows = np.arange(drawn, min(drawn + batch, n_max))
        todo = rows[outcome[rows] == NOT_SIMULATED]
        if todo.size:
            drawn_cells, integrated = simulate_cells(m, draws.rows(todo), grid[order[todo]][:, None], blk)
            outcome[todo] = drawn_cells[:, 0]
            sims += integrated
        drawn = int(rows[-1]) + 1
        v = outcome[:drawn]
        k, unknown = int(np.sum(v == Verdict.overturns)), int(np.sum(v == Verdict.no_verdict))
        if drawn == unknown:
            continue
        # the draws without a verdict are unknown: the interval spans them (standing below, overturning above)
        mean = k / (drawn - unknown)
        low, high = spanning_interval(k, unknown, drawn, confidence=u.confidence)
        if unknown == 0 and drawn >= grid.size > 1:
            by_plane = _by_plane(v, order[:drawn], grid, confidence=u.confidence)
            # its mean is k / drawn: only the bounds differ; where every plane's fraction is the same, its
            # variance estimate is 0 and says nothing: Wilson's stays
            if 0.0 < by_plane.high - by_plane.low < high - low:
                low, high = by_plane.low, by_plane.high
        sampling_halfwidth = (high - low - unknown / drawn) / 2.0      # the unknown draws' share is no sampling error
        if drawn >= SELECTION_BATCHES * batch and sampling_halfwidth <= u.orientation_average_halfwidth:
            break
    return mean, low, high, sims


def _by_plane(outcome: np.ndarray, planes: np.ndarray, grid_deg: np.ndarray, *, confidence: float) -> StratifiedMean:
    """The draws' mean (``outcome`` 1 or 0, draw k in grid plane ``planes[k]``, every plane drawn) and its interval
    by successive differences over the planes in azimuth order (:mod:`.stratified`)."""
    counts = np.bincount(planes, minlength=grid_deg.size)
    overturned = np.bincount(planes, weights=(outcome == Verdict.overturns), minlength=grid_deg.size)
    by_azimuth = np.argsort(np.asarray(grid_deg) % 180.0, kind="stable")
    return successive_difference_interval(overturned[by_azimuth] / counts[by_azimuth], counts[by_azimuth],
                                          confidence=confidence)


def plane_order(n_planes: int, n_draws: int) -> np.ndarray:
    """The grid plane of each draw of the random orientation: random permutations of the grid one after another,
    from :data:`PERMUTATION_SEED` (the same for every scene)."""
    rng = np.random.Generator(np.random.PCG64(PERMUTATION_SEED))
    cycles = -(-n_draws // max(n_planes, 1))
    return np.concatenate([rng.permutation(n_planes) for _ in range(cycles)])[:n_draws]


def orientation_probability(m: SceneMotion, z: np.ndarray, shape: BlockShape, *, grid_deg: np.ndarray,
                            prefer_deg: float, settings: UncertaintyConfig,
                            simulation: SimulationConfig = SimulationConfig(), g_ms2: float = G,
                            z_estimate: np.ndarray | None = None, z_average: np.ndarray | None = None,
                            nominal_overturned: bool = True, ranked_deg=None) -> OrientationProbability:
    """P(overturn) per orientation of a block whose rocking plane is unknown.

    Parameters
    ----------
    m : SceneMotion
        The record and the candidate planes (``m.planes_deg``: the pulse axis and the grid).
    z : ndarray, shape (n, 6)
        The selection draws (common random numbers); n is the largest number of samples.
    grid_deg : ndarray
        The uniform grid of planes on [0, 180) of the random orientation [deg].
    shape : BlockShape
        The nominal block (restitution NaN: Housner's; its azimuth is not read: the planes are ``m``'s).
    prefer_deg : float
        The nominal scan's governing plane [deg].
    settings, simulation, g_ms2
        As for :func:`~.scenes.scene_probability`.
    z_estimate, z_average : ndarray, optional
        The independent draws that estimate a chosen plane, and the random orientation's draws, when the caller
        made them once for many scenes (default: :func:`estimation_normals`, :func:`average_normals`).
    nominal_overturned : bool
        The nominal scan overturned the block (default: taken as overturned, every plane a candidate).
    ranked_deg : sequence of float, optional
        The planes by decreasing nominal peak rotation (the candidates beside the governing plane when the
        nominal stands); None: every plane is a candidate.
    """
    planes_deg = np.asarray(m.planes_deg, dtype=float)
    if len(z) == 0 or planes_deg.size == 0:
        return NOT_EVALUATED_ORIENTATION
    blk = _Block(dataclasses.replace(shape, azimuth_deg=math.nan), settings, simulation, g_ms2)
    z2 = estimation_normals(settings, len(z)) if z_estimate is None else z_estimate
    worst = worst_orientation(m, z, z2, blk, governing_deg=prefer_deg, nominal_overturned=nominal_overturned,
                              ranked_deg=ranked_deg)
    if math.isnan(worst.azimuth_deg):
        return NOT_EVALUATED_ORIENTATION
    za = average_normals(settings) if z_average is None else z_average
    mean, low, high, sims = random_orientation(m, za, blk, grid_deg=grid_deg, cells=worst.cells)
    return OrientationProbability(worst.prob, worst.azimuth_deg, mean, low, high, worst.simulations + sims)
