"""The named structures the rocking kernel and the general contact model take and return (numba namedtuples).

:mod:`.kernel` and :mod:`.contact` integrate; these say what goes in and what comes out, by name rather than
by position.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np


class GroundPiece(NamedTuple):
    """The ground motion between two instants, linear in time: a_h(t) = a0 + sa (t - t0), a_v likewise.

    Attributes
    ----------
    k : int
        Index of the sample at the piece's start (the record's last or later: the ground is still).
    t0, t1 : float
        Start and end of the piece [s].
    a0, a1, v0, v1 : float
        Horizontal and vertical ground acceleration at t0 and at the next sample [m s-2].
    sa, sv : float
        Their rates [m s-3].
    """

    k: int
    t0: float
    t1: float
    a0: float
    a1: float
    v0: float
    v1: float
    sa: float
    sv: float


class RigidBlock(NamedTuple):
    """The block as every compiled model sees it (a numba namedtuple): the rocking kernel, the general contact
    model, the hand-off between them and the sampled kernels. Built by :func:`rigid_block`, which derives b, h
    and J once.

    Attributes
    ----------
    p : float
        Frequency parameter sqrt(3 g / (4 R)) [rad s-1].
    alpha : float
        Slenderness [rad].
    e : float
        Restitution, the angular-velocity ratio across a sticking rocking impact [-].
    R : float
        Corner distance [m].
    mu : float
        Friction coefficient [-] (the contact model's).
    g : float
        Gravity [m s-2].
    b, h : float
        Half-width R sin(alpha) and half-height R cos(alpha) [m].
    J : float
        Centroidal inertia per unit mass of a rectangle, R^2 / 3 [m2].
    rest_ratio : float
        The contact model's rest rule: a rebound below ``rest_ratio * p * alpha`` at theta = 0 ends in rest [-]
        (the kernel takes its own from :class:`StepControl`).
    linear : bool
        The rocking kernel's linearised equation of motion (cross-checks against closed forms).
    stop_mu : float
        The rocking kernel stops where the pivot's friction demand exceeds this, or where the block's own
        motion lifts the pivot (f_z <= 0), so that the general contact model continues from there (``inf``:
        never stop; the demand is only recorded and a lift-off only flagged).
    """

    p: float
    alpha: float
    e: float
    R: float
    mu: float
    g: float
    b: float
    h: float
    J: float
    rest_ratio: float
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
    chatter : bool
        Take the small flights of an impact cascade in closed form where they hold (:mod:`.chatter`).
    """

    rtol: float
    atol: float
    rest_ratio: float
    max_step_p: float
    max_events: int
    chatter: bool


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
    theta_max_rad : float
        Largest |theta| [rad].
    n_impacts, n_uplifts : int
        Impacts, and uplifts from rest.
    friction_max : float
        Largest friction demand |f_x| / f_z while |theta| < alpha [-].
    status : int
        :class:`~.codes.Status` bits.
    t_stop, theta_end, omega_end : float
        Where the integration stopped [s], and the state there: at the instant the ground's g + a_v
        reached 0, or, when the block's ``stop_mu`` stopped it, at the start of the step in which the friction
        demand exceeded it or the pivot lifted off (the last state where pure rocking held).
    mode_end : int
        :class:`~.codes.Mode` there: ``REST``, ``ROCK`` or ``OVERTURNED``.
    t_first_impact : float
        Time of the first impact [s] (NaN without one).
    pivot_end : float
        The pivot side there (+1 tipping towards +x, -1 towards -x) [-].
    """

    overturned: bool
    t_overturn: float
    theta_max_rad: float
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


class ContactState(NamedTuple):
    """Where the model starts (or stopped).

    Attributes
    ----------
    t : float
        Time [s].
    mode : int
        REST, SLIDE, ROCK, SLIDE_ROCK, FLIGHT or OVERTURNED (:mod:`.contact`).
    corner : float
        The contact corner in rock and slide-rock (+1 at +x, -1 at -x) [-].
    sigma : float
        The slip direction in slide and slide-rock (+1, -1) [-].
    x, y, theta : float
        Centre of mass relative to its place at the start, flat on the base (y = 0 at rest) [m], and
        rotation [rad]. A base corner is at height y + h + r_y.
    u, v, w : float
        Their rates [m s-1], [m s-1], [rad s-1].
    slip : float
        Net slip of the base so far [m] (:class:`ContactOutcome`).
    """

    t: float
    mode: int
    corner: float
    sigma: float
    x: float
    y: float
    theta: float
    u: float
    v: float
    w: float
    slip: float


class ContactOutcome(NamedTuple):
    """What :func:`move` returns.

    Attributes
    ----------
    overturned : bool
    t_overturn : float
        Time |theta| reached pi/2, or the record's end when free rocking after it escapes [s] (NaN: stands).
    theta_max_rad : float
        Largest |theta| [rad].
    n_impacts : int
        Impacts (corners meeting the base).
    slip_max : float
        Largest |net slip| of the base: the contact point's slip in slide and slide-rock, plus the base's
        horizontal travel in flight [m].
    slip_end : float
        Net slip at the end [m].
    modes : int
        ``MODE_*`` bits of the modes that occurred (:mod:`.contact`).
    status : int
        :class:`~.codes.Status` bits.
    end : ContactState
        The state at the end.
    """

    overturned: bool
    t_overturn: float
    theta_max_rad: float
    n_impacts: int
    slip_max: float
    slip_end: float
    modes: int
    status: int
    end: ContactState
