"""Record processing as ordered, named steps, applied the obspy way.

A step is ``{"step": name, **params}``. The steps are obspy's own trace
methods (which also write ``stats.processing``, the per-trace history), plus
``integrate``, which turns acceleration into velocity and must come last.
Which list applies depends on how the file was delivered: ``uncorrected``
(raw counts, V1, K-NET, SAC, MiniSEED) or ``corrected`` (AT2, V2), so
already-processed records are not filtered again by default.
"""

from __future__ import annotations

import numpy as np

#: Parameters each step accepts, with their types.
STEP_PARAMS: dict[str, dict[str, type]] = {
    "demean": {},
    "detrend": {"type": str},
    "taper": {"max_percentage": float, "type": str},
    "highpass": {"freq": float, "corners": int, "zerophase": bool},
    "lowpass": {"freq": float, "corners": int, "zerophase": bool},
    "bandpass": {"freqmin": float, "freqmax": float, "corners": int, "zerophase": bool},
    "integrate": {"method": str},
}
INTEGRATION_METHODS = ("trapezoid", "rectangle")


def apply_steps(trace, steps) -> None:
    """Apply the acceleration steps (all but ``integrate``) to an obspy trace in place."""
    for step in steps:
        name, params = step["step"], {k: v for k, v in step.items() if k != "step"}
        if name == "integrate":
            continue
        if name == "demean":
            trace.detrend("demean")
        elif name == "detrend":
            trace.detrend(params.get("type", "linear"))
        elif name == "taper":
            trace.taper(max_percentage=params.get("max_percentage", 0.05),
                        type=params.get("type", "hann"))
        else:  # highpass, lowpass, bandpass
            trace.filter(name, **params)


def integration_method(steps) -> str:
    """Return the method of the (last) ``integrate`` step."""
    return steps[-1].get("method", "trapezoid")


def integrate(acc: np.ndarray, dt_s: float, *, method: str) -> np.ndarray:
    """Integrate acceleration to velocity along the last axis, starting from rest.

    Parameters
    ----------
    acc : ndarray
        Acceleration [m s-2].
    dt_s : float
        Sampling interval [s].
    method : {"trapezoid", "rectangle"}
        ``rectangle`` is ``cumsum(a) * dt``, as the Shahi & Baker (2014)
        MATLAB code does; ``trapezoid`` is second-order accurate.

    Returns
    -------
    ndarray
        Velocity [m s-1], same shape as ``acc``.
    """
    if method == "rectangle":
        return np.cumsum(acc, axis=-1) * dt_s
    from scipy.integrate import cumulative_trapezoid  # here: scipy.integrate costs 0.8 s to import

    return cumulative_trapezoid(acc, dx=dt_s, axis=-1, initial=0.0)
