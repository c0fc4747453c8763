"""Hypothesis property tests: the events the rocking kernel reads off a step's Hermite cubic, against a second
algorithm, the roots of the cubic's and of its rate's polynomials by numpy (the eigenvalues of their companion
matrices):

* ``first_crossing`` (the probes' bracket, then safeguarded Newton) is a root of the cubic inside the first probe
  interval where theta changes sign, where the cubic is not flat there to rounding;
* ``hermite_peak`` (the rate's root in closed form) is the cubic's largest |theta| at its turning point.
"""

from __future__ import annotations

import math

import numpy as np
from hypothesis import assume, example, given, settings
from hypothesis import strategies as st

from pipeline.rocking.numerics import dopri

magnitude = st.floats(min_value=-9.0, max_value=-1.0)
step = st.floats(min_value=-6.0, max_value=-1.0).map(lambda e: 10.0 ** e)


def _scaled(sign: float):
    return st.tuples(st.floats(min_value=0.1, max_value=3.0), magnitude).map(lambda v: sign * v[0] * 10.0 ** v[1])


rates = st.tuples(st.floats(min_value=-3.0, max_value=3.0), st.floats(min_value=-4.0, max_value=1.0)).map(
    lambda v: v[0] * 10.0 ** v[1])


def _cubic(th0, om0, th1, om1, h) -> np.ndarray:
    """The Hermite cubic's coefficients in x, highest first (expanding :func:`dopri.hermite`)."""
    a0, a1 = h * om0, h * om1
    return np.array([2 * th0 + a0 - 2 * th1 + a1, -3 * th0 - 2 * a0 + 3 * th1 - a1, a0, th0])


@settings(max_examples=300, deadline=None)            # the first example compiles
@given(_scaled(1.0), rates, _scaled(-1.0), rates, step)
def test_the_first_crossing_is_a_root_of_the_cubic_in_the_first_bracket(th0, om0, th1, om1, h):
    x = dopri.first_crossing(th0, om0, th1, om1, h, 1.0)
    assert 0.0 <= x <= 1.0                                # the step ends below 0: a crossing is found
    probes = np.arange(1, dopri.CROSSING_PROBES + 1) / dopri.CROSSING_PROBES
    values = np.array([dopri.hermite(th0, om0, th1, om1, h, p) for p in probes])
    k = int(np.argmax(values < 0.0))                       # the first probe below 0
    lo, hi = (probes[k - 1] if k else 0.0), probes[k]
    assert lo <= x <= hi
    scale = max(abs(th0), abs(th1), abs(h * om0), abs(h * om1))
    rate = dopri.hermite_rate(th0, om0, th1, om1, h, x)
    assume(abs(rate) > 1e-6 * scale)                       # a root the cubic's rounding does not blur
    roots = np.roots(_cubic(th0, om0, th1, om1, h))
    real = roots[np.abs(roots.imag) <= 1e-9].real
    near = real[(real >= lo - 1e-9) & (real <= hi + 1e-9)]
    # the root is known to the rounding of theta over the slope (and numpy's roots to about as much)
    assert near.size and np.min(np.abs(near - x)) <= 1e-12 + 1e-12 * scale / abs(rate)


@settings(max_examples=300, deadline=None)
@given(_scaled(1.0), rates, _scaled(1.0), rates, step, st.sampled_from([1.0, -1.0]))
@example(0.01, -5e-324, 0.001, 1.0, 0.1, 1.0)     # h omega0 a subnormal: the rate's root just below 0, not at it
def test_the_peak_is_the_cubics_value_at_its_turning_point(th0, om0, th1, om1, h, sign):
    th0, th1 = sign * th0, sign * th1
    assume(om0 * om1 < 0.0)
    peak = dopri.hermite_peak(th0, om0, th1, om1, h)
    rate = np.polyder(_cubic(th0, om0, th1, om1, h))
    turning = [r.real for r in np.roots(rate) if abs(r.imag) <= 1e-12 and -1e-12 <= r.real <= 1 + 1e-12]
    expected = max([abs(th0), abs(th1)] + [abs(dopri.hermite(th0, om0, th1, om1, h, min(max(x, 0.0), 1.0)))
                                           for x in turning])
    assert math.isclose(peak, expected, rel_tol=1e-9, abs_tol=1e-15 * max(abs(th0), abs(th1)))
