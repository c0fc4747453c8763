"""The ground-motion record handed from the reading stage to the pulse stage."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

import numpy as np


def project(rows: np.ndarray, azimuth0_deg: float, azimuth_deg: float) -> np.ndarray:
    """Horizontal motion in the vertical plane of ``azimuth_deg``: a1 cos(phi - phi1) + a2 sin(phi - phi1),
    from one or two horizontals (``rows``, the second 90 deg clockwise of the first, which points to
    ``azimuth0_deg``). One horizontal is returned as it is, whatever the azimuth."""
    if rows.shape[0] == 1:
        return rows[0]
    phi = np.deg2rad(azimuth_deg - azimuth0_deg)
    return np.cos(phi) * rows[0] + np.sin(phi) * rows[1]


@dataclass
class Record:
    """One station recording in SI units, ready for screening.

    Attributes
    ----------
    record_id : str
        Stable identifier (station and event, or file stem).
    dt_s : float
        Sampling interval [s].
    horizontal_ms2 : ndarray, shape (n_h, npts)
        Horizontal accelerations [m s-2]; ``n_h`` is 1 or 2. With two
        components the second points 90 deg clockwise of the first.
    azimuths_deg : tuple of float
        Azimuth of each horizontal [deg clockwise from north] (nominal 0/90
        when ``azimuth_known`` is False).
    azimuth_known : bool
        False when only the relative orientation of the pair is known.
    vertical_ms2 : ndarray, shape (npts,), or None
        Vertical acceleration [m s-2], positive up.
    files : tuple of str
        Source files.
    formats : tuple of str
        obspy format names of the source files.
    component_codes : tuple of str
        Codes of the horizontals then the vertical (as in the files).
    processing_level : str
        ``"corrected"`` or ``"uncorrected"`` as delivered.
    notes : list of str
        Human-readable notes (trimming, flags).
    history : list of str
        Ordered processing history (units conversion, obspy steps).
    header_peaks_ms2 : dict
        Peak acceleration stated in a file header, by component code [m s-2].
    velocity_ms : ndarray, shape (n_h, npts)
        Horizontal ground velocity [m s-1] from the configured integration step.
    label : str
        The station and earthquake as the files name them ("" when they name neither).
    """

    record_id: str
    dt_s: float
    horizontal_ms2: np.ndarray
    azimuths_deg: tuple[float, ...]
    azimuth_known: bool
    vertical_ms2: np.ndarray | None
    files: tuple[str, ...]
    formats: tuple[str, ...]
    component_codes: tuple[str, ...]
    processing_level: str
    notes: list[str] = field(default_factory=list)
    history: list[str] = field(default_factory=list)
    header_peaks_ms2: dict[str, float] = field(default_factory=dict)
    velocity_ms: np.ndarray | None = None
    #: the station and earthquake as the files name them ("" when they name neither)
    label: str = ""

    @property
    def npts(self) -> int:
        """Number of samples."""
        return int(self.horizontal_ms2.shape[1])

    def scaled(self, factor: float) -> "Record":
        """The record with every component (horizontals, vertical, velocity) multiplied by ``factor``,
        as multiple-stripe analyses scale records."""
        f = float(factor)
        return dataclasses.replace(
            self, horizontal_ms2=f * self.horizontal_ms2,
            vertical_ms2=None if self.vertical_ms2 is None else f * self.vertical_ms2,
            velocity_ms=None if self.velocity_ms is None else f * self.velocity_ms,
            notes=[*self.notes, f"scaled by {f:g}"])

    @property
    def single_component(self) -> bool:
        """True when only one horizontal component was recorded."""
        return self.horizontal_ms2.shape[0] == 1

    def along(self, azimuth_deg: float) -> np.ndarray:
        """Horizontal acceleration projected on ``azimuth_deg`` [m s-2].

        With one component the azimuth is ignored and that component returned.
        """
        return self._project(self.horizontal_ms2, azimuth_deg)

    def velocity_along(self, azimuth_deg: float) -> np.ndarray:
        """Horizontal velocity projected on ``azimuth_deg`` [m s-1]."""
        return self._project(self._velocity(), azimuth_deg)

    def _project(self, rows: np.ndarray, azimuth_deg: float) -> np.ndarray:
        return project(rows, self.azimuths_deg[0], azimuth_deg)

    def pgv_ms(self) -> float:
        """Peak of the horizontal velocity vector [m s-1]."""
        return float(np.max(np.sqrt(np.sum(self._velocity() ** 2, axis=0))))

    def _velocity(self) -> np.ndarray:
        if self.velocity_ms is None:
            raise ValueError(f"record {self.record_id}: no velocity; the reader integrates every record")
        return self.velocity_ms

    def pga_ms2(self) -> float:
        """Peak of the horizontal acceleration vector [m s-2]."""
        return float(np.max(np.sqrt(np.sum(self.horizontal_ms2**2, axis=0))))

    def pga_azimuth_deg(self) -> float:
        """Axis of the peak horizontal acceleration vector, clockwise from north, modulo 180 [deg]."""
        if self.single_component:
            return float(self.azimuths_deg[0]) % 180.0
        h = self.horizontal_ms2
        k = int(np.argmax(np.hypot(h[0], h[1])))
        turn = np.degrees(np.arctan2(h[1][k], h[0][k]))     # from the first component towards the second
        return float(round(self.azimuths_deg[0] + turn) % 180.0)
