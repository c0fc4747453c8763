"""The toppling rate of each branch against OpenQuake's own ``classical_damage`` (openquake-engine, a test extra:
skipped loudly where it is not installed, as it cannot be installed beside this project from the package index).

OpenQuake sums the fragility at each level times the annual frequency of occurrence between the midpoints of the
levels; rockscreen integrates the curve log-log between its points. Given the branch's curve on OpenQuake's
own levels the two differ by OpenQuake's midpoint sum (1-6 % on the example's 50 levels, measured); given the same
curve refined 40 times (log-log), OpenQuake's sum converges to rockscreen's integral, within 0.1 %. Above the last
level OpenQuake counts nothing; rockscreen counts the exceedances of the last level at the fragility there
(P(C | im_max) lambda(im_max), a lower bound of their share): that term is added to OpenQuake's sum here.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest
from scipy.stats import norm

from pipeline.constants import G
from pipeline.uncertainty.branches import read_branches
from pipeline.uncertainty.hazard import annual_rates

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "constrain" / "openquake"

#: Each level interval of the branch's curve split into this many (log-log) for OpenQuake's sum
REFINE = 40


def classical_damage():
    try:
        from openquake.risklib.scientific import classical_damage as oq
    except ImportError:
        message = ("OPENQUAKE-ENGINE IS NOT INSTALLED: the toppling rates were NOT checked against OpenQuake's "
                   "classical_damage. Install it in this environment (pip install openquake-engine, with GDAL) to "
                   "run this check.")
        print(f"\n{'!' * 80}\n{message}\n{'!' * 80}", file=sys.stderr)
        pytest.skip(message)
    return oq


@pytest.mark.slow
@pytest.mark.parametrize("theta_g, beta", [(0.21, 0.42), (0.05, 0.3), (0.8, 0.6)])
def test_each_branch_s_rate_equals_openquake_s_classical_damage(theta_g, beta):
    oq = classical_damage()
    tree = read_branches(EXAMPLE, im="pga")
    for curve in tree.curves:
        ln = np.log(curve.levels)
        fine = np.exp(np.interp(np.linspace(0, 1, (ln.size - 1) * REFINE + 1), np.linspace(0, 1, ln.size), ln))
        rates = np.exp(np.interp(np.log(fine), ln, np.log(curve.rates)))
        poes = -np.expm1(-rates)                                      # one year, as OpenQuake's curves
        fragility = [lambda x: norm.cdf(np.log(np.asarray(x) / theta_g) / beta)]
        theirs = -np.log(oq(fragility, fine / G, poes, 1.0, 1.0)[0])    # P(no damage) in a year -> rate
        theirs += fragility[0](fine[-1] / G) * rates[-1]                # the tail above the last level (below)
        ours = annual_rates([curve], [theta_g * G], [beta])[0, 0]
        assert ours == pytest.approx(theirs, rel=1e-3)
