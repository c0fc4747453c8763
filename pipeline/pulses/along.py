"""The pulse of a two-component record along many orientations.

A block of given azimuth is checked against the pulse along its own plane: the Shahi & Baker (2014)
extraction (:func:`.shahi_baker.extract`) on v(phi) = cos(phi) v1 + sin(phi) v2 for every distinct azimuth of the
inventory. What the orientations share is computed once per record:

* the coefficients of v(phi) are cos C1 + sin C2 of the components' transforms, so its strongest point needs no
  new transform (:func:`_strongest_point`);
* the scale refinement evaluates one sample of v(phi) at every integer scale between the strongest point's
  neighbouring scales, in one compiled loop (:func:`.cwt.column_coefficients`) over those scales' kernels, kept for
  the record (:class:`AlongCache`);
* the ten iterations take the residual's coefficients over the search window as cos C1 + sin C2 of the components'
  over that window (kept for the record: neighbouring orientations share the window) less the wavelets already
  extracted, each a shift of one response (:class:`SharedSteps`), instead of transforming the residual.

Equal to the extraction with the refinement's coefficients taken one by one (:func:`.cwt.cwt_point`) and the
residual transformed itself, up to rounding
(``tests/pulses/test_along.py``, on real records at every degree).

References
----------
Shahi, S. K., & Baker, J. W. (2014). An efficient algorithm to identify strong-velocity pulses in
multicomponent ground motions. BSSA 104(5), 2456-2466.
"""

from __future__ import annotations

import math
from collections import OrderedDict

import numpy as np

from .cwt import column_coefficients, cwt_point, cwt_window, step_bank
from .shahi_baker import (
    WINDOW_FRACTION,
    ExtractionSteps,
    PulseResult,
    extract,
    shifted_response,
    unit_wavelet,
    wavelet_on_grid,
)

#: Refinement banks (:func:`.cwt.step_bank`) an :class:`AlongCache` keeps, the least recently used dropped first:
#: the azimuths come in order, so neighbours share them, and memory stays bounded (a bank of the largest scales at
#: dt = 0.005 s is about 10 MB)
BANKS_KEPT = 2
#: The components' transforms over a search window (:meth:`AlongCache.component_window`) an :class:`AlongCache`
#: keeps: the orientations near each other share the strongest point, so most share the windows too
WINDOWS_KEPT = 16
#: The coefficients of wavelets cut by the record's ends (:meth:`AlongCache.cut_response`) it keeps: at most
#: 1.6 scale + 3 values each (about 28 kB at the largest scale at dt = 0.005 s)
CUT_RESPONSES_KEPT = 128
#: A head of the strongest points is selected row by row where its k + 1 points are less than 1 / ROW_HEADS_BELOW of
#: a row: the rows' heads together are then less than that fraction of the transform [-]
ROW_HEADS_BELOW = 8


class _Kept:
    """The most recently used ``size`` values of a function, the least recently used dropped first."""

    def __init__(self, size: int) -> None:
        self._size = size
        self._values: OrderedDict = OrderedDict()

    def get(self, key, make):
        """The value kept for ``key``, or ``make()`` kept for it."""
        if key in self._values:
            self._values.move_to_end(key)
            return self._values[key]
        self._values[key] = value = make()
        if len(self._values) > self._size:
            self._values.popitem(last=False)
        return value


class AlongCache:
    """What every orientation of one record shares (kept with the record's result, and freed with it): the scale
    refinement's kernel steps, the components' transforms over the search windows and the coefficients of the
    wavelets cut by the record's ends, each the most recently used few."""

    def __init__(self) -> None:
        self._banks = _Kept(BANKS_KEPT)
        self._windows = _Kept(WINDOWS_KEPT)
        self._cut = _Kept(CUT_RESPONSES_KEPT)

    def bank(self, first_scale: int, last_scale: int) -> tuple[np.ndarray, np.ndarray]:
        """The kernel steps of the scales first..last (:func:`.cwt.step_bank`)."""
        return self._banks.get((first_scale, last_scale), lambda: step_bank(first_scale, last_scale))

    def component_window(self, components: np.ndarray, scale: int, lo: int, hi: int) -> list[np.ndarray]:
        """Each component's coefficients at ``scale`` over output samples ``lo..hi`` (:func:`.cwt.cwt_window`)."""
        return self._windows.get((scale, lo, hi), lambda: [cwt_window(v, scale, lo, hi) for v in components])

    def cut_response(self, scale: int, position: int, lo: int, hi: int, n: int) -> np.ndarray:
        """The coefficients at ``scale`` over output samples ``lo..hi`` of the wavelet of coefficient 1 at
        ``position`` on a record of ``n`` samples (for a wavelet the unit response's shift does not give,
        :func:`.shahi_baker.shifted_response`). The wavelet is transformed once over every window that can hold
        its position (within twice the search window's half-width of it); a wider window is transformed itself."""
        reach = 2 * int(math.ceil(WINDOW_FRACTION * scale))
        start, stop = max(0, position - reach), min(n - 1, position + reach)
        if not (start <= lo and hi <= stop):
            return cwt_window(wavelet_on_grid(1.0, scale, position, n), scale, lo, hi)
        around = self._cut.get((scale, position, n),
                               lambda: cwt_window(wavelet_on_grid(1.0, scale, position, n), scale, start, stop))
        return around[lo - start:hi - start + 1]


class SharedSteps(ExtractionSteps):
    """The extraction's iterations along one orientation (ca, sa) from what the record's orientations share: the
    residual's coefficients over a window are ca C1 + sa C2 of the components' (kept per window) less those of the
    wavelets already in the pulse (the transform is linear); a wavelet's are the unit response's shift, or for one
    cut by the record's ends, the unit wavelet's own (:meth:`AlongCache.cut_response`), times its coefficient; a
    wavelet added is :func:`.shahi_baker.unit_wavelet` shifted. Equal to transforming the residual (the base
    class) to rounding."""

    def __init__(self, components: np.ndarray, ca: float, sa: float, cache: AlongCache) -> None:
        self._components, self._ca, self._sa, self._cache = components, ca, sa, cache

    def residual_window(self, velocity: np.ndarray, pulse: np.ndarray, wavelets: list[tuple[float, int]],
                        scale: int, lo: int, hi: int) -> np.ndarray:
        c1, c2 = self._cache.component_window(self._components, scale, lo, hi)
        c = self._ca * c1 + self._sa * c2
        for coef, position in wavelets:
            c -= self.response(coef, scale, position, lo, hi, velocity.size)
        return c

    def response(self, coef: float, scale: int, position: int, lo: int, hi: int, n: int) -> np.ndarray:
        shifted = shifted_response(coef, scale, position, lo, hi, n)
        if shifted is not None:
            return shifted
        return coef * self._cache.cut_response(scale, position, lo, hi, n)

    def add(self, pulse: np.ndarray, coef: float, scale: int, position: int) -> None:
        first, values = unit_wavelet(scale)
        start = position + first
        lo, hi = max(0, start), min(pulse.size, start + values.size)
        if hi > lo:
            pulse[lo:hi] += coef * values[lo - start:hi - start]


def _strongest_point(result: PulseResult, ca: float, sa: float) -> tuple[int, int]:
    """(row, column) of the largest (ca C1 + sa C2)^2, ties in MATLAB's column-major order.

    Exact and cheap for many orientations: the projection of a point never
    exceeds its amplitude C1^2 + C2^2. For a head of k points (the k largest
    amplitudes), the best projection in the head is the maximum over the whole
    transform as soon as it beats the largest amplitude outside the head;
    otherwise k grows 4x. Heads are built once per transform and size (every
    orientation shares them) by :func:`_head`; the amplitudes are not kept.
    """
    c = result.coeffs
    assert c is not None                                 # set by classify
    n_rows = c.shape[1]
    if result._strongest is None:
        result._strongest = {}
    heads = result._strongest
    k = 1024
    while True:
        if k not in heads:
            heads[k] = _head(c, k)
        c1, c2, f_index, bound = heads[k]
        proj = (ca * c1 + sa * c2) ** 2
        best = float(np.max(proj))
        if bound == -math.inf or best > bound * (1.0 + 1e-12):   # margin: rounding of the projection
            break
        k *= 4
    flat = int(np.min(f_index[proj == best]))
    return flat % n_rows, flat // n_rows


def _head(c: np.ndarray, k: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    """The k points of largest amplitude C1^2 + C2^2 of the transform ``c`` (2, rows, columns): their C1, C2 and
    column-major flat index, and the largest amplitude of the points left out (-inf when none is).

    The k largest of the whole are among the k + 1 largest of each row, so where those are a small part of a row
    each row is partitioned alone (by partial selection, not a full sort) and the union of the rows' heads
    partitioned again: the same amplitudes as a selection over the whole transform, with arrays of one row's size
    and of the union (less than 1 / :data:`ROW_HEADS_BELOW` of the transform). Otherwise the whole transform's
    amplitudes are partitioned at once.
    """
    n_rows, n_cols = c.shape[1], c.shape[2]
    if k >= n_rows * n_cols:
        rows, cols = np.divmod(np.arange(n_rows * n_cols), n_cols)
        return c[0].ravel(), c[1].ravel(), cols * n_rows + rows, -math.inf
    if (k + 1) * ROW_HEADS_BELOW >= n_cols:
        amp = (c[0] ** 2 + c[1] ** 2).ravel()
        part = np.argpartition(-amp, k)                  # [:k] the k largest, [k] the largest of the rest
        rows, cols = np.divmod(part[:k], n_cols)
        return c[0, rows, cols], c[1, rows, cols], cols * n_rows + rows, float(amp[part[k]])
    rows_of, cols_of, amps = [], [], []
    for r in range(n_rows):
        amp = c[0, r] ** 2 + c[1, r] ** 2
        top = np.argpartition(-amp, k)[:k + 1]
        rows_of.append(np.full(top.size, r))
        cols_of.append(top)
        amps.append(amp[top])
    rows, cols, amp = np.concatenate(rows_of), np.concatenate(cols_of), np.concatenate(amps)
    part = np.argpartition(-amp, k)
    rows, cols = rows[part[:k]], cols[part[:k]]
    return c[0, rows, cols], c[1, rows, cols], cols * n_rows + rows, float(amp[part[k]])


def extract_along(result: PulseResult, angle_rad: float, *, compiled: bool = True) -> tuple[np.ndarray, np.ndarray]:
    """Extract the largest pulse along ``angle_rad`` from the first component.

    Returns (velocity, pulse) along that orientation [cm/s]. A single-component record returns its own pulse.
    ``compiled=False`` takes the refinement's coefficients one by one (:func:`.cwt.cwt_point`) and transforms the
    residual itself: the second algorithm the tests compare with.
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
    scales = result.scales
    steps: ExtractionSteps | None = None
    if compiled:
        if result._along is None:
            result._along = AlongCache()
        first, last = int(scales[max(0, row - 1)]), int(scales[min(len(scales) - 1, row + 1)])
        values = column_coefficients(v_phi, first, last, col, result._along.bank(first, last))
        steps = SharedSteps(v, ca, sa, result._along)

        def column_coef(a: int) -> float:
            return float(values[a - first])
    else:
        def column_coef(a: int) -> float:
            return cwt_point(v_phi, a, col)

    _, pulse, _, _ = extract(v_phi, column_coef, column=col, row=row, scales=scales, steps=steps)
    return v_phi, pulse
