"""Property tests of the 3D cylinder over random sizes, friction and two-component ground motions: axisymmetry (the
record rotated, the motion rotated with it), mirror symmetry (the record reflected, the motion reflected), the
similitude of time (a cylinder scaled by s^2 under the record slowed by s behaves alike), and that every run ends
with a verdict or a flag within its caps."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import HealthCheck, event, example, given, settings
from hypothesis import strategies as st

from pipeline.constants import G
from pipeline.rocking.solids.cylinder3d import FLAG_NONE, FLAG_STEPS, Cylinder, housner_e, simulate_cylinder

#: 25 cases each, the same in every run (derandomized): CI judges a fixed set, the cases found are kept as examples
SETTINGS = settings(max_examples=25, deadline=None, derandomize=True,
                    suppress_health_check=[HealthCheck.too_slow])
#: Below this peak tilt (fraction of alpha) a run stays near the vertical, where the tilt's azimuth spins up (the
#: rolling disk's finite-time singularity) and the model's flags and tiny tilts depend on roundoff (a documented
#: weakness, docs/validation.md): there the properties are asserted only as "no verdict contradicts another"
NEAR_VERTICAL_ALPHA = 1e-3
DT = 0.01

radii = st.floats(0.05, 0.5)
slender = st.floats(2.0, 8.0)                 # h / a
mus = st.floats(0.3, 1.2)
seeds = st.integers(0, 2**31 - 1)
levels = st.floats(0.8, 3.0)                  # peak |a_h| over g tan alpha


def _motion(seed: int, level: float, tan_alpha: float, n: int = 300) -> tuple[np.ndarray, np.ndarray]:
    """Two smooth random horizontal components (a sum of a few sines), scaled to ``level`` g tan(alpha)."""
    rng = np.random.default_rng(seed)
    t = np.arange(n) * DT
    comps = []
    for _ in range(2):
        f, ph, amp = rng.uniform(0.3, 3.0, 3), rng.uniform(0, 2 * np.pi, 3), rng.uniform(0.2, 1.0, 3)
        comps.append(np.sum(amp[:, None] * np.sin(2 * np.pi * f[:, None] * t + ph[:, None]), axis=0))
    ax, ay = comps
    peak = np.max(np.hypot(ax, ay))
    return level * G * tan_alpha * ax / peak, level * G * tan_alpha * ay / peak


def _comparable(one, two, alpha: float) -> bool:
    """Whether two runs that should agree are held to full agreement: neither flagged (a flag is no verdict) and
    one of them past the near-vertical band. Otherwise only this holds: neither reached the step cap, and two
    verdicts never contradict (a flagged run has none)."""
    assert FLAG_STEPS not in (one.flag, two.flag)
    if one.flag == FLAG_NONE and two.flag == FLAG_NONE:
        if max(one.theta_max_rad, two.theta_max_rad) >= NEAR_VERTICAL_ALPHA * alpha:
            event("held to full agreement")
            return True
        assert not one.overturned and not two.overturned
    event("near the vertical, or flagged: no contradiction only")
    return False


def _cylinder(a: float, ratio: float, mu: float) -> Cylinder:
    return Cylinder(radius_m=a, half_height_m=a * ratio, mu=mu, restitution=housner_e(a, a * ratio))


@SETTINGS
@given(a=radii, ratio=slender, mu=mus, seed=seeds, level=levels, beta=st.floats(0.0, 2 * math.pi))
@example(a=0.5, ratio=2.0, mu=1.0, seed=1_825_113_676, level=1.03125, beta=1.0)     # found: near the vertical
@example(a=0.5, ratio=2.0, mu=1.0, seed=76, level=1.03125, beta=1.0)                # found: a flag there
def test_rotating_the_record_rotates_the_motion(a, ratio, mu, seed, level, beta):
    c = _cylinder(a, ratio, mu)
    ax, ay = _motion(seed, level, 1.0 / ratio)
    one = simulate_cylinder(ax, ay, None, DT, c)
    cb, sb = math.cos(beta), math.sin(beta)
    two = simulate_cylinder(cb * ax - sb * ay, sb * ax + cb * ay, None, DT, c)
    alpha = math.atan2(a, a * ratio)
    if not _comparable(one, two, alpha):
        return
    assert one.overturned == two.overturned and one.impacts == two.impacts
    assert abs(one.theta_max_rad - two.theta_max_rad) < 1e-5 * alpha


@SETTINGS
@given(a=radii, ratio=slender, mu=mus, seed=seeds, level=levels)
def test_reflecting_the_record_reflects_the_motion(a, ratio, mu, seed, level):
    """y -> -y: the same tilt history, the azimuth of the tilt reflected."""
    c = _cylinder(a, ratio, mu)
    ax, ay = _motion(seed, level, 1.0 / ratio)
    one = simulate_cylinder(ax, ay, None, DT, c)
    two = simulate_cylinder(ax, -ay, None, DT, c)
    alpha = math.atan2(a, a * ratio)
    if not _comparable(one, two, alpha):
        return
    assert one.overturned == two.overturned
    assert np.nanmax(np.abs(one.theta - two.theta)) < 1e-5 * alpha
    moving = one.theta > 1e-3 * alpha
    assert np.max(np.abs(np.sin(one.azimuth[moving] + two.azimuth[moving])), initial=0.0) < 1e-4


@SETTINGS
@given(a=radii, ratio=slender, mu=mus, seed=seeds, level=levels, s=st.floats(1.2, 3.0))
@example(a=0.5, ratio=2.0, mu=1.0, seed=1_459_203_549, level=1.53125, s=1.5)
def test_a_cylinder_scaled_by_s_squared_under_the_record_slowed_by_s_behaves_alike(a, ratio, mu, seed, level, s):
    """Similitude: lengths x s^2 and time x s leave accelerations and angles alike (p scales as 1/s). Where both
    runs end unflagged they agree; a flag may differ, never a verdict. The example is the case Hypothesis found:
    near the vertical, where the tilt's azimuth spins up (the rolling disk's finite-time singularity), the contact
    force loses its digits and the friction check flagged the scaled run at a tilt of 3e-6 rad (no verdict) while
    the other rocked to 0.1 rad (docs/validation.md)."""
    c = _cylinder(a, ratio, mu)
    big = _cylinder(a * s * s, ratio, mu)
    ax, ay = _motion(seed, level, 1.0 / ratio)
    one = simulate_cylinder(ax, ay, None, DT, c)
    two = simulate_cylinder(ax, ay, None, DT * s, big)
    alpha = math.atan2(a, a * ratio)
    if _comparable(one, two, alpha):
        assert one.overturned == two.overturned
        assert abs(one.theta_max_rad - two.theta_max_rad) < 1e-4 * alpha


@SETTINGS
@given(a=radii, ratio=slender, mu=mus, seed=seeds, level=st.floats(0.5, 6.0))
def test_every_run_ends_with_a_verdict_or_a_flag(a, ratio, mu, seed, level):
    c = _cylinder(a, ratio, mu)
    ax, ay = _motion(seed, level, 1.0 / ratio)
    out = simulate_cylinder(ax, ay, 0.3 * ax, DT, c)
    assert out.flag != FLAG_STEPS
    assert out.overturned or out.flag != FLAG_NONE or out.theta_max_rad < math.pi / 2
    assert np.all(np.isfinite(out.theta[: int(out.t_overturn_s / DT)] if out.overturned else
                              out.theta[np.isfinite(out.theta)]))
