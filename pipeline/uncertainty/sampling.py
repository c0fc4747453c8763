"""Common random numbers and the sampled scenes.

One matrix of standard normal draws, made from the seed alone, serves every scene of a run:
sample k of every (record, block) uses row k. Comparisons between assets and records are then
not blurred by sampling noise (common random numbers), and a scene's samples do not depend on
the executor, the order of the tasks or the other scenes.

Every factor is lognormal with median 1 (the nominal value is the median sample):
X = exp(s z), s = sqrt(ln(1 + cov^2)).

Impossible samples cannot occur: lognormal sizes are positive; a sampled block too squat to
rock (alpha >= 54.7 deg) is simulated as sliding, as such a block in the inventory is; the
restitution is clipped to [0, 1].

References
----------
FEMA P-58-1 (2012). Seismic Performance Assessment of Buildings, Volume 1: Methodology (uncertainties
as lognormal factors about a median, here 1).
Housner (1963) BSSA 53(2), eq. 5: e = 1 - 1.5 sin^2(alpha).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..constants import G
from ..rocking.block import Block, BlockShape, ShapeKind
from ..rocking.geometry import effective_restitution, geometry
from .settings import UncertaintyConfig

#: Columns of the common random numbers.
COLUMNS = ("amplitude", "restitution", "friction", "height", "width", "azimuth")


def common_normals(seed: int, samples: int) -> np.ndarray:
    """Standard normal draws, shape (samples, len(COLUMNS)), from the seed alone.

    Row k is the same whatever ``samples`` is (the first rows of a longer draw), so a run
    with more samples extends, and never reshuffles, a shorter one.
    """
    rng = np.random.Generator(np.random.PCG64(seed))
    return rng.standard_normal((samples, len(COLUMNS)))


def lognormal_factor(z: np.ndarray, cov: float) -> np.ndarray:
    """exp(s z) with s = sqrt(ln(1 + cov^2)): median 1, coefficient of variation ``cov``."""
    return np.exp(np.sqrt(np.log1p(cov * cov)) * np.asarray(z, dtype=float))


@dataclass(frozen=True)
class SampledBlock:
    """One block's samples (arrays of the samples' length)."""

    #: factor on the record's accelerations [-]
    amplitude: np.ndarray
    p: np.ndarray
    alpha: np.ndarray
    R_m: np.ndarray
    e: np.ndarray
    mu: np.ndarray
    #: azimuth of the rocking plane [deg] (NaN for a blank azimuth)
    azimuth_deg: np.ndarray
    #: gravity [m s-2]
    g_ms2: float = G

    def rows(self, index) -> SampledBlock:
        """The samples ``index`` (a slice or an array of row numbers) of these: each derived value depends on its own
        row of the common random numbers alone, so that they equal :func:`sample_block` of those rows."""
        return SampledBlock(amplitude=self.amplitude[index], p=self.p[index], alpha=self.alpha[index],
                            R_m=self.R_m[index], e=self.e[index], mu=self.mu[index],
                            azimuth_deg=self.azimuth_deg[index], g_ms2=self.g_ms2)

    def block(self, k: int) -> Block:
        """Sample ``k`` as the planar simulator takes it."""
        return Block(p=float(self.p[k]), alpha=float(self.alpha[k]), e=float(self.e[k]), R_m=float(self.R_m[k]),
                     mu=float(self.mu[k]), g_ms2=self.g_ms2)


def sample_block(z: np.ndarray, shape: BlockShape, *, settings: UncertaintyConfig, g_ms2: float = G) -> SampledBlock:
    """The samples of one block under one record: the derivation of :func:`~pipeline.rocking.block.dynamics` on
    the sampled sizes, restitution and friction.

    Parameters
    ----------
    z : ndarray, shape (n, 6)
        Rows of :func:`common_normals`.
    shape : BlockShape
        The nominal block: its height and width [m], friction [-], restitution (NaN: Housner's value of each
        sampled block) [-] and azimuth (NaN when blank: scanned, not sampled) [deg].
    settings : UncertaintyConfig
        The spreads.
    g_ms2 : float
        Gravity [m s-2].
    """
    c = settings
    geom = geometry(shape.height_m * lognormal_factor(z[:, 3], c.size_cov),
                    shape.width_m * lognormal_factor(z[:, 4], c.size_cov), g_ms2=g_ms2,
                    cylinder=shape.kind == ShapeKind.cylinder)
    e = effective_restitution(shape.restitution, geom.e_housner, lognormal_factor(z[:, 1], c.restitution_cov))
    az = np.full(len(z), np.nan) if np.isnan(shape.azimuth_deg) else shape.azimuth_deg + c.azimuth_sd_deg * z[:, 5]
    return SampledBlock(amplitude=lognormal_factor(z[:, 0], c.amplitude_cov), p=geom.p, alpha=geom.alpha,
                        R_m=geom.R, e=e, mu=shape.mu * lognormal_factor(z[:, 2], c.friction_cov), azimuth_deg=az,
                        g_ms2=g_ms2)
