"""The probability of overturning of a body given by its scan (a rock or a statue): each draw of the declared
uncertainty (:class:`~.settings.UncertaintyConfig`: the amplitude, the height and the width, the restitution) is
one run of its model in one plane (:func:`pipeline.rocking.scanned.planes.plane_scene`: the rolling or the two-sided
model), with the same common random numbers (:func:`~.sampling.common_normals`) as every other scene. The friction
coefficient is not drawn: neither model slides.

A draw the model cannot decide (the ground falling faster than gravity, the step budget, the free motion after
the record outlasting its cap) has no verdict and is counted apart.
"""

from __future__ import annotations

import dataclasses
import math
from typing import NamedTuple

import numpy as np

from ..constants import G
from ..rocking.block import BlockShape
from ..rocking.codes import Verdict
from ..rocking.scanned.planes import PlaneGeometry, ScannedPlane, along, plane_geometry, plane_scene
from ..rocking.settings import SimulationConfig
from .sampling import lognormal_factor
from .scenes import NOT_EVALUATED, Probability, SceneMotion, sample_until_decided
from .settings import UncertaintyConfig

#: Planes nearest to overturning at the nominal (the body's orientation unknown) in which the draws are run; the
#: worst orientation's p is the largest of theirs
CANDIDATES = 4


class DrawFactors(NamedTuple):
    """One draw's factors on a scanned scene [-]: the record's amplitude, the body's width and height, its impact
    ratios and its friction (a plane in which it is a uniform rectangle only; the same columns of the common random
    numbers as :func:`~.sampling.sample_block` reads)."""

    amplitude: float
    width: float
    height: float
    restitution: float
    friction: float


def draw_factors(z_row: np.ndarray, settings: UncertaintyConfig) -> DrawFactors:
    """The :class:`DrawFactors` of one row of :func:`~.sampling.common_normals`."""
    return DrawFactors(amplitude=float(lognormal_factor(z_row[0], settings.amplitude_cov)),
                       width=float(lognormal_factor(z_row[4], settings.size_cov)),
                       height=float(lognormal_factor(z_row[3], settings.size_cov)),
                       restitution=float(lognormal_factor(z_row[1], settings.restitution_cov)),
                       friction=float(lognormal_factor(z_row[2], settings.friction_cov)))


def drawn_scene(ah_ms2: np.ndarray, av_ms2: np.ndarray | None, dt_s: float, body: PlaneGeometry, f: DrawFactors, *,
                restitution: float, mu: float, simulation: SimulationConfig, g_ms2: float):
    """One draw's :class:`~pipeline.rocking.scene.Scene` (:func:`pipeline.rocking.scanned.planes.plane_scene` under the
    record scaled by ``f.amplitude``)."""
    return plane_scene(f.amplitude * np.asarray(ah_ms2, dtype=float), None if av_ms2 is None else f.amplitude * av_ms2,
                       dt_s, body, restitution=restitution, mu=mu, settings=simulation, g_ms2=g_ms2,
                       width_factor=f.width, height_factor=f.height, restitution_scale=f.restitution,
                       friction_scale=f.friction)


class PlaneDraws(NamedTuple):
    """The draws of one plane.

    Attributes
    ----------
    overturned : ndarray of bool
    undecided : ndarray of bool
        No verdict (see the module).
    """

    overturned: np.ndarray
    undecided: np.ndarray

    @property
    def p(self) -> float:
        """Overturned among the draws with a verdict [-] (NaN: none has one)."""
        n = int(np.sum(~self.undecided))
        return float(np.sum(self.overturned & ~self.undecided) / n) if n else float("nan")


def plane_draws(ah_ms2: np.ndarray, dt_s: float, body: PlaneGeometry, z: np.ndarray, *, settings: UncertaintyConfig,
                simulation: SimulationConfig = SimulationConfig(), av_ms2: np.ndarray | None = None,
                restitution: float = math.nan, g_ms2: float = G) -> PlaneDraws:
    """Run every draw of ``z`` (rows of :func:`~.sampling.common_normals`) of ``body`` under the record, in one
    plane (:func:`pipeline.rocking.scanned.planes.plane_scene`).

    Parameters
    ----------
    ah_ms2 : ndarray
        Ground acceleration along the plane's + side [m s-2].
    dt_s : float
        Sampling interval [s].
    body : PlaneBody or HullChain
        The body in the plane (:func:`pipeline.rocking.scanned.planes.plane_geometry`).
    z : ndarray, shape (n, 6)
    settings : UncertaintyConfig
        The spreads.
    simulation : SimulationConfig
        The simulator's tolerances.
    av_ms2 : ndarray, optional
        Vertical, up positive [m s-2].
    restitution : float
        The declared restitution (NaN: the impact rule's own) [-].
    """
    over, undecided = np.zeros(len(z), dtype=bool), np.zeros(len(z), dtype=bool)
    for k in range(len(z)):
        sc = drawn_scene(ah_ms2, av_ms2, dt_s, body, draw_factors(z[k], settings), restitution=restitution,
                         mu=math.inf, simulation=simulation, g_ms2=g_ms2)
        over[k], undecided[k] = sc.overturned, sc.verdict < 0
    return PlaneDraws(over, undecided)


def _uniform(z: np.ndarray) -> np.ndarray:
    """Standard normal draws mapped to uniform ones on [0, 1) (the normal distribution function)."""
    from scipy.special import ndtr

    return np.minimum(ndtr(z), np.nextafter(1.0, 0.0))


def scanned_probability(m: SceneMotion, z: np.ndarray, shape: BlockShape, *, candidates: list[ScannedPlane],
                        planes: list[ScannedPlane] | None, settings: UncertaintyConfig,
                        simulation: SimulationConfig = SimulationConfig(), g_ms2: float = G
                        ) -> tuple[Probability, Probability]:
    """The probabilities of a scanned body's scene (:mod:`pipeline.rocking.scanned.planes`). The worst orientation's: in
    each plane of ``candidates`` (the governing plane where the orientation is given; else the
    :data:`CANDIDATES` planes nearest to overturning at the nominal) each draw's amplitude, sizes and restitution
    (and, for a given azimuth on two horizontals, the azimuth's scatter on the record's plane, the body's plane
    kept), the largest p of the candidates kept (the first on ties; chosen on the same draws it is estimated on, so
    it leans high). Where the orientation is unknown (``planes``: those simulated), an orientation at random: each
    draw in one of them drawn at random (uniform, from the draw's azimuth number). Both with the sampling and
    stopping rule of every other scene (:func:`~.scenes.sample_until_decided`). Returns (worst, random); random is
    NOT_EVALUATED without ``planes``."""
    scan = shape.scan
    assert scan is not None
    h = np.vstack([m.h1, m.h2]) if not m.single else m.h1[None, :]
    av = m.vertical if m.vertical.size else None
    scatter = not m.single and planes is None and math.isfinite(shape.azimuth_deg)

    bodies: dict[float, PlaneGeometry] = {}              # each plane's geometry once, whatever the draws

    def body_of(deg: float) -> PlaneGeometry:
        if deg not in bodies:
            bodies[deg] = plane_geometry(scan, deg, simulation)
        return bodies[deg]

    def judge_in(pick):
        def judge(sl: slice, verdicts: np.ndarray, runs: np.ndarray) -> None:
            for k in range(sl.start, sl.stop):
                pl = pick(k)
                sc = drawn_scene(along(h, m.azimuth0_deg, pl), av, m.dt_s, body_of(pl.body_deg),
                                 draw_factors(z[k], settings), restitution=shape.restitution, mu=shape.mu,
                                 simulation=simulation, g_ms2=g_ms2)
                verdicts[k] = (Verdict.overturns if sc.overturned else Verdict.no_verdict if sc.verdict < 0
                               else Verdict.stands)
                runs[k] = 1
        return judge

    def in_plane(plane: ScannedPlane):
        def pick(k: int) -> ScannedPlane:
            if scatter:
                return plane._replace(record_deg=(plane.record_deg + settings.azimuth_sd_deg * z[k, 5]) % 360.0)
            return plane
        return pick

    estimates = [sample_until_decided(len(z), judge_in(in_plane(pl)), settings=settings) for pl in candidates]
    worst = max(estimates, key=lambda e: -1.0 if math.isnan(e.p) else e.p)
    worst = dataclasses.replace(worst, simulations=sum(e.simulations for e in estimates))
    if planes is None:
        return worst, NOT_EVALUATED
    idx = (_uniform(z[:, 5]) * len(planes)).astype(int)
    return worst, sample_until_decided(len(z), judge_in(lambda k: planes[int(idx[k])]), settings=settings)
