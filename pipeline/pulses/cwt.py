"""The legacy-MATLAB-style continuous wavelet transform with the db4 wavelet.

``pywt.cwt`` accepts only continuous wavelets and rejects ``db4``, but the
Shahi & Baker (2014) classifier is calibrated on MATLAB's legacy
``cwt(x, scales, 'db4')``. That transform is rebuilt here from its
definition (the legacy MATLAB ``cwt`` that the published code of Shahi & Baker 2014 calls):

* Psi = running integral of the db4 wavelet function sampled by
  ``pywt.Wavelet('db4').wavefun(level=10)`` on x in [0, 7], step h = 2^-10;
* for an integer scale a: j_m = floor(m / (a h)), m = 0..floor(7a);
  kernel f = reverse(Psi[j]);
* C(a, .) = -sqrt(a) * central_N(diff(conv_full(v, f))).

The kernel spectra are cached per (scale, FFT length), so a record's two
components are transformed at all scales with one FFT each plus one
multiply per scale.

References
----------
Shahi, S. K., & Baker, J. W. (2014). An efficient algorithm to identify
strong-velocity pulses in multicomponent ground motions. BSSA 104(5), 2456-2466.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np
import pywt
from scipy import fft as sfft

from ..compiled import jit
from ..errors import PulseError

#: db4 support length [in units of the scale].
SUPPORT = 7.0
#: Resolution of the sampled wavelet function (MATLAB ``intwave(db4, 10)``).
WAVEFUN_LEVEL = 10
#: Kernels (and their steps) a process keeps, the least recently used dropped first: the scales of a record's grid
#: and of its refinements. 128 of each held 21 MB after 23 records of the scale benchmark against 32 MB for 512 and
#: 256, in the same time (the pulses of the 23 records 3.7-4.0 s against 3.6-4.4 s of CPU) [-].
KERNELS_KEPT = 128


@lru_cache(maxsize=1)
def _psi_integral() -> tuple[np.ndarray, float]:
    _, psi, x = pywt.Wavelet("db4").wavefun(level=WAVEFUN_LEVEL)
    h = float(x[1] - x[0])
    return np.cumsum(psi) * h, h


@lru_cache(maxsize=KERNELS_KEPT)
def kernel(scale: int) -> np.ndarray:
    """The reversed integrated-wavelet kernel f of one integer scale (read-only)."""
    integ, h = _psi_integral()
    m = np.arange(int(np.floor(scale * SUPPORT)) + 1)
    j = np.floor(m / (scale * h)).astype(int)
    if j.size == 1:
        j = np.array([j[0], j[0]])
    f = integ[j][::-1].copy()
    f.setflags(write=False)
    return f


@lru_cache(maxsize=64)
def _kernel_spectrum(scale: int, nfft: int) -> np.ndarray:
    spec = sfft.rfft(kernel(scale), nfft)
    spec.setflags(write=False)
    return spec


def _first_kept(n_signal: int, n_kernel: int) -> int:
    """0-based start of MATLAB ``wkeep1(diff(conv_full), N)``, central part."""
    n_diff = n_signal + n_kernel - 2
    return (n_diff - n_signal) // 2


def cwt(signal: np.ndarray, scales) -> np.ndarray:
    """Legacy MATLAB ``cwt(signal, scales, 'db4')``.

    Parameters
    ----------
    signal : ndarray, shape (N,) or (n, N)
        Signal(s), one per row.
    scales : sequence of int
        Integer scales [samples].

    Returns
    -------
    ndarray, shape (n_scales, N) or (n, n_scales, N)
        Coefficients.
    """
    x = np.atleast_2d(np.asarray(signal, dtype=float))
    n = x.shape[-1]
    scales = [int(s) for s in scales]
    longest = max(len(kernel(s)) for s in scales)
    nfft = sfft.next_fast_len(n + longest - 1, real=True)
    xs = sfft.rfft(x, nfft, axis=-1)
    out = np.empty((x.shape[0], len(scales), n))
    for k, a in enumerate(scales):
        f = kernel(a)
        # the record's own length: its spectra are not kept (another record's transform cannot use them)
        full = sfft.irfft(xs * sfft.rfft(f, nfft), nfft, axis=-1)[:, : n + len(f) - 1]
        first = _first_kept(n, len(f))
        d = np.diff(full[:, first:first + n + 1], axis=-1)
        out[:, k, :] = -np.sqrt(a) * d
    return out[0] if np.ndim(signal) == 1 else out


def cwt_window(signal: np.ndarray, scale: int, lo: int, hi: int) -> np.ndarray:
    """Coefficients of one scale at output samples ``lo..hi`` (inclusive, 0-based) only.

    Only the part of ``signal`` that reaches those outputs is convolved.
    """
    f = kernel(scale)
    n, L = signal.size, f.size
    first = _first_kept(n, L)
    k0, k1 = first + lo, first + hi + 1           # needed indices of conv_full
    j0, j1 = max(0, k0 - L + 1), min(n - 1, k1)   # signal samples that reach them
    seg = signal[j0:j1 + 1]
    nfft = sfft.next_fast_len(seg.size + L - 1, real=True)
    full = sfft.irfft(sfft.rfft(seg, nfft) * _kernel_spectrum(scale, nfft), nfft)
    # full_segment[k - j0] == conv_full(signal)[k] for k in [k0, k1]
    part = full[k0 - j0:k1 - j0 + 1]
    return -np.sqrt(scale) * np.diff(part)


@lru_cache(maxsize=KERNELS_KEPT)
def _kernel_step(scale: int) -> np.ndarray:
    """g[i] = f[i] - f[i-1] for i = 0..L (f zero outside 0..L-1): the kernel of diff(conv)."""
    f = kernel(scale)
    g = np.diff(np.concatenate([[0.0], f, [0.0]]))
    g.setflags(write=False)
    return g


def cwt_point(signal: np.ndarray, scale: int, column: int) -> float:
    """The coefficient of one scale at one output sample, as a direct dot product.

    Equal to ``cwt_window(signal, scale, column, column)[0]`` (to rounding):
    ``-sqrt(a) (conv_full[k+1] - conv_full[k])`` with ``k = first + column``
    is ``-sqrt(a) sum_j s[j] g[k + 1 - j]`` for the kernel step ``g``. One
    O(L) product instead of an FFT of the window, for the scale refinement
    that evaluates one column at dozens of scales.
    """
    g = _kernel_step(scale)
    n, L = signal.size, g.size - 1
    k = _first_kept(n, L) + column
    j0, j1 = max(0, k + 1 - L), min(n - 1, k + 1)
    if j1 < j0:
        return 0.0
    # s[j] pairs with g[k + 1 - j]: j = j0..j1 -> g indices k+1-j0 down to k+1-j1
    taps = g[k + 1 - j1:k + 2 - j0][::-1]
    return float(-np.sqrt(scale) * np.dot(signal[j0:j1 + 1], taps))


def column_coefficients(signal: np.ndarray, first_scale: int, last_scale: int, column: int,
                        bank: tuple[np.ndarray, np.ndarray] | None = None) -> np.ndarray:
    """The coefficients of ``signal`` at one output sample ``column`` for every integer scale from
    ``first_scale`` to ``last_scale``: :func:`cwt_point` at each (to rounding), in one compiled loop over the
    scales' kernel steps (``bank``: :func:`step_bank` of the range, when the caller keeps it). The scale refinement
    of the pulse along each block's azimuth evaluates one column at dozens of scales, a different column for each
    azimuth."""
    flat, offsets = step_bank(int(first_scale), int(last_scale)) if bank is None else bank
    return _column_coefficients(np.ascontiguousarray(signal, dtype=np.float64), flat, offsets,
                                int(first_scale), int(column))


def step_bank(first_scale: int, last_scale: int) -> tuple[np.ndarray, np.ndarray]:
    """The kernel steps (:func:`_kernel_step`) of scales first..last, each reversed, end to end, and where each
    starts (about 7 (first + last) (last - first + 1) / 2 values)."""
    steps = [_kernel_step(a)[::-1] for a in range(first_scale, last_scale + 1)]
    offsets = np.concatenate([[0], np.cumsum([g.size for g in steps])]).astype(np.int64)
    flat = np.concatenate(steps)
    flat.setflags(write=False)
    offsets.setflags(write=False)
    return flat, offsets


@jit
def _column_coefficients(signal, flat, offsets, first_scale, column):
    n = signal.size
    out = np.empty(offsets.size - 1)
    for i in range(out.size):
        r = flat[offsets[i]:offsets[i + 1]]              # g reversed: g[k + 1 - j] = r[L - k - 1 + j]
        L = r.size - 1                                   # the kernel's length
        k = (L - 2) // 2 + column                        # _first_kept(n, L) + column
        j0, j1 = max(0, k + 1 - L), min(n - 1, k + 1)
        acc = 0.0
        if j1 >= j0:                                     # sum of s[j] g[k + 1 - j]
            acc = np.dot(signal[j0:j1 + 1], r[L - k - 1 + j0:L - k + j1])
        out[i] = -np.sqrt(first_scale + i) * acc
    return out


def scales_for(dt_s: float, *, tp_min_s: float = 0.25, tp_max_s: float = 15.0, n_scales: int = 50) -> np.ndarray:
    """The 51 integer scales searched (the scale grid of the published code of Shahi & Baker 2014).

    ``s_min = floor(TpMin/1.4/dt)``, ``step = ceil((TpMax/1.4/dt - s_min)/50)``,
    scales ``s_min : step : s_min + 50 step``.

    Raises
    ------
    PulseError
        When the sampling is too coarse for the shortest period searched (``s_min`` below one sample).
    """
    s_min = int(np.floor(tp_min_s / 1.4 / dt_s))
    if s_min < 1:
        raise PulseError(f"sampling interval dt = {dt_s:g} s is too coarse for the pulse search from Tp = "
                         f"{tp_min_s:g} s (its smallest wavelet scale would be below one sample: dt must be at most "
                         f"{tp_min_s / 1.4:.3g} s); resample the record finer, or raise [pulses] tp_min_s to at "
                         f"least {1.4 * dt_s:.3g} s")
    step = int(np.ceil((tp_max_s / 1.4 / dt_s - s_min) / n_scales))
    return s_min + step * np.arange(n_scales + 1)


def pseudo_period(scale: int, dt_s: float) -> float:
    """Tp = 1 / scal2frq(a, 'db4', dt) = a dt / centfrq(db4) [s] (centfrq = 5/7)."""
    return scale * dt_s / pywt.central_frequency("db4")
