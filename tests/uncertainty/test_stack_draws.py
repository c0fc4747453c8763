"""A stack's draws (pipeline.uncertainty.stacks.drawn_stack): the declared lognormal factors on the bodies' heights,
widths (offsets with them) and friction, one factor each for all the bodies, the median draw the nominal stack."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pipeline.assemblies.stack import StackBody, StackPlace
from pipeline.uncertainty.settings import UncertaintyConfig
from pipeline.uncertainty.stacks import drawn_stack

PLACE = StackPlace((StackBody(0.7, 1.0, 3.0, 0.6), StackBody(0.45, 1.7, 2.0, 0.5, 0.05)), 1, ("P", "S"))


@pytest.mark.parametrize("row", [(0.0, 0.0, 1.3, -0.7, 0.4, 0.0), (0.2, -1.0, -2.0, 0.0, 0.0, 1.0)])
def test_a_draw_scales_every_body_by_the_same_factors(row):
    settings = UncertaintyConfig()
    got = drawn_stack(PLACE, np.array(row), settings)

    def factor(z, cov):                          # ln X ~ N(0, s^2), s^2 = ln(1 + cov^2): the settings' definition
        return math.exp(z * math.sqrt(math.log(1.0 + cov * cov)))

    fh, fw = factor(row[3], settings.size_cov), factor(row[4], settings.size_cov)
    fmu = factor(row[2], settings.friction_cov)
    for b, nominal in zip(got.bodies, PLACE.bodies):
        assert b.height_m == pytest.approx(nominal.height_m * fh, rel=1e-12)
        assert b.width_m == pytest.approx(nominal.width_m * fw, rel=1e-12)
        assert b.offset_m == pytest.approx(nominal.offset_m * fw, rel=1e-12, abs=0.0)
        assert b.mu == pytest.approx(nominal.mu * fmu, rel=1e-12)
        assert b.mass_kg == nominal.mass_kg


def test_the_median_draw_is_the_nominal_stack():
    assert drawn_stack(PLACE, np.zeros(6), UncertaintyConfig()) == PLACE
