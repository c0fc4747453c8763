"""The same station recording of the same earthquake, found in two files of other formats or processings.

A records directory often holds one recording more than once: a PEER NGA-West2 file and an older NGA
processing of it, or a rotated fault-normal component beside the as-recorded pair. Byte-identical copies
are caught at the scan; these are not identical, so they are found by their waveforms. Two records are the
same recording when their ground accelerations along the pulse orientation, low-passed at
:data:`LOWPASS_HZ`, match: the largest normalized cross-correlation over time shifts (and sign) is at least
:data:`SAME_RECORDING_CORRELATION`.

Why acceleration, low-passed: velocities are dominated by one pulse, and the velocities of different
stations correlate up to 0.87 (El Centro Array #6 against Array #4; 0.85 against Sturno, Irpinia, another
earthquake; measured on the bundled records), while acceleration above a few hertz differs between
processings of one recording (0.24 for the two Lucerne files). Low-passed at 2 Hz, the same recordings in
other formats or processings correlate 0.91-0.99 and different stations at most 0.74 (El Centro Arrays #4
and #6); ``docs/validation.md`` lists the values.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np

#: Normalized cross-correlation of two velocity series at or above which they are one recording [-].
SAME_RECORDING_CORRELATION = 0.85
#: The common sampling interval the series are compared at [s] (velocity has little energy above 10 Hz).
COMPARE_DT_S = 0.02
#: Two records whose peaks differ by more than this factor are not compared (a cheap filter) [-].
PEAK_RATIO_LIMIT = 1.5
#: Corner of the zero-phase 4-pole Butterworth low-pass applied to the acceleration before comparing [Hz].
LOWPASS_HZ = 2.0


@dataclass(frozen=True)
class RecordingGroup:
    """Records that are one station recording.

    Attributes
    ----------
    kept : str
        The record that stands for the group (the first by the caller's preference, then by name).
    records : tuple of str
        Every record of the group, ``kept`` first.
    correlation : float
        The smallest correlation that joined a record to the group [-] (pairs already in one group are not
        compared again).
    """

    kept: str
    records: tuple[str, ...]
    correlation: float


def compared_series(velocity_ms: np.ndarray, dt_s: float) -> np.ndarray:
    """What two records are compared on: the acceleration from the velocity resampled at
    :data:`COMPARE_DT_S` (linear interpolation), low-passed at :data:`LOWPASS_HZ` (zero phase) [m s-2]."""
    v = np.asarray(velocity_ms, dtype=float)
    if v.size < 2:
        return np.zeros(0)
    t = np.arange(v.size) * dt_s
    vr = np.interp(np.arange(0.0, t[-1] + 1e-12, COMPARE_DT_S), t, v)
    a = np.diff(vr) / COMPARE_DT_S
    if a.size <= 27:                          # too short for the filter's padding: nothing to compare
        return np.zeros(0)
    from scipy.signal import sosfiltfilt  # imported where used: scipy.signal costs 0.4 s to import

    return sosfiltfilt(_lowpass(), a - a.mean())


@lru_cache(maxsize=1)
def _lowpass() -> np.ndarray:
    """The 4-pole Butterworth low-pass at :data:`LOWPASS_HZ` for series at :data:`COMPARE_DT_S` (made once)."""
    from scipy.signal import butter

    return butter(4, LOWPASS_HZ, fs=1.0 / COMPARE_DT_S, output="sos")


def correlation(a: np.ndarray, b: np.ndarray) -> float:
    """The largest absolute normalized cross-correlation of two series over every time shift [-]."""
    na, nb = float(np.linalg.norm(a)), float(np.linalg.norm(b))
    if na == 0.0 or nb == 0.0:
        return 0.0
    n = a.size + b.size - 1
    size = 1 << (n - 1).bit_length()
    xc = np.fft.irfft(np.fft.rfft(a, size) * np.conj(np.fft.rfft(b, size)), size)
    return float(np.max(np.abs(xc)) / (na * nb))


def same_recordings(series: dict[str, tuple[np.ndarray, float]], *,
                    threshold: float = SAME_RECORDING_CORRELATION,
                    preference: dict[str, tuple] | None = None) -> list[RecordingGroup]:
    """Group the records that are one station recording.

    Parameters
    ----------
    series : dict
        Record id -> (velocity along the pulse orientation [m s-1], sampling interval [s]).
        Records are compared by :func:`compared_series`.
    threshold : float
        The correlation at or above which two records are one recording [-].
    preference : dict, optional
        Record id -> sort key; the smallest key of a group is kept (e.g. the record with the most components).

    Returns
    -------
    list of RecordingGroup
        The groups of two or more records, sorted by their kept record.
    """
    return group_compared({rid: compared_series(*v) for rid, v in series.items()}, threshold=threshold,
                          preference=preference)


def group_compared(x: dict[str, np.ndarray], *, threshold: float = SAME_RECORDING_CORRELATION,
                   preference: dict[str, tuple] | None = None) -> list[RecordingGroup]:
    """:func:`same_recordings` on series already made by :func:`compared_series` (record id -> series), so that
    a caller reading many records holds only these short series, not the records' velocities."""
    ids = sorted(x)
    peak = {rid: float(np.max(np.abs(x[rid]))) if x[rid].size else 0.0 for rid in ids}
    parent = {rid: rid for rid in ids}
    joined: dict[str, float] = {}

    def root(r: str) -> str:
        while parent[r] != r:
            parent[r] = parent[parent[r]]
            r = parent[r]
        return r

    for i, a in enumerate(ids):
        for b in ids[i + 1:]:
            if peak[a] == 0.0 or peak[b] == 0.0 or max(peak[a], peak[b]) > PEAK_RATIO_LIMIT * min(peak[a], peak[b]):
                continue
            ra, rb = root(a), root(b)
            if ra == rb:                      # already one recording through other records
                continue
            c = correlation(x[a], x[b])
            if c >= threshold:
                parent[max(ra, rb)] = min(ra, rb)
                joined[b] = min(joined.get(b, 1.0), c)
                joined[a] = min(joined.get(a, 1.0), c)
    members: dict[str, list[str]] = {}
    for rid in ids:
        members.setdefault(root(rid), []).append(rid)
    rank = preference or {}
    groups = []
    for rs in members.values():
        if len(rs) > 1:
            ordered = sorted(rs, key=lambda r: (rank.get(r, ()), r))
            groups.append(RecordingGroup(ordered[0], tuple(ordered), min(joined[r] for r in rs)))
    return sorted(groups, key=lambda grp: grp.kept)
