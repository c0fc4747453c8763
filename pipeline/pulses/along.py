"""The pulse of a two-component record along many orientations, by superposition.

A block of given azimuth is checked against the pulse along its own plane: the Shahi & Baker (2014)
extraction (:func:`.shahi_baker.extract`) repeated on v(phi) = cos(phi) v1 + sin(phi) v2 for every distinct
azimuth of the inventory. Each repetition transforms the residual ten times; here the transform is linear in
everything it is applied to, so no transform of the record is repeated:

* the coefficients of v(phi) are cos C1 + sin C2 of the components' transforms (the strongest point,
  :func:`_strongest_point`); the scale refinement's coefficients at one sample are computed for all its
  scales in one compiled loop (:func:`.cwt.column_coefficients`);
* the residual after m wavelets is v(phi) minus m db4 wavelets of one scale a at integer positions p_i:
  C_res(a, k) = cos W1(a, k) + sin W2(a, k) - sum_i c_i R_a(k - p_i), where W1, W2 are the components'
  rows at scale a (one transform each per record and scale) and R_a the transform of a unit wavelet at that
  scale, a function of k - p only while the wavelet lies wholly inside the record (a wavelet cut by the
  record's ends is transformed on its own, once per record, scale and position).

Equal to :func:`.shahi_baker.extract` on v(phi) up to rounding (``tests/pulses/test_along.py`` compares the
two on real records at every azimuth, with wavelets cut by the record's ends).

References
----------
Shahi, S. K., & Baker, J. W. (2014). An efficient algorithm to identify strong-velocity pulses in
multicomponent ground motions. BSSA 104(5), 2456-2466.
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np
from scipy import fft as sfft

from .cwt import column_coefficients, cwt_point, cwt_window, kernel, step_bank
from .shahi_baker import N_WAVELETS, WINDOW_FRACTION, PulseResult, _add_wavelet, _wavefun4, extract


class AlongCache:
    """What every orientation of one record shares: the components' rows per scale, the scale refinement's kernel
    steps, and the transforms of wavelets cut by the record's ends (kept with the record's result, and freed
    with it).

    Parameters
    ----------
    velocity_cms : ndarray, shape (2, N)
        The two horizontal velocities [cm/s].
    """

    def __init__(self, velocity_cms: np.ndarray) -> None:
        self.v = velocity_cms
        self._rows: dict[int, tuple[np.ndarray, np.ndarray]] = {}
        self._cut: dict[tuple[int, int], tuple[int, np.ndarray]] = {}
        self._banks: dict[tuple[int, int], tuple[np.ndarray, np.ndarray]] = {}

    def rows(self, scale: int) -> tuple[np.ndarray, np.ndarray]:
        """Both components' coefficients at ``scale``, every sample."""
        if scale not in self._rows:
            n = self.v.shape[1]
            self._rows[scale] = (cwt_window(self.v[0], scale, 0, n - 1), cwt_window(self.v[1], scale, 0, n - 1))
        return self._rows[scale]


    def bank(self, first_scale: int, last_scale: int) -> tuple[np.ndarray, np.ndarray]:
        """The kernel steps of a refinement's scales (:func:`.cwt.step_bank`), kept for the record."""
        key = (first_scale, last_scale)
        if key not in self._banks:
            self._banks[key] = step_bank(first_scale, last_scale)
        return self._banks[key]

    def cut(self, scale: int, position: int) -> tuple[int, np.ndarray]:
        """The transform at ``scale`` of a unit wavelet cut by the record's ends, on the samples within two
        search half-windows of its position (every window that can hold it): (first sample, values)."""
        key = (scale, position)
        if key not in self._cut:
            n = self.v.shape[1]
            reach = 2 * int(math.ceil(WINDOW_FRACTION * scale))
            lo, hi = max(0, position - reach), min(n - 1, position + reach)
            self._cut[key] = (lo, cwt_window(_add_wavelet(np.zeros(n), 1.0, scale, position), scale, lo, hi))
        return self._cut[key]


def _support(scale: int, position: int) -> tuple[float, float]:
    """First and last sample time of a wavelet's support [samples] (as :func:`.shahi_baker._add_wavelet`)."""
    _, x, centre = _wavefun4()
    return (x[0] - centre) * scale + position, (x[-1] - centre) * scale + position


@lru_cache(maxsize=16)
def unit_response(scale: int) -> tuple[np.ndarray, int]:
    """The transform at ``scale`` of a unit wavelet of that scale, against k - p (output sample minus the
    wavelet's position): (values, offset), values[offset + d] at k - p = d, for |d| up to the wavelet's
    support plus the kernel's length (zero beyond)."""
    f = kernel(scale)
    t0, t1 = _support(scale, 0)
    pad = f.size + 2
    lo = int(math.floor(t0)) - pad
    n = int(math.ceil(t1)) - lo + pad + 1
    pos = -lo                                   # the wavelet's position in a zero signal of n samples
    w = _add_wavelet(np.zeros(n), 1.0, scale, pos)
    nfft = sfft.next_fast_len(n + f.size - 1, real=True)
    full = sfft.irfft(sfft.rfft(w, nfft) * sfft.rfft(f, nfft), nfft)[: n + f.size - 1]
    first = (f.size - 2) // 2                   # cwt._first_kept: independent of the signal's length
    values = -math.sqrt(scale) * np.diff(full[first:first + n + 1])
    values.setflags(write=False)
    return values, pos


def _inside(scale: int, position: int, n: int) -> bool:
    """True when the wavelet at ``position`` lies wholly on samples 0..n-1 (its transform is R_a shifted)."""
    t0, t1 = _support(scale, position)
    return math.ceil(t0) >= 0 and math.floor(t1) <= n - 1


def _residual_window(cache: AlongCache, base: np.ndarray, scale: int, lo: int, hi: int,
                     positions: list[int], coefs: list[float]) -> np.ndarray:
    """Coefficients at ``scale`` on samples lo..hi of v(phi) minus the wavelets found so far (``base``: those
    of v(phi) there)."""
    n = cache.v.shape[1]
    resp, offset = unit_response(scale)
    c = base.copy()
    for p, coef in zip(positions, coefs):
        if _inside(scale, p, n):
            d0, d1 = lo - p + offset, hi - p + offset          # R_a(k - p) for k = lo..hi, zero off its span
            a0, a1 = max(d0, 0), min(d1, resp.size - 1)
            if a1 >= a0:
                c[a0 - d0:a1 - d0 + 1] -= coef * resp[a0:a1 + 1]
            continue
        first, cut = cache.cut(scale, p)
        if first <= lo and hi - first < cut.size:
            c -= coef * cut[lo - first:hi - first + 1]
        else:                                                  # a window beyond the cached span: on its own
            c -= cwt_window(_add_wavelet(np.zeros(n), coef, scale, p), scale, lo, hi)
    return c


def extract_linear(cache: AlongCache, ca: float, sa: float, v_phi: np.ndarray, *, column: int, row: int,
                   scales: np.ndarray) -> np.ndarray:
    """The pulse of v(phi) = ca v1 + sa v2 [cm/s]: :func:`.shahi_baker.extract` by superposition.

    Parameters
    ----------
    cache : AlongCache
        The record's shared transforms.
    ca, sa : float
        cos and sin of the orientation from the first component.
    v_phi : ndarray
        ca v1 + sa v2 [cm/s].
    column, row : int
        The strongest point of v(phi)'s transform (sample, index in ``scales``).
    scales : ndarray
        The searched scales.
    """
    n = cache.v.shape[1]
    lo_s = scales[max(0, row - 1)]
    hi_s = scales[min(len(scales) - 1, row + 1)]
    values = np.abs(column_coefficients(v_phi, int(lo_s), int(hi_s), column, cache.bank(int(lo_s), int(hi_s))))
    scale = int(lo_s) + int(np.argmax(values))
    half = int(math.ceil(WINDOW_FRACTION * scale))
    w1, w2 = cache.rows(scale)
    pulse = np.zeros(n)
    positions: list[int] = []
    coefs: list[float] = []
    centre = column
    for i in range(N_WAVELETS):
        lo, hi = max(0, centre - half), min(n - 1, centre + half)
        c = _residual_window(cache, ca * w1[lo:hi + 1] + sa * w2[lo:hi + 1], scale, lo, hi, positions, coefs)
        k = int(np.argmax(np.abs(c)))
        pos, coef = lo + k, float(c[k])
        if i == 0:
            centre = pos                        # as extract: later windows centre on the first wavelet
        _add_wavelet(pulse, coef, scale, pos)
        positions.append(pos)
        coefs.append(coef)
    return pulse


def _strongest_point(result: PulseResult, ca: float, sa: float) -> tuple[int, int]:
    """(row, column) of the largest (ca C1 + sa C2)^2, ties in MATLAB's column-major order.

    Exact and cheap for many orientations: the projection of a point never
    exceeds its amplitude C1^2 + C2^2. For a head of k points (the k largest
    amplitudes, found by partial selection, not a full sort), the best
    projection in the head is the maximum over the whole transform as soon as
    it beats the largest amplitude outside the head; otherwise k grows 4x.
    Heads are built once per transform and size (every orientation shares them).
    """
    c = result.coeffs
    assert c is not None                                 # set by classify
    n_rows, n_cols = c.shape[1], c.shape[2]
    if result._strongest is None:
        result._strongest = ((c[0] ** 2 + c[1] ** 2).ravel(), {})
    amp, heads = result._strongest
    k = 1024
    while True:
        if k not in heads:
            if k < amp.size:
                part = np.argpartition(-amp, k)               # [:k] the k largest, [k] the largest of the rest
                head, bound = part[:k], float(amp[part[k]])
            else:
                head, bound = np.arange(amp.size), -math.inf
            rows, cols = np.divmod(head, n_cols)
            heads[k] = (c[0].ravel()[head], c[1].ravel()[head], cols * n_rows + rows, bound)
        c1, c2, f_index, bound = heads[k]
        proj = (ca * c1 + sa * c2) ** 2
        best = float(np.max(proj))
        if bound == -math.inf or best > bound * (1.0 + 1e-12):   # margin: rounding of the projection
            break
        k *= 4
    flat = int(np.min(f_index[proj == best]))
    return flat % n_rows, flat // n_rows


def extract_along(result: PulseResult, angle_rad: float, *, superpose: bool = True) -> tuple[np.ndarray, np.ndarray]:
    """Extract the largest pulse along ``angle_rad`` from the first component.

    The transform is linear, so the coefficients along any orientation are
    ``cos * C1 + sin * C2`` of the cached component transforms: no new
    transform of the record is needed. Returns (velocity, pulse) along that
    orientation [cm/s]. A single-component record returns its own pulse.
    ``superpose=False`` runs :func:`.shahi_baker.extract` on v(phi) itself (the second algorithm the tests
    compare :func:`extract_linear` with).
    """
    v, c = result.velocity_cms, result.coeffs
    assert v is not None and c is not None and result.scales is not None      # set by classify
    if c.shape[0] == 1:
        best = result.best
        assert best.velocity_cms is not None and best.pulse_cms is not None
        return best.velocity_cms, best.pulse_cms
    ca, sa = math.cos(angle_rad), math.sin(angle_rad)
    row, col = _strongest_point(result, ca, sa)
    v_phi = ca * v[0] + sa * v[1]
    if superpose:
        if result._along is None:
            result._along = AlongCache(v)
        return v_phi, extract_linear(result._along, ca, sa, v_phi, column=col, row=row, scales=result.scales)

    def column_coef(a: int) -> float:
        return cwt_point(v_phi, a, col)

    _, pulse, _, _ = extract(v_phi, column_coef, column=col, row=row, scales=result.scales)
    return v_phi, pulse
