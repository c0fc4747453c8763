"""The pulse as the reference paper's (a_p, t_p, beta).

The acceleration is read as the piecewise-linear function through its
samples (the same interpolation the simulator integrates). A lobe is a
maximal interval of one sign between zero crossings (located by linear
interpolation); its velocity change dv is the exact integral of the
interpolant. The dominant lobe is the one with the largest |dv|; then
t_p is its duration, a_p its peak |acceleration| and the fullness factor
beta = |dv| / (a_p t_p): 2/pi for a half-sine, 1 for a step, 1/2 for a
linear (triangular) and 2/3 for a parabolic pulse (the paper's Eq. 8).

References
----------
The reference paper, "Rocking Blocks Stability under Critical Pulses from Near-Fault Earthquakes Using a
Novel Energy Based Approach", Applied Sciences (MDPI), Eqs. (5)-(9):
v = beta t_p a_p = integral of a(t) over the pulse.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Lobe:
    """The dominant single-sign acceleration lobe.

    Attributes
    ----------
    ap_ms2 : float
        Peak |acceleration| in the lobe [m s-2].
    tp_s : float
        Lobe duration [s].
    beta : float
        Fullness factor |dv| / (a_p t_p) [-].
    dv_ms : float
        Velocity change over the lobe (signed) [m s-1].
    t_start_s, t_end_s : float
        Lobe start and end [s from the first sample].
    """

    ap_ms2: float
    tp_s: float
    beta: float
    dv_ms: float
    t_start_s: float
    t_end_s: float


def dominant_lobe(acc_ms2: np.ndarray, dt_s: float, *, first_sample: int = 0) -> Lobe:
    """Return the single-sign acceleration lobe with the largest |velocity change|.

    Parameters
    ----------
    acc_ms2 : ndarray, shape (N,)
        Acceleration samples [m s-2], linearly interpolated between samples.
    dt_s : float
        Sampling interval [s].
    first_sample : int, optional
        The index of ``acc_ms2[0]`` in a longer series that is zero outside it (the lobe's times are then on that
        series' clock, the same values as from the whole series: :func:`pulse_lobe`).
    """
    a = np.asarray(acc_ms2, dtype=float)
    n = a.size
    if n < 2 or not np.any(a):
        return Lobe(0.0, 0.0, float("nan"), 0.0, 0.0, 0.0)
    # cumulative integral at the samples (trapezoid = exact for the interpolant)
    F = np.concatenate([[0.0], np.cumsum(0.5 * (a[1:] + a[:-1]) * dt_s)])
    # zero crossings: sample k where a changes sign towards k+1, at fraction tau
    k = np.flatnonzero((a[:-1] * a[1:] < 0))
    tau = a[k] / (a[k] - a[k + 1])
    t_cross = (k + first_sample + tau) * dt_s
    F_cross = F[k] + 0.5 * a[k] * tau * dt_s           # triangle from a[k] down to zero
    zeros = np.flatnonzero(a == 0.0)
    t_b = np.concatenate([[first_sample * dt_s], t_cross, (zeros + first_sample) * dt_s,
                          [(first_sample + n - 1) * dt_s]])
    F_b = np.concatenate([[0.0], F_cross, F[zeros], [F[-1]]])
    order = np.argsort(t_b, kind="stable")
    t_b, F_b = t_b[order], F_b[order]
    dv = np.diff(F_b)
    j = int(np.argmax(np.abs(dv)))
    t0, t1 = float(t_b[j]), float(t_b[j + 1])
    inside = slice(int(np.floor(t0 / dt_s + 1e-9)) - first_sample, int(np.ceil(t1 / dt_s - 1e-9)) + 1 - first_sample)
    ap = float(np.max(np.abs(a[inside])))
    tp = t1 - t0
    beta = abs(float(dv[j])) / (ap * tp) if ap > 0 and tp > 0 else float("nan")
    return Lobe(ap, tp, beta, float(dv[j]), t0, t1)


def pulse_lobe(pulse_ms: np.ndarray, dt_s: float) -> Lobe:
    """The dominant lobe of a pulse's acceleration (``np.gradient`` of its velocity [m s-1]): the same values as
    :func:`dominant_lobe` of the whole series, computed over the pulse's support only (a sum of wavelets is zero
    outside it; two zeros are kept on either side, so the gradient and the lobes' bounds there are unchanged)."""
    v = np.asarray(pulse_ms, dtype=float)
    nonzero = np.flatnonzero(v)
    if nonzero.size == 0:
        return dominant_lobe(np.zeros(v.size), dt_s)
    start, stop = max(0, int(nonzero[0]) - 2), min(v.size, int(nonzero[-1]) + 3)
    return dominant_lobe(np.gradient(v[start:stop], dt_s), dt_s, first_sample=start)


def record_peak_in(acc_ms2: np.ndarray, dt_s: float, lobe: Lobe) -> float:
    """Peak |acceleration| of the record itself during the lobe [m s-2].

    The extracted pulse is a smooth sum of wavelets and understates the
    record's own peak; this is that peak along the same orientation.
    """
    i0 = int(np.floor(lobe.t_start_s / dt_s))
    i1 = int(np.ceil(lobe.t_end_s / dt_s)) + 1
    seg = np.abs(np.asarray(acc_ms2)[max(0, i0):max(i0 + 1, i1)])
    return float(seg.max()) if seg.size else 0.0
