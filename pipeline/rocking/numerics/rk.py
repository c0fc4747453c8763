"""One explicit Runge-Kutta step for every ODE model of the package, its method's coefficients as data.

For y' = f(t, y), a step of length h from (t, y) with the stages

    k_1 = f(t, y)                       (given: a method "first same as last" has it from the last step's k_s)
    k_i = f(t + c_i h, y + h sum_{j<i} a_ij k_j),      i = 2 .. r + 1   (the tableau's r rows)
    y_1 = y + h sum_{j <= r + 1} b_j k_j
    k_s = f(t + h, y_1)                 (first same as last only: s = r + 2 weights, b_s = 0)
    err = h sum_j e_j k_j               (e = b - b^*, the embedded lower-order solution's difference; 0 without one)

as scipy's ``integrate/_ivp/rk.py`` writes ``rk_step`` with each method's tableau as class attributes. The state is
a tuple of floats, so that the compiled step makes no array whatever its size (a plane's two states, a box's seven;
measured at par with a step written out over a plane's two scalars, docs/validation.md). The model's right-hand side
is passed in, compiled: ``fun(t, y, args)`` returns f (a tuple like ``y``) and what the model wants kept at the
step's end (the contact forces of the 3D models, the pivot's sin and cos of the planar one). Every sum runs over j
in order from 0.0, so that a step gives the same doubles wherever it is called.

References
----------
Dormand, J. R. & Prince, P. J. (1980). A family of embedded Runge-Kutta formulae. J. Comput. Appl. Math.
6(1), 19-26.
Hairer, E., Norsett, S. P. & Wanner, G. (1993). Solving Ordinary Differential Equations I, 2nd ed., Springer,
section II.1 (Table 1.2: the classical method) and II.5 (embedded formulae, Table 5.2: DOPRI5).
Kutta, W. (1901). Beitrag zur naeherungsweisen Integration totaler Differentialgleichungen. Z. Math. Phys. 46,
435-453.
"""

from __future__ import annotations

from typing import NamedTuple

from ...compiled import filled_like, jit_inline, tuple_with

# The step-size control of the 3D models, named once (as scipy's _ivp names its step factors): the next step is
# h SAFETY err^ERROR_EXPONENT (the error of order 4 of DOPRI54 over the tolerance), within the factors below
SAFETY = 0.9                    # the step-size controller's safety factor
MIN_FACTOR, MAX_FACTOR = 0.2, 5.0
ERROR_EXPONENT = -0.2           # -1 / (4 + 1)


class Tableau(NamedTuple):
    """An explicit Runge-Kutta method, embedded or not (its Butcher tableau), as tuples (constants of the compiled
    step).

    Attributes
    ----------
    nodes : tuple of float, length r
        c_2 .. c_{r+1} [-] (c_1 = 0; a method first same as last has its last stage at c_s = 1)
    rows : tuple of tuples of float, r x r
        a_ij of stages 2 .. r + 1, row i - 2 (zeros beyond the diagonal)
    b : tuple of float, length s (r + 1, or r + 2 for a method first same as last, its last weight 0)
        the weights of the solution kept
    e : tuple of float, length s
        the weights of the error estimate (zeros for a method without one)
    """

    nodes: tuple
    rows: tuple
    b: tuple
    e: tuple


#: Dormand & Prince (1980) RK5(4)7M, first same as last (7 stages, the 7th at the new point).
DOPRI54 = Tableau(
    nodes=(1 / 5, 3 / 10, 4 / 5, 8 / 9, 1.0),
    rows=((1 / 5, 0.0, 0.0, 0.0, 0.0),
          (3 / 40, 9 / 40, 0.0, 0.0, 0.0),
          (44 / 45, -56 / 15, 32 / 9, 0.0, 0.0),
          (19372 / 6561, -25360 / 2187, 64448 / 6561, -212 / 729, 0.0),
          (9017 / 3168, -355 / 33, 46732 / 5247, 49 / 176, -5103 / 18656)),
    b=(35 / 384, 0.0, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84, 0.0),
    e=(71 / 57600, 0.0, -71 / 16695, 71 / 1920, -17253 / 339200, 22 / 525, -1 / 40),
)

#: The classical Runge-Kutta method of order 4 (Kutta 1901; Hairer et al. 1993, Table 1.2), without an error
#: estimate: for the fixed steps of the planar contact model.
RK4 = Tableau(
    nodes=(1 / 2, 1 / 2, 1.0),
    rows=((1 / 2, 0.0, 0.0),
          (0.0, 1 / 2, 0.0),
          (0.0, 0.0, 1.0)),
    b=(1 / 6, 1 / 3, 1 / 3, 1 / 6),
    e=(0.0, 0.0, 0.0, 0.0),
)


class Step(NamedTuple):
    """What one step returns.

    Attributes
    ----------
    y : tuple of float
        the solution at t + h (the higher order)
    err : tuple of float
        the error estimate of ``y``, per state
    f : tuple of float
        a method first same as last: f(t + h, y), the next step's first stage; otherwise the last stage's f
    kept : object
        what the model's right-hand side returned beside f at its last evaluation (first same as last: at t + h)
    """

    y: tuple
    err: tuple
    f: tuple
    kept: object


@jit_inline
def _combined(y, h, weights, stages, count):
    """y + h sum_{j < count} weights_j stages_j, per state (the sum from 0.0, in j's order)."""
    out = y
    for q in range(len(y)):
        acc = 0.0
        for j in range(count):
            acc += weights[j] * stages[j][q]
        out = tuple_with(out, q, y[q] + h * acc)
    return out


@jit_inline
def _weighted(h, weights, stages):
    """h sum_j weights_j stages_j, per state (the sum from 0.0, in j's order)."""
    out = stages[0]
    for q in range(len(out)):
        acc = 0.0
        for j in range(len(weights)):
            acc += weights[j] * stages[j][q]
        out = tuple_with(out, q, h * acc)
    return out


@jit_inline
def rk_step(fun, args, t, y, f, h, tableau):
    """One step of ``tableau`` of length ``h`` [s] from ``(t, y)`` for the model ``fun`` with its ``args``, ``f``
    being f(t, y); returns a :class:`Step`."""
    stages = filled_like(f, tableau.b)
    for s in range(len(tableau.rows)):
        y_s = _combined(y, h, tableau.rows[s], stages, s + 1)
        f_s, kept = fun(t + tableau.nodes[s] * h, y_s, args)
        stages = tuple_with(stages, s + 1, f_s)
    solved = len(tableau.rows) + 1
    y_new = _combined(y, h, tableau.b, stages, solved)
    f_new = stages[solved - 1]
    if len(tableau.b) > solved:                     # first same as last: the last stage is f at the new point
        f_new, kept = fun(t + h, y_new, args)
        stages = tuple_with(stages, solved, f_new)
    return Step(y_new, _weighted(h, tableau.e, stages), f_new, kept)


@jit_inline
def rejected_step(h, norm):
    """The step to retry after a step of ``h`` [s] whose error over the tolerance was ``norm`` > 1 (NaN: the
    smallest factor)."""
    return h * max(MIN_FACTOR, SAFETY * norm ** ERROR_EXPONENT) if norm == norm else h * MIN_FACTOR


@jit_inline
def next_step(h, norm):
    """The step after an accepted step of ``h`` [s] whose error over the tolerance was ``norm`` <= 1."""
    return h * (MAX_FACTOR if norm == 0.0 else min(MAX_FACTOR, SAFETY * norm ** ERROR_EXPONENT))
