"""Property: wherever the other-axis certificate holds (pipeline.rocking.solids.box_planar), the 3D box (a second
algorithm) never leaves the edges of its depth axis, never slides, and stands as the planar scene does, on random
boxes under random two-component pulses with a vertical."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import event, given, settings
from hypothesis import strategies as st

from pipeline.rocking.solids.box3d import Box, simulate_box
from pipeline.rocking.solids.box_planar import planar_box_scene, width_block

G = 9.80665
DT = 0.005
N = 1000


def _pulse(amplitude_g: float, period_s: float, start_s: float) -> np.ndarray:
    t = np.arange(N) * DT - start_s
    return np.where((t >= 0) & (t < period_s), amplitude_g * G * np.sin(2 * np.pi * t / period_s), 0.0)


@settings(max_examples=80, deadline=None)
@given(h=st.floats(0.5, 3.0), alpha_deg=st.floats(6.0, 30.0), d_over_w=st.floats(0.4, 5.0), mu=st.floats(0.55, 1.0),
       ax_f=st.floats(1.02, 3.0), tx=st.floats(0.2, 1.2), ay_f=st.floats(0.0, 0.9), ty=st.floats(0.2, 1.2),
       shift=st.floats(0.0, 0.5), av_g=st.floats(-0.3, 0.3))
def test_certified_means_the_3d_box_stays_on_the_edges(h, alpha_deg, d_over_w, mu, ax_f, tx, ay_f, ty, shift, av_g):
    tan_a = math.tan(math.radians(alpha_deg))
    w = h * tan_a
    ax_g, ay_g = ax_f * tan_a, ay_f * d_over_w * tan_a         # as factors on the thresholds of uplift at rest
    box = Box(half_width_m=w / 2, half_depth_m=d_over_w * w / 2, half_height_m=h / 2, mu=mu)
    along, across, vertical = _pulse(ax_g, tx, 0.0), _pulse(ay_g, ty, shift), _pulse(av_g, 0.3, 0.1)
    cs = planar_box_scene(along, -across, vertical, DT, box, 0.0)
    event(f"certified {cs.other_axis.certified}, rocks {cs.scene is not None and cs.scene.theta_max > 0}")
    if not cs.other_axis.certified:
        return
    assert cs.scene is not None
    out = simulate_box(along, across, vertical, DT, box, azimuth_deg=0.0, rtol=1e-9, atol_alpha=1e-10)
    assert out.corner_s == 0.0 and out.flag == 0
    assert not out.overturned and not cs.scene.overturned
    assert abs(out.theta_max_rad / width_block(box).alpha - cs.scene.theta_max) < 1e-3
