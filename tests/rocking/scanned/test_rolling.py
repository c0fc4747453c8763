"""A scanned body rolling on its convex hull (pipeline.shapes.hull, pipeline.rocking.scanned.rolling) against
independent truth: a rectangle's chain is its two corners, and it rocks as Housner's block in the planar rocking kernel
(same
verdicts and peaks); a rocker with a circular base under a constant push reaches the tilt at which the push's work
equals the potential energy gained (rolling without slip, closed form); uplift at the base pivot's threshold
exactly; mirror symmetry of a real scan."""

from __future__ import annotations

import math

import numpy as np
import pytest
from planar_reference import DT, PULSES, RECTANGLE, G, housner_block, pulse
from scipy.optimize import brentq

from pipeline.rocking.codes import STATUS_GROUND_FLIGHT
from pipeline.rocking.scanned.rolling import roll_on_hull
from pipeline.shapes.hull import chain_from_outline, hull_chain, rectangle_chain


def test_a_rectangles_chain_is_its_two_corners():
    ch = rectangle_chain(0.3, 1.5)
    np.testing.assert_allclose(ch.pivots_m, [[-0.15, -0.75], [0.15, -0.75]])
    np.testing.assert_allclose(ch.bounds_rad, [-math.pi / 2, 0.0, math.pi / 2])
    assert ch.rest == 1 and ch.inertia_m2 == pytest.approx((0.3 ** 2 + 1.5 ** 2) / 12)


def test_a_chain_of_one_pivot_per_side_is_the_footprints_two_sided_body(scans_dir):
    """pipeline.shapes.plane.chain_plane (the hull's two pivots) against plane_body (the footprint's extremes, a
    second path) for a box given as a mesh, in planes across and along it and oblique."""
    pytest.importorskip("trimesh")
    from pipeline.shapes.plane import chain_plane, plane_body
    from pipeline.shapes.scan import read_scan

    shape = read_scan(scans_dir / "box-0.3x3.0x1.5.obj")
    for az in (0.0, 90.0, 180.0, 30.0):
        chain = hull_chain(shape, az)
        assert len(chain.pivots_m) == 2
        np.testing.assert_allclose(chain_plane(chain), plane_body(shape, az), atol=1e-9)
    with pytest.raises(ValueError, match="not one pivot per side"):
        chain_plane(chain_from_outline(_rocker(0.3, 0.2, facets=40), 0.01, 0.01))


def test_a_box_is_a_uniform_rectangle_in_its_base_planes_and_a_cylinder_never(scans_dir, tmp_path):
    """rectangle_section: a box mesh is its width x height rectangle across, its depth x height along, and no
    rectangle obliquely (its outline there is a rectangle, its inertia not that rectangle's); an upright cylinder's
    outline is a rectangle in every plane, its inertia never a uniform rectangle's."""
    trimesh = pytest.importorskip("trimesh")
    from pipeline.rocking.scanned.planes import RectangleSection, rectangle_section
    from pipeline.shapes.scan import read_scan

    box = read_scan(scans_dir / "box-0.3x3.0x1.5.obj")
    for az, expected in ((0.0, (0.3, 1.5)), (180.0, (0.3, 1.5)), (90.0, (3.0, 1.5)), (270.0, (3.0, 1.5))):
        got = rectangle_section(hull_chain(box, az))
        assert isinstance(got, RectangleSection) and got == pytest.approx(expected, rel=1e-9)
    assert rectangle_section(hull_chain(box, 30.0)) is None
    cyl = trimesh.creation.cylinder(radius=0.2, height=1.0, sections=256)
    cyl.apply_translation([0.0, 0.0, 0.5])
    cyl.export(tmp_path / "cyl.stl")
    shape = read_scan(tmp_path / "cyl.stl")
    for az in (0.0, 45.0):
        chain = hull_chain(shape, az)
        assert len(chain.pivots_m) == 2 and rectangle_section(chain) is None


def test_a_box_given_as_a_mesh_has_the_rectangles_chain(scans_dir):
    pytest.importorskip("trimesh")
    from pipeline.shapes.scan import read_scan

    shape = read_scan(scans_dir / "box-0.3x3.0x1.5.obj")
    for az, width in ((0.0, 0.3), (90.0, 3.0), (180.0, 0.3)):
        ours, closed = hull_chain(shape, az), rectangle_chain(width, 1.5)
        np.testing.assert_allclose(ours.pivots_m, closed.pivots_m, atol=1e-9)
        np.testing.assert_allclose(ours.bounds_rad, closed.bounds_rad, atol=1e-9)
        assert ours.inertia_m2 == pytest.approx(closed.inertia_m2, rel=1e-6)


@pytest.mark.parametrize("amp_g,period_s", PULSES)
def test_a_rectangle_rolls_as_the_planar_kernels_block(amp_g, period_s):
    a, alpha = pulse(amp_g, period_s), math.atan2(RECTANGLE[0], RECTANGLE[1])
    ours = roll_on_hull(a, DT, rectangle_chain(*RECTANGLE))
    ref = housner_block(a, *RECTANGLE)
    assert ours.overturned == ref.overturned and ours.verdict == int(ref.overturned)
    if not ours.overturned:
        assert ours.theta_max / alpha == pytest.approx(ref.theta_max, abs=1e-4)


HALF_ARC = math.radians(80.0)


def _rocker(radius_m, drop_m, *, facets, half_arc=HALF_ARC):
    """A body whose base is a circular arc of radius ``radius_m`` centred ``drop_m`` above G, closed by a chord:
    its outline relative to G, counter-clockwise, a vertex straight below G."""
    step = 2 * half_arc / facets
    angles = -math.pi / 2 - half_arc + step * np.arange(facets + 1)
    return np.column_stack([radius_m * np.cos(angles), drop_m + radius_m * np.sin(angles)])


@pytest.mark.parametrize("radius_m,drop_m,push_g", [(0.3, 0.2, 0.1), (0.5, 0.3, 0.15), (0.2, 0.15, 0.3)])
def test_a_rocker_reaches_the_tilt_where_the_pushs_work_equals_the_potential_gained(radius_m, drop_m, push_g):
    """Rolling without slip on a circle of radius r with G a distance d below its centre, under a constant
    ground acceleration -a: G rises by d (1 - cos theta) and moves r theta - d sin theta with the push, so the first
    peak solves g d (1 - cos theta) = a (r theta - d sin theta). The facets between the arc's vertices keep the
    energy, as the circle would: the polygon's peak converges to the circle's as the facets shrink."""
    a = np.full(1000, -push_g * G)

    def work_minus_potential(th):
        return push_g * (radius_m * th - drop_m * math.sin(th)) - drop_m * (1 - math.cos(th))

    peak = brentq(work_minus_potential, 1e-3, math.radians(79.0))
    errors = []
    for facets in (2000, 20000):
        got = roll_on_hull(a, DT, chain_from_outline(_rocker(radius_m, drop_m, facets=facets), 0.01, 0.01))
        assert not got.overturned and got.status == 0
        errors.append(abs(got.theta_max / peak - 1.0))
    assert errors[1] < 5e-3 and errors[1] < errors[0] / 4 + 1e-4, errors


@pytest.mark.parametrize("side", [1.0, -1.0])
def test_uplift_at_the_base_pivots_threshold_exactly(side):
    outline = np.array([[-0.1, -0.5], [0.2, -0.5], [0.25, 0.3], [-0.15, 0.4]])
    chain = chain_from_outline(outline, 0.025, 0.025)
    u, z = chain.pivots_m[chain.rest if side > 0 else chain.rest - 1]
    threshold = abs(u) / -z
    at = roll_on_hull(np.full(400, -side * G * threshold), DT, chain)
    assert at.theta_max == 0.0 and at.n_pivot_changes == 0
    above = roll_on_hull(np.full(400, -side * G * threshold * (1 + 1e-6)), DT, chain)
    assert above.theta_max > 0.0


def test_a_scan_rolls_the_same_seen_from_the_other_side(scans_dir):
    pytest.importorskip("trimesh")
    from pipeline.shapes.scan import read_scan

    shape = read_scan(scans_dir / "balanced-rock.obj")
    a = pulse(0.35, 0.6)
    for az in (0.0, 40.0, 115.0):
        one, other = hull_chain(shape, az), hull_chain(shape, az + 180.0)
        np.testing.assert_allclose(other.pivots_m[::-1] * [-1.0, 1.0], one.pivots_m, atol=1e-12)
        r1, r2 = roll_on_hull(a, DT, one), roll_on_hull(-a, DT, other)
        assert r1.overturned == r2.overturned and r1.theta_max == pytest.approx(r2.theta_max, rel=1e-9, abs=1e-12)
        assert r1.theta_max_plus == pytest.approx(r2.theta_max_minus, rel=1e-9, abs=1e-12)   # each side's peak
        assert r1.theta_max_minus == pytest.approx(r2.theta_max_plus, rel=1e-9, abs=1e-12)
        assert r1.theta_max == max(r1.theta_max_plus, r1.theta_max_minus)
        assert one.tipping_rad() == pytest.approx(other.tipping_rad()[::-1], abs=1e-12)


@pytest.mark.parametrize("name", ["balanced-rock.obj", "leaning-statue.obj"])
def test_the_chains_tipping_angles_are_the_scans_bisected_ones(scans_dir, name):
    """HullChain.tipping_rad (G over the pivot of the chain's interval) against pipeline.shapes.scan.pivots (a
    second algorithm: the tilt at which G passes over the hull's lowest point, bracketed on a grid and bisected)."""
    pytest.importorskip("trimesh")
    from pipeline.shapes.scan import pivots, read_scan

    shape = read_scan(scans_dir / name)
    for az in (0.0, 35.0, 90.0, 200.0, 290.0):
        plus, minus = hull_chain(shape, az).tipping_rad()
        piv = pivots(shape, az)
        assert plus == pytest.approx(piv.tipping_plus, abs=1e-6) and minus == pytest.approx(piv.tipping_minus,
                                                                                             abs=1e-6)


@pytest.mark.parametrize("restitution", [0.5, 0.8, 0.95])
def test_a_declared_restitution_is_a_rectangles_landing_ratio(restitution):
    """The factor on the landing ratio makes a rectangle's landing keep the declared ratio, as the planar kernel's
    restitution does; the rule's own ratio is Housner's 1 - 3/2 sin^2 alpha."""
    from pipeline.rocking.scanned.planes import restitution_factor
    from pipeline.rocking.scanned.rolling import landing_ratio

    chain = rectangle_chain(*RECTANGLE)
    alpha = math.atan(RECTANGLE[0] / RECTANGLE[1])
    for onto_plus in (True, False):
        assert landing_ratio(chain, onto_plus=onto_plus) == pytest.approx(1 - 1.5 * math.sin(alpha) ** 2, rel=1e-12)
        assert (landing_ratio(chain, onto_plus=onto_plus) * restitution_factor(chain, restitution)
                == pytest.approx(restitution, rel=1e-12))
    assert restitution_factor(chain, math.nan) == 1.0


@pytest.mark.parametrize("fw,fh", [(1.2, 0.9), (0.8, 1.1)])
def test_a_scaled_chain_is_the_scaled_bodys(fw, fh):
    w, h = RECTANGLE
    got, closed = rectangle_chain(w, h).scaled(width_factor=fw, height_factor=fh), rectangle_chain(w * fw, h * fh)
    np.testing.assert_allclose(got.pivots_m, closed.pivots_m, atol=1e-12)
    np.testing.assert_allclose(got.bounds_rad, closed.bounds_rad, atol=1e-12)
    assert got.inertia_m2 == pytest.approx(closed.inertia_m2, rel=1e-12)
    outline = _rocker(0.3, 0.2, facets=40)
    stretched = chain_from_outline(outline * [fw, fh], 0.01 * fw ** 2, 0.02 * fh ** 2)
    scaled = chain_from_outline(outline, 0.01, 0.02).scaled(width_factor=fw, height_factor=fh)
    np.testing.assert_allclose(scaled.pivots_m, stretched.pivots_m, atol=1e-12)
    np.testing.assert_allclose(scaled.bounds_rad, stretched.bounds_rad, atol=1e-12)


def test_a_constant_vertical_is_another_gravity():
    """theta'' has g + a_v where the planar equation has g (Yim et al. 1980): a constant vertical c is the same
    body under gravity g + c."""
    chain = chain_from_outline(_rocker(0.3, 0.2, facets=400), 0.01, 0.01)
    a = pulse(0.25, 0.7)
    for c in (-0.3 * G, 0.2 * G):
        with_v, other_g = np.zeros(a.size), np.zeros(a.size)
        roll_on_hull(a, DT, chain, av_ms2=np.full(a.size, c), theta_out=with_v)
        roll_on_hull(a, DT, chain, g_ms2=G + c, theta_out=other_g)
        assert np.max(np.abs(with_v)) > 0.1
        np.testing.assert_allclose(with_v, other_g, rtol=1e-12, atol=1e-15)      # (after the record, the vertical
        # is 0 and gravity g: the free motions differ)


def test_the_history_follows_the_tilt_and_a_falling_ground_leaves_no_verdict():
    chain = rectangle_chain(*RECTANGLE)
    a = pulse(0.25, 0.6)
    theta = np.zeros(a.size)
    out = roll_on_hull(a, DT, chain, theta_out=theta)
    assert 0.0 < np.max(np.abs(theta)) <= out.theta_max
    assert np.max(np.abs(theta)) == pytest.approx(out.theta_max, rel=0.02)        # sampled at DT
    av = np.where(np.arange(a.size) * DT > 0.3, -1.01 * G, 0.0)                    # the ground falls faster than g
    flight = roll_on_hull(a, DT, chain, av_ms2=av)
    assert flight.verdict == -1 and not flight.overturned and flight.status & STATUS_GROUND_FLIGHT


@pytest.mark.parametrize("amp_g,period_s", PULSES)
def test_a_rectangles_rolling_scene_is_the_planar_kernels_with_a_declared_restitution(amp_g, period_s):
    """The scene screen stores for a rectangle given as a mesh (pipeline.rocking.scanned.planes.plane_scene, the rolling
    model) against the planar kernel's block with the same declared restitution: verdict, theta_max / alpha, the
    time it overturns (to a sampling interval) and the response class."""
    from pipeline.rocking.scanned.planes import plane_scene
    from pipeline.rocking.scene import Physics, Response
    from pipeline.rocking.settings import SimulationConfig
    from pipeline.rocking.simulate import rock

    w, h = RECTANGLE
    alpha, R = math.atan2(w / 2, h / 2), math.hypot(w / 2, h / 2)
    a = pulse(amp_g, period_s)
    ours = plane_scene(a, None, DT, rectangle_chain(w, h), restitution=0.7, mu=1.0)
    ref = rock(a, DT, p=math.sqrt(0.75 * G / R), alpha=alpha, e=0.7, R_m=R,
               settings=SimulationConfig(closed_form_chatter=False))
    assert ours.physics == Physics.rolling and ours.overturned == ref.overturned
    assert ours.response == (Response.overturn if ref.overturned else Response.rock if ref.theta_max > 0
                             else Response.rest)
    if ref.overturned:
        assert ours.t_overturn == pytest.approx(ref.t_overturn, abs=DT)
    else:
        assert ours.theta_max == pytest.approx(ref.theta_max, abs=1e-4) and math.isnan(ours.t_overturn)


@pytest.mark.parametrize("amp_g,period_s", PULSES)
def test_a_rectangles_friction_demand_is_the_planar_kernels(amp_g, period_s):
    """The pivot's largest |f_x| / f_z while G has not passed it (Zhang & Makris 2001, eqs. 16-20, in the planar
    kernel) against the rolling kernel's, from Newton's law for G on the same rectangle."""
    a = pulse(amp_g, period_s)
    ours = roll_on_hull(a, DT, rectangle_chain(*RECTANGLE))
    ref = housner_block(a, *RECTANGLE)
    if ref.friction_demand == 0.0:
        assert ours.friction_demand == 0.0
    else:
        assert ours.friction_demand == pytest.approx(ref.friction_demand, rel=1e-4)
