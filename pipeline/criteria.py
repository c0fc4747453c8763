"""The reference paper's critical-pulse criterion, uplift and rock-or-slide at onset.

The first tier of the screening, evaluated for every (record, block) scene at
once from the pulse characterization (a_p, t_p, beta, dv) along the block's
direction:

* uplift (Eq. 1): a_p >= g tan(alpha) (``form="exact"``) or alpha g
  (``form="small_angle"``, the paper's linearised statement);
* energy (Eqs. 2-5): the pulse velocity increment dv = beta t_p a_p reaches the
  critical velocity of Eq. 4, exact sqrt(8 g R / 3 (1 - cos a) / cos^2 a) or
  small-angle alpha g / p;
* the paper's sliding line a_p <= mu g (mu / alpha in units of alpha g).

The criterion is a first-order heuristic: it raises false alarms for single lobes and can miss trains of
pulses (measured in docs/validation.md against the simulator and Makris & Roussos 2000, eq. 27).
The simulator is the truth it is measured against.

A block with Housner restitution e = 1 - 1.5 sin^2(alpha) <= 0
(alpha >= 54.7 deg) is too squat for the pure-rocking model: it is never
given a rocking verdict (flag value -1), only the rock-or-slide onset test.

References
----------
The reference paper: "Rocking Blocks Stability under Critical Pulses from Near-Fault Earthquakes Using a
Novel Energy Based Approach", Applied Sciences (MDPI), Eqs. (1)-(9).
Makris, N. & Roussos, Y. (2000). Rocking response of rigid blocks under near-source ground motions.
Geotechnique 50(3), 243-262.
Housner, G. W. (1963). BSSA 53(2), 403-417.
Zhang, J. & Makris, N. (2001). J. Eng. Mech. 127(5), 473-483, eq. 7.
Shenton, H. W. (1996). J. Eng. Mech. 122(7), 690-693.
"""

from __future__ import annotations

from enum import IntEnum

import numpy as np

from .closed_forms import makris_roussos_halfsine
from .constants import G
from .errors import ParameterError
from .rocking.geometry import ALPHA_MAX_ROCKING, check_friction

#: Forms of Eqs. 1 and 4: "exact" (g tan(alpha), exact critical velocity) or "small_angle".
FORMS = ("exact", "small_angle")


#: Onset modes (flag values of ``onset``).
class Onset(IntEnum):
    """Mode at the onset of motion (Zhang & Makris 2001 eq. 7)."""

    rest = 0
    slide = 1
    rock = 2
    slide_rock = 3




def _form(form: str) -> str:
    if form not in FORMS:
        raise ParameterError(f"criterion form {form!r} is unknown; valid: {list(FORMS)}")
    return form


def rocking_applicable(alpha) -> np.ndarray:
    """True where the pure-rocking model applies (Housner e > 0, alpha < 54.7 deg)."""
    return np.asarray(alpha, dtype=float) < ALPHA_MAX_ROCKING


def uplift_acceleration(alpha, *, g_ms2: float = G, form: str = "exact"):
    """Ground acceleration that starts rocking from rest [m s-2].

    Parameters
    ----------
    alpha : float or array_like
        Slenderness angle atan(b/h) [rad].
    g_ms2 : float
        Gravity [m s-2].
    form : {"exact", "small_angle"}
        g tan(alpha) (moment balance m a h = m g b) or the paper's alpha g (Eq. 1).
    """
    alpha = np.asarray(alpha, dtype=float)
    return g_ms2 * (np.tan(alpha) if _form(form) == "exact" else alpha)     # Eq. (1)


def critical_velocity(R_m, alpha, *, g_ms2: float = G, form: str = "exact"):
    """Velocity increment a pulse must impart to overturn the block [m s-1].

    Parameters
    ----------
    R_m : float or array_like
        Corner-to-centre-of-mass distance R [m].
    alpha : float or array_like
        Slenderness angle [rad].
    g_ms2 : float
        Gravity [m s-2].
    form : {"exact", "small_angle"}
        Eq. 4 exact, sqrt(8 g R / 3 (1 - cos a) / cos^2 a), or its small-angle
        form alpha g / p = alpha sqrt(4 g R / 3).

    Notes
    -----
    The exact form equals the nonlinear impulse limit (2 g / p) sin(alpha/2) /
    cos(alpha): the velocity step whose kinetic energy after the impact-like uplift (Housner 1963, angular
    momentum about the corner) equals the potential barrier (a test checks the identity).
    """
    R = np.asarray(R_m, dtype=float)
    alpha = np.asarray(alpha, dtype=float)
    if _form(form) == "exact":
        return np.sqrt(8.0 * g_ms2 * R / 3.0 * (1.0 - np.cos(alpha)) / np.cos(alpha) ** 2)   # Eq. (4), exact
    return alpha * np.sqrt(4.0 * g_ms2 * R / 3.0)                                          # Eq. (4), small angle


def transition_duration(R_m, alpha, beta, *, g_ms2: float = G, form: str = "exact"):
    """Pulse duration where the energy curve meets the uplift line [s].

    With ``form="small_angle"`` this is the paper's Eq. 6, t_p = 1 / (p beta);
    with ``"exact"`` it is v_crit / (beta g tan(alpha)) from the exact Eqs. 1 and 4,
    which makes the normalized boundary exactly Eq. 7.
    """
    beta = np.asarray(beta, dtype=float)
    return critical_velocity(R_m, alpha, g_ms2=g_ms2, form=form) / (
        beta * uplift_acceleration(alpha, g_ms2=g_ms2, form=form))                   # Eqs. (5)-(6)


def transition_period(p, beta):
    """The paper's transition period T = 2 / (p beta) [s] (pi / p for a half-sine).

    References
    ----------
    Reference paper Eq. (9): t_p = 1 / (p beta) = T / 2, p T = pi for a sinusoidal pulse.
    """
    return 2.0 / (np.asarray(p, dtype=float) * np.asarray(beta, dtype=float))        # Eq. (9)


def critical_acceleration(tp_s, R_m, alpha, beta, *, g_ms2: float = G, form: str = "exact"):
    """Smallest pulse amplitude that overturns by the criterion, for a pulse of duration t_p [m s-2].

    max(v_crit / (beta t_p), a_uplift): the energy hyperbola (Eq. 5) above
    the transition duration's left, the uplift line (Eq. 1) right of it (Eq. 7).
    """
    tp = np.asarray(tp_s, dtype=float)
    beta = np.asarray(beta, dtype=float)
    energy = critical_velocity(R_m, alpha, g_ms2=g_ms2, form=form) / (beta * tp)     # Eq. (5)
    return np.maximum(energy, uplift_acceleration(alpha, g_ms2=g_ms2, form=form))   # Eq. (7)


def onset_friction_demand(accel_ms2, alpha, *, g_ms2: float = G):
    """Friction coefficient needed to start rocking without sliding [-].

    Zhang & Makris (2001) eq. 7 (Shenton's condition) with the ground
    acceleration at uplift ``accel_ms2`` = lambda a_p. For a pulse that builds
    up gradually, uplift happens at g tan(alpha) and the demand is tan(alpha);
    for a pulse that arrives at full amplitude (lambda = 1) it grows with a_p.
    Below the uplift acceleration the demand is that of sliding alone, |a| / g.
    """
    a = np.abs(np.asarray(accel_ms2, dtype=float))
    alpha = np.asarray(alpha, dtype=float)
    excess = a / (g_ms2 * np.tan(alpha)) - 1.0                         # lambda a_p / (g tan a) - 1
    num = a - 0.75 * g_ms2 * np.sin(alpha) * np.cos(alpha) * excess    # Z&M eq. 7, numerator
    den = g_ms2 + 0.75 * g_ms2 * np.sin(alpha) ** 2 * excess           # Z&M eq. 7, denominator
    return np.where(excess > 0, num / den, a / g_ms2)


def onset_mode(ap_ms2, alpha, mu, *, g_ms2: float = G, demand=None) -> np.ndarray:
    """Mode at the onset of motion under a pulse of peak ``ap_ms2`` (codes of :class:`Onset`).

    * rest: the pulse neither lifts (a_p < g tan alpha) nor slides (a_p <= mu g) the block;
    * slide: mu <= tan(alpha) and a_p > mu g, so the block slides before it can tip;
    * rock: mu > tan(alpha) and mu covers Zhang & Makris eq. 7 even for a pulse
      arriving at full amplitude;
    * slide_rock: mu > tan(alpha) (rocks under a gradual pulse) but a pulse
      arriving at full amplitude needs more friction than mu (eq. 7 with lambda = 1).

    NaN amplitudes give -1. ``demand`` is :func:`onset_friction_demand` of ``ap_ms2``
    when the caller has it already.
    """
    a = np.abs(np.asarray(ap_ms2, dtype=float))
    alpha = np.asarray(alpha, dtype=float)
    mu = np.asarray(mu, dtype=float)
    tan_a = np.tan(alpha)
    if demand is None:
        demand = onset_friction_demand(a, alpha, g_ms2=g_ms2)
    rocks_first = mu > tan_a                                             # static test (section 1.8)
    lifts = a >= g_ms2 * tan_a
    code = np.where(
        rocks_first,
        np.where(lifts, np.where(demand <= mu, Onset.rock, Onset.slide_rock), Onset.rest),
        np.where(a > mu * g_ms2, Onset.slide, Onset.rest),
    )
    return np.where(np.isnan(a), -1, code).astype("i1")


def _flag(cond, valid) -> np.ndarray:
    """Boolean -> int8 flag with -1 where not evaluated."""
    return np.where(valid, np.asarray(cond, dtype="i1"), -1).astype("i1")


def evaluate(ap_ms2, tp_s, beta, dv_ms, *, R_m, alpha, p, mu, g_ms2: float = G,
             form: str = "exact") -> dict[str, np.ndarray]:
    """The criterion tier for every scene at once (arrays broadcast together).

    Parameters
    ----------
    ap_ms2, tp_s, beta, dv_ms : array_like
        Pulse peak acceleration [m s-2], lobe duration [s], fullness [-] and
        velocity increment [m s-1] along each block's direction (NaN where no
        pulse was extracted). Signs are ignored: the block is symmetric.
    R_m, alpha, p, mu : array_like
        Block geometry [m], [rad], [rad s-1] and friction [-].
    g_ms2 : float
        Gravity [m s-2].
    form : {"exact", "small_angle"}
        Forms of Eqs. 1 and 4.

    Returns
    -------
    dict
        ``uplift``, ``overturn_criterion``, ``above_sliding_line``,
        ``overturn_closed_form``, ``onset`` (int8 flags, -1 not evaluated),
        ``velocity_ratio`` = |dv| / v_crit (the ratio Eqs. 4-5 compare with 1),
        ``energy_ratio`` = (|dv| / v_crit)^2 (the pulse's kinetic energy over the energy
        that overturns), ``criterion_scale`` (the smallest factor
        on the record that reaches the criterion's boundary; inf where the
        sliding line is crossed first), ``onset_friction_demand``,
        ``normalized_acceleration`` = a_p / a_uplift, ``normalized_duration`` =
        t_p / t_transition, ``closed_form_ratio`` = a_p over the Makris & Roussos
        half-sine minimum for the same t_p.
    """
    mu = check_friction(mu)
    a = np.abs(np.asarray(ap_ms2, dtype=float))
    dv = np.abs(np.asarray(dv_ms, dtype=float))
    tp = np.asarray(tp_s, dtype=float)
    beta = np.asarray(beta, dtype=float)
    alpha = np.asarray(alpha, dtype=float)
    a_up = uplift_acceleration(alpha, g_ms2=g_ms2, form=form)
    v_crit = critical_velocity(R_m, alpha, g_ms2=g_ms2, form=form)
    have = np.isfinite(a) & np.isfinite(dv) & np.isfinite(tp)
    rocking = have & rocking_applicable(alpha)
    with np.errstate(divide="ignore", invalid="ignore"):
        uplift = a >= a_up                                                  # Eq. (1)
        velocity_ratio = dv / v_crit                                        # Eqs. (4)-(5)
        below_sliding = a <= mu * g_ms2                                     # paper: a_p / (alpha g) <= mu / alpha
        overturn = uplift & (velocity_ratio >= 1.0) & below_sliding
        scale = np.maximum(a_up / a, v_crit / dv)                           # reach both Eq. 1 and Eq. 5
        scale = np.where(scale * a <= mu * g_ms2, scale, np.inf)
        t_bar = transition_duration(R_m, alpha, beta, g_ms2=g_ms2, form=form)
        # second tier: the lobe as a half-sine of the same a_p and t_p (w_p = pi / t_p), M&R eq. 27
        omega_over_p = np.where(tp > 0, np.pi / (np.where(tp > 0, tp, 1.0) * p), 1.0)
        a_min_hs = makris_roussos_halfsine(omega_over_p) * alpha * g_ms2
        cf_ratio = a / a_min_hs
        demand = onset_friction_demand(a, alpha, g_ms2=g_ms2)
    return {
        "uplift": _flag(uplift, have),
        "velocity_ratio": np.where(have, velocity_ratio, np.nan),
        "energy_ratio": np.where(have, velocity_ratio ** 2, np.nan),
        "overturn_criterion": _flag(overturn, rocking),
        "above_sliding_line": _flag(~below_sliding, have),
        "criterion_scale": np.where(rocking, scale, np.nan),
        "onset": onset_mode(np.where(have, a, np.nan), alpha, mu, g_ms2=g_ms2, demand=demand),
        "onset_friction_demand": np.where(have, demand, np.nan),
        "normalized_acceleration": np.where(have, a / a_up, np.nan),
        "normalized_duration": np.where(have, tp / t_bar, np.nan),
        "closed_form_ratio": np.where(rocking, cf_ratio, np.nan),
        "overturn_closed_form": _flag((cf_ratio >= 1.0) & below_sliding, rocking),
    }
