"""Benchmark: pulse extraction and classification against a straightforward MATLAB port.

The straightforward port does what ``classification_algo.m``/``analyze_record.m`` do
literally: the 51-scale transform of both components for the candidate search, one
``fftconvolve`` per scale with the kernel rebuilt each time, and in every one of the
10 iterations a full-length transform of the residual at the refined scales. The
optimized path (pipeline.pulses) transforms each component once, caches kernel
spectra, uses one scale in the iterations and only the search window.

Then the pulse along 360 orientations (an inventory's distinct azimuths), as ``screen`` extracts it, against the
second algorithm of ``tests/pulses/test_along.py`` (the refinement one coefficient at a time, the residual
transformed itself).

Run: .venv/bin/python benchmarks/bench_pulses.py   (prints measured times and the ratios;
both paths must give identical candidates, and the pulses along each orientation must agree).
"""

from __future__ import annotations

import heartbeat  # noqa: F401  # isort: skip  (first: a line every 2 s of silence, imports included)

import math
import sys
import time
from pathlib import Path

import numpy as np
import obspy
import pywt
from scipy.signal import fftconvolve

from pipeline.pulses.along import extract_along
from pipeline.pulses.characterize import dominant_lobe, pulse_lobe
from pipeline.pulses.cwt import pseudo_period, scales_for
from pipeline.pulses.shahi_baker import (
    N_CANDIDATES,
    N_WAVELETS,
    WINDOW_FRACTION,
    classify,
    dwt_energy,
    is_late,
    pulse_indicator,
    wavelet_on_grid,
)

RECORDS = Path(__file__).resolve().parents[1] / "records" / "pulse-reference"


def naive_cwt(x, scales):
    _, psi, xv = pywt.Wavelet("db4").wavefun(level=10)
    h = xv[1] - xv[0]
    integ = np.cumsum(psi) * h
    out = np.empty((len(scales), x.size))
    for k, a in enumerate(scales):
        j = np.floor(np.arange(int(np.floor(a * 7)) + 1) / (a * h)).astype(int)
        f = integ[j][::-1]
        d = np.diff(fftconvolve(x, f))
        first = (d.size - x.size) // 2
        out[k] = -math.sqrt(a) * d[first:first + x.size]
    return out


def naive_classify(v, dt):
    scales = scales_for(dt)
    n = v.shape[1]
    zeroed = np.zeros(n, dtype=bool)
    out = []
    for _ in range(N_CANDIDATES):
        c1, c2 = naive_cwt(v[0], scales), naive_cwt(v[1], scales)
        energy = c1**2 + c2**2
        energy[:, zeroed] = 0
        flat = int(np.argmax(energy.ravel(order="F")))
        row, col = flat % len(scales), flat // len(scales)
        theta = math.atan(c2[row, col] / c1[row, col])
        vt = math.cos(theta) * v[0] + math.sin(theta) * v[1]
        refined = np.arange(scales[max(0, row - 1)], scales[min(len(scales) - 1, row + 1)] + 1)
        scale = int(refined[np.argmax(np.abs(naive_cwt(vt, refined)[:, col]))])
        pulse = np.zeros(n)
        centre, half = col, int(math.ceil(WINDOW_FRACTION * scale))
        for i in range(N_WAVELETS):
            c = naive_cwt(vt - pulse, refined)[list(refined).index(scale)]
            lo, hi = max(0, centre - half), min(n - 1, centre + half)
            k = lo + int(np.argmax(np.abs(c[lo:hi + 1])))
            centre = k if i == 0 else centre
            pulse += wavelet_on_grid(float(c[k]), scale, k, n)
        resid = vt - pulse
        pgv = np.max(np.abs(vt))
        pi = pulse_indicator(np.max(np.abs(resid)) / pgv, dwt_energy(resid) / dwt_energy(vt), pgv)
        out.append((scale, pseudo_period(scale, dt), pi, is_late(vt, pulse)))
        zeroed |= np.abs(np.arange(n) - col) < WINDOW_FRACTION * scales[row]
    return out


def main() -> int:
    a = [obspy.read(str(RECORDS / f"example{k}.AT2"))[0].data for k in (1, 2)]
    dt = 0.005
    v = np.vstack([np.cumsum(x) * dt * 981 for x in a])
    classify(v, dt)  # warm caches once, as a batch run would
    t0 = time.perf_counter()
    naive = naive_classify(v, dt)
    t_naive = time.perf_counter() - t0
    reps = 5
    t0 = time.perf_counter()
    for _ in range(reps):
        fast = classify(v, dt)
    t_fast = (time.perf_counter() - t0) / reps
    same = all(c.scale == s and abs(c.tp_s - tp) < 1e-12 and abs(c.pulse_indicator - pi) < 1e-6
               and c.late == late for c, (s, tp, pi, late) in zip(fast.candidates, naive))
    print(f"record: example1/2.AT2 (2 components x {v.shape[1]} samples, dt = {dt} s)")
    print(f"straightforward port: {t_naive:.3f} s   optimized: {t_fast:.4f} s   ratio: {t_naive / t_fast:.1f}x")
    print(f"identical candidates (scale, Tp, PI to 1e-6, late): {same}")
    close = along_orientations(fast)
    return 0 if same and close else 1


def along_orientations(res, n_orientations: int = 360) -> bool:
    """The pulse along every half degree (an inventory's distinct azimuths), as ``screen`` extracts it
    (:func:`extract_along`: the components' window transforms shared by the orientations) against the second
    algorithm the tests use (``compiled=False``: the refinement one coefficient at a time, the residual transformed
    itself, :func:`dominant_lobe` of the whole series), both with their lobes; True when the pulses agree to 1e-9 of
    their peak and the lobes to 1e-9."""
    angles = np.radians(np.arange(n_orientations) * 180.0 / n_orientations)
    dt = res.dt_s

    def run(compiled: bool) -> tuple[float, list]:
        res._along, res._strongest = None, None           # nothing kept from an earlier pass
        t0 = time.perf_counter()
        out = []
        for phi in angles:
            _, pulse = extract_along(res, float(phi), compiled=compiled)
            lobe = (pulse_lobe(pulse / 100.0, dt) if compiled
                    else dominant_lobe(np.gradient(pulse / 100.0, dt), dt))
            out.append((pulse, lobe))
        return time.perf_counter() - t0, out

    t_one, one = run(False)
    t_shared, shared = run(True)
    close = all(np.max(np.abs(p1 - p2)) <= 1e-9 * max(np.max(np.abs(p2)), 1e-300)
                and np.allclose([l1.ap_ms2, l1.tp_s, l1.dv_ms], [l2.ap_ms2, l2.tp_s, l2.dv_ms], rtol=1e-9, atol=0)
                for (p1, l1), (p2, l2) in zip(shared, one))
    print(f"pulse along {n_orientations} orientations: one by one {t_one:.3f} s ({1e3 * t_one / n_orientations:.2f} ms "
          f"each)   shared: {t_shared:.3f} s ({1e3 * t_shared / n_orientations:.2f} ms each)   "
          f"ratio: {t_one / t_shared:.1f}x")
    print(f"pulses within 1e-9 of their peak, lobes to 1e-9: {close}")
    return close


if __name__ == "__main__":
    sys.exit(main())
