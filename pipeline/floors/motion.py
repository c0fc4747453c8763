"""The acceleration history of a floor, from the ground record, by modal superposition (Miranda & Taghavi 2005).

At height ratio x = z / H of a building whose modes are those of the continuous shear-flexural cantilever
(:mod:`.model`), the floor's total acceleration is

    a_f(x, t) = a_g(t) + sum_i Gamma_i phi_i(x) u_i''(t),

with u_i the relative displacement of a damped oscillator of the mode's period T_i = T_1 / (T_1 / T_i) and
the building's damping ratio under a_g: u'' + 2 zeta omega u' + omega^2 u = -a_g. Each oscillator is advanced
exactly for ground acceleration linear between samples (the exponential of the augmented system, the
exactness of Nigam & Jennings 1969), so no time step is introduced. Both horizontals are filtered the same
way; the vertical passes unchanged (the model is lateral). The modes kept reach
:data:`~.model.MASS_SHARE` of the mass.

References
----------
Miranda, E. & Taghavi, S. (2005). Approximate floor acceleration demands in multistory buildings. I:
Formulation. J. Struct. Eng. 131(2), 203-211. Nigam, N. C. & Jennings, P. C. (1969). Calculation of response
spectra from strong-motion earthquake records. BSSA 59(2), 909-922.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ..compiled import jit
from ..errors import ParameterError
from ..records.intensity import oscillator_matrices
from .model import Modes, modes


class Building(NamedTuple):
    """A building for the floor-motion model.

    Attributes
    ----------
    building_id : str
    period_s : float
        Fundamental period T_1 [s].
    damping : float
        Modal damping ratio [-] (e.g. 0.05).
    stiffness_ratio : float
        Lateral-stiffness ratio alpha of the shear-flexural model [-] (0 flexure; large: shear).
    height_m : float
        Height H [m].
    n_stories : int
        Storeys (0: not given), for blocks placed by floor number.
    """

    building_id: str
    period_s: float
    damping: float
    stiffness_ratio: float
    height_m: float
    n_stories: int = 0


class FloorFilter(NamedTuple):
    """What a floor applies to a ground record: the modes, their periods and their weights at the floor.

    Attributes
    ----------
    periods_s : ndarray
        T_i [s].
    weights : ndarray
        Gamma_i phi_i(x) at the floor [-].
    damping : float
        Modal damping ratio [-].
    mass_share : float
        The share of the mass the modes reach [-].
    """

    periods_s: np.ndarray
    weights: np.ndarray
    damping: float
    mass_share: float


def floor_filter(building: Building, height_m: float, *, model: Modes | None = None) -> FloorFilter:
    """The modal filter of the floor at ``height_m`` [m] above the base of ``building``.

    Raises
    ------
    ParameterError
        For a period, damping or height outside its range, or a floor above the roof.
    """
    b = building
    if not (math.isfinite(b.period_s) and b.period_s > 0):
        raise ParameterError(f"building {b.building_id}: period_s = {b.period_s!r}; expected a period > 0 s")
    if not (math.isfinite(b.damping) and 0 <= b.damping < 1):
        raise ParameterError(f"building {b.building_id}: damping = {b.damping!r}; expected a ratio in [0, 1)")
    if not (math.isfinite(b.height_m) and b.height_m > 0):
        raise ParameterError(f"building {b.building_id}: height_m = {b.height_m!r}; expected a height > 0 m")
    if not (0 <= height_m <= b.height_m * (1 + 1e-9)):
        raise ParameterError(f"building {b.building_id}: a floor at {height_m} m is outside its height "
                             f"0-{b.height_m} m")
    m = modes(b.stiffness_ratio) if model is None else model
    x = min(height_m / b.height_m, 1.0)
    # phi_i(0) = 0 is a boundary condition: the ground floor is the ground, exactly
    shapes = np.array([float(m.shape(i, x)) for i in range(m.gamma.size)]) if x > 0 else np.zeros(m.gamma.size)
    return FloorFilter(b.period_s / m.period_ratio, m.participation * shapes, float(b.damping),
                       float(np.sum(m.mass_share)))


@jit
def _relative_response(a, dt, phi, g1, g2, omega, zeta, acc, vel):
    """u'' and u' of the oscillator under ground acceleration ``a`` (linear between samples), exact per step,
    into ``acc`` and ``vel``."""
    u = v = 0.0
    acc[0] = -a[0]
    vel[0] = 0.0
    for k in range(a.size - 1):
        r = (a[k + 1] - a[k]) / dt
        nu = phi[0, 0] * u + phi[0, 1] * v + g1[0] * a[k] + g2[0] * r
        v = phi[1, 0] * u + phi[1, 1] * v + g1[1] * a[k] + g2[1] * r
        u = nu
        acc[k + 1] = -a[k + 1] - 2.0 * zeta * omega * v - omega * omega * u
        vel[k + 1] = v


def relative_response(ground_ms2: np.ndarray, dt_s: float, period_s: float, damping: float
                      ) -> tuple[np.ndarray, np.ndarray]:
    """u''(t) [m s-2] and u'(t) [m s-1] of a damped oscillator of period ``period_s`` under the ground
    acceleration."""
    a = np.ascontiguousarray(ground_ms2, dtype=float)
    phi, g1, g2 = oscillator_matrices(period_s, dt_s, damping)
    acc, vel = np.empty(a.size), np.empty(a.size)
    _relative_response(a, float(dt_s), phi, g1, g2, 2.0 * math.pi / period_s, float(damping), acc, vel)
    return acc, vel


def relative_acceleration(ground_ms2: np.ndarray, dt_s: float, period_s: float, damping: float) -> np.ndarray:
    """u''(t) of a damped oscillator of period ``period_s`` under the ground acceleration [m s-2]."""
    return relative_response(ground_ms2, dt_s, period_s, damping)[0]


def floor_response(horizontal_ms2: np.ndarray, dt_s: float, flt: FloorFilter,
                   velocity_ms: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray | None]:
    """The floor's total acceleration [m s-2] and, given the ground velocity, total velocity [m s-1] for each
    horizontal (shape as the input): the ground's plus sum_i Gamma_i phi_i(x) times the mode's relative
    response, from the same oscillator states (nothing is integrated twice)."""
    h = np.atleast_2d(np.asarray(horizontal_ms2, dtype=float))
    acc = h.copy()
    vel = None if velocity_ms is None else np.atleast_2d(np.asarray(velocity_ms, dtype=float)).copy()
    for T, w in zip(flt.periods_s, flt.weights):
        if w == 0.0:
            continue
        for c in range(h.shape[0]):
            ra, rv = relative_response(h[c], dt_s, float(T), flt.damping)
            acc[c] += w * ra
            if vel is not None:
                vel[c] += w * rv
    return acc, vel


def floor_motion(horizontal_ms2: np.ndarray, dt_s: float, flt: FloorFilter) -> np.ndarray:
    """The floor's total acceleration for each horizontal of the ground record [m s-2], shape as the input."""
    return floor_response(horizontal_ms2, dt_s, flt)[0]


def describe(building: Building) -> str:
    """One line on a building and the modes its floors are filtered by: how many, their share of the mass
    and their periods [s]."""
    m = modes(building.stiffness_ratio)
    periods = ", ".join(f"{building.period_s / r:.3g}" for r in m.period_ratio)
    storeys = f", {building.n_stories} storeys" if building.n_stories else ""
    return (f"{building.building_id}: T1 {building.period_s:g} s, damping {building.damping:g}, stiffness ratio "
            f"{building.stiffness_ratio:g}, H {building.height_m:g} m{storeys}; {m.gamma.size} modes reach "
            f"{float(np.sum(m.mass_share)):.1%} of the mass, periods {periods} s")
