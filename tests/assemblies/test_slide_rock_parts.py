"""A taller stack in the slide-rock model (pipeline.assemblies.slide_rock_parts): the blocks below the sliding joint
and above it as two rigid parts, and the loads the parts' own joints carry. Against independent truth: the two-block
model's own blocks, the union of glued drums as one block, Newton's and Euler's laws summed block by block against
the model's Lagrange equations, the new corner as the landing's only ground impulse (angular momentum about it), the
stack's contact model on the same motion, and, on whole scenes, the verdicts of the contact model alone."""

from __future__ import annotations

import math
from functools import partial
from pathlib import Path
from unittest import mock

import numpy as np
import pytest
from rigid_body_peer import short_records

from pipeline.assemblies import n_block as nbm
from pipeline.assemblies import n_block_verdicts
from pipeline.assemblies import slide_rock as srm
from pipeline.assemblies.n_block_verdicts import judge_n_block
from pipeline.assemblies.slide_rock_parts import (
    INNER_HOLDS,
    inner,
    joint_load,
    landing_load,
    parts_of,
)
from pipeline.assemblies.stack import StackBody
from pipeline.assemblies.stack_contact import MAX_STEP_S, simulate_stack_contact
from pipeline.assemblies.stack_pose import slide_rock_pose
from pipeline.constants import G
from pipeline.errors import ParameterError

RHO = 2500.0
ROOT = Path(__file__).resolve().parents[2]
#: (width, height) of each drum, bottom first [m]: a tapering column of three, and one of five
COLUMNS = {"three": ((0.62, 1.10), (0.60, 1.10), (0.58, 1.00)),
           "five": ((0.70, 0.80), (0.70, 0.80), (0.70, 0.80), (0.70, 0.80), (0.70, 0.60))}


def _column(drums, mu, offsets=None) -> nbm.NBlock:
    """The column's NBlock (deep drums of RHO), each drum's base ``offsets`` [m] from the top under it."""
    nb = nbm.n_block([StackBody(w, h, RHO * w * h, m) for (w, h), m in zip(drums, mu)])
    return nb if offsets is None else nb._replace(off=tuple(offsets) + (0.0,) * (nbm.MAX_BODIES - len(offsets)))


def _field(phi, ah, av):
    """The field per unit mass along the lower part's base and normal to it [m s-2]."""
    c, s = math.cos(phi), math.sin(phi)
    return -ah * c + (G + av) * s, -ah * s - (G + av) * c


def test_two_blocks_are_each_a_part():
    """Two blocks: each part is its block, with the values the model took for them before it took parts."""
    nb = _column(((0.6, 1.5), (0.55, 1.2)), (0.5, 0.25))
    sr, _ = parts_of(nb, (0.5, 0.25))
    assert (sr.b0, sr.h0, sr.m0, sr.i0, sr.b1, sr.h1, sr.m1, sr.i1) == (nb.b[0], nb.h[0], nb.m[0], nb.i[0], nb.b[1],
                                                                       nb.h[1], nb.m[1], nb.i[1])
    assert (sr.x0, sr.top0, sr.xt0, sr.bt0, sr.x1, sr.mu0, sr.mu1) == (0.0, 2.0 * nb.h[0], 0.0, nb.b[0], 0.0, 0.5,
                                                                       0.25)


@pytest.mark.parametrize("slip", [-1, 0, 1])
def test_glued_drums_are_the_block_of_their_outline(slip):
    """Three drums of one width, the lower two shut: the model's accelerations and forces are those of two blocks,
    the lower the one block of the two drums' outline, at 200 random states."""
    three = _column(((0.6, 1.0), (0.6, 0.8), (0.5, 1.2)), (0.8, 0.8, 0.3))
    two = _column(((0.6, 1.8), (0.5, 1.2)), (0.8, 0.3))
    parts, blocks = parts_of(three, (0.8, 0.8, 0.3), 2)[0], parts_of(two, (0.8, 0.3))[0]
    rng = np.random.default_rng(5)
    for _ in range(200):
        pivot = int(rng.choice([-1, 1]))
        y = (pivot * rng.uniform(1e-3, 0.3), rng.uniform(-0.05, 0.05), rng.uniform(-1, 1),
             slip * rng.uniform(0.01, 0.5))
        ah, av = rng.uniform(-6, 6), rng.uniform(-3, 3)
        assert tuple(srm.forces(parts, pivot, slip, y, ah, av)) == pytest.approx(
            tuple(srm.forces(blocks, pivot, slip, y, ah, av)), rel=1e-9, abs=1e-9)


@pytest.mark.parametrize("column", sorted(COLUMNS))
def test_joint_loads_are_newton_and_euler_block_by_block(column):
    """The blocks' own Newton's and Euler's laws, summed above a joint (:func:`joint_load`), against the model's
    Lagrange equations: at the sliding joint the friction, normal force and centre of pressure the model gives; at the
    ground its reaction; and the ground's centre of pressure at the pivot corner, where the whole reaction acts (Euler's
    law about it, which holds only where phi'' and u'' are right); every joint, 200 random states each, the drums
    offset."""
    drums = COLUMNS[column]
    rng = np.random.default_rng(len(drums))
    mu = (0.6,) + (0.3,) * (len(drums) - 1)
    nb = _column(drums, mu, (0.0,) + tuple(rng.uniform(-0.03, 0.03, len(drums) - 1)))
    for joint in range(1, nb.n):
        sr, parts = parts_of(nb, mu, joint)
        for _ in range(200):
            pivot, slip = int(rng.choice([-1, 1])), int(rng.choice([-1, 0, 1]))
            y = (pivot * rng.uniform(1e-3, 0.3), rng.uniform(-0.05, 0.05), rng.uniform(-1, 1),
                 slip * rng.uniform(0.01, 0.5))
            ah, av = rng.uniform(-6, 6), rng.uniform(-3, 3)
            fo = srm.forces(sr, pivot, slip, y, ah, av)
            fe, fn = _field(y[0], ah, av)
            f_e, f_n, x_p = joint_load(parts, pivot, y, fo.ddphi, fo.ddu, fe, fn, joint)
            scale = abs(fo.normal)
            assert (f_e, f_n) == pytest.approx((fo.friction, fo.normal), abs=1e-9 * scale)
            if fo.normal > 0.0:
                assert x_p == pytest.approx(fo.x_p, abs=1e-9)
            g_e, g_n, g_p = joint_load(parts, pivot, y, fo.ddphi, fo.ddu, fe, fn, 0)
            c, s = math.cos(y[0]), math.sin(y[0])
            assert (c * g_e + s * g_n, -s * g_e + c * g_n) == pytest.approx((fo.rx, fo.rz), abs=1e-9 * abs(fo.rz))
            if g_n > 0.0:
                assert g_p == pytest.approx(pivot * nb.b[0], abs=1e-9)


@pytest.mark.parametrize("column", sorted(COLUMNS))
def test_landing_impulses_are_the_blocks_momenta(column):
    """A landing by the model's impact law: the blocks' momentum changes summed above the sliding joint are its
    normal and friction impulses, summed over the whole stack the ground's, and the ground's impulse acts at the new
    corner alone (the stack's angular momentum about it kept), 100 random landings per joint."""
    drums = COLUMNS[column]
    rng = np.random.default_rng(10 + len(drums))
    mu = (5.0,) + (0.3,) * (len(drums) - 1)
    nb = _column(drums, mu)
    for joint in range(1, nb.n):
        sr, parts = parts_of(nb, mu, joint)
        for _ in range(100):
            u, w, du = rng.uniform(-0.03, 0.03), -rng.uniform(0.05, 1.0), rng.uniform(-0.3, 0.3)
            ld = srm.landing(sr, parts, 1, (0.0, u, w, du), 0.0)
            j_e, j_n, _ = landing_load(parts, 1, u, w, du, ld.dphi, ld.du, joint)
            assert (j_e, j_n) == pytest.approx((ld.friction, ld.normal), abs=1e-9 * max(1.0, abs(ld.normal)))
            g_e, g_n, g_p = landing_load(parts, 1, u, w, du, ld.dphi, ld.du, 0)
            assert (g_e, g_n) == pytest.approx((ld.ground_x, ld.ground_z), abs=1e-9 * max(1.0, abs(ld.ground_z)))
            if g_n > 0.0:
                assert g_p == pytest.approx(-nb.b[0], abs=1e-9)


def test_three_drums_follow_the_contact_model():
    """Three drums rocking as one on a corner while the top drum slides (joint 0.1, the others 0.9) under a constant
    ground of 0.55 g: the model's rotation and slip after 0.2 s are the stack's contact model's with 0.1 ms steps
    to 0.2 % (the contact model's own change from 0.25 to 0.05 ms steps is 0.1 %), and the lower joint stays shut
    and sticking throughout."""
    drums, mu = COLUMNS["three"], (0.9, 0.9, 0.1)
    nb = _column(drums, mu)
    ah = np.full(40, 0.55 * G)
    start = (-1e-4, 0.0, -0.05, 0.0)
    out = srm.simulate_slide_rock(nb, mu, ah, np.zeros(0), 0.01, start=start, t0_s=0.0, origin_m=0.0, joint=2,
                                  until_s=0.2)
    assert out.end == srm.END_STOPPED
    phi, u = out.state[0], out.state[1]
    assert phi < -0.04 and u < -0.004                  # it rocked and slid, the way the ground pushes it
    q, v = slide_rock_pose(nb, start, -1, 2)
    flight = simulate_stack_contact(nb, mu, ah, 0.01, pose=(q, v), t0_s=0.0, hand_back=False, until_s=out.t_end_s,
                                    step_s=1e-4)
    assert flight.peak_rad[0] == pytest.approx(-phi, rel=2e-3)
    assert flight.offsets_m[2] == pytest.approx(u, rel=2e-3)
    assert abs(flight.offsets_m[1]) < 1e-5 and flight.peak_rad[1] < 1e-5
    sr, parts = parts_of(nb, mu, 2)
    fo = srm.forces(sr, -1, -1, out.state, 0.55 * G, 0.0)
    assert inner(parts, -1, out.state, fo.ddphi, fo.ddu, *_field(out.state[0], 0.55 * G, 0.0)) == INNER_HOLDS


@pytest.fixture(scope="module")
def columns():
    """The three- and five-drum columns (floor 0.5, joints 0.25) under the 21 bundled records of at most 60 s at
    0.5 g: (column, record, verdicts as shipped, the contact model alone at a quarter of its step: the reference),
    and how many slide-rock runs the shipped verdicts took."""
    records = short_records(ROOT / "records")[:21]
    out, runs = [], 0
    for name, drums in sorted(COLUMNS.items()):
        mu = (0.5,) + (0.25,) * (len(drums) - 1)
        nb = _column(drums, mu)
        for rec in records:
            a = rec.horizontal_ms2[0] * (0.5 * G / abs(rec.horizontal_ms2[0]).max())
            with mock.patch.object(n_block_verdicts, "simulate_slide_rock",
                                   wraps=n_block_verdicts.simulate_slide_rock) as calls:
                ours = judge_n_block(nb, a, rec.dt_s, mu=mu)
            runs += calls.call_count
            with mock.patch.object(n_block_verdicts, "simulate_stack_contact",
                                   partial(simulate_stack_contact, step_s=MAX_STEP_S / 4)):
                ref = judge_n_block(nb, a, rec.dt_s, mu=mu, slide_rock=False)
            out.append((name, nb, rec, a, ours.verdicts, ref.verdicts))
    return out, runs


@pytest.mark.slow       # the columns' fixture: 42 scenes by both models, 17-23 s
def test_columns_have_the_reference_verdicts(columns):
    """Three and five drums whose joints slip while the column rocks (42 scenes): each drum's verdict as shipped (the
    slide-rock model on the column's two parts) is the reference's in at least 95 % of them, every scene that differs
    not robust (its verdict turns at 0.98 or 1.02 of the record), and the slide-rock model ran (measured: 42 of 42,
    with 1,247 slide-rock runs)."""
    scenes, runs = columns
    assert runs > 100
    differ = [(name, rec.record_id) for name, nb, rec, a, ours, ref in scenes if ours != ref]
    for name, nb, rec, a, ours, ref in scenes:
        if ours != ref:
            again = {judge_n_block(nb, a * f, rec.dt_s, mu=(0.5,) + (0.25,) * (nb.n - 1)).verdicts
                     for f in (0.98, 1.02)}
            assert again != {ours}, f"{name} {rec.record_id}: a robust difference"
    assert len(differ) <= 0.05 * len(scenes), differ


@pytest.mark.parametrize("joint", [0, 3])
def test_a_joint_outside_the_stack_is_refused(joint):
    """The sliding joint must lie between two blocks of the stack: the error names it and the range."""
    with pytest.raises(ParameterError, match=f"joint = {joint}: expected .* 1 to 2"):
        parts_of(_column(COLUMNS["three"], (0.5, 0.25, 0.25)), (0.5, 0.25, 0.25), joint)
