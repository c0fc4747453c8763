"""Each part of a scene by the cheapest model that holds for it: pure rocking, or the general contact model.

The pure-rocking kernel (:mod:`.kernel`) runs with ``stop_mu = mu``: it stops at the start of the step
in which the pivot's friction demand exceeds mu or the pivot lifts off, or at the instant the ground
falls faster than gravity. The general contact model (:mod:`.contact`) continues from that state (time,
rotation, rate, pivot), in whatever modes the block then takes, locating the event itself; the scene is
not restarted. Where the block is back on a sticking pivot or at rest (at least one sample interval
later), the kernel takes over again from that state, and so on to the end. A scene that never leaves
pure rocking is the kernel's result, unchanged.

A block that cannot rock (mu <= tan alpha, or too squat) slides; where the ground reaches free flight the
Coulomb sliding kernel stops, and the general model simulates the scene from rest instead (its slide
mode integrates the same Coulomb law: the ground is linear between samples, the slip cubic in time,
and the fourth-order Runge-Kutta step exact for it; the stops of the slip are located by bisection, and the
slip matches the sliding kernel's to 1e-9, tested).

References
----------
Zhang, J. & Makris, N. (2001). Rocking response of free-standing blocks under cycloidal pulses.
J. Eng. Mech. 127(5), 473-483 (eqs. 16-20: the pivot's friction demand).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ...compiled import jit
from ..codes import (
    FLIGHT,
    MODE_ROCK,
    OVERTURNED,
    REST,
    ROCK,
    STATUS_CHATTER,
    STATUS_ENDED,
    STATUS_EVENT_CAP,
    STATUS_FRICTION,
    STATUS_GROUND_FLIGHT,
    STATUS_LIFTOFF,
    STATUS_STEP_CAP,
    STATUS_TIE_HOLD,
)
from ..numerics.ground import QuietTable
from ..structures import RigidBlock, RockingOutcome, RockingOutput, RockingState, StepControl
from . import contact
from .contact import ContactOutcome, ContactState
from .contact_laws import corner_offsets
from .kernel import rock

#: Cap on the alternations between the two models in one scene (each needs at least a sample interval of
#: general motion, or ends the scene at a cap; the cap is a guard, flagged as STATUS_EVENT_CAP).
MAX_SEGMENTS = 100000


class HandOff(NamedTuple):
    """Why pure rocking stopped (a numba namedtuple): each flag, or none of them."""

    friction: bool       # the friction demand exceeded mu
    liftoff: bool        # the pivot lifted off (f_z <= 0)
    ground_flight: bool  # the ground's g + a_v reached 0


@jit
def hand_off(o: RockingOutcome) -> HandOff:
    """Why the kernel's outcome ``o`` (run with a finite ``stop_mu``) stopped short, if it did."""
    if o.overturned or o.mode_end == OVERTURNED:
        return HandOff(False, False, False)
    flight = bool(o.status & STATUS_GROUND_FLIGHT)
    friction = bool(o.status & STATUS_FRICTION)
    return HandOff(friction, bool(o.status & STATUS_LIFTOFF) and not (friction or flight), flight)


@jit
def stopped_short(o: RockingOutcome) -> bool:
    """True when pure rocking stopped short of the end (:func:`hand_off` gives why): the general model goes on."""
    why = hand_off(o)
    return why.friction or why.liftoff or why.ground_flight


@jit
def kernel_guards(status: int) -> int:
    """The guard bits of the kernel's ``status`` as the contact model sets them, so that a scene's flags say what
    happened in either model: the kernel's chatter cap counts as the event cap; tie rule 6 and the step budget
    are the same bits in both (codes.py)."""
    return (STATUS_EVENT_CAP if status & STATUS_CHATTER else 0) | (status & (STATUS_TIE_HOLD | STATUS_STEP_CAP))


@jit
def start_state(o: RockingOutcome, blk: RigidBlock, slip: float) -> ContactState:
    """The general model's state where the kernel stopped: rocking on the kernel's pivot (the pivot where it
    started) at the start of the step in which pure rocking stopped holding, so that the general model
    locates the friction exceedance or the lift-off itself; free flight from the instant the ground's
    g + a_v reached 0 (from rest, or rocking). ``slip``: the net slip of the base so far [m]."""
    b, h = blk.b, blk.h
    t, th, w, c = o.t_stop, o.theta_end, o.omega_end, o.pivot_end
    if o.mode_end == REST:
        return ContactState(t=t, mode=FLIGHT, corner=1.0, sigma=1.0, x=0.0, y=0.0, theta=0.0, u=0.0, v=0.0, w=0.0,
                            slip=slip)
    rx, ry = corner_offsets(th, c, b, h)
    mode = FLIGHT if o.status & STATUS_GROUND_FLIGHT else ROCK
    return ContactState(t=t, mode=mode, corner=c, sigma=1.0, x=c * b - rx, y=-h - ry, theta=th, u=-ry * w, v=rx * w,
                        w=w, slip=slip)


@jit
def continue_rocking(first: RockingOutcome, ah, av, dt, blk: RigidBlock, control: StepControl, tail_energy: bool,
                     theta_out=None) -> ContactOutcome:
    """The scene from where the kernel's outcome ``first`` stopped short to its end, alternating the general
    model (where pure rocking does not hold) and the kernel (where it does), on one block (the kernel's
    ``stop_mu = mu``). The outcome's counts (impacts, theta_max, modes) cover that part of the scene.
    ``theta_out``: the scene's theta history [rad] at the samples, filled on from where ``first`` stopped."""
    t_end = (ah.shape[0] - 1) * dt
    hist = theta_out if theta_out is not None else ah[:0]
    no_output = RockingOutput(theta=hist, impacts=ah[:0].reshape((0, 3)))
    o = first
    slip, slip_max, theta_max, n_imp, modes, status = 0.0, 0.0, 0.0, 0, 0, kernel_guards(first.status)
    for _ in range(MAX_SEGMENTS):
        if o.status & STATUS_GROUND_FLIGHT:
            status |= STATUS_GROUND_FLIGHT
        # bool(): one compiled version of the contact model for both hand-backs (pipeline.compiled)
        g = contact.move(ah, av, dt, blk, start_state(o, blk, slip), tail_energy, math.inf, bool(True), hist)
        theta_max = max(theta_max, g.theta_max_rad)
        n_imp += g.n_impacts
        slip, slip_max = g.slip_end, max(slip_max, g.slip_max)
        modes |= g.modes
        status |= g.status
        end = g.end
        if g.overturned or g.status & STATUS_ENDED or not (end.mode == ROCK
                                                                  or end.mode == REST):
            # overturned, ended at a cap (the state's verdict), or still in motion at the end
            return ContactOutcome(overturned=g.overturned, t_overturn=g.t_overturn, theta_max_rad=theta_max,
                                  n_impacts=n_imp, slip_max=slip_max, slip_end=slip, modes=modes, status=status,
                                  end=end)
        theta = end.theta if end.mode == ROCK else 0.0
        omega = end.w if end.mode == ROCK else 0.0
        restart = RockingState(theta=theta, omega=omega, t=end.t)
        o = rock(ah, av, dt, t_end, blk, control, restart, tail_energy, no_output, QuietTable(np.zeros(0), np.zeros(0)))
        theta_max = max(theta_max, o.theta_max_rad)
        n_imp += o.n_impacts
        status |= kernel_guards(o.status)
        modes |= MODE_ROCK if o.n_impacts > 0 or o.n_uplifts > 0 or theta != 0.0 else 0
        if not stopped_short(o):
            end = ContactState(t=o.t_stop, mode=OVERTURNED if o.overturned else ROCK, corner=o.pivot_end, sigma=1.0,
                               x=0.0, y=0.0, theta=o.theta_end, u=0.0, v=0.0, w=o.omega_end, slip=slip)
            return ContactOutcome(overturned=o.overturned, t_overturn=o.t_overturn, theta_max_rad=theta_max,
                                  n_impacts=n_imp, slip_max=slip_max, slip_end=slip, modes=modes, status=status,
                                  end=end)
    return ContactOutcome(overturned=False, t_overturn=math.nan, theta_max_rad=theta_max, n_impacts=n_imp,
                          slip_max=slip_max, slip_end=slip, modes=modes, status=status | STATUS_EVENT_CAP,
                          end=start_state(o, blk, slip))


@jit
def from_rest(ah, av, dt, blk: RigidBlock, tail_energy: bool, theta_out=None) -> ContactOutcome:
    """The general model from rest at t = 0 (a sliding scene that meets free flight); ``theta_out``: its theta
    history at the samples [rad]."""
    at_rest = ContactState(t=0.0, mode=REST, corner=1.0, sigma=1.0, x=0.0, y=0.0, theta=0.0, u=0.0, v=0.0, w=0.0,
                           slip=0.0)
    hist = theta_out if theta_out is not None else ah[:0]
    return contact.move(ah, av, dt, blk, at_rest, tail_energy, math.inf, bool(False), hist)
