"""Velocity pulses: db4 transform, Shahi & Baker extraction and classification, (a_p, t_p, beta)."""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..constants import M_TO_CM
from ..errors import PulseError
from ..records.record import Record
from .along import extract_along
from .characterize import Lobe, dominant_lobe, pulse_lobe, record_peak_in
from .shahi_baker import PulseResult, classify

__all__ = ["RecordPulse", "analyze", "classify", "dominant_lobe", "Lobe"]

CM = M_TO_CM  # cm per m (the pulse algorithm works in cm/s, as the published code)


@dataclass
class RecordPulse:
    """The pulse of one record and its characterization.

    Attributes
    ----------
    result : PulseResult
        Classification and candidates.
    azimuth_deg : float
        Axis of the chosen pulse [deg clockwise from north, mod 180]
        (relative to the first component when its azimuth is unknown).
    lobe : Lobe
        (a_p, t_p, beta, dv) of the chosen pulse's acceleration [SI].
    record_ap_ms2 : float
        The record's own peak |acceleration| along the pulse during the lobe.
    """

    result: PulseResult
    azimuth_deg: float
    lobe: Lobe
    record_ap_ms2: float

    def along(self, record: Record, azimuth_deg: float) -> tuple[Lobe, float]:
        """(Lobe, record peak in it) of the pulse extracted along ``azimuth_deg``."""
        phi = math.radians(azimuth_deg - record.azimuths_deg[0])
        _, pulse_cms = extract_along(self.result, phi)
        lobe = pulse_lobe(pulse_cms / CM, record.dt_s)
        return lobe, record_peak_in(record.along(azimuth_deg), record.dt_s, lobe)


def analyze(record: Record, *, method: str = "shahi_baker_2014", tp_min_s: float = 0.25,
            tp_max_s: float = 15.0) -> RecordPulse:
    """Classify the record's velocity pulse and characterize it as (a_p, t_p, beta).

    Raises
    ------
    PulseError
        When no pulse can be extracted (record too short, all zero).
    """
    if record.velocity_ms is None:
        raise PulseError(f"{record.record_id}: no velocity (the record was not integrated)")
    res = classify(record.velocity_ms * CM, record.dt_s, method=method, tp_min_s=tp_min_s,
                   tp_max_s=tp_max_s)
    best = res.best
    azimuth = (record.azimuths_deg[0] + math.degrees(best.angle_rad)) % 180.0
    assert best.pulse_cms is not None                    # classify fills the chosen candidate's series
    lobe = pulse_lobe(best.pulse_cms / CM, record.dt_s)
    rec_ap = record_peak_in(record.along(azimuth), record.dt_s, lobe)
    return RecordPulse(res, azimuth, lobe, rec_ap)
