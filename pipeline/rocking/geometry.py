"""Rigid-block geometry in Housner's notation: half-height h, half-width b, R, the slenderness alpha, the frequency
parameter p and the restitution, from a block's full height and width; and the slenderness beyond which a block
cannot rock.

References
----------
Housner, G. W. (1963). The behavior of inverted pendulum structures during earthquakes. BSSA 53(2), 403-417.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..constants import G
from ..errors import BlockParameterError

#: Slenderness at which Housner's restitution 1 - 1.5 sin^2(alpha) reaches 0 [rad] (54.7 deg): a block at or
#: beyond it cannot rock, only slide or stand.
ALPHA_MAX_ROCKING = math.asin(math.sqrt(2.0 / 3.0))


@dataclass(frozen=True)
class Geometry:
    """Rocking geometry of one or many blocks (arrays broadcast together).

    Attributes
    ----------
    h : ndarray
        Half-height, height of the centre of mass [m].
    b : ndarray
        Half-width [m].
    R : ndarray
        Distance from a base corner to the centre of mass, sqrt(b^2 + h^2) [m].
    alpha : ndarray
        Slenderness angle atan(b/h) [rad].
    p : ndarray
        Frequency parameter sqrt(3 g / (4 R)) of a rectangular block (a cylinder's: :func:`cylinder_p_e`)
        [rad s-1].
    e_housner : ndarray
        Housner coefficient of restitution, the angular-velocity ratio across an
        impact, 1 - 1.5 sin^2(alpha) for a rectangular block [-] (its square is the energy ratio).
    """

    h: np.ndarray
    b: np.ndarray
    R: np.ndarray
    alpha: np.ndarray
    p: np.ndarray
    e_housner: np.ndarray


def geometry(height_m, width_m, *, g_ms2: float = G, cylinder=False) -> Geometry:
    """Return the rocking geometry of rectangular blocks (and of solid cylinders where ``cylinder``).

    Parameters
    ----------
    height_m : float or array_like
        Full height 2h [m], > 0.
    width_m : float or array_like
        Full base width 2b in the rocking plane [m], > 0.
    g_ms2 : float
        Gravity [m s-2].
    cylinder : bool or array_like of bool
        Where the block is a solid cylinder rocking in a vertical plane through its axis (``width_m`` its
        diameter): p and e from its own inertia (:func:`cylinder_p_e`).

    Raises
    ------
    BlockParameterError
        If a size is not a positive finite number.

    References
    ----------
    Housner (1963) eqs. 1-5: I0 = (4/3) m R^2, p^2 = 3g/(4R), e = 1 - 1.5 sin^2(alpha).
    """
    height = np.asarray(height_m, dtype=float)
    width = np.asarray(width_m, dtype=float)
    for name, v in (("height_m", height), ("width_m", width)):
        if not np.all(np.isfinite(v)) or np.any(v <= 0):
            raise BlockParameterError(f"{name} = {v.tolist()!r}: must be a positive, finite size in metres")
    h, b = height / 2.0, width / 2.0
    R = np.hypot(b, h)
    alpha = np.arctan2(b, h)
    p = np.sqrt(3.0 * g_ms2 / (4.0 * R))          # rectangle: p^2 = m g R / I0
    e = 1.0 - 1.5 * np.sin(alpha) ** 2             # Housner (1963) eq. 5, velocity ratio
    cyl = np.broadcast_to(np.asarray(cylinder, dtype=bool), np.shape(R))
    if np.any(cyl):
        p_c, e_c = cylinder_p_e(b, h, g_ms2=g_ms2)
        p, e = np.where(cyl, p_c, p), np.where(cyl, e_c, e)
    return Geometry(h=h, b=b, R=R, alpha=alpha, p=p, e_housner=e)


def cylinder_p_e(radius_m, half_height_m, *, g_ms2: float = G):
    """The frequency parameter [rad s-1] and Housner's restitution [-] of a solid cylinder (radius a, half-height h)
    rocking in a vertical plane through its axis: I_G = m (a^2/4 + h^2/3), I_0 = I_G + m R^2, p^2 = m g R / I_0,
    and, angular momentum about the new pivot conserved at the impact (Housner 1963, his eq. 5 derived for the
    block), e = (I_G + m (h^2 - a^2)) / (I_G + m (h^2 + a^2))."""
    a, h = np.asarray(radius_m, dtype=float), np.asarray(half_height_m, dtype=float)
    i_g = a * a / 4.0 + h * h / 3.0
    r2 = a * a + h * h
    return np.sqrt(g_ms2 * np.sqrt(r2) / (i_g + r2)), (i_g + h * h - a * a) / (i_g + h * h + a * a)


def effective_restitution(declared, e_housner, factor=1.0) -> np.ndarray:
    """The restitution the simulator takes: the declared value where given (NaN: Housner's ``e_housner``), times
    ``factor`` (a sample's lognormal factor), clipped to [0, 1] (0 for a block too squat to rock, whose
    Housner value is negative) [-]. The one derivation of the nominal block and of its samples."""
    base = np.where(np.isnan(declared), e_housner, declared)
    return np.clip(base * factor, 0.0, 1.0)


def check_friction(mu) -> np.ndarray:
    """Validate friction coefficients: finite and > 0.

    Raises
    ------
    BlockParameterError
        Naming the value and the valid range.
    """
    mu = np.asarray(mu, dtype=float)
    bad = ~(np.isfinite(mu) & (mu > 0))
    if np.any(bad):
        raise BlockParameterError(f"mu = {mu[bad].tolist()[:3]}: the friction coefficient must be a finite "
                                  "number > 0 (typical 0.3-0.8)")
    return mu
