"""An independent form of the equations of n stacked rocking blocks, for the tests: Lagrange's equations of the
blocks' energy, the positions as complex numbers built corner by corner, the kinetic energy's mass matrix from the
bodies' velocities, its derivative and the potential's gradient by central differences. It shares with
:mod:`pipeline.assemblies.n_block` only the model's rules (each body turns about a corner of its support on the body
below; a shut joint holds its rotation at 0), not its code.
"""

from __future__ import annotations

import cmath
import math

import numpy as np
from two_block_reference import TerminalEvent

G = 9.80665
DIFF = 1e-6


class Stack:
    """Blocks bottom first: half-widths b, half-heights h, masses m, each base's offset from the top's centre below."""

    def __init__(self, b, h, m, off):
        self.b, self.h, self.m, self.off = (np.asarray(v, dtype=float) for v in (b, h, m, off))
        self.n = len(self.b)
        self.inertia = self.m * (self.b ** 2 + self.h ** 2) / 3.0

    def support(self, k):
        """Joint k's support in block k's frame: the overlap of its base with the face below."""
        if k == 0:
            return -self.b[0], self.b[0]
        return max(-self.b[k], -self.b[k - 1] - self.off[k]), min(self.b[k], self.b[k - 1] - self.off[k])


def _corner(stack: Stack, k: int, s: int) -> float:
    lo, hi = stack.support(k)
    return hi if s >= 0 else lo


def centres(stack: Stack, phi, corners_):
    """Each block's centre as x + i z; the ground's origin at block 0's base centre at rest."""
    out = []
    point = complex(_corner(stack, 0, corners_[0]), 0.0)           # the corner block 0 turns about
    for k in range(stack.n):
        spin = cmath.exp(-1j * phi[k])                                # a clockwise rotation of x + i z
        px = _corner(stack, k, corners_[k])
        out.append(point + spin * complex(-px, stack.h[k]))
        if k + 1 < stack.n:
            qx = _corner(stack, k + 1, corners_[k + 1]) + stack.off[k + 1]
            point = point + spin * complex(qx - px, 2.0 * stack.h[k])
    return out


def _absolute(psi):
    return np.cumsum(psi)


def _map(joints):
    """S: the open joints' relative rates to the absolute rates."""
    n = len(joints)
    cols = [j for j in range(n) if joints[j] != 0]
    return np.array([[1.0 if k >= j else 0.0 for j in cols] for k in range(n)]).reshape(n, len(cols))


def _mass(stack: Stack, q, joints):
    """S^T M S from the kinetic energy: the velocities of unit rates by differences of the positions."""
    corners_ = [1 if j >= 0 else -1 for j in joints]
    S = _map(joints)
    cols = []
    for c in range(S.shape[1]):
        plus = centres(stack, q + DIFF * S[:, c], corners_)
        minus = centres(stack, q - DIFF * S[:, c], corners_)
        cols.append(([(p - m) / (2 * DIFF) for p, m in zip(plus, minus)], S[:, c]))
    out = np.zeros((S.shape[1], S.shape[1]))
    for a, (va, wa) in enumerate(cols):
        for b, (vb, wb) in enumerate(cols):
            out[a, b] = sum(stack.m[k] * (va[k].real * vb[k].real + va[k].imag * vb[k].imag)
                            + stack.inertia[k] * wa[k] * wb[k] for k in range(stack.n))
    return out


def _potential(stack: Stack, q, joints, ah, av):
    corners_ = [1 if j >= 0 else -1 for j in joints]
    return sum(stack.m[k] * (ah * c.real + (G + av) * c.imag) for k, c in enumerate(centres(stack, q, corners_)))


def accelerations(stack: Stack, joints, psi, psi_rate, ah, av):
    """q'' (absolute) from Lagrange's equations in the open joints' coordinates."""
    S = _map(joints)
    q = _absolute(psi)
    if S.shape[1] == 0:
        return np.zeros(stack.n)
    z_rate = np.array([psi_rate[j] for j in range(stack.n) if joints[j] != 0])
    m = _mass(stack, q, joints)
    dm = [(_mass(stack, q + DIFF * S[:, c], joints) - _mass(stack, q - DIFF * S[:, c], joints)) / (2 * DIFF)
          for c in range(S.shape[1])]
    dv = np.array([(_potential(stack, q + DIFF * S[:, c], joints, ah, av)
                    - _potential(stack, q - DIFF * S[:, c], joints, ah, av)) / (2 * DIFF) for c in range(S.shape[1])])
    mdot = sum(dm[c] * z_rate[c] for c in range(S.shape[1]))
    dT = np.array([0.5 * z_rate @ dm[c] @ z_rate for c in range(S.shape[1])])
    return S @ np.linalg.solve(m, -mdot @ z_rate + dT - dv)


# --- the run: one solve_ivp per mode, scipy's DOP853 and its event location --------------------------------------

TAIL_S = 60.0


def _velocities(stack: Stack, q, qd, corners_):
    """Each block's centre velocity (x + i z) and rotation rate at the absolute rates ``qd``."""
    plus, minus = centres(stack, q + DIFF * qd, corners_), centres(stack, q - DIFF * qd, corners_)
    return [(p - m) / (2 * DIFF) for p, m in zip(plus, minus)], qd


def _momenta(stack: Stack, q, velocity, joints):
    """The momenta conjugate to the open joints' coordinates of ``joints`` for the blocks' ``velocity``."""
    corners_ = [1 if j >= 0 else -1 for j in joints]
    S = _map(joints)
    v_b, w_b = velocity
    out = []
    for c in range(S.shape[1]):
        v_c, w_c = _velocities(stack, q, S[:, c], corners_)
        out.append(sum(stack.m[k] * (v_c[k].real * v_b[k].real + v_c[k].imag * v_b[k].imag)
                       + stack.inertia[k] * w_c[k] * w_b[k] for k in range(stack.n)))
    return np.array(out)


def impact(stack: Stack, psi, psi_rate, before, after):
    """The relative rates after an impulse at the contacts of ``after``: the momentum conjugate to its coordinates
    kept (the impulses do no work on its free directions)."""
    q, qd = _absolute(psi), _absolute(psi_rate)
    S = _map(after)
    if S.shape[1] == 0:
        return np.zeros(stack.n)
    velocity = _velocities(stack, q, qd, [1 if j >= 0 else -1 for j in before])
    qd_after = S @ np.linalg.solve(_mass(stack, q, after), _momenta(stack, q, velocity, after))
    return np.diff(np.concatenate([[0.0], qd_after]))


def _release(stack: Stack, joints, k, s, psi, psi_rate, ah, av):
    """s x joint k's rotation's acceleration were it released on corner s."""
    released = list(joints)
    released[k] = s
    qdd = accelerations(stack, released, psi, psi_rate, ah, av)
    return s * (qdd[k] - (qdd[k - 1] if k else 0.0))


class Result:
    """The first fall (the lowest falling block, -1 none) and each joint's largest |psi| [rad]."""

    def __init__(self, n):
        self.falls, self.peaks = -1, np.zeros(n)


def simulate(stack: Stack, ah: np.ndarray, dt: float, *, rest, tail_s: float = TAIL_S) -> Result:
    """The stack at rest under ``ah`` [m s-2] to rest after the record, its first fall or ``tail_s`` [s] after the
    record; ``rest``: each joint's rebound below which an impact shuts it [rad s-1]."""
    times = np.arange(ah.size) * dt
    t_rec = times[-1]

    def ground(t):
        return float(np.interp(t, times, ah, right=0.0)), 0.0

    out = Result(stack.n)
    joints, psi, rate, t = [0] * stack.n, np.zeros(stack.n), np.zeros(stack.n), 0.0
    while t < t_rec + tail_s:
        if not any(joints):
            if t >= t_rec:
                return out
            t, joints = _first_opening(stack, ground, times, t)
            if joints is None:
                return out
            continue
        t, psi, rate, joints, fell = _segment(stack, joints, psi, rate, t, t_rec + tail_s, ground, out, rest)
        if fell:
            return out
    return out


def _first_opening(stack: Stack, ground, times, t):
    """At rest: the first time a joint's release condition turns positive (a root by brentq), and the joints then."""
    from scipy.optimize import brentq

    cands = [(k, s) for k in range(stack.n) for s in (1, -1)]
    zero = np.zeros(stack.n)

    def indicator(tt, k, s):
        return _release(stack, [0] * stack.n, k, s, zero, zero, *ground(tt))

    def opened(k, s):
        joints = [0] * stack.n
        joints[k] = s
        return joints

    prev = [indicator(t, k, s) for k, s in cands]
    for c, value in enumerate(prev):
        if value > 0:
            return t, opened(*cands[c])
    grid = np.concatenate([[t], times[times > t]])
    for a, b in zip(grid[:-1], grid[1:]):
        now = [indicator(b, k, s) for k, s in cands]
        hits = [(brentq(lambda tt, k=k, s=s: indicator(tt, k, s), a, b, xtol=1e-14), (k, s))
                for (k, s), x0, x1 in zip(cands, prev, now) if x0 <= 0 < x1]
        if hits:
            t_open, (k, s) = min(hits)
            return t_open + 1e-12, opened(k, s)
        prev = now
    return times[-1], None


def _segment(stack: Stack, joints, psi, rate, t, t_end, ground, out: Result, rest):
    """One mode from t until an event: returns (t, psi, rates, the next joints, fell)."""
    from scipy.integrate import solve_ivp

    for k in range(stack.n):
        if not joints[k]:
            for s in (1, -1):
                if _release(stack, joints, k, s, psi, rate, *ground(t)) > 0:     # opens at once (after a stop)
                    nxt = list(joints)
                    nxt[k] = s
                    return t, psi, rate, nxt, False
    open_ = [k for k in range(stack.n) if joints[k]]
    nz = len(open_)

    def unpack(y):
        p, r = np.zeros(stack.n), np.zeros(stack.n)
        p[open_], r[open_] = y[:nz], y[nz:]
        return p, r

    def rhs(tt, y):
        p, r = unpack(y)
        qdd = accelerations(stack, joints, p, r, *ground(tt))
        rel = np.diff(np.concatenate([[0.0], qdd]))
        return np.concatenate([y[nz:], rel[open_]])

    def event(fun, direction):
        return TerminalEvent(fun, direction, unpack)

    events = [event(lambda tt, p, r, k=k: joints[k] * p[k], -1) for k in open_]
    events.append(event(lambda tt, p, r: math.pi / 2 - max(np.abs(np.cumsum(p)).max(), np.abs(p).max()), -1))
    shut = [(k, s) for k in range(stack.n) if not joints[k] for s in (1, -1)]
    events += [event(lambda tt, p, r, k=k, s=s: _release(stack, joints, k, s, p, r, *ground(tt)), 1)
               for k, s in shut]
    sol = solve_ivp(rhs, (t, t_end), np.concatenate([psi[open_], rate[open_]]), method="DOP853", rtol=1e-9,
                    atol=1e-10, events=events, dense_output=True, max_step=0.01)
    z = sol.sol(np.linspace(t, sol.t[-1], 4000))
    for c, k in enumerate(open_):
        out.peaks[k] = max(out.peaks[k], float(np.max(np.abs(z[c]))))
    psi, rate = unpack(sol.y[:, -1])
    if sol.status != 1:
        return sol.t[-1], psi, rate, joints, False
    t_ev = sol.t[-1]
    fired = [c for c, te in enumerate(sol.t_events) if te.size][0]
    if fired == nz:                                          # a fall: the lowest block past pi / 2
        phi = np.cumsum(psi)
        out.falls = min(k for k in range(stack.n) if max(abs(phi[k]), abs(psi[k])) >= math.pi / 2 - 1e-9)
        return t_ev, psi, rate, joints, True
    if fired > nz:                                           # a shut joint lifts off
        k, s = shut[fired - nz - 1]
        nxt = list(joints)
        nxt[k] = s
        return t_ev, psi, rate, nxt, False
    k = open_[fired]                                         # an impact at joint k
    psi = psi.copy()
    psi[k] = 0.0
    after = list(joints)
    after[k] = -joints[k]
    rate = impact(stack, psi, rate, joints, after)
    if after[k] * rate[k] <= rest[k]:
        stopped = list(after)
        stopped[k] = 0
        rate, after = impact(stack, psi, rate, after, stopped), stopped
    return t_ev, psi, rate, after, False
