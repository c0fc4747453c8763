"""The named structures the rocking kernel takes and returns (numba namedtuples).

:mod:`.kernel` integrates; these say what goes in and what comes out, by name rather than by position.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np


class RockingBlock(NamedTuple):
    """The block as the rocking kernel sees it (a numba namedtuple).

    Attributes
    ----------
    p : float
        Frequency parameter [rad s-1].
    alpha : float
        Slenderness [rad].
    e : float
        Restitution, the angular-velocity ratio across an impact [-].
    g : float
        Gravity [m s-2].
    R : float
        Corner distance [m].
    linear : bool
        Linearised equation of motion (cross-checks against closed forms).
    stop_mu : float
        Stop where the pivot's friction demand exceeds this, or where the block's own motion lifts the
        pivot (f_z <= 0), so that the general contact model (:mod:`.contact`) continues from there
        (``inf``: never stop; the demand is only recorded and a lift-off only flagged).
    """

    p: float
    alpha: float
    e: float
    g: float
    R: float
    linear: bool
    stop_mu: float


class StepControl(NamedTuple):
    """The integration settings the kernel takes (from :class:`~.settings.SimulationConfig`).

    Attributes
    ----------
    rtol, atol : float
        Relative tolerance, and absolute tolerance as a fraction of alpha (theta) and p alpha (omega).
    rest_ratio : float
        A rebound below ``rest_ratio * p * alpha`` ends the impact cascade.
    max_step_p : float
        Largest step as a fraction of 1/p.
    max_events : int
        Cap on impacts plus uplifts (chatter guard).
    """

    rtol: float
    atol: float
    rest_ratio: float
    max_step_p: float
    max_events: int


class RockingState(NamedTuple):
    """Where the kernel starts: rotation [rad] and angular velocity [rad s-1] (both 0: at rest), at time
    ``t`` [s] (0: the record's start; later when the kernel takes over from the general contact model)."""

    theta: float
    omega: float
    t: float


class RockingOutput(NamedTuple):
    """Arrays the kernel fills, empty to skip: theta at t = k dt, and (t, omega before, omega after) of the
    first impacts (shape (m, 3))."""

    theta: np.ndarray
    impacts: np.ndarray


class RockingOutcome(NamedTuple):
    """What :func:`rock` returns.

    Attributes
    ----------
    overturned : bool
    t_overturn : float
        Time of overturning [s] (NaN when it stands).
    theta_max : float
        Largest |theta| [rad].
    n_impacts, n_uplifts : int
        Impacts, and uplifts from rest.
    friction_max : float
        Largest friction demand |f_x| / f_z while |theta| < alpha [-].
    status : int
        ``STATUS_*`` bits.
    t_stop, theta_end, omega_end : float
        Where the integration stopped [s], and the state there: at the instant the ground's g + a_v
        reached 0, or, when the block's ``stop_mu`` stopped it, at the start of the step in which the friction
        demand exceeded it or the pivot lifted off (the last state where pure rocking held).
    mode_end : int
        ``REST``, ``ROCK`` or ``OVERTURNED`` there.
    t_first_impact : float
        Time of the first impact [s] (NaN without one).
    pivot_end : float
        The pivot side there (+1 tipping towards +x, -1 towards -x) [-].
    """

    overturned: bool
    t_overturn: float
    theta_max: float
    n_impacts: int
    friction_max: float
    status: int
    t_stop: float
    theta_end: float
    omega_end: float
    mode_end: int
    n_uplifts: int
    t_first_impact: float
    pivot_end: float
