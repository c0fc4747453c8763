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
from ..rocking.geometry import geometry
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


def sample_block(z: np.ndarray, *, height_m: float, width_m: float, mu: float, restitution: float,
                 azimuth_deg: float, settings: UncertaintyConfig, g_ms2: float = G) -> SampledBlock:
    """The samples of one block under one record.

    Parameters
    ----------
    z : ndarray, shape (n, 6)
        Rows of :func:`common_normals`.
    height_m, width_m : float
        Nominal full height and base width [m].
    mu : float
        Nominal friction coefficient [-].
    restitution : float
        The inventory's restitution, or NaN for Housner's value of each sampled block [-].
    azimuth_deg : float
        Given azimuth of the rocking plane [deg], NaN when blank (scanned, not sampled).
    settings : UncertaintyConfig
        The spreads.
    g_ms2 : float
        Gravity [m s-2].
    """
    c = settings
    geom = geometry(height_m * lognormal_factor(z[:, 3], c.size_cov),
                    width_m * lognormal_factor(z[:, 4], c.size_cov), g_ms2=g_ms2)
    base_e = geom.e_housner if np.isnan(restitution) else np.full(len(z), restitution)
    e = np.clip(base_e * lognormal_factor(z[:, 1], c.restitution_cov), 0.0, 1.0)
    az = np.full(len(z), np.nan) if np.isnan(azimuth_deg) else azimuth_deg + c.azimuth_sd_deg * z[:, 5]
    return SampledBlock(amplitude=lognormal_factor(z[:, 0], c.amplitude_cov), p=geom.p, alpha=geom.alpha,
                        R_m=geom.R, e=e, mu=mu * lognormal_factor(z[:, 2], c.friction_cov), azimuth_deg=az)
