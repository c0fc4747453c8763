"""An independent solution of two stacked rocking blocks, for the tests: Lagrange's equations of the blocks' energy
(positions as complex numbers, the mass matrix's derivative and the potential's gradient by central differences),
integrated by scipy's DOP853 with its event location, one ``solve_ivp`` per mode.

It shares with :mod:`pipeline.assemblies.two_block_run` only the rules of the model (the impact conserves the
momentum conjugate to the new mode's coordinates; a rebound below ``rest_ratio`` p alpha shuts the joint; a fall is a
rotation of pi/2), not its code.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

G = 9.80665
TAIL_S = 60.0
DIFF = 1e-6


@dataclass(frozen=True)
class Pair:
    """Two blocks: lower (b1, h1, m1), upper (b2, h2, m2) half-sizes [m] and masses [kg], the upper's offset [m]."""

    b1: float
    h1: float
    m1: float
    b2: float
    h2: float
    m2: float
    offset: float = 0.0

    @property
    def support(self) -> tuple[float, float]:
        return max(-self.b1, self.offset - self.b2), min(self.b1, self.offset + self.b2)

    def inertia(self) -> tuple[float, float]:
        return self.m1 * (self.b1 ** 2 + self.h1 ** 2) / 3, self.m2 * (self.b2 ** 2 + self.h2 ** 2) / 3


def _spin(phi):
    return complex(math.cos(phi), -math.sin(phi))           # exp(-i phi): a clockwise rotation of x + i z


def _centres(pair: Pair, q, corners):
    """The two centres of mass as x + i z, and d(centre_k)/dq_j, for the corners (s1, s2)."""
    s1, s2 = corners
    o = s1 * pair.b1
    c = pair.support[1] if s2 > 0 else pair.support[0]
    lever1, joint, lever2 = complex(-o, pair.h1), complex(c - o, 2 * pair.h1), complex(pair.offset - c, pair.h2)
    r1, rj, r2 = _spin(q[0]) * lever1, _spin(q[0]) * joint, _spin(q[1]) * lever2
    return (o + r1, o + rj + r2), ((-1j * r1, 0j), (-1j * rj, -1j * r2))


def _velocities(pair: Pair, q, qd, corners):
    """The blocks' velocities (v1x, v1z, w1, v2x, v2z, w2) at rates qd."""
    _, jac = _centres(pair, q, corners)
    v1 = jac[0][0] * qd[0]
    v2 = jac[1][0] * qd[0] + jac[1][1] * qd[1]
    return (v1.real, v1.imag, qd[0], v2.real, v2.imag, qd[1])


def _weights(pair: Pair):
    i1, i2 = pair.inertia()
    return (pair.m1, pair.m1, i1, pair.m2, pair.m2, i2)


def _dot(w, a, b):
    return sum(wk * ak * bk for wk, ak, bk in zip(w, a, b))


@dataclass(frozen=True)
class Mode:
    """Joint states (0 shut, +-1 open on that corner) and the map q = S z."""

    j1: int
    j2: int

    @property
    def corners(self):
        return (1 if self.j1 >= 0 else -1, 1 if self.j2 >= 0 else -1)

    def z(self, q):
        """The mode's coordinates of q."""
        if self.j1 and self.j2:
            return np.asarray(q, dtype=float)
        return np.array([q[0] if self.j1 else q[1]])

    @property
    def S(self):
        if self.j1 and self.j2:
            return np.eye(2)
        if self.j1:
            return np.array([[1.0], [1.0]])
        return np.array([[0.0], [1.0]])


def _mass(pair: Pair, mode: Mode, q):
    """S^T M(q) S from the kinetic energy's quadratic form."""
    S, w = mode.S, _weights(pair)
    cols = [_velocities(pair, q, S[:, k], mode.corners) for k in range(S.shape[1])]
    return np.array([[_dot(w, a, b) for b in cols] for a in cols])


def _potential(pair: Pair, mode: Mode, q, ah, av):
    (c1, c2), _ = _centres(pair, q, mode.corners)
    return (pair.m1 * (ah * c1.real + (G + av) * c1.imag) + pair.m2 * (ah * c2.real + (G + av) * c2.imag))


def accelerations(pair: Pair, mode: Mode, q, qd, ah, av):
    """q'' from Lagrange's equations in the mode's coordinates z (q = S z on the mode's manifold)."""
    S = mode.S
    zd = mode.z(qd)
    m = _mass(pair, mode, q)
    dm = [(_mass(pair, mode, q + DIFF * S[:, k]) - _mass(pair, mode, q - DIFF * S[:, k])) / (2 * DIFF)
          for k in range(S.shape[1])]
    dv = np.array([(_potential(pair, mode, q + DIFF * S[:, k], ah, av)
                    - _potential(pair, mode, q - DIFF * S[:, k], ah, av)) / (2 * DIFF) for k in range(S.shape[1])])
    mdot = sum(dm[k] * zd[k] for k in range(S.shape[1]))
    dT = np.array([0.5 * zd @ dm[k] @ zd for k in range(S.shape[1])])
    zdd = np.linalg.solve(m, -mdot @ zd + dT - dv)
    return S @ zdd


def _release_rate(pair: Pair, mode: Mode, joint: int, corner: int, q, qd, ah, av):
    """corner x the joint's rotation's acceleration were it released on ``corner``."""
    released = Mode(corner, mode.j2) if joint == 1 else Mode(mode.j1, corner)
    qdd = accelerations(pair, released, q, qd, ah, av)
    return corner * (qdd[0] if joint == 1 else qdd[1] - qdd[0])


def _impact(pair: Pair, q, qd, before: Mode, after: Mode):
    """The rates after an impulse at the contacts of ``after``: the momentum conjugate to its coordinates kept."""
    S, w = after.S, _weights(pair)
    v_before = _velocities(pair, q, qd, before.corners)
    cols = [_velocities(pair, q, S[:, k], after.corners) for k in range(S.shape[1])]
    momentum = np.array([_dot(w, c, v_before) for c in cols])
    return S @ np.linalg.solve(_mass(pair, after, q), momentum)


@dataclass
class Result:
    falls: int = 0             # 0 none, 1 the top, 2 the stack
    peak_phi1: float = 0.0
    peak_psi: float = 0.0
    modes: set = None  # type: ignore[assignment]


def simulate(pair: Pair, ah: np.ndarray, dt: float, *, rest1: float, rest2: float, av: np.ndarray | None = None
             ) -> Result:
    """The stack at rest under ``ah`` [m s-2] (and the vertical ``av``, when given) to rest after the record or a
    fall."""
    times = np.arange(ah.size) * dt
    t_rec = times[-1]
    vertical = np.zeros(ah.size) if av is None else av

    def ground(t):
        return float(np.interp(t, times, ah, right=0.0)), float(np.interp(t, times, vertical, right=0.0))

    out = Result(modes=set())
    mode, q, qd, t = Mode(0, 0), np.zeros(2), np.zeros(2), 0.0
    while t < t_rec + TAIL_S:
        if mode.j1 == 0 and mode.j2 == 0:
            if t >= t_rec:
                return out
            t, mode = _first_opening(pair, q, ground, times, t)
            if mode is None:
                return out
            continue
        out.modes.add((mode.j1 != 0, mode.j2 != 0))
        t, q, qd, mode, fell = _segment(pair, mode, q, qd, t, t_rec + TAIL_S, ground, out, rest1, rest2)
        if fell:
            return out
    return out


def _first_opening(pair: Pair, q, ground, times, t):
    """At rest: the first time a joint's release condition turns positive (a root by brentq), and its mode."""
    cands = [(j, s) for j in (1, 2) for s in (1, -1)]

    def indicator(tt, j, s):
        return _release_rate(pair, Mode(0, 0), j, s, q, np.zeros(2), *ground(tt))

    grid = np.concatenate([[t], times[times > t]])
    prev = [indicator(t, j, s) for j, s in cands]
    for k, s0 in enumerate(prev):
        if s0 > 0:
            j, s = cands[k]
            return t, (Mode(s, 0) if j == 1 else Mode(0, s))
    for a, b in zip(grid[:-1], grid[1:]):
        now = [indicator(b, j, s) for j, s in cands]
        hits = [(brentq(lambda tt, j=j, s=s: indicator(tt, j, s), a, b, xtol=1e-14), (j, s))
                for (j, s), x0, x1 in zip(cands, prev, now) if x0 <= 0 < x1]
        if hits:
            t_open, (j, s) = min(hits)
            return t_open + 1e-12, (Mode(s, 0) if j == 1 else Mode(0, s))
        prev = now
    return times[-1], None


class TerminalEvent:
    """A terminal event of solve_ivp (its attributes ``terminal`` and ``direction``): ``fun(t, *unpack(y))``."""

    terminal = True

    def __init__(self, fun, direction, unpack):
        self.fun, self.direction, self.unpack = fun, direction, unpack

    def __call__(self, tt, y):
        return self.fun(tt, *self.unpack(y))


def _segment(pair: Pair, mode: Mode, q, qd, t, t_end, ground, out: Result, rest1, rest2):
    """One mode from t until an event: returns (t, q, qd, the next mode, fell)."""
    for j, s in [(1, s) for s in (1, -1) if not mode.j1] + [(2, s) for s in (1, -1) if not mode.j2]:
        if _release_rate(pair, mode, j, s, q, qd, *ground(t)) > 0:       # opens at once (after a stop)
            return t, q, qd, (Mode(s, mode.j2) if j == 1 else Mode(mode.j1, s)), False
    S = mode.S
    nz = S.shape[1]

    def unpack(y):
        return S @ y[:nz], S @ y[nz:]

    def rhs(tt, y):
        qq, qqd = unpack(y)
        qdd = accelerations(pair, mode, qq, qqd, *ground(tt))
        return np.concatenate([y[nz:], mode.z(qdd)])

    events = []

    def event(fun, direction):
        events.append(TerminalEvent(fun, direction, unpack))

    if mode.j1:
        event(lambda tt, qq, qqd: mode.j1 * qq[0], -1)
    if mode.j2:
        event(lambda tt, qq, qqd: mode.j2 * (qq[1] - qq[0]), -1)
    event(lambda tt, qq, qqd: math.pi / 2 - max(abs(qq[0]), abs(qq[1]), abs(qq[1] - qq[0])), -1)
    shut = [(1, s) for s in (1, -1) if not mode.j1] + [(2, s) for s in (1, -1) if not mode.j2]
    for j, s in shut:
        event(lambda tt, qq, qqd, j=j, s=s: _release_rate(pair, mode, j, s, qq, qqd, *ground(tt)), 1)
    y0 = np.concatenate([mode.z(q), mode.z(qd)])
    sol = solve_ivp(rhs, (t, t_end), y0, method="DOP853", rtol=1e-9, atol=1e-10, events=events,
                    dense_output=True, max_step=0.01)
    grid = np.linspace(t, sol.t[-1], 4000)
    z = sol.sol(grid)
    qs = S @ z[:nz]
    out.peak_phi1 = max(out.peak_phi1, float(np.max(np.abs(qs[0]))))
    out.peak_psi = max(out.peak_psi, float(np.max(np.abs(qs[1] - qs[0]))))
    if sol.status != 1:
        return sol.t[-1], *unpack(sol.y[:, -1]), mode, False
    t_ev = sol.t[-1]
    q, qd = unpack(sol.y[:, -1])
    fired = [k for k, te in enumerate(sol.t_events) if te.size]
    k = fired[0]
    n_impacts = (1 if mode.j1 else 0) + (1 if mode.j2 else 0)
    if k == n_impacts:                                      # the fall
        out.falls = 2 if abs(q[0]) >= math.pi / 2 - 1e-9 else 1
        return t_ev, q, qd, mode, True
    if k > n_impacts:                                       # a shut joint lifts off
        j, s = shut[k - n_impacts - 1]
        return t_ev, q, qd, (Mode(s, mode.j2) if j == 1 else Mode(mode.j1, s)), False
    joint = 1 if (mode.j1 and k == 0) else 2
    if joint == 1:
        q = np.array([0.0, q[1] if mode.j2 else 0.0])
        after = Mode(-mode.j1, mode.j2)
    else:
        q = np.array([q[0], q[0]])
        after = Mode(mode.j1, -mode.j2)
    qd = _impact(pair, q, qd, mode, after)
    if joint == 1 and after.j1 * qd[0] <= rest1:
        qd, after = _impact(pair, q, qd, after, Mode(0, after.j2)), Mode(0, after.j2)
        q = np.array([0.0, q[1]])
    elif joint == 2 and after.j2 * (qd[1] - qd[0]) <= rest2:
        qd, after = _impact(pair, q, qd, after, Mode(after.j1, 0)), Mode(after.j1, 0)
    return t_ev, q, qd, after, False
