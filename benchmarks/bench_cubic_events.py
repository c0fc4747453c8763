"""Benchmark: the rocking kernel's events on a step's Hermite cubic, solved against searched.

Where a step crosses theta = 0 the kernel reads the crossing off the step's cubic (``dopri.first_crossing``: 16
probes, then safeguarded Newton in the first bracket), and where omega changes sign the peak |theta| at the cubic's
turning point (``dopri.hermite_peak``: the root of the rate, a quadratic, by the quadratic formula). The searches
they replaced are kept here as the reference: the same probes then 50 bisections, and 40 bisections on the rate.
On random steps (theta, omega, the step's length over decades) the script prints each one's time per call in a
compiled loop, and how far the two agree: the crossings as a fraction of the step, the peaks relative.

Run: .venv/bin/python benchmarks/bench_cubic_events.py [--steps N]
"""

from __future__ import annotations

import heartbeat  # noqa: F401  # isort: skip  (first: a line every 2 s of silence, imports included)

import argparse
import time

import numba
import numpy as np

from pipeline.rocking.numerics.dopri import CROSSING_PROBES, first_crossing, hermite, hermite_peak, hermite_rate

BISECTIONS_CROSSING = 50
BISECTIONS_PEAK = 40


@numba.njit(cache=False)
def crossing_by_bisection(th0, om0, th1, om1, h, s):
    prev = 0.0
    for i in range(1, CROSSING_PROBES + 1):
        x = i / CROSSING_PROBES
        if s * hermite(th0, om0, th1, om1, h, x) < 0.0:
            lo, hi = prev, x
            for _ in range(BISECTIONS_CROSSING):
                mid = 0.5 * (lo + hi)
                if s * hermite(th0, om0, th1, om1, h, mid) < 0.0:
                    hi = mid
                else:
                    lo = mid
            return 0.5 * (lo + hi)
        prev = x
    return -1.0


@numba.njit(cache=False)
def peak_by_bisection(th0, om0, th1, om1, h):
    best = max(abs(th0), abs(th1))
    lo, hi = 0.0, 1.0
    for _ in range(BISECTIONS_PEAK):
        mid = 0.5 * (lo + hi)
        if hermite_rate(th0, om0, th1, om1, h, mid) * om0 > 0:
            lo = mid
        else:
            hi = mid
    return max(best, abs(hermite(th0, om0, th1, om1, h, 0.5 * (lo + hi))))


@numba.njit(cache=False)
def _crossings(cases, solved):
    out = np.empty(cases.shape[0])
    for i in range(cases.shape[0]):
        c = cases[i]
        out[i] = (first_crossing(c[0], c[1], c[2], c[3], c[4], 1.0) if solved
                  else crossing_by_bisection(c[0], c[1], c[2], c[3], c[4], 1.0))
    return out


@numba.njit(cache=False)
def _peaks(cases, solved):
    out = np.empty(cases.shape[0])
    for i in range(cases.shape[0]):
        c = cases[i]
        out[i] = (hermite_peak(c[0], c[1], c[2], c[3], c[4]) if solved
                  else peak_by_bisection(c[0], c[1], c[2], c[3], c[4]))
    return out


def _cases(n: int, rng: np.random.Generator, *, crossing: bool) -> np.ndarray:
    """Steps (theta0, omega0, theta1, omega1, h) with theta0 > 0: ending below 0 (a crossing) or with omega changing
    sign (a turning point)."""
    h = 10.0 ** rng.uniform(-6, -1, n)
    th0 = np.abs(rng.normal(size=n)) * 10.0 ** rng.uniform(-8, -1, n)
    om0 = rng.normal(size=n) * 10.0 ** rng.uniform(-4, 1, n)
    om1 = rng.normal(size=n) * 10.0 ** rng.uniform(-4, 1, n)
    if crossing:
        th1 = -np.abs(rng.normal(size=n)) * 10.0 ** rng.uniform(-10, -1, n)
    else:
        th1 = np.abs(rng.normal(size=n)) * 10.0 ** rng.uniform(-8, -1, n)
        om1 = np.where(om0 * om1 < 0, om1, -om1)
    return np.ascontiguousarray(np.column_stack([th0, om0, th1, om1, h]))


def time_per_case(f, cases, variant) -> tuple[np.ndarray, float]:
    """``f(cases, variant)``'s output and its time per case [s], compiled outside the timing (also used by
    bench_step_trig.py)."""
    f(cases[:10], variant)
    t0 = time.perf_counter()
    out = f(cases, variant)
    return out, (time.perf_counter() - t0) / cases.shape[0]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--steps", type=int, default=1_000_000)
    args = ap.parse_args()
    rng = np.random.default_rng(2026)
    cross = _cases(args.steps, rng, crossing=True)
    x_new, t_new = time_per_case(_crossings, cross, True)
    x_old, t_old = time_per_case(_crossings, cross, False)
    print(f"crossings ({args.steps} steps): solved {1e6 * t_new:.3f} us, bisected {1e6 * t_old:.3f} us a call "
          f"({t_old / t_new:.1f}x); largest difference {np.max(np.abs(x_new - x_old)):.2e} of the step")
    worst = int(np.argmax(np.abs(x_new - x_old)))
    th0, om0, th1, om1, h = cross[worst]
    scale = max(abs(th0), abs(th1), abs(h * om0), abs(h * om1))
    at_new = abs(hermite(th0, om0, th1, om1, h, x_new[worst])) / scale
    at_old = abs(hermite(th0, om0, th1, om1, h, x_old[worst])) / scale
    slope = abs(hermite_rate(th0, om0, th1, om1, h, x_new[worst])) / scale
    print(f"  there |theta| / the step's scale: solved {at_new:.1e}, bisected {at_old:.1e}; the cubic's slope / scale "
          f"{slope:.1e}")
    turn = _cases(args.steps, rng, crossing=False)
    p_new, t_new = time_per_case(_peaks, turn, True)
    print("  turning points solved; bisecting them", flush=True)    # a compiled call of about 1 s follows
    p_old, t_old = time_per_case(_peaks, turn, False)
    rel = np.abs(p_new - p_old) / np.maximum(np.abs(p_old), 1e-300)
    print(f"turning points ({args.steps} steps): solved {1e6 * t_new:.4f} us, bisected {1e6 * t_old:.3f} us a call "
          f"({t_old / t_new:.0f}x); largest relative difference of the peak {np.max(rel):.2e}")


if __name__ == "__main__":
    main()
