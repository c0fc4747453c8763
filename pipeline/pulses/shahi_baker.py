"""Velocity-pulse extraction and classification (Shahi & Baker 2014; Baker 2007).

The algorithm follows the authors' published MATLAB code, step by step (Shahi, S. K. & Baker, J. W.
(2014), An efficient algorithm to identify strong-velocity pulses in multicomponent ground motions,
BSSA 104(5), 2456-2466):
five candidate pulses from the largest combined wavelet energy of the two
horizontals, each extracted as the sum of ten db4 wavelets at one refined
scale, classified by the pulse indicator PI and the late-arrival rule.

Speed (against a straightforward port that repeats one FFT convolution per
scale at every step): each component is transformed once at the 51 scales;
the scale refinement evaluates three integer scales at a single time; the
ten iterations transform the residual at one scale over the search window
only, and only when the window moves (the first two iterations at most):
the transform is linear, so each later iteration subtracts the coefficients
of the wavelet just added, a shift of the unit wavelet's response computed
once per scale (equal to transforming the residual, to rounding; tested).
The pulse along other orientations (the blocks' azimuths) is in :mod:`.along`.

Units: velocity in cm/s inside the classifier (its PI constants use cm/s).

References
----------
Baker, J. W. (2007). Quantitative classification of near-fault ground
motions using wavelet analysis. BSSA 97(5), 1486-1501.
Shahi, S. K., & Baker, J. W. (2014). An efficient algorithm to identify
strong-velocity pulses in multicomponent ground motions. BSSA 104(5), 2456-2466.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import lru_cache
from typing import Any

import numpy as np
import pywt

from ..errors import PulseError
from .cwt import SUPPORT, cwt, cwt_point, cwt_window, pseudo_period, scales_for

#: Number of candidate pulses examined (Shahi & Baker 2014).
N_CANDIDATES = 5
#: Wavelets summed into one extracted pulse.
N_WAVELETS = 10
#: Half-width of the search window and of the zeroed band, in units of the scale.
WINDOW_FRACTION = 0.4
#: Late-arrival rule: pulse energy fraction and record energy fraction [%].
LATE_PULSE_PCT, LATE_RECORD_PCT = 5.0, 17.0
#: Pulse-indicator constants of the MATLAB code (code form; section 2.7).
PC_MEAN, PC_STD = 1.208421, 0.2462717
PGV_MEAN_CMS, PGV_STD_CMS = 11.58861, 18.88015
PI_COEFFS = (-7.817, -0.5679, -0.1516, -3.0253, -1.7396, -2.7156)  # 1, P^2, V^2, P, V, PV


@dataclass
class Candidate:
    """One candidate pulse (all indices 0-based; add 1 for MATLAB's)."""

    angle_rad: float            #: orientation atan(C2/C1) relative to the first component
    column: int                 #: sample of the largest combined coefficient
    row: int                    #: index of its scale in the 51 searched
    scale: int                  #: refined integer scale
    tp_s: float                 #: pulse period 1.4 a dt [s]
    pgv_cms: float              #: PGV along the orientation [cm/s]
    pgv_resid_cms: float        #: PGV of the residual [cm/s]
    dwt_sq_orig: float
    dwt_sq_resid: float
    energy_ratio: float
    pulse_indicator: float
    late: bool
    is_pulse: bool
    positions: list[int] = field(default_factory=list)
    coefficients: list[float] = field(default_factory=list)
    pulse_cms: np.ndarray | None = None     #: extracted pulse [cm/s]
    velocity_cms: np.ndarray | None = None  #: velocity along the orientation [cm/s]


@dataclass
class PulseResult:
    """Classification of one record.

    ``chosen`` is the first pulse-like candidate in extraction order, or the
    first candidate when none is pulse-like.
    """

    is_pulse: bool
    tp_s: float
    candidates: list[Candidate]
    chosen: int
    method: str
    flags: list[str] = field(default_factory=list)
    velocity_cms: np.ndarray | None = None   #: the input components [cm/s]
    coeffs: np.ndarray | None = None         #: their transforms, (n_c, 51, N)
    scales: np.ndarray | None = None
    dt_s: float = math.nan
    #: the two-component transform's heads of strongest points by size, for :func:`extract_along` (built on
    #: first use)
    _strongest: dict | None = field(default=None, repr=False, compare=False)
    #: the components' transforms shared by every orientation (:class:`.along.AlongCache`, built on first use)
    _along: Any = field(default=None, repr=False, compare=False)

    @property
    def best(self) -> Candidate:
        return self.candidates[self.chosen]


def pulse_indicator(pgv_ratio: float, energy_ratio: float, pgv_cms: float) -> float:
    """Shahi & Baker (2014) pulse indicator, code form (PI > 0: pulse-like)."""
    pc = 0.63 * pgv_ratio + 0.777 * energy_ratio
    P = (pc - PC_MEAN) / PC_STD
    V = (pgv_cms - PGV_MEAN_CMS) / PGV_STD_CMS
    c0, cpp, cvv, cp, cv, cpv = PI_COEFFS
    return c0 + cpp * P**2 + cvv * V**2 + cp * P + cv * V + cpv * P * V


def dwt_energy(x: np.ndarray) -> float:
    """Sum of squared single-level db4 approximation coefficients ('symmetric' extension)."""
    cA, _ = pywt.dwt(x, "db4", mode="symmetric")
    return float(np.sum(cA**2))


def is_late(velocity: np.ndarray, pulse: np.ndarray) -> bool:
    """Late-arrival rule: record energy >= 17 % when the pulse reaches 5 % of its own."""
    ev = np.cumsum(velocity**2)
    ep = np.cumsum(pulse**2)
    if ev[-1] <= 0 or ep[-1] <= 0:
        return False
    ev, ep = 100 * ev / ev[-1], 100 * ep / ep[-1]
    idx = np.flatnonzero(ep <= LATE_PULSE_PCT)
    if idx.size == 0:   # the pulse holds > 5 % of its energy in its first sample (guarded MATLAB crash)
        return False
    return bool(ev[idx[-1]] >= LATE_RECORD_PCT)


def wavelet_on_grid(coef: float, scale: int, position: int, n: int) -> np.ndarray:
    """One db4 wavelet c psi / sqrt(a), centred at ``position``, sampled at 0..n-1.

    ``wavefun(db4, 4)`` on x in [0, 7] is stretched by the scale and
    interpolated linearly onto the sample grid, zero outside its support.
    """
    return _add_wavelet(np.zeros(n), coef, scale, position)


def _add_wavelet(out: np.ndarray, coef: float, scale: int, position: int) -> np.ndarray:
    """``out`` plus :func:`wavelet_on_grid` (in place, on the wavelet's support only); returns ``out``."""
    psi, x, centre = _wavefun4()
    t = (x - centre) * scale + position  # in samples
    lo, hi = max(0, int(math.ceil(t[0]))), min(out.size - 1, int(math.floor(t[-1])))
    if hi >= lo:
        grid = np.arange(lo, hi + 1, dtype=float)
        out[lo:hi + 1] += np.interp(grid, t, coef * psi / math.sqrt(scale))
    return out


@lru_cache(maxsize=8)
def unit_wavelet(scale: int) -> tuple[int, np.ndarray]:
    """The wavelet of coefficient 1 at ``scale`` positioned at sample 0 (:func:`wavelet_on_grid`): the offset of its
    first sample from the position and its samples (read-only). A wavelet at ``position`` is this shifted, cut by
    the record's ends (equal to :func:`wavelet_on_grid` times its coefficient, to rounding)."""
    psi, x, centre = _wavefun4()
    t = (x - centre) * scale
    first, last = int(math.ceil(t[0])), int(math.floor(t[-1]))
    values = np.interp(np.arange(first, last + 1, dtype=float), t, psi / math.sqrt(scale))
    values.setflags(write=False)
    return first, values


@lru_cache(maxsize=1)
def _wavefun4() -> tuple[np.ndarray, np.ndarray, float]:
    """db4's wavelet function at level 4: (psi, x, median of x), computed once."""
    _, psi, x = pywt.Wavelet("db4").wavefun(level=4)
    return psi, x, float(np.median(x))


def extract(velocity: np.ndarray, c_theta_column, *, column: int, row: int, scales: np.ndarray,
            steps: ExtractionSteps | None = None) -> tuple[int, np.ndarray, list[int], list[float]]:
    """Extract the pulse of a candidate from ``velocity`` (the record along its orientation).

    Parameters
    ----------
    velocity : ndarray
        Velocity along the candidate's orientation [cm/s].
    c_theta_column : callable
        ``c(scale) -> coefficient`` of ``velocity`` at ``column`` (for the refinement).
    column, row : int
        Location of the candidate (0-based sample, index in ``scales``).
    scales : ndarray
        The searched scales.
    steps : ExtractionSteps, optional
        How the iterations transform the residual and add a wavelet (default: on the residual itself).

    Returns
    -------
    scale : int
        Refined scale.
    pulse : ndarray
        Sum of the ten wavelets [cm/s].
    positions, coefficients : list
        Centre (0-based sample) and coefficient of each wavelet.
    """
    n = velocity.size
    lo_s = scales[max(0, row - 1)]
    hi_s = scales[min(len(scales) - 1, row + 1)]
    refined = np.arange(lo_s, hi_s + 1)
    values = np.abs([c_theta_column(int(a)) for a in refined])
    scale = int(refined[int(np.argmax(values))])
    half = int(math.ceil(WINDOW_FRACTION * scale))
    pulse = np.zeros(n)
    positions: list[int] = []
    coefs: list[float] = []
    centre = column

    def search_window(at: int) -> tuple[int, int]:
        return max(0, at - half), min(n - 1, at + half)

    ops = steps if steps is not None else ExtractionSteps()
    window, c = (-1, -1), np.zeros(0)
    for i in range(N_WAVELETS):
        lo, hi = search_window(centre)
        if (lo, hi) != window:     # the residual transformed over a new window (the first two iterations at most)
            window, c = (lo, hi), ops.residual_window(velocity, pulse, list(zip(coefs, positions)), scale, lo, hi)
        k = int(np.argmax(np.abs(c)))
        pos, coef = lo + k, float(c[k])
        if i == 0:
            centre = pos  # MATLAB overwrites col(1): later windows centre on this
        ops.add(pulse, coef, scale, pos)
        positions.append(pos)
        coefs.append(coef)
        if i + 1 < N_WAVELETS and search_window(centre) == window:
            c = c - ops.response(coef, scale, pos, lo, hi, n)   # the residual's coefficients, the wavelet removed
    return scale, pulse, positions, coefs


class ExtractionSteps:
    """The three operations of :func:`extract`'s iterations, on the residual itself: its transform over a window,
    a wavelet's coefficients over a window (:func:`_window_response`), and a wavelet added to the pulse
    (:func:`_add_wavelet`). :class:`.along.SharedSteps` computes the same from what every orientation of a record
    shares."""

    def residual_window(self, velocity: np.ndarray, pulse: np.ndarray, wavelets: list[tuple[float, int]],
                        scale: int, lo: int, hi: int) -> np.ndarray:
        """The coefficients of ``velocity - pulse`` at ``scale`` over output samples ``lo..hi`` (``wavelets``: the
        (coefficient, position) of the wavelets in ``pulse``)."""
        return cwt_window(velocity - pulse, scale, lo, hi)

    def response(self, coef: float, scale: int, position: int, lo: int, hi: int, n: int) -> np.ndarray:
        """:func:`_window_response`."""
        return _window_response(coef, scale, position, lo, hi, n)

    def add(self, pulse: np.ndarray, coef: float, scale: int, position: int) -> None:
        """:func:`_add_wavelet`, in place."""
        _add_wavelet(pulse, coef, scale, position)


def _window_response(coef: float, scale: int, position: int, lo: int, hi: int, n: int) -> np.ndarray:
    """The coefficients at ``scale`` over output samples ``lo..hi`` of the wavelet ``coef`` at ``position`` on a
    record of ``n`` samples (:func:`wavelet_on_grid`): the transform is linear, so the residual's coefficients
    over a window are the previous ones less this. A wavelet inside the record is a shift of the unit wavelet
    (its samples depend on sample - position only), whose response is computed once per scale
    (:func:`_unit_response`); one cut by the record's ends, or a window wider than the search's, is transformed
    itself."""
    shifted = shifted_response(coef, scale, position, lo, hi, n)
    if shifted is not None:
        return shifted
    return cwt_window(wavelet_on_grid(coef, scale, position, n), scale, lo, hi)


def shifted_response(coef: float, scale: int, position: int, lo: int, hi: int, n: int) -> np.ndarray | None:
    """:func:`_window_response` where it is a shift of the unit wavelet's response (the wavelet inside the record,
    the window within reach); None elsewhere."""
    _, x, centre = _wavefun4()
    if (x[0] - centre) * scale + position >= 0 and (x[-1] - centre) * scale + position <= n - 1:
        response, reach = _unit_response(scale)
        d0, d1 = lo - position, hi - position
        if -reach <= d0 and d1 <= reach:
            return coef * response[d0 + reach:d1 + reach + 1]
    return None


@lru_cache(maxsize=128)
def _unit_response(scale: int) -> tuple[np.ndarray, int]:
    """The coefficients at ``scale`` of the unit wavelet (coefficient 1) at offsets -reach..reach from its
    position, and reach = twice the search window's half-width (a window holds the wavelet's position, so no
    offset within it is farther); read-only."""
    _, x, centre = _wavefun4()
    reach = 2 * int(math.ceil(WINDOW_FRACTION * scale))
    below, above = int(math.ceil((centre - x[0]) * scale)), int(math.ceil((x[-1] - centre) * scale))
    at = reach + below + 1                                 # the unit wavelet's position in a buffer that holds it
    u = wavelet_on_grid(1.0, scale, at, at + above + reach + 2)
    response = cwt_window(u, scale, at - reach, at + reach)
    response.setflags(write=False)
    return response, reach


def classify(velocity_cms: np.ndarray, dt_s: float, *, method: str = "shahi_baker_2014",
             tp_min_s: float = 0.25, tp_max_s: float = 15.0) -> PulseResult:
    """Find and classify the velocity pulse of a one- or two-component record.

    Parameters
    ----------
    velocity_cms : ndarray, shape (n_h, N)
        Horizontal velocities [cm/s]; two rows are an orthogonal pair
        (second 90 deg clockwise of the first), one row a single component.
    dt_s : float
        Sampling interval [s].
    method : {"shahi_baker_2014", "baker_2007"}
        ``baker_2007`` examines only the largest candidate of one component
        with the Baker (2007) logistic indicator.

    Raises
    ------
    PulseError
        If the record is too short for the smallest wavelet, or all zero.
    """
    v = np.atleast_2d(np.asarray(velocity_cms, dtype=float))
    n = v.shape[1]
    flags = []
    scales = scales_for(dt_s, tp_min_s=tp_min_s, tp_max_s=tp_max_s)
    if n < 2 * int(math.ceil(WINDOW_FRACTION * scales[0])) + 8:
        raise PulseError(f"record of {n} samples is shorter than the smallest pulse wavelet "
                         f"({scales[0]} samples at dt = {dt_s:g} s); no pulse can be extracted")
    if not np.any(v):
        raise PulseError("velocity is zero everywhere; no pulse to extract")
    single = v.shape[0] == 1 or method == "baker_2007"
    if v.shape[0] == 1:
        flags.append("single-component extraction")
    coeffs = cwt(v[:1] if single else v, scales)       # (n_c, 51, N)
    energy = coeffs[0] ** 2                             # the sum over the components, without a squared copy
    for component in coeffs[1:]:
        energy += component**2
    n_cand = 1 if method == "baker_2007" else N_CANDIDATES
    candidates = []
    for _ in range(n_cand):
        flat = int(np.argmax(energy.ravel(order="F")))   # MATLAB max(E(:)): column-major order
        row, col = flat % energy.shape[0], flat // energy.shape[0]
        if energy[row, col] <= 0:
            break
        theta = 0.0 if single else math.atan(coeffs[1, row, col] / coeffs[0, row, col])
        ct, st = math.cos(theta), math.sin(theta)
        v_theta = v[0] if single else ct * v[0] + st * v[1]

        def column_coef(a: int, _col=col, _vt=v_theta) -> float:
            return cwt_point(_vt, a, _col)

        scale, pulse, positions, coefs = extract(v_theta, column_coef, column=col, row=row,
                                                 scales=scales)
        resid = v_theta - pulse
        pgv = float(np.max(np.abs(v_theta)))
        pgv_res = float(np.max(np.abs(resid)))
        if method == "baker_2007":
            e_orig, e_res = float(np.sum(v_theta**2)), float(np.sum(resid**2))
        else:
            e_orig, e_res = dwt_energy(v_theta), dwt_energy(resid)
        er = e_res / e_orig if e_orig > 0 else math.nan
        ratio = pgv_res / pgv if pgv > 0 else math.nan
        if method == "baker_2007":
            pi = 1.0 / (1.0 + math.exp(-23.3 + 14.6 * ratio + 20.5 * er))
            late = _baker_late(v_theta, pulse)
            pulse_like = pi > 0.85 and not late and pgv >= 30.0
        else:
            pi = pulse_indicator(ratio, er, pgv)
            late = is_late(v_theta, pulse)
            pulse_like = pi > 0 and not late
        candidates.append(Candidate(theta, col, row, scale, pseudo_period(scale, dt_s), pgv, pgv_res,
                                    e_orig, e_res, er, pi, late, pulse_like, positions, coefs,
                                    pulse, v_theta))
        band = np.abs(np.arange(n) - col) < WINDOW_FRACTION * scales[row]
        energy[:, band] = 0.0
    chosen = next((k for k, c in enumerate(candidates) if c.is_pulse), 0)
    if SUPPORT * candidates[chosen].scale > n:  # db4 support is 7 scales = 5 Tp
        flags.append("pulse wavelet (5 Tp) longer than the record: Tp may be cut short")
    is_pulse = any(c.is_pulse for c in candidates)
    return PulseResult(is_pulse, candidates[chosen].tp_s if is_pulse else math.nan, candidates,
                       chosen, method, flags, v, coeffs, scales, dt_s)


def _baker_late(velocity: np.ndarray, pulse: np.ndarray) -> bool:
    """Baker (2007) early-arrival rule: late unless t10%(pulse) < t20%(record)."""
    ev, ep = np.cumsum(velocity**2), np.cumsum(pulse**2)
    if ev[-1] <= 0 or ep[-1] <= 0:
        return False
    t_pulse = int(np.searchsorted(ep / ep[-1], 0.10))
    t_record = int(np.searchsorted(ev / ev[-1], 0.20))
    return not t_pulse < t_record
