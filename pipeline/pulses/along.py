"""The pulse of a two-component record along many orientations.

A block of given azimuth is checked against the pulse along its own plane: the Shahi & Baker (2014)
extraction (:func:`.shahi_baker.extract`) on v(phi) = cos(phi) v1 + sin(phi) v2 for every distinct azimuth of the
inventory. What the orientations share is computed once per record:

* the coefficients of v(phi) are cos C1 + sin C2 of the components' transforms, so its strongest point needs no
  new transform (:func:`_strongest_point`);
* the scale refinement evaluates one sample of v(phi) at every integer scale between the strongest point's
  neighbouring scales, in one compiled loop (:func:`.cwt.column_coefficients`) over those scales' kernels, kept for
  the record (:class:`AlongCache`);
* the ten iterations transform the residual at the refined scale over the search window, as the extraction does.

Equal to the extraction with the refinement's coefficients taken one by one (:func:`.cwt.cwt_point`) up to rounding
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

from .cwt import column_coefficients, cwt_point, step_bank
from .shahi_baker import PulseResult, extract

#: Refinement banks (:func:`.cwt.step_bank`) an :class:`AlongCache` keeps, the least recently used dropped first:
#: the azimuths come in order, so neighbours share them, and memory stays bounded (a bank of the largest scales at
#: dt = 0.005 s is about 10 MB)
BANKS_KEPT = 2
#: A head of the strongest points is selected row by row where its k + 1 points are less than 1 / ROW_HEADS_BELOW of
#: a row: the rows' heads together are then less than that fraction of the transform [-]
ROW_HEADS_BELOW = 8


class AlongCache:
    """What every orientation of one record shares: the scale refinement's kernel steps, the most recently used
    :data:`BANKS_KEPT` ranges (kept with the record's result, and freed with it)."""

    def __init__(self) -> None:
        self._banks: OrderedDict[tuple[int, int], tuple[np.ndarray, np.ndarray]] = OrderedDict()

    def bank(self, first_scale: int, last_scale: int) -> tuple[np.ndarray, np.ndarray]:
        """The kernel steps of the scales first..last (:func:`.cwt.step_bank`)."""
        key = (first_scale, last_scale)
        if key in self._banks:
            self._banks.move_to_end(key)
            return self._banks[key]
        self._banks[key] = bank = step_bank(first_scale, last_scale)
        if len(self._banks) > BANKS_KEPT:
            self._banks.popitem(last=False)
        return bank


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
    ``compiled=False`` takes the refinement's coefficients one by one (:func:`.cwt.cwt_point`): the second
    algorithm the tests compare with.
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
    if compiled:
        if result._along is None:
            result._along = AlongCache()
        first, last = int(scales[max(0, row - 1)]), int(scales[min(len(scales) - 1, row + 1)])
        values = column_coefficients(v_phi, first, last, col, result._along.bank(first, last))

        def column_coef(a: int) -> float:
            return float(values[a - first])
    else:
        def column_coef(a: int) -> float:
            return cwt_point(v_phi, a, col)

    _, pulse, _, _ = extract(v_phi, column_coef, column=col, row=row, scales=scales)
    return v_phi, pulse
