"""Scenes drawn on the simulator's boundaries (the tie rules of :mod:`pipeline.rocking.rules`), and a runner that
holds each scene to a wall-clock budget.

The budget is enforced twice: each scene's time is measured and compared with :data:`SCENE_BUDGET_S`, and a
watchdog (:func:`faulthandler.dump_traceback_later`) ends the whole test process, with the stack of the scene
that hung, should a scene never return (compiled code cannot be interrupted from Python), so that a regression
fails CI instead of hanging it.
"""

from __future__ import annotations

import faulthandler
import math
import time
from dataclasses import dataclass

import numpy as np

from pipeline.rocking import rules
from pipeline.rocking.block import Block
from pipeline.rocking.planar.sampled import SampledBlocks, SampledMotion, SampleRules, sample_verdicts
from pipeline.rocking.planner import Scene, simulate_scene
from pipeline.rocking.settings import SimulationConfig
from pipeline.rocking.simulate import step_control

G = 9.80665
#: A scene's wall-clock budget [s] (the slowest boundary scene measured takes milliseconds)
SCENE_BUDGET_S = 5.0
#: The watchdog that ends a process whose scene never returns [s]
WATCHDOG_S = 120.0
#: The largest slenderness that rocks [rad] (tie rule 5)
ALPHA_MAX = rules.ALPHA_MAX_ROCKING


def block(height_m: float, alpha: float, mu: float) -> Block:
    """A rectangular block of full height ``height_m`` [m] and slenderness ``alpha`` [rad] (Housner 1963)."""
    R = 0.5 * height_m / math.cos(alpha)
    return Block(p=math.sqrt(3 * G / (4 * R)), alpha=alpha, e=max(0.0, 1.0 - 1.5 * math.sin(alpha) ** 2), R_m=R,
                 mu=mu, g_ms2=G)


def mu_ties(alpha: float) -> dict[str, float]:
    """Friction at the tie mu = tan(alpha), one double either side, and just beyond the tie's tolerance."""
    t = math.tan(alpha)
    return {"tie": t, "tie_up": math.nextafter(t, math.inf), "tie_down": math.nextafter(t, 0.0),
            "above": t * (1.0 + 4.0 * rules.TIE_RTOL), "below": t * (1.0 - 4.0 * rules.TIE_RTOL)}


@dataclass(frozen=True)
class Motion:
    """A ground motion: horizontal and vertical [m s-2] (vertical None: none), sampling interval [s]."""

    name: str
    ah: np.ndarray
    av: np.ndarray | None
    dt: float


def at_level(level_ms2: float, ulps: int) -> float:
    """``level_ms2`` moved by ``ulps`` doubles (0: exactly)."""
    if abs(ulps) > 16:
        return level_ms2 + ulps * math.ulp(level_ms2)
    x = level_ms2
    for _ in range(abs(ulps)):
        x = math.nextafter(x, math.inf if ulps > 0 else 0.0)
    return x


def motions(level_ms2: float, *, ulps: int, n: int, dt: float, rng: np.random.Generator) -> list[Motion]:
    """Excitations whose peak demand is ``level_ms2`` moved by ``ulps`` doubles: constant, a step, a half-sine
    pulse peaking on a sample, a noisy record scaled to the level, and the same with a vertical that reaches
    exactly -g."""
    a = at_level(level_ms2, ulps)
    t = np.arange(n) * dt
    step = np.where((t >= 0.2 * t[-1]) & (t <= 0.6 * t[-1]), a, 0.0)
    m = max(n // 2, 1)
    pulse = np.zeros(n)
    pulse[:2 * m - 1] = a * np.sin(np.pi * np.arange(2 * m - 1) / (2 * m - 2)) if m > 1 else a
    pulse[m - 1] = a                                      # the peak on a sample, exactly at the level
    noise = rng.standard_normal(n)
    noise = np.convolve(noise, np.ones(5) / 5, mode="full")[2:2 + n]
    peak = np.max(np.abs(noise))
    noise = a * noise / peak if peak > 0 else noise
    k = int(np.argmax(np.abs(noise)))
    noise[k] = math.copysign(a, noise[k])                 # exactly at the level, not a rounding off it
    av = np.zeros(n)
    av[n // 2] = -G                                       # g + a_v = 0 at one sample, exactly (tie rule 3)
    av_flat = np.where(t >= 0.5 * t[-1], -G, 0.0)         # ... and for the rest of the record
    return [Motion("constant", np.full(n, a), None, dt), Motion("step", step, None, dt),
            Motion("pulse", pulse, None, dt), Motion("noise", noise, None, dt),
            Motion("noise_minus_g", noise, av, dt), Motion("step_minus_g_after", step, av_flat, dt)]


@dataclass(frozen=True)
class Timed:
    """A scene's outcome and the wall-clock time it took [s]."""

    scene: Scene
    seconds: float


def run_scene(motion: Motion, blk: Block, *, settings: SimulationConfig = SimulationConfig()) -> Timed:
    """The nominal scene (:func:`~pipeline.rocking.planner.simulate_scene`), timed, under the watchdog."""
    faulthandler.dump_traceback_later(WATCHDOG_S, exit=True)
    try:
        t0 = time.perf_counter()
        sc = simulate_scene(motion.ah, motion.av, motion.dt, block=blk, settings=settings)
        return Timed(sc, time.perf_counter() - t0)
    finally:
        faulthandler.cancel_dump_traceback_later()


def sampled_verdict(motion: Motion, blk: Block, *, settings: SimulationConfig = SimulationConfig()) -> int:
    """The same scene through the sampled path (one sample, unit factor, the nominal block, one plane):
    1 overturns, 0 stands, -1 free flight (no verdict)."""
    n = motion.ah.size
    verdict, planes = np.zeros(1, dtype=np.int64), np.zeros(1, dtype=np.int64)
    av = np.zeros(0) if motion.av is None else np.ascontiguousarray(motion.av, dtype=float)
    faulthandler.dump_traceback_later(WATCHDOG_S, exit=True)
    try:
        sample_verdicts(SampledMotion(np.ascontiguousarray(motion.ah, dtype=float), np.zeros(n), av, motion.dt),
                        np.ones((1, 1)), np.zeros((1, 1)),
                        SampledBlocks(np.ones(1), np.array([blk.p]), np.array([blk.alpha]), np.array([blk.e]),
                                      np.array([blk.R_m]), np.array([blk.mu])),
                        SampleRules(blk.g_ms2, settings.vertical_fraction, settings.contact_model,
                                    step_control(settings)), verdict, planes)
    finally:
        faulthandler.cancel_dump_traceback_later()
    return int(verdict[0])


def verdict(sc: Scene) -> int:
    """1 overturns, 0 stands, -1 undetermined."""
    return sc.verdict
