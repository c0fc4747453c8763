"""Benchmark: the rocking step with its stages' sine and cosine rotated from the step's start, against calling
math.sin and math.cos at every stage.

``dopri.dopri_step`` takes sin and cos of alpha s - theta by math.sin and math.cos at the step's two ends and, at
the stages inside it, rotates the start's by the stage's change of theta (``dopri._rotated``, where that change
is at most ``ROTATION_MAX_RAD``). The reference here is the same Dormand-Prince step with math.sin and math.cos at
all seven stages (``rk_step`` with ``dopri._plane``). On random steps of the planar rocking equation (tilts, rates,
ground pieces and step lengths over the ranges the kernel meets) the script prints each one's time per step in a
compiled loop, and how far they agree: theta and omega relative to the step's scale, and the error estimates.

Run: .venv/bin/python benchmarks/bench_step_trig.py [--steps N]
"""

from __future__ import annotations

import heartbeat  # noqa: F401  # isort: skip  (first: a line every 2 s of silence, imports included)

import argparse

import numba
import numpy as np
from bench_cubic_events import time_per_case

from pipeline.rocking.numerics.dopri import _plane, dopri_step
from pipeline.rocking.numerics.rk import DOPRI54, rk_step
from pipeline.rocking.structures import GroundPiece

G = 9.80665


@numba.njit(cache=False)
def _all_stages_by_libm(t, th, om, h, pc, s, p2, alpha, g, linear):
    args = (pc, s, p2, alpha, g, linear)
    f, _ = _plane(t, (th, om), args)
    st = rk_step(_plane, args, t, (th, om), f, h, DOPRI54)
    return st.y[0], st.y[1], st.err[0], st.err[1]


@numba.njit(cache=False)
def _steps(cases, rotated):
    out = np.empty((cases.shape[0], 4))
    for i in range(cases.shape[0]):
        c = cases[i]
        pc = GroundPiece(0, c[0], c[0] + 0.01, c[5], c[6], 0.0, 0.0, c[7], 0.0)
        if rotated:
            th1, om1, et, eo, _a, _s, _c = dopri_step(c[1], c[2], c[3], c[4], pc, c[8], c[9], c[10], G, False)
        else:
            th1, om1, et, eo = _all_stages_by_libm(c[1], c[2], c[3], c[4], pc, c[8], c[9], c[10], G, False)
        out[i, 0], out[i, 1], out[i, 2], out[i, 3] = th1, om1, et, eo
    return out


def _cases(n: int, rng: np.random.Generator) -> np.ndarray:
    """(t0, t, theta, omega, h, a0, a1, slope, s, p^2, alpha): blocks of p 1-5 rad/s and alpha 0.05-0.5 rad,
    tilts up to alpha, rates up to 2 p alpha, steps 1e-4-1e-2 s, ground up to 1 g."""
    t0 = rng.uniform(0, 20, n)
    t = t0 + rng.uniform(0, 0.005, n)
    alpha = rng.uniform(0.05, 0.5, n)
    p = rng.uniform(1.0, 5.0, n)
    theta = rng.uniform(-1, 1, n) * alpha
    omega = rng.uniform(-2, 2, n) * p * alpha
    h = 10.0 ** rng.uniform(-4, -2, n)
    a0, a1 = rng.normal(0, 3, n), rng.normal(0, 3, n)
    s = np.where(theta > 0, 1.0, -1.0)
    return np.ascontiguousarray(np.column_stack([t0, t, theta, omega, h, a0, a1, (a1 - a0) / 0.01, s, p * p,
                                                 alpha]))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--steps", type=int, default=1_000_000)
    args = ap.parse_args()
    cases = _cases(args.steps, np.random.default_rng(2026))
    new, t_new = time_per_case(_steps, cases, True)
    old, t_old = time_per_case(_steps, cases, False)
    scale = np.abs(cases[:, 2]) + np.abs(cases[:, 4] * cases[:, 3])
    d_theta = np.max(np.abs(new[:, 0] - old[:, 0]) / scale)
    d_omega = np.max(np.abs(new[:, 1] - old[:, 1]) / (np.abs(cases[:, 3]) + cases[:, 4] * cases[:, 9]))
    d_err = np.max(np.abs(new[:, 2] - old[:, 2]) / scale)
    identical = int(np.sum(np.all(new[:, :2] == old[:, :2], axis=1)))
    print(f"steps ({args.steps}): rotated stages {1e9 * t_new:.0f} ns, math.sin and math.cos at every stage "
          f"{1e9 * t_old:.0f} ns a step ({t_old / t_new:.2f}x)")
    print(f"  theta differs by at most {d_theta:.1e} of the step's scale, omega by {d_omega:.1e}; "
          f"{identical} of {args.steps} steps give the same doubles; theta's error estimate differs by at most "
          f"{d_err:.1e} of the scale")


if __name__ == "__main__":
    main()
