"""One explicit embedded Runge-Kutta step for every ODE model of the package, its method's coefficients as data.

For y' = f(t, y), a step of length h from (t, y) with the stages

    k_1 = f(t, y)                       (given: the last step's k_s, "first same as last")
    k_i = f(t + c_i h, y + h sum_{j<i} a_ij k_j),      i = 2 .. s - 1
    y_1 = y + h sum_j b_j k_j
    k_s = f(t + h, y_1)
    err = h sum_j e_j k_j               (e = b - b^*, the embedded lower-order solution's difference)

as scipy's ``integrate/_ivp/rk.py`` writes ``rk_step`` with each method's tableau as class attributes. The model's
right-hand side is passed in, compiled: ``fun(t, y, args, out)`` writes f into ``out`` and returns what the model
wants kept at the step's end (the contact forces of the 3D models, the pivot's sin and cos of the planar one).

References
----------
Dormand, J. R. & Prince, P. J. (1980). A family of embedded Runge-Kutta formulae. J. Comput. Appl. Math.
6(1), 19-26.
Hairer, E., Norsett, S. P. & Wanner, G. (1993). Solving Ordinary Differential Equations I, 2nd ed., Springer,
section II.5 (embedded formulae, Table 5.2: DOPRI5).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ...compiled import jit_inline

# The step-size control of the 3D models, named once (as scipy's _ivp names its step factors): the next step is
# h SAFETY err^ERROR_EXPONENT (the error of order 4 of DOPRI54 over the tolerance), within the factors below
SAFETY = 0.9                    # the step-size controller's safety factor
MIN_FACTOR, MAX_FACTOR = 0.2, 5.0
ERROR_EXPONENT = -0.2           # -1 / (4 + 1)


class Tableau(NamedTuple):
    """An embedded explicit Runge-Kutta method (its Butcher tableau).

    Attributes
    ----------
    nodes : ndarray, shape (s - 1,)
        c_2 .. c_s [-] (c_1 = 0)
    rows : ndarray, shape (s - 2, s - 2)
        a_ij of stages 2 .. s - 1, row i - 2 (zeros beyond the diagonal)
    b : ndarray, shape (s,)
        the weights of the solution kept
    e : ndarray, shape (s,)
        the weights of the error estimate
    """

    nodes: np.ndarray
    rows: np.ndarray
    b: np.ndarray
    e: np.ndarray


#: Dormand & Prince (1980) RK5(4)7M, first same as last (7 stages, the 7th at the new point).
DOPRI54 = Tableau(
    nodes=np.array([1 / 5, 3 / 10, 4 / 5, 8 / 9, 1.0]),
    rows=np.array([[1 / 5, 0.0, 0.0, 0.0, 0.0],
                   [3 / 40, 9 / 40, 0.0, 0.0, 0.0],
                   [44 / 45, -56 / 15, 32 / 9, 0.0, 0.0],
                   [19372 / 6561, -25360 / 2187, 64448 / 6561, -212 / 729, 0.0],
                   [9017 / 3168, -355 / 33, 46732 / 5247, 49 / 176, -5103 / 18656]]),
    b=np.array([35 / 384, 0.0, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84, 0.0]),
    e=np.array([71 / 57600, 0.0, -71 / 16695, 71 / 1920, -17253 / 339200, 22 / 525, -1 / 40]),
)


@jit_inline
def rk_step(fun, args, t, y, h, k, tmp, y_new, err, tableau):
    """One step of ``tableau`` of length ``h`` [s] from ``(t, y)`` for the model ``fun`` (with its ``args``):
    ``k[0]`` holds f at the start; the solution in ``y_new``, the error estimate in ``err``, every stage's f in
    ``k`` (f at the end in its last row); ``tmp`` is room for a stage's state. Returns what ``fun`` returns at the
    step's end."""
    n, stages = y.shape[0], tableau.b.shape[0]
    for s in range(stages - 2):
        for q in range(n):
            acc = 0.0
            for j in range(s + 1):
                acc += tableau.rows[s, j] * k[j, q]
            tmp[q] = y[q] + h * acc
        fun(t + tableau.nodes[s] * h, tmp, args, k[s + 1])
    for q in range(n):
        acc = 0.0
        for j in range(stages - 1):
            acc += tableau.b[j] * k[j, q]
        y_new[q] = y[q] + h * acc
    kept = fun(t + h, y_new, args, k[stages - 1])
    for q in range(n):
        acc = 0.0
        for j in range(stages):
            acc += tableau.e[j] * k[j, q]
        err[q] = h * acc
    return kept


@jit_inline
def rejected_step(h, norm):
    """The step to retry after a step of ``h`` [s] whose error over the tolerance was ``norm`` > 1 (NaN: the
    smallest factor)."""
    return h * max(MIN_FACTOR, SAFETY * norm ** ERROR_EXPONENT) if norm == norm else h * MIN_FACTOR


@jit_inline
def next_step(h, norm):
    """The step after an accepted step of ``h`` [s] whose error over the tolerance was ``norm`` <= 1."""
    return h * (MAX_FACTOR if norm == 0.0 else min(MAX_FACTOR, SAFETY * norm ** ERROR_EXPONENT))
