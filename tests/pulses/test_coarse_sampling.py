"""A record sampled too coarsely for the pulse search is named, not a traceback: the smallest wavelet scale of the
search from Tp = 0.25 s is floor(0.25 / 1.4 / dt), below one sample for dt > 0.18 s (Shahi & Baker 2014's grid)."""

from __future__ import annotations

import pytest

from pipeline.errors import PulseError
from pipeline.pulses.cwt import scales_for


@pytest.mark.parametrize("dt_s", [0.2, 1.0])
def test_a_sampling_too_coarse_for_the_shortest_pulse_is_named_with_the_fix(dt_s):
    with pytest.raises(PulseError, match=rf"dt = {dt_s:g} s is too coarse.*tp_min_s"):
        scales_for(dt_s)


def test_the_coarsest_sampling_the_search_takes():
    assert scales_for(0.25 / 1.4)[0] == 1
