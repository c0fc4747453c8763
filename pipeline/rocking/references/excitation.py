"""Idealized ground-acceleration pulses, sampled for the simulator.

Every pulse starts at t = 0. Shapes: ``half-sine`` a_p sin(w t) for one
half period; ``one-sine`` and ``one-cosine`` one full period of a_p sin and
a_p cos (Makris & Roussos 2000 types A and B); ``harmonic`` ``cycles`` full
periods of a_p sin; ``step`` a rectangle lasting T/2; ``linear`` a
triangle decaying from a_p to 0 over T/2; ``parabolic`` 4 a_p x (1 - x)
over T/2. The half-pulse shapes last t_p = T/2, as in the reference paper.
"""

from __future__ import annotations

import math

import numpy as np

from ...errors import ParameterError

SHAPES = ("half-sine", "one-sine", "one-cosine", "harmonic", "step", "linear", "parabolic")


def pulse(shape: str, *, amplitude_ms2: float, period_s: float, dt_s: float | None = None,
          cycles: int = 1, samples_per_period: int = 2000) -> tuple[np.ndarray, float]:
    """Sampled ground acceleration of an idealized pulse.

    Parameters
    ----------
    shape : str
        One of :data:`SHAPES`.
    amplitude_ms2 : float
        Peak acceleration a_p [m s-2].
    period_s : float
        Period T [s] (the half-pulse shapes last T/2).
    dt_s : float, optional
        Sampling interval [s]; default T / samples_per_period. The duration is
        an exact multiple of it, so a step is represented exactly (the
        simulator sets the ground still after the last sample).
    cycles : int
        Number of periods for ``harmonic``.

    Returns
    -------
    acc : ndarray
        Acceleration at t = k dt [m s-2].
    dt : float
        The sampling interval used [s].
    """
    if shape not in SHAPES:
        raise ParameterError(f"pulse shape {shape!r} is unknown; valid: {list(SHAPES)}")
    if not (math.isfinite(period_s) and period_s > 0):
        raise ParameterError(f"period = {period_s!r} s: must be > 0")
    if shape == "harmonic" and (int(cycles) != cycles or cycles < 1):
        raise ParameterError(f"cycles = {cycles!r}: must be a positive integer")
    duration = {"half-sine": 0.5, "step": 0.5, "linear": 0.5, "parabolic": 0.5,
                "one-sine": 1.0, "one-cosine": 1.0, "harmonic": float(cycles)}[shape] * period_s
    dt = period_s / samples_per_period if dt_s is None else float(dt_s)
    n = max(int(round(duration / dt)), 1)
    dt = duration / n
    t = np.arange(n + 1) * dt
    w = 2.0 * math.pi / period_s
    if shape in ("half-sine", "one-sine", "harmonic"):
        acc = np.sin(w * t)
        acc[-1] = 0.0
    elif shape == "one-cosine":
        acc = np.cos(w * t)
    elif shape == "step":
        acc = np.ones_like(t)
    elif shape == "linear":
        acc = 1.0 - t / duration
    else:
        x = t / duration
        acc = 4.0 * x * (1.0 - x)
    return amplitude_ms2 * acc, dt
