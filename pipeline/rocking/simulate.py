"""Simulation of one scene (a ground motion and a block): rocking, sliding, or the general contact model.

Thin, validated wrappers around the kernels of :mod:`pipeline.rocking.planar.kernel`,
returning plain dataclasses.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..constants import G
from ..errors import ParameterError
from .block import rigid_block
from .numerics.ground import NO_QUIET, QuietTable
from .planar import handoff, kernel, sliding
from .settings import SimulationConfig
from .structures import RigidBlock, RockingOutcome, RockingOutput, RockingState, StepControl


@dataclass(frozen=True)
class RockResult:
    """Outcome of a rocking simulation.

    Attributes
    ----------
    overturned : bool
    t_overturn : float
        Time [s] at which |theta| reached pi/2, or at which the free motion after the
        record was found to escape (NaN if it stands).
    theta_max : float
        Largest |theta| / alpha [-] (pi / (2 alpha) when it overturns); the kernel's own outcome keeps radians
        (``theta_max_rad``).
    n_impacts : int
        Impacts simulated (during the record when the tail is decided by energy).
    friction_demand : float
        Largest |f_x / f_z| along the trajectory [-].
    status : int
        :class:`~.codes.Status` bits: chatter (the event cap), ground_flight (the ground's g + a_v reached 0:
        contact lost, the simulation stopped at ``t_stop``), step_underflow, liftoff (f_z <= 0 met while
        rocking: flagged, the simulation goes on), friction (stopped where the demand exceeded ``stop_mu``),
        tie_hold, step_cap.
    t_stop, theta_end, omega_end : float
        Where the simulation stopped [s], [rad], [rad s-1].
    mode_end : int
        :class:`~.codes.Mode` there: rest, rock or overturned.
    n_uplifts : int
    t_first_impact : float
    theta : ndarray or None
        theta [rad] at t = k dt when asked for.
    impacts : ndarray or None
        (t, omega before, omega after) of each impact when asked for.
    """

    overturned: bool
    t_overturn: float
    theta_max: float
    n_impacts: int
    friction_demand: float
    status: int
    t_stop: float
    theta_end: float
    omega_end: float
    mode_end: int
    n_uplifts: int
    t_first_impact: float
    theta: np.ndarray | None = None
    impacts: np.ndarray | None = None
    #: pivot side where it stopped (+1 tipping towards +x, -1 towards -x)
    pivot_end: float = 1.0
    #: the kernel's own outcome (theta_max in radians), from which :func:`continued` goes on
    outcome: RockingOutcome | None = field(default=None, compare=False, repr=False)

    @property
    def free_flight(self) -> bool:
        """The ground's g + a_v reached 0 before the block overturned: the simulation stopped there."""
        return bool(self.status & kernel.STATUS_GROUND_FLIGHT)

    @property
    def liftoff(self) -> bool:
        """The contact force f_z of the rocking block reached 0 somewhere (its own motion lifts it)."""
        return bool(self.status & kernel.STATUS_LIFTOFF)

    @property
    def chatter(self) -> bool:
        return bool(self.status & kernel.STATUS_CHATTER)


@dataclass(frozen=True)
class SlideResult:
    """Outcome of a Coulomb stick-slip simulation.

    ``free_flight``: the ground's g + a_v reached 0 (at ``t_flight_s``); the simulation stopped
    there (no normal force, no friction: the Coulomb model holds no further).
    """

    sliding_max_m: float
    sliding_end_m: float
    n_slips: int
    time_slipping_s: float
    #: time the ground's g + a_v reached 0 [s], NaN when it never did
    t_flight_s: float
    #: samples whose search for slip starts and stops reached :data:`.sliding.MAX_STOPS_PER_SAMPLE` (0: none)
    capped_samples: int = 0

    @property
    def free_flight(self) -> bool:
        """The ground's g + a_v reached 0: the simulation stopped there."""
        return not math.isnan(self.t_flight_s)


class FiniteSeries(np.ndarray):
    """A 1-D float64, C-contiguous series of at least 2 finite samples, checked once.

    The wrappers below check every series they are given; a scene scanned over dozens of
    planes and blocks would check the same record hundreds of times. A series made by
    :func:`finite_series` (or projected from such series, :class:`~.orientation.Planes`)
    skips the check.
    """


def finite_series(name: str, a) -> FiniteSeries:
    """``a`` checked (:func:`_series`) and marked as checked.

    Raises
    ------
    ParameterError
        For a series that is not 1-D, shorter than 2 samples or not finite.
    """
    return _series(name, a).view(FiniteSeries)


def _series(name: str, a, n: int | None = None) -> np.ndarray:
    if type(a) is FiniteSeries and (n is None or a.size == n):
        return a.view(np.ndarray)
    arr = np.ascontiguousarray(a, dtype=np.float64)
    if arr.ndim != 1 or arr.size < 2:
        raise ParameterError(f"{name}: expected a 1-D series of at least 2 samples, got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise ParameterError(f"{name}: holds NaN or infinite values at sample "
                             f"{int(np.flatnonzero(~np.isfinite(arr))[0])}; clean the record first")
    if n is not None and arr.size != n:
        raise ParameterError(f"{name}: {arr.size} samples, expected {n} as the horizontal")
    return arr


def _positive(**values) -> None:
    for name, v in values.items():
        if not (math.isfinite(v) and v > 0):
            raise ParameterError(f"{name} = {v!r}: must be a finite number > 0")


def rock(ah_ms2, dt_s: float, *, p: float, alpha: float, e: float, R_m: float, av_ms2=None, g_ms2: float = G,
         settings: SimulationConfig = SimulationConfig(), linear: bool = False, t_end_s: float | None = None,
         tail: str = "energy", theta0: float = 0.0, omega0: float = 0.0, history: bool = False,
         log_impacts: int = 0, stop_mu: float = math.inf, quiet: QuietTable | None = None) -> RockResult:
    """Rocking response of a rectangular block to a sampled ground acceleration.

    Parameters
    ----------
    ah_ms2 : array_like
        Horizontal ground acceleration along the block's rocking plane [m s-2].
    dt_s : float
        Sampling interval [s].
    p, alpha, e, R_m : float
        Frequency parameter [rad s-1], slenderness [rad] (0 < alpha < pi/2),
        angular-velocity restitution [-] (0 <= e <= 1), corner distance [m].
    av_ms2 : array_like, optional
        Vertical ground acceleration, positive up [m s-2].
    g_ms2 : float
        Gravity [m s-2].
    settings : SimulationConfig
        Tolerances and thresholds.
    linear : bool
        Use the linearised equation of motion.
    t_end_s : float, optional
        End time [s]; default the record's end.
    tail : {"energy", "integrate"}
        After the record: decide overturning from the energy of the free motion
        (no integration), or integrate free rocking until rest, overturning or t_end_s.
    theta0, omega0 : float
        Initial rotation [rad] and angular velocity [rad s-1].
    history : bool
        Return theta at every sample time up to t_end_s.
    log_impacts : int
        Log the first ``log_impacts`` impacts.
    stop_mu : float
        Stop where the friction demand exceeds ``stop_mu`` or the pivot lifts off, for the general
        contact model to continue (default ``inf``: pure rocking throughout, the demand recorded).
    quiet : QuietTable, optional
        The :class:`~.numerics.ground.QuietTable` of ``ah_ms2`` and ``av_ms2`` (a plane's, shared by the blocks
        simulated in it): the same result, the samples that cannot lift the block passed over in runs.

    Raises
    ------
    ParameterError
        For impossible parameters or non-finite input.
    """
    ah = _series("horizontal acceleration", ah_ms2)
    av = np.zeros(0) if av_ms2 is None else _series("vertical acceleration", av_ms2, ah.size)
    _positive(dt_s=dt_s, p=p, R_m=R_m, g_ms2=g_ms2)
    if not 0 < alpha < math.pi / 2:
        raise ParameterError(f"alpha = {alpha!r}: the slenderness must be in (0, pi/2) rad")
    if not 0 <= e <= 1:
        raise ParameterError(f"e = {e!r}: the restitution (angular-velocity ratio) must be in [0, 1]")
    if tail not in ("energy", "integrate"):
        raise ParameterError(f"tail = {tail!r}: expected 'energy' or 'integrate'")
    t_rec = (ah.size - 1) * dt_s
    t_end = t_rec if t_end_s is None else float(t_end_s)
    n_out = int(math.floor(t_end / dt_s + kernel.SAMPLE_INDEX_TOL)) + 1
    theta_out = np.full(n_out, np.nan) if history else kernel.empty_theta()
    impacts_out = np.full((log_impacts, 3), np.nan) if log_impacts else kernel.empty_impacts()
    o = kernel.rock(ah, av, float(dt_s), t_end,
                    rigid_block(float(p), float(alpha), float(e), float(R_m), float(stop_mu), float(g_ms2),
                                float(settings.rest_ratio), bool(linear), float(stop_mu)),
                    step_control(settings), RockingState(theta=float(theta0), omega=float(omega0), t=0.0),
                    tail == "energy", RockingOutput(theta=theta_out, impacts=impacts_out),
                    NO_QUIET if quiet is None else quiet)
    return RockResult(bool(o.overturned), float(o.t_overturn), float(o.theta_max_rad) / alpha, int(o.n_impacts),
                      float(o.friction_max), int(o.status), float(o.t_stop), float(o.theta_end), float(o.omega_end),
                      int(o.mode_end), int(o.n_uplifts), float(o.t_first_impact), theta_out if history else None,
                      impacts_out[: min(log_impacts, int(o.n_impacts))] if log_impacts else None, float(o.pivot_end),
                      o)


def step_control(settings: SimulationConfig) -> StepControl:
    """The kernel's step control from the simulator's settings."""
    return StepControl(rtol=float(settings.rtol), atol=float(settings.atol), rest_ratio=float(settings.rest_ratio),
                       max_step_p=float(settings.max_step_p), max_events=int(settings.max_events),
                       chatter=bool(settings.closed_form_chatter))


def slide(ah_ms2, dt_s: float, *, mu: float, av_ms2=None, g_ms2: float = G) -> SlideResult:
    """Coulomb stick-slip sliding of a block on a moving base (exact per sample).

    Parameters
    ----------
    ah_ms2 : array_like
        Horizontal ground acceleration [m s-2].
    dt_s : float
        Sampling interval [s].
    mu : float
        Friction coefficient [-], > 0.
    av_ms2 : array_like, optional
        Vertical ground acceleration, positive up [m s-2].
    g_ms2 : float
        Gravity [m s-2].
    """
    ah = _series("horizontal acceleration", ah_ms2)
    av = np.zeros(0) if av_ms2 is None else _series("vertical acceleration", av_ms2, ah.size)
    _positive(dt_s=dt_s, mu=mu, g_ms2=g_ms2)
    out = sliding.slide(ah, av, float(dt_s), float(mu), float(g_ms2))
    return SlideResult(sliding_max_m=float(out.u_max_m), sliding_end_m=float(out.u_end_m), n_slips=int(out.n_slips),
                       time_slipping_s=float(out.t_slip_s), t_flight_s=float(out.t_flight_s),
                       capped_samples=int(out.capped_samples))


@dataclass(frozen=True)
class ContactResult:
    """Outcome of the general contact model (:mod:`.contact`).

    Attributes
    ----------
    overturned : bool
    t_overturn : float
        Time of overturning [s] (NaN: it stands).
    theta_max_rad : float
        Largest |theta| over the part the model simulated [rad].
    n_impacts : int
        Impacts in that part.
    slip_max_m, slip_end_m : float
        Largest and final net slip of the base [m] (:class:`.contact.ContactOutcome`).
    modes : int
        Bits of the modes that occurred (:class:`.planner.ContactMode`).
    status : int
        :class:`~.codes.Status` bits.
    """

    overturned: bool
    t_overturn: float
    theta_max_rad: float
    n_impacts: int
    slip_max_m: float
    slip_end_m: float
    modes: int
    status: int


def contact_block(block, settings: SimulationConfig) -> RigidBlock:
    """The compiled models' block from a :class:`~.block.Block`, the kernel stopping where the pivot's friction
    demand exceeds the block's mu (for the general contact model to continue)."""
    return rigid_block(float(block.p), float(block.alpha), float(block.e), float(block.R_m), float(block.mu),
                       float(block.g_ms2), float(settings.rest_ratio), False, float(block.mu))


def _history(theta_out: np.ndarray | None) -> np.ndarray:
    """The contact model's history argument: ``theta_out``, or the kernel's empty one for none (an array either way,
    so that one compiled version serves both: pipeline.compiled, 'One version per solver')."""
    return kernel.empty_theta() if theta_out is None else theta_out


def _contact_result(o) -> ContactResult:
    return ContactResult(bool(o.overturned), float(o.t_overturn), float(o.theta_max_rad), int(o.n_impacts),
                         float(o.slip_max), float(o.slip_end), int(o.modes), int(o.status))


def continued(ah_ms2, av_ms2, dt_s: float, rr: RockResult, *, block,
              settings: SimulationConfig = SimulationConfig()) -> ContactResult | None:
    """The rest of the scene from where the pure rocking ``rr`` (run with ``stop_mu = mu``) stopped: the general
    contact model, handing back to the kernel where pure rocking holds again (:func:`.handoff.continue_rocking`);
    None when ``rr`` did not stop short (overturned, or stood on a sticking pivot to the end). When ``rr`` kept a
    history (``rr.theta``), it is filled on to the scene's end, in place."""
    outcome = rr.outcome
    if outcome is None or not handoff.stopped_short(outcome):
        return None
    ah = _series("horizontal acceleration", ah_ms2)
    av = np.zeros(0) if av_ms2 is None else _series("vertical acceleration", av_ms2, ah.size)
    return _contact_result(handoff.continue_rocking(outcome, ah, av, float(dt_s), contact_block(block, settings),
                                                    step_control(settings), True, _history(rr.theta)))


def from_rest(ah_ms2, av_ms2, dt_s: float, *, block, settings: SimulationConfig = SimulationConfig(),
              theta_out: np.ndarray | None = None) -> ContactResult:
    """The general contact model over the whole record, from rest; ``theta_out``: filled with theta [rad] at
    every sample, when given."""
    ah = _series("horizontal acceleration", ah_ms2)
    av = np.zeros(0) if av_ms2 is None else _series("vertical acceleration", av_ms2, ah.size)
    _positive(dt_s=dt_s)
    return _contact_result(handoff.from_rest(ah, av, float(dt_s), contact_block(block, settings), True,
                                             _history(theta_out)))
