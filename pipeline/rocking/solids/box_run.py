"""The 3D box's run over a record (:mod:`.box3d` states the model): rest and the lift about an edge, the steps on
an edge or a corner, a corner lifting off an edge, a corner landing on an edge, a flat landing, overturning, and
the flags."""

from __future__ import annotations

import math

import numpy as np

from ...compiled import copy_into, jit, jit_inline, jit_lean, store
from ..numerics.rk import next_step, rejected_step
from .box_kernel import (
    CORNER,
    EDGE,
    FORCE_SIZE,
    MAX_STEPS_PER_SAMPLE,
    REST,
    REST_RATE,
    STATE_SIZE,
    TWIST_NEXT,
    TWIST_PREV,
    BoxRun,
    _apply,
    _error_norm,
    _inertia_g,
    _params,
    _sym_apply,
    corner,
    derivatives,
    dopri_step,
    edge_axis,
    edge_ends_hold,
    flatten,
    height,
    lever,
    rotation,
    tilt_of,
)
from .box_rest import lift_off, quiet, slides_at_rest
from .vec3 import (
    FLAG_NONE,
    FLAG_SLIDE,
    FLAG_STEPS,
    Ground,
    contact_flag,
    cross,
    effective_gravity,
    final_flag,
    first_below,
    friction_demand,
    hermite,
    keep_first,
    shifted,
    solve_sym3,
)

MAX_FLAT_LANDINGS_PER_SAMPLE = 100   # flat landings inside one sample interval before the box is held at rest
UNLOADED = 1e-12                # an edge's corner pressed less than this x g [m s-2] per unit mass is unloaded
MAX_STALLED = 10000             # passes in a row that leave the time where it was before the run ends, flagged
TOGETHER_S = 1e-12              # two corners landing within this of each other [s] land together (a flat landing)

@jit
def edge_of(mode, pivot):
    """The edge a box on an edge, or sliding on one, turns on (corners j and j + 1)."""
    return (pivot - 1) % 4 if mode == TWIST_PREV else pivot


@jit
def _landing(y, k0, y_new, k6, hh, mode, pivot, prm):
    """The fraction of the step at which a base corner first lands (an adjacent corner on a corner, the far side on
    an edge), that corner, and the fraction at which another lands (2 when none)."""
    best_x, best_c, next_x = 2.0, -1, 2.0
    m0, m1 = rotation(y), rotation(y_new)
    for off in (1, 2, 3):
        if ((mode == CORNER and off == 2) or ((mode == EDGE or mode == TWIST_NEXT) and off == 1)
                or (mode == TWIST_PREV and off == 3)):
            continue
        kc = (pivot + off) % 4
        z0, v0 = height(m0, y, kc, pivot, prm)
        z1, v1 = height(m1, y_new, kc, pivot, prm)
        # a corner that is down lands where it returns to the ground: one rising from it (after a flat landing) at
        # the ground; one that has just lifted off an edge from rest (its rise of order roundoff at first, the edge
        # level to the integration's error) only land_m below where it started
        level = prm.land_m if z0 >= prm.land_m else (0.0 if v0 > 0.0 else min(z0, 0.0) - prm.land_m)
        if not (z1 < level and z1 < z0):
            continue
        hi = first_below(z0, v0, z1, v1, hh, level)
        if hi < best_x:
            best_x, best_c, next_x = hi, kc, best_x
        else:
            next_x = min(next_x, hi)
    return best_x, best_c, next_x


@jit
def _corner_lands(y, pivot, kc, prm):
    """A corner adjacent to the pivot lands and cannot take over alone (:func:`_corner_passes`): the box turns on the
    edge they share, its angular momentum about that edge's axis conserved (the impulses act on the axis). Returns
    the edge."""
    j = pivot if kc == (pivot + 1) % 4 else kc
    m = rotation(y)
    rx, ry, rz = lever(m, pivot, prm)
    ig = _inertia_g(m, prm)
    ip = shifted(ig[0], ig[1], ig[2], ig[3], ig[4], ig[5], rx, ry, rz)
    ux, uy, uz, _ = edge_axis(m, j, prm)
    lx, ly, lz = _sym_apply(ip, y[4], y[5], y[6])
    iu = _sym_apply(ip, ux, uy, uz)
    s = (ux * lx + uy * ly + uz * lz) / (ux * iu[0] + uy * iu[1] + uz * iu[2])
    y[4], y[5], y[6] = s * ux, s * uy, s * uz
    return j


@jit
def _about_point(y, pivot, other, prm):
    """Turning on corner ``pivot``, the box lands on corner ``other`` alone: its rate after, the angular momentum about
    ``other`` conserved (the impulse acts there; Housner's rule about a point), ``omega+ = I_Q^-1 (I_G omega- + s x
    v_G-)`` with ``s = G - Q``; returned with G's velocity before and the levers ``r = G - pivot`` and ``s``."""
    m = rotation(y)
    wx, wy, wz = y[4], y[5], y[6]
    r = lever(m, pivot, prm)
    ig = _inertia_g(m, prm)
    gx, gy, gz = _sym_apply(ig, wx, wy, wz)
    v = cross(wx, wy, wz, r[0], r[1], r[2])
    sx, sy, sz = lever(m, other, prm)
    hx, hy, hz = cross(sx, sy, sz, v[0], v[1], v[2])
    ip = shifted(ig[0], ig[1], ig[2], ig[3], ig[4], ig[5], sx, sy, sz)
    n = solve_sym3(ip[0], ip[1], ip[2], ip[3], ip[4], ip[5], gx + hx, gy + hy, gz + hz)
    return n, v, r, (sx, sy, sz)


@jit
def _corner_passes(y, pivot, kc, prm):
    """A corner adjacent to the pivot lands and takes over alone (:func:`_about_point`), where that is consistent:
    the landing corner pressed (its impulse up, inside its friction cone) and the old pivot rising (faster than
    :data:`REST_RATE` p alpha times the base's smaller half side, so that a grazing landing, where rounding would
    choose, stays on the edge). Returns whether it is (the state then updated; else unchanged, and the box turns on
    the edge the two share: :func:`_corner_lands`)."""
    (nx, ny, nz), (vx, vy, vz), (rx, ry, rz), (sx, sy, sz) = _about_point(y, pivot, kc, prm)
    ux, uy, uz = cross(nx, ny, nz, sx, sy, sz)             # G's velocity after, turning on the landing corner
    px, py, pz = ux - vx, uy - vy, uz - vz                 # the impulse at it, per unit mass
    old = cross(nx, ny, nz, sx - rx, sy - ry, sz - rz)     # the old pivot's velocity after
    rising = REST_RATE * prm.p * prm.alpha * min(prm.bx, prm.by)      # below it the old pivot stays (an edge)
    if pz <= 0.0 or math.hypot(px, py) > prm.mu * pz or old[2] <= rising:
        return False
    y[4], y[5], y[6] = nx, ny, nz
    return True


@jit
def _diagonal_landing(y, pivot, prm):
    """Both corners adjacent to the pivot land together (the base lands flat while turning on a corner): the box
    turns on the opposite corner (:func:`_about_point`), scaled by the declared restitution; returns whether the
    rebound is too slow to go on (rest)."""
    (nx, ny, nz), _, _, _ = _about_point(y, pivot, pivot + 2, prm)
    flatten(y)
    if math.hypot(nx, ny) * prm.scale < REST_RATE * prm.p * prm.alpha:
        y[4], y[5], y[6] = 0.0, 0.0, 0.0
        return True
    y[4], y[5], y[6] = nx * prm.scale, ny * prm.scale, nz
    return False


@jit
def _flat_landing(y, j, keep, prm):
    """The base lands flat while turning on edge j (corner ``keep`` of it fixed, the other on the ground): the box
    turns on the opposite edge with its angular momentum about it conserved (Housner 1963), scaled by the declared
    restitution; returns whether the rebound is too slow to go on (rest)."""
    m = rotation(y)
    wx, wy, wz = y[4], y[5], y[6]
    rx, ry, rz = lever(m, keep, prm)
    ig = _inertia_g(m, prm)
    gx, gy, gz = _sym_apply(ig, wx, wy, wz)
    vx, vy, vz = cross(wx, wy, wz, rx, ry, rz)
    jn = (j + 2) % 4
    sx, sy, sz = lever(m, jn, prm)
    hx, hy, hz = cross(sx, sy, sz, vx, vy, vz)
    ip = shifted(ig[0], ig[1], ig[2], ig[3], ig[4], ig[5], sx, sy, sz)
    ux, uy, uz, _ = edge_axis(m, jn, prm)
    iu = _sym_apply(ip, ux, uy, uz)
    s = prm.scale * (ux * (gx + hx) + uy * (gy + hy) + uz * (gz + hz)) / (ux * iu[0] + uy * iu[1] + uz * iu[2])
    flatten(y)
    if s < REST_RATE * prm.p * prm.alpha:
        y[4], y[5], y[6] = 0.0, 0.0, 0.0
        return True
    ux, uy, uz, _ = edge_axis(rotation(y), jn, prm)
    y[4], y[5], y[6] = s * ux, s * uy, s * uz
    return False


@jit
def _lifts(y, t, i, grd, prm, keep, free):
    """Whether corner ``free`` of an edge would rise with the box turning on corner ``keep`` alone (its vertical
    acceleration there > 0). With the edge's normal force at ``free`` <= 0 this is the consistent lift; where it
    would not rise, that corner can neither pull nor lift, and only a slip of it (a twist) resolves the contact."""
    gx, gy, gz = effective_gravity(t, i, grd)
    f, _ = derivatives(y, gx, gy, gz, prm, CORNER, keep)
    m = rotation(y)
    ax_, ay_, az_ = corner(free, prm)
    bx_, by_, bz_ = corner(keep, prm)
    dx, dy, dz = _apply(m, ax_ - bx_, ay_ - by_, az_ - bz_)
    a1 = cross(f[4], f[5], f[6], dx, dy, dz)
    vx, vy, vz = cross(y[4], y[5], y[6], dx, dy, dz)
    a2 = cross(y[4], y[5], y[6], vx, vy, vz)
    return a1[2] + a2[2] > 0.0


@jit
def _fill(tilt_out, azimuth_out, dt, t, hh, y, k, y_new, n, scratch):
    """The samples inside (t, t + hh]: the quaternion by the step's Hermite cubic, then its tilt and azimuth."""
    j = int(t / dt + 1e-9) + 1
    while j < n and j * dt <= t + hh + 1e-12 * dt:
        x = (j * dt - t) / hh
        for q in range(4):
            scratch[q] = hermite(y[q], k[0, q], y_new[q], k[1, q], hh, x)
        tilt_out[j], azimuth_out[j] = tilt_of(scratch)
        j += 1


@jit
def _past_tipping(y, mode, pivot, prm):
    """Whether G is beyond the pivot (its horizontal offset from the pivot, across the edge on an edge, points away
    from the base's centre), and whether it falls."""
    m = rotation(y)
    rx, ry, rz = lever(m, pivot, prm)
    dx, dy = rx - prm.hz * m[2], ry - prm.hz * m[5]
    vz = cross(y[4], y[5], y[6], rx, ry, rz)[2]
    if mode != CORNER:
        ux, uy, uz, _ = edge_axis(m, edge_of(mode, pivot), prm)
        ru, du = rx * ux + ry * uy, dx * ux + dy * uy
        rx, ry, dx, dy = rx - ru * ux, ry - ru * uy, dx - du * ux, dy - du * uy
    return rx * dx + ry * dy < 0.0, vz < 0.0


@jit
def _rzz(y):
    """R_zz of the quaternion ``y[0:4]`` (not necessarily unit): the cosine of the body axis's tilt [-]."""
    return 1.0 - 2.0 * (y[1] * y[1] + y[2] * y[2]) / (y[0] * y[0] + y[1] * y[1] + y[2] * y[2] + y[3] * y[3])


@jit
def _partial(t, hh, x, i, grd, prm, mode, pivot, y, k, y_new, err, force, tilt_out, azimuth_out, scratch):
    """Advance to the fraction ``x`` of the step (an exact Runge-Kutta step there); returns the new time."""
    hl = max(x * hh, 1e-15 * grd.dt)
    dopri_step(t, y, hl, i, grd, prm, mode, pivot, k, y_new, err, force)
    _fill(tilt_out, azimuth_out, grd.dt, t, hl, y, k, y_new, grd.ax.shape[0], scratch)
    copy_into(y, y_new)
    return t + hl


@jit
def certify(cert, t, y, mode, pivot):
    """The last state the model certifies before its first stop (the contact model's hand-off): ``cert`` = (t, the
    7 states, the mode, the pivot), kept from the first call (:func:`~.vec3.keep_first`)."""
    if keep_first(cert, t, y):
        cert[8], cert[9] = mode, pivot


@jit
def _rest_pass(t, i, grd, prm, y, quiet_ratio, tilt_out, azimuth_out, cert):
    """At rest over sample interval ``i`` from ``t``: (the time reached, the mode, the pivot edge, the flag): the
    next sample where nothing moves, the instant it lifts (EDGE), or where it would slide first (flagged, and
    certified at rest there)."""
    last = grd.ax.shape[0] - 1
    j = i
    if quiet(j, grd, quiet_ratio):
        while j < last and quiet(j + 1, grd, quiet_ratio):   # neither lifts nor slides in these intervals
            j += 1                                              # (quiet at both ends: throughout, by convexity)
            tilt_out[j], azimuth_out[j] = 0.0, 0.0
    if j > i:
        return j * grd.dt, REST, 0, FLAG_NONE
    start, j = lift_off(t, i, grd, prm, y)
    slip = slides_at_rest(t, i, grd, prm)
    if slip >= 0.0 and (start < 0.0 or slip < start):
        certify(cert, slip, y, REST, 0)
        return slip, REST, 0, FLAG_SLIDE                      # it would slide before it rocks: not followed in 3D
    if start < 0.0:
        tilt_out[i + 1], azimuth_out[i + 1] = 0.0, 0.0
        return (i + 1) * grd.dt, REST, 0, FLAG_NONE
    return start, EDGE, j, FLAG_NONE


@jit
def _fresh_pass(y, t, i, grd, prm, mode, pivot, k, force0):
    """f and the contact forces at a fresh state (after a transition); then a corner of an edge that is unloaded
    lifts (it would rise) or slides (it can neither press nor rise), and a sliding corner that is unloaded lifts.
    Returns (mode, pivot, whether they changed)."""
    gx, gy, gz = effective_gravity(t, i, grd)
    f0, f = derivatives(y, gx, gy, gz, prm, mode, pivot)
    store(k[0], f0)
    store(force0, f)
    if mode == EDGE and min(f[3], f[4]) <= UNLOADED * grd.g and f[2] > 0.0:
        keep = pivot if f[4] <= f[3] else (pivot + 1) % 4
        free = (pivot + 1) % 4 if keep == pivot else pivot
        if _lifts(y, t, i, grd, prm, keep, free):
            return CORNER, keep, True
        return (TWIST_NEXT if keep == pivot else TWIST_PREV), keep, True
    if (mode == TWIST_NEXT or mode == TWIST_PREV) and f[4] <= 0.0 and f[2] > 0.0:
        return CORNER, pivot, True
    return mode, pivot, False


@jit
def _after_landing(y, mode, pivot, kc, together, prm):
    """The mode and pivot after a landing (the state at the landing, impact applied)."""
    if mode == CORNER and together:
        rests = _diagonal_landing(y, pivot, prm)
        return (REST if rests else CORNER), (pivot + 2) % 4
    if mode == CORNER:
        if _corner_passes(y, pivot, kc, prm):
            return CORNER, kc
        return EDGE, _corner_lands(y, pivot, kc, prm)
    j = edge_of(mode, pivot)
    rests = _flat_landing(y, j, pivot, prm)
    return (REST if rests else EDGE), (j + 2) % 4


@jit
def _contact_event(y, y_new, force, force0, mode, held, prm):
    """Where a step ends with a corner of the edge unloaded, the sliding corner unloaded, or the twist stopped:
    the fraction of the step where it happened (located linearly) and what follows (the mode, -1 for the next
    fresh pass to decide); (-1, mode) where nothing happened."""
    if force[2] <= 0.0:
        return -1.0, mode
    if mode == EDGE and held == FLAG_NONE and min(force[3], force[4]) <= 0.0:
        second = force[4] <= force[3]
        n0, n1 = (force0[4], force[4]) if second else (force0[3], force[3])
        return (min(1.0, max(0.0, n0 / (n0 - n1))) if n0 > n1 else 1.0), EDGE
    if mode == TWIST_NEXT or mode == TWIST_PREV:
        if force[4] <= 0.0:                                         # the sliding corner lifts
            n0 = force0[4]
            return (min(1.0, max(0.0, n0 / (n0 - force[4]))) if n0 > force[4] else 1.0), CORNER
        if y[6] * y_new[6] < 0.0 and abs(y[6]) > REST_RATE * prm.p * prm.alpha:   # the twist stops: it may stick
            return y[6] / (y[6] - y_new[6]), EDGE
    return -1.0, mode


@jit
def _stick(y, mode, pivot, prm):
    """The sliding corner sticks (its twist stopped): the box turns on the edge; returns the edge."""
    j = edge_of(mode, pivot)
    ux, uy, uz, _ = edge_axis(rotation(y), j, prm)
    sp = y[4] * ux + y[5] * uy + y[6] * uz
    y[4], y[5], y[6] = sp * ux, sp * uy, sp * uz
    return j


@jit
def _checked(force, mu, held, y_new, mode, pivot, prm, cert, t, y):
    """:func:`_contact_flags` of the step from (t, y) to ``y_new``; at the first that flags or holds, (t, y)
    certified (:func:`certify`)."""
    flag, now_held = _contact_flags(force, mu, held, y_new, mode, pivot, prm)
    if flag != FLAG_NONE or now_held != held:
        certify(cert, t, y, mode, pivot)
    return flag, now_held


@jit
def _contact_flags(force, mu, held, y_new, mode, pivot, prm):
    """The flag of an accepted step and the held flag (held past the tipping point: see box3d); on an edge whose two
    corners press, friction is checked at each corner (:func:`~.box_kernel.edge_ends_hold`): one that slips is a
    slide (the box would twist)."""
    flag = contact_flag(force, mu)
    if flag == FLAG_NONE and mode == EDGE and force[3] > 0.0 and force[4] > 0.0:
        ux, uy, _uz, _length = edge_axis(rotation(y_new), pivot, prm)
        if not edge_ends_hold(force, mu, ux, uy):
            flag = FLAG_SLIDE
    if held == FLAG_NONE and flag == FLAG_NONE:
        return flag, held
    beyond, falling = _past_tipping(y_new, mode, pivot, prm)
    if held != FLAG_NONE:
        return (held if not beyond else FLAG_NONE), held      # until it comes back: then no verdict
    if beyond and falling:
        return FLAG_NONE, flag
    return flag, held


@jit
def _accept(y, y_new, k, force, force0):
    """Take an accepted step's end as the state (the quaternion normalised), f there as the next step's first."""
    nq = math.sqrt(y_new[0] ** 2 + y_new[1] ** 2 + y_new[2] ** 2 + y_new[3] ** 2)
    for q in range(4):
        y_new[q] /= nq
    copy_into(y, y_new)
    copy_into(k[0], k[1])
    for q in range(FORCE_SIZE):
        force0[q] = force[q]


@jit
def _hold(y, i, dt, tilt_out, azimuth_out):
    """A cascade of flat landings at the threshold of uplift (rebounds too small to show at the samples): the box
    held at rest to the next sample, as the planar kernel's tie rule holds a flat block; returns (REST, the time)."""
    y[4], y[5], y[6] = 0.0, 0.0, 0.0
    tilt_out[i + 1], azimuth_out[i + 1] = 0.0, 0.0
    return REST, (i + 1) * dt


@jit_inline
def _landed(t, hh, x, x_next, kc, i, grd, prm, mode, pivot, y, k, y_new, err, force, tilt_out, azimuth_out,
            scratch, i_landed, landed_here):
    """A base corner lands at the fraction ``x`` of the step (corner ``kc``; another at ``x_next``): the state
    advanced there, the impact applied, and a cascade of flat landings in one sample interval held at rest
    (:func:`_hold`). Returns the time, the mode and pivot, the landings counted in this interval and whether it was
    held."""
    flat = mode != CORNER or (x_next - x) * hh <= TOGETHER_S
    t = _partial(t, hh, x, i, grd, prm, mode, pivot, y, k, y_new, err, force, tilt_out, azimuth_out, scratch)
    mode, pivot = _after_landing(y, mode, pivot, kc, (x_next - x) * hh <= TOGETHER_S, prm)
    landed_here = landed_here + 1 if i == i_landed and flat else (1 if flat else 0)
    if landed_here > MAX_FLAT_LANDINGS_PER_SAMPLE and mode != REST:
        mode, t = _hold(y, i, grd.dt, tilt_out, azimuth_out)
        return t, mode, pivot, 0, True
    return t, mode, pivot, landed_here, False


@jit_inline
def _event_taken(t, hh, x, then, i, grd, prm, mode, pivot, y, k, y_new, err, force, tilt_out, azimuth_out,
                 scratch):
    """A contact event at the fraction ``x`` of the step (:func:`_contact_event`): the state advanced there and
    the sliding corner stuck where an edge follows. Returns the time, the mode that follows and the pivot."""
    t = _partial(t, hh, x, i, grd, prm, mode, pivot, y, k, y_new, err, force, tilt_out, azimuth_out, scratch)
    if then == EDGE and mode != EDGE:
        pivot = _stick(y, mode, pivot, prm)
    return t, then, pivot


@jit_inline
def _peak(y_new, tilt_max, az_max):
    """The run's largest tilt and its azimuth [rad] with the state ``y_new``'s."""
    tilt, azimuth = tilt_of(y_new)
    return (tilt, azimuth) if tilt > tilt_max else (tilt_max, az_max)


@jit_inline
def _start_state(y0, mode):
    """The state to start from: ``y0``, set flat and still where the box starts at rest."""
    y = y0.copy()
    if mode == REST:
        flatten(y)
        y[4], y[5], y[6] = 0.0, 0.0, 0.0
    return y


@jit
def run_box(ax, ay, az, dt, g, bx, by, hz, mu, scale, rtol, atol_alpha, y0, mode0, pivot0, tilt_out, azimuth_out,
            y_end, cert):
    """Run a box on the ground ``ax, ay, az`` [m s-2] at ``dt`` [s] from ``y0`` in ``mode0`` on ``pivot0`` (REST: at
    rest): the tilt and azimuth at the samples, the last state, the last certified before a stop (:func:`certify`)."""
    return _run_box(ax, ay, az, dt, g, bx, by, hz, mu, scale, rtol, atol_alpha, _start_state(y0, mode0), mode0,
                    pivot0, tilt_out, azimuth_out, y_end, cert, np.zeros((2, STATE_SIZE)), np.empty(STATE_SIZE),
                    np.empty(STATE_SIZE), np.zeros(FORCE_SIZE), np.zeros(FORCE_SIZE), np.empty(4))


@jit_lean
def _run_box(ax, ay, az, dt, g, bx, by, hz, mu, scale, rtol, atol_alpha, y, mode0, pivot0, tilt_out, azimuth_out,
             y_end, cert, k, y_new, err, force, force0, scratch):
    """:func:`run_box`'s loop on the arrays it made."""
    grd, prm = Ground(ax, ay, az, dt, g), _params(g, bx, by, hz, mu, scale, rtol, atol_alpha)
    n, mode, pivot = ax.shape[0], mode0, pivot0
    t, t_end, hh_next, steps, stalled, t_last = 0.0, (n - 1) * dt, dt, 0, 0, -1.0
    i_landed, landed_here, holds = -1, 0, 0
    tilt_max, az_max, flag, impacts, t_over, demand, held, corner_s = 0.0, 0.0, FLAG_NONE, 0, math.nan, 0.0, 0, 0.0
    tilt_out[0], azimuth_out[0] = tilt_of(y)
    quiet_ratio, fresh = min(min(bx, by) / hz, mu), True
    while t < t_end - 1e-12 * dt and flag == FLAG_NONE and math.isnan(t_over):
        i = min(int(t / dt + 1e-9), n - 2)
        if mode == REST:
            t, mode, pivot, flag = _rest_pass(t, i, grd, prm, y, quiet_ratio, tilt_out, azimuth_out, cert)
            fresh = True
            continue
        steps, stalled, t_last = steps + 1, (stalled + 1 if t <= t_last else 0), t
        if steps > MAX_STEPS_PER_SAMPLE * n or stalled > MAX_STALLED:
            flag = FLAG_STEPS
            break
        if fresh:
            mode, pivot, fresh = _fresh_pass(y, t, i, grd, prm, mode, pivot, k, force0)
            if fresh:
                continue        # the mode changed: f again
        hh = min(hh_next, (i + 1) * dt - t)
        dopri_step(t, y, hh, i, grd, prm, mode, pivot, k, y_new, err, force)
        norm = _error_norm(y, y_new, err, prm)
        if not norm <= 1.0:          # rejected (NaN too)
            hh_next = rejected_step(hh, norm)
            continue
        r0, r1 = _rzz(y), _rzz(y_new)
        if r1 <= 0.0:                                                # overturned: the axis reaches the horizontal
            t_over, tilt_max, az_max = t + r0 / (r0 - r1) * hh, 0.5 * math.pi, tilt_of(y_new)[1]
            break
        x, kc, x_next = _landing(y, k[0], y_new, k[1], hh, mode, pivot, prm)
        if kc >= 0:
            t, mode, pivot, landed_here, was_held = _landed(t, hh, x, x_next, kc, i, grd, prm, mode, pivot, y, k, y_new,
                                                            err, force, tilt_out, azimuth_out, scratch,
                                                            i_landed, landed_here)
            impacts, holds, i_landed, fresh = impacts + 1, holds + was_held, i, True
            continue
        x, then = _contact_event(y, y_new, force, force0, mode, held, prm)
        if x >= 0.0:        # an edge's unloaded corner: the fresh pass decides lift or slide
            t, mode, pivot = _event_taken(t, hh, x, then, i, grd, prm, mode, pivot, y, k, y_new, err, force,
                                          tilt_out, azimuth_out, scratch)
            fresh = True
            continue
        flag, held = _checked(force, mu, held, y_new, mode, pivot, prm, cert, t, y)
        demand = friction_demand(force, demand)
        _fill(tilt_out, azimuth_out, dt, t, hh, y, k, y_new, n, scratch)
        tilt_max, az_max = _peak(y_new, tilt_max, az_max)
        corner_s += hh if mode == CORNER else 0.0
        t, hh_next = t + hh, next_step(hh, norm)
        _accept(y, y_new, k, force, force0)
    copy_into(y_end, y)
    return BoxRun(not math.isnan(t_over), t_over, tilt_max, az_max, final_flag(flag, held, t_over), impacts,
                  corner_s, demand, held, steps, holds, mode, pivot)
