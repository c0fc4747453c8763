"""Results as an xarray Dataset in netCDF: schema, CF attributes, atomic writes.

One table, :data:`SCHEMA`, gives every variable its dimensions, UDUNITS
units (``m s-2``, never ``g``, which UDUNITS reads as gram) and
``long_name``; categorical variables carry ``flag_values``/``flag_meanings``.
Files are written to a temporary name in the same directory, flushed to disk,
then renamed over the target, so a reader sees the old or the new file,
never a partial one.
"""

from __future__ import annotations

import csv
import json
import os
import socket
import tempfile
import time
from pathlib import Path
from typing import Callable, Hashable

import numpy as np
import xarray as xr

from .errors import OutputError, OutputLockedError, ResultsError

FLAG3 = np.array([-1, 0, 1], dtype="i1")
#: Sub-directory of an output directory holding the run state (lock, scene and margin caches).
STATE_DIR = ".rockscreen"

#: name -> (dims, units or None, long_name, extra attributes)
SCHEMA: dict[str, tuple[tuple[str, ...], str | None, str, dict]] = {
    # per record
    "status": (("record",), None, "screening status: 'ok' or the reason the record failed", {}),
    "files": (("record",), None, "source files of the record, ';'-separated", {}),
    "formats": (("record",), None, "obspy format names of the source files", {}),
    "notes": (("record",), None, "notes on the record (trimming, orientation, flags)", {}),
    "history": (("record",), None, "ordered processing history, newline-separated", {}),
    "content_sha256": (("record",), None, "SHA-256 of the source files' names and content", {}),
    "screened_utc": (("record",), None, "UTC time the record was screened (ISO 8601); older than the run "
                     "when its results were reused", {}),
    "source_present": (("record",), None, "the record's files were in the records directory at this run",
                       {"flag_values": np.array([0, 1], dtype="i1"), "flag_meanings": "false true",
                        "comment": "false: the files vanished; the results of the last run that saw them "
                                   "are kept"}),
    "dt": (("record",), "s", "sampling interval", {}),
    "npts": (("record",), "1", "number of samples after alignment", {}),
    "duration": (("record",), "s", "record duration", {}),
    "n_horizontal": (("record",), "1", "number of horizontal components", {}),
    "has_vertical": (("record",), "1", "record has a vertical component", {}),
    "azimuth_known": (("record",), "1", "absolute azimuth of the horizontals is known", {}),
    "processing_level": (("record",), None, "delivery level: corrected or uncorrected", {}),
    "pga": (("record",), "m s-2", "peak ground acceleration, peak of the horizontal vector", {}),
    "pgv": (("record",), "m s-1", "peak ground velocity, peak of the horizontal vector", {}),
    # pulses (Shahi & Baker 2014), per record, at the chosen candidate's orientation
    "is_pulse": (("record",), None, "record is pulse-like (Shahi & Baker 2014)",
                 {"flag_values": np.array([-1, 0, 1], dtype="i1"),
                  "flag_meanings": "unavailable non_pulse pulse_like"}),
    "pulse_indicator": (("record",), "1", "pulse indicator PI of the chosen candidate (pulse-like if > 0)", {}),
    "pulse_period": (("record",), "s", "pulse period Tp of the first pulse-like candidate", {}),
    "pulse_azimuth": (("record",), "degree", "axis of the chosen pulse, clockwise from north, modulo 180", {}),
    "pulse_late": (("record",), None, "chosen pulse arrives late (Shahi & Baker 2014 rule)",
                   {"flag_values": np.array([-1, 0, 1], dtype="i1"), "flag_meanings": "unavailable early late"}),
    "pulse_ap": (("record",), "m s-2", "peak acceleration of the dominant lobe of the extracted pulse", {}),
    "pulse_tp": (("record",), "s", "duration of the dominant acceleration lobe of the extracted pulse", {}),
    "pulse_beta": (("record",), "1", "fullness factor dv / (a_p t_p) of the dominant lobe", {}),
    "pulse_dv": (("record",), "m s-1", "velocity change over the dominant lobe (signed)", {}),
    "pulse_record_ap": (("record",), "m s-2", "record's own peak acceleration along the pulse during the lobe", {}),
    "pulse_candidate": (("record",), "1", "index (1-based) of the chosen candidate", {}),
    "pulse_method": (("record",), None, "pulse extraction method", {}),
    "pulse_flags": (("record",), None, "flags of the pulse extraction (single component, truncation, failure)", {}),
    # pulses along each block's direction (the strongest pulse axis when blank or unknown); the criterion's input
    "block_pulse_azimuth": (("record", "block"), "degree", "direction the pulse was characterized along", {}),
    "block_pulse_ap": (("record", "block"), "m s-2", "pulse peak acceleration a_p along the block direction", {}),
    "block_pulse_tp": (("record", "block"), "s", "pulse lobe duration t_p along the block direction", {}),
    "block_pulse_beta": (("record", "block"), "1", "pulse fullness factor beta along the block direction", {}),
    "block_pulse_dv": (("record", "block"), "m s-1", "pulse velocity change along the block direction", {}),
    "block_record_ap": (("record", "block"), "m s-2", "record peak acceleration during the lobe, block direction", {}),
    # the reference paper's criterion per (record, block) scene (pipeline.criteria)
    "uplift": (("record", "block"), None, "pulse peak acceleration reaches the uplift acceleration (Eq. 1)",
               {"flag_values": FLAG3, "flag_meanings": "not_evaluated false true"}),
    "velocity_ratio": (("record", "block"), "1", "pulse velocity increment over the critical velocity (Eqs. 4-5)",
                       {"comment": "the paper's energy criterion holds where this is >= 1"}),
    "energy_ratio": (("record", "block"), "1", "pulse kinetic energy over the energy that overturns, "
                     "(|dv| / v_crit)^2", {}),
    "overturn_criterion": (("record", "block"), None,
                           "overturning by the paper's criterion: uplift, velocity ratio >= 1, below the sliding line",
                           {"flag_values": FLAG3, "flag_meanings": "not_evaluated false true",
                            "comment": "not_evaluated: no pulse, or block too squat for pure rocking"}),
    "above_sliding_line": (("record", "block"), None, "pulse peak acceleration exceeds mu g (the paper's line)",
                           {"flag_values": FLAG3, "flag_meanings": "not_evaluated false true"}),
    "criterion_scale": (("record", "block"), "1",
                        "smallest factor on the record that reaches the criterion's overturning boundary",
                        {"comment": "inf where the scaled pulse crosses the sliding line first"}),
    "onset": (("record", "block"), None, "mode at the onset of motion (Zhang & Makris 2001 eq. 7)",
              {"flag_values": np.array([-1, 0, 1, 2, 3], dtype="i1"),
               "flag_meanings": "not_evaluated rest slide rock slide_rock",
               "comment": "slide_rock: mu > tan(alpha) but a pulse arriving at full amplitude needs more friction"}),
    "onset_friction_demand": (("record", "block"), "1",
                              "friction needed to start rocking without sliding, pulse at full amplitude", {}),
    "normalized_acceleration": (("record", "block"), "1", "pulse peak acceleration over the uplift acceleration", {}),
    "normalized_duration": (("record", "block"), "1", "pulse lobe duration over the block's transition duration",
                            {}),
    "closed_form_ratio": (("record", "block"), "1",
                          "pulse peak over the Makris & Roussos (2000) half-sine minimum at the same duration", {}),
    "overturn_closed_form": (("record", "block"), None,
                             "overturning of the equivalent half-sine pulse (Makris & Roussos 2000 eq. 27)",
                             {"flag_values": FLAG3, "flag_meanings": "not_evaluated false true"}),
    # the run's verdict at its fidelity tier (config [fidelity])
    "overturn": (("record", "block"), None, "overturning verdict at the run's fidelity: the simulation's where it "
                 "ran, else the criterion's", {"flag_values": FLAG3, "flag_meanings": "not_evaluated false true",
                                               "comment": "not_evaluated also where the ground's g + a_v reached 0 "
                                                          "before any overturning (response free_flight)"}),
    "verdict_source": (("record", "block"), None, "model behind the verdict 'overturn'",
                       {"flag_values": FLAG3, "flag_meanings": "none criterion simulation"}),
    # the simulator per (record, block) scene (pipeline.rocking)
    "physics": (("record", "block"), None, "physics simulated for the scene (scene planner)",
                {"flag_values": np.array([-1, 0, 1, 2, 3], dtype="i1"),
                 "flag_meanings": "not_evaluated none sliding rocking rocking_vertical",
                 "comment": "none: proven at rest (no uplift and no slip at any sample, vertical included)"}),
    "response": (("record", "block"), None, "simulated response class",
                 {"flag_values": np.array([-1, 0, 1, 2, 3, 4, 5], dtype="i1"),
                  "flag_meanings": "not_evaluated rest slide rock slide_rock overturn free_flight",
                  "comment": "slide_rock: the friction demand of pure rocking exceeded mu; the pure-rocking "
                             "result is not to be trusted. free_flight: the ground's g + a_v reached 0 before "
                             "any overturning; the contact model stops there and gives no verdict"}),
    "overturn_simulated": (("record", "block"), None, "overturning by the nonlinear time history",
                           {"flag_values": FLAG3, "flag_meanings": "not_evaluated false true",
                            "comment": "scenes proven at rest are false without integration; not_evaluated: "
                                       "not simulated, or free flight before any overturning"}),
    "theta_max": (("record", "block"), "1", "peak rotation over alpha, max |theta| / alpha", {}),
    "n_impacts": (("record", "block"), "1", "impacts during the record (and the one before an escape after it)",
                  {}),
    "time_overturn": (("record", "block"), "s",
                      "time |theta| reached pi/2, or end of the record when the free motion escapes", {}),
    "friction_demand": (("record", "block"), "1", "peak |f_x / f_z| along the rocking trajectory", {}),
    "friction_exceeded": (("record", "block"), None, "friction demand of pure rocking exceeded mu",
                          {"flag_values": FLAG3, "flag_meanings": "not_evaluated false true"}),
    "sliding_max": (("record", "block"), "m", "peak sliding displacement relative to the ground", {}),
    "free_flight": (("record", "block"), None, "loss of contact with the base",
                    {"flag_values": np.array([-1, 0, 1, 2], dtype="i1"),
                     "flag_meanings": "not_evaluated none ground_flight block_liftoff",
                     "comment": "ground_flight: the ground's g + a_v reached 0 (the simulation stopped there); "
                                "block_liftoff: the rocking block's own contact force f_z reached 0 (flagged, "
                                "the rigid-contact result is kept)"}),
    "time_free_flight": (("record", "block"), "s", "time the ground's g + a_v reached 0 (free flight)", {}),
    "governing_azimuth": (("record", "block"), "degree",
                          "azimuth of the rocking plane whose result is reported, clockwise from north, modulo 180",
                          {"comment": "for orientation scanned_relative: relative to the record's first component "
                                      "taken as 0 deg"}),
    "orientation": (("record", "block"), None, "how the rocking plane was chosen",
                    {"flag_values": np.array([-1, 0, 1, 2, 3], dtype="i1"),
                     "flag_meanings": "not_evaluated given scanned scanned_relative single_component",
                     "comment": "scanned: worst of every plane k * simulation.orientation_step_deg and the pulse "
                                "axis that moves the block, refined around the worst standing plane; "
                                "scanned_relative: the same on a record of unknown absolute azimuth"}),
    "planes_simulated": (("record", "block"), "1", "rocking planes integrated for the scene (-1: not simulated)",
                         {}),
    # per record and component
    "component_code": (("record", "component"), None, "channel or component code in the file", {}),
    "component_azimuth": (("record", "component"), "degree", "component azimuth clockwise from north", {}),
    "component_pga": (("record", "component"), "m s-2", "peak absolute acceleration of the component", {}),
    "component_header_pga": (("record", "component"), "m s-2", "peak acceleration stated in the file header", {}),
    # per block
    "block_name": (("block",), None, "block name", {}),
    "site": (("block",), None, "site or collection of the block", {}),
    "height": (("block",), "m", "full block height 2h", {}),
    "width": (("block",), "m", "full base width 2b in the rocking plane", {}),
    "half_height": (("block",), "m", "half-height h (centre-of-mass height)", {}),
    "half_width": (("block",), "m", "half-width b", {}),
    "corner_distance": (("block",), "m", "R = sqrt(b^2 + h^2), base corner to centre of mass", {}),
    "slenderness": (("block",), "rad", "alpha = atan(b/h)", {}),
    "frequency_parameter": (("block",), "rad s-1", "p = sqrt(3 g / (4 R))", {}),
    "restitution": (("block",), "1", "angular-velocity restitution across an impact (Housner where not given)", {}),
    "mu": (("block",), "1", "friction coefficient between block and base", {}),
    "block_sha256": (("block",), None, "SHA-256 of the block's inventory entry (what its results depend on)",
                     {}),
    "block_azimuth": (("block",), "degree", "rocking direction clockwise from north (NaN: worst orientation)", {}),
    "uplift_acceleration": (("block",), "m s-2", "ground acceleration that starts rocking (Eq. 1)", {}),
    "critical_velocity": (("block",), "m s-1", "pulse velocity increment that overturns (Eq. 4)", {}),
    "transition_period": (("block",), "s", "the paper's transition period pi / p of a half-sine pulse (Eq. 9)", {}),
    "governing_record": (("block",), None, "record whose scene is worst for the block (simulated overturn, then "
                         "criterion overturn, then max theta/alpha, then velocity ratio)", {}),
    "overturn_scale": (("block",), "1", "margin by the criterion: smallest factor on the governing record that "
                       "reaches the criterion's boundary (closed form)",
                       {"comment": "inf: the scaled pulse crosses the sliding line first; NaN: not evaluated"}),
    "overturn_scale_simulated": (("block",), "1", "margin by simulation: smallest factor of an upward scan on the "
                                 "governing record, in its rocking plane, under which the block overturns",
                                 {"comment": "<= 1 where the governing scene overturns; also < 1 for a standing "
                                             "scene with a window of overturning below the nominal amplitude "
                                             "(overturns_below_nominal). inf: none up to "
                                             "simulation.margin_max_factor; NaN: the rocking model does not apply "
                                             "(the block slides or is squat), free flight, or no record"}),
    "margin_simulations": (("block",), "1", "scenes simulated by the margin scan (-1: none)", {}),
    "overturns_below_nominal": (("block",), None, "the governing scene stands, yet a smaller factor on the "
                                "record overturns the block (margin below 1)",
                                {"flag_values": FLAG3, "flag_meanings": "not_evaluated false true",
                                 "comment": "overturning is not monotonic in amplitude: a window of overturning "
                                            "below the nominal amplitude"}),
    "rocking_applicable": (("block",), None, "pure-rocking model applies (Housner e > 0, alpha < 54.7 deg)",
                           {"flag_values": np.array([0, 1], dtype="i1"), "flag_meanings": "false true"}),
}

COMPONENTS = ("h1", "h2", "v")


def apply_schema(ds: xr.Dataset) -> xr.Dataset:
    """Attach units and long names from :data:`SCHEMA` to every known variable."""
    for name, (_, units, long_name, extra) in SCHEMA.items():
        if name in ds:
            attrs = {"long_name": long_name, **extra}
            if units is not None:
                attrs["units"] = units
            ds[name].attrs.update(attrs)
    return ds


def _encoding(ds: xr.Dataset) -> dict:
    enc: dict[Hashable, dict] = {}
    for name, var in ds.variables.items():
        if var.dtype.kind == "f":
            enc[name] = {"zlib": True, "complevel": 4, "_FillValue": np.nan}
        elif var.dtype.kind in "OU":
            enc[name] = {"dtype": str}
    return enc


def write_atomic(ds: xr.Dataset, path: str | Path) -> Path:
    """Write ``ds`` to ``path`` (netCDF4) atomically (:func:`replace_atomically`).

    Raises
    ------
    OutputError
        If the directory is not writable or the disk is full; the previous
        file at ``path``, if any, is left untouched.
    """
    return replace_atomically(path, lambda tmp: ds.to_netcdf(tmp, engine="netcdf4", encoding=_encoding(ds)))


def replace_atomically(path: str | Path, write: Callable[[str], None]) -> Path:
    """Create or replace ``path`` through ``write(temporary_path)``: temporary file, fsync, rename.

    The temporary ``.<name>.*.tmp`` lies in the same directory, so the rename is atomic:
    a reader, or a run killed at any instant, sees the old file or the new one.

    Raises
    ------
    OutputError
        If the directory is not writable or the disk is full; the previous
        file at ``path``, if any, is left untouched.
    """
    path = Path(path)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
        os.close(fd)
        os.chmod(tmp, default_file_mode())
    except OSError as exc:
        raise OutputError(f"{path.parent}: cannot write results here ({exc.strerror or exc}); "
                          "choose another --out directory or fix its permissions") from exc
    try:
        write(tmp)
        with open(tmp, "rb+") as fh:
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    except OSError as exc:
        _remove_quietly(tmp)
        raise OutputError(f"{path}: writing failed ({exc.strerror or exc}); the previous results, if "
                          "any, are intact. Free disk space or choose another --out") from exc
    except BaseException:
        _remove_quietly(tmp)
        raise
    return path


def write_text_atomic(path: str | Path, text: str) -> Path:
    """Write UTF-8 text atomically (:func:`replace_atomically`)."""
    def write(tmp: str) -> None:
        Path(tmp).write_text(text, encoding="utf-8")

    return replace_atomically(path, write)


def write_csv_atomic(path: str | Path, columns, rows: list[dict]) -> Path:
    """Write a CSV table (header ``columns``; missing keys blank) atomically (:func:`replace_atomically`)."""
    def write(tmp: str) -> None:
        with open(tmp, "w", newline="", encoding="utf-8") as fh:
            w = csv.DictWriter(fh, fieldnames=list(columns), restval="", extrasaction="ignore")
            w.writeheader()
            w.writerows(rows)

    return replace_atomically(path, write)


def remove_stale_temporaries(out_dir: str | Path) -> int:
    """Delete temporaries a killed run left in ``out_dir`` (call only while holding its lock)."""
    out = Path(out_dir)
    n = 0
    for pattern in (".*.tmp", f"{STATE_DIR}/*/.*.tmp"):
        for p in out.glob(pattern):
            _remove_quietly(p)
            n += 1
    return n


def default_file_mode() -> int:
    """The mode an ordinary new file gets under the process umask (mkstemp alone gives 0600)."""
    umask = os.umask(0)
    os.umask(umask)
    return 0o666 & ~umask


def _remove_quietly(path) -> None:
    try:
        os.unlink(path)
    except OSError:
        pass


def ragged_dataset(id_name: str, id_long_name: str, rows: list[dict], series: dict[str, dict],
                   station: dict[str, dict] | None = None) -> xr.Dataset:
    """Time series of different lengths as a CF contiguous ragged array (featureType timeSeries).

    Parameters
    ----------
    id_name, id_long_name : str
        Name and long name of the series id variable (``cf_role = timeseries_id``).
    rows : list of dict
        One per series: ``"id"``, ``"dt"`` [s] and an array per name in ``series``.
    series : dict
        Name -> attributes of each per-sample variable (stored as float32).
    station : dict, optional
        Name -> attributes of further per-series string variables taken from ``rows``.

    References
    ----------
    CF conventions 1.11, section 9 and appendix H (contiguous ragged array representation).
    """
    first = next(iter(series))
    ids = np.array([r["id"] for r in rows], dtype=str)   # unicode: an empty object array cannot be written
    data = {"row_size": (("station",), np.array([np.size(r[first]) for r in rows], dtype="i4"),
                         {"sample_dimension": "sample", "long_name": f"samples per {id_long_name}"}),
            "dt": (("station",), np.array([r["dt"] for r in rows], dtype=float),
                   {"units": "s", "long_name": "sampling interval"}),
            id_name: (("station",), ids, {"cf_role": "timeseries_id", "long_name": id_long_name})}
    for name, attrs in (station or {}).items():
        data[name] = (("station",), np.array([r[name] for r in rows], dtype=str), attrs)
    for name, attrs in series.items():
        values = np.concatenate([np.asarray(r[name]) for r in rows]) if rows else np.zeros(0)
        data[name] = (("sample",), values.astype("f4"), attrs)
    return xr.Dataset(data, attrs={"Conventions": "CF-1.11", "featureType": "timeSeries"})


def ragged_rows(ds: xr.Dataset, id_name: str) -> dict[str, slice]:
    """Series id -> slice of the ``sample`` dimension, for a :func:`ragged_dataset`."""
    sizes = ds["row_size"].values
    ends = np.cumsum(sizes)
    return {sid: slice(int(e - n), int(e)) for sid, n, e in zip(ds[id_name].values.tolist(), sizes, ends)}


def pulse_series_dataset(results) -> xr.Dataset:
    """Extracted pulses of all records as a CF contiguous ragged array (:func:`ragged_dataset`).

    Variables on dimension ``sample``: ``velocity`` and ``pulse`` [m s-1] along each record's
    chosen pulse orientation; ``row_size`` gives each record's number of samples.
    """
    rows = [{"id": r.record_id, **r.series} for r in results if r.series]
    return ragged_dataset("record_id", "record", rows, {
        "velocity": {"units": "m s-1", "long_name": "ground velocity along the chosen pulse orientation"},
        "pulse": {"units": "m s-1", "long_name": "extracted velocity pulse (sum of 10 db4 wavelets)"}})


def open_results(path: str | Path) -> xr.Dataset:
    """Open a results file fully into memory (the file is closed on return).

    Raises
    ------
    ResultsError
        If the file is missing or not a netCDF file.
    """
    path = Path(path)
    if not path.is_file():
        raise ResultsError(f"{path}: results file not found; run 'screen --records DIR --blocks CSV --out DIR' "
                           "first, which writes DIR/screening.nc")
    try:
        with xr.open_dataset(path, engine="netcdf4") as ds:
            return ds.load()
    except (OSError, ValueError) as exc:
        raise ResultsError(f"{path}: not a readable netCDF results file ({exc})") from exc


class OutputLock:
    """An exclusive lock on an output directory, held for the length of a run.

    The lock is the file ``OUT/.rockscreen/lock``, created with ``O_EXCL``
    and holding the owner's pid, host, start time and command. A lock left by
    a run that died on this host (its pid no longer exists) is taken over
    with a warning; a live one raises :class:`OutputLockedError`.
    """

    def __init__(self, out_dir: str | Path, *, command: str = ""):
        self.path = Path(out_dir) / STATE_DIR / "lock"
        self.command = command
        self.stale_owner: dict | None = None

    def _owner(self) -> dict:
        try:
            return json.loads(self.path.read_text())
        except (OSError, ValueError):
            return {}

    def acquire(self) -> "OutputLock":
        self.path.parent.mkdir(parents=True, exist_ok=True)
        info = {"pid": os.getpid(), "host": socket.gethostname(),
                "started_utc": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()), "command": self.command}
        for _ in range(2):
            try:
                fd = os.open(self.path, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o644)
            except FileExistsError:
                owner = self._owner()
                if owner.get("host") == info["host"] and not _pid_alive(int(owner.get("pid", -1))):
                    self.stale_owner = owner
                    self.path.unlink(missing_ok=True)   # the run that held it is dead: take over
                    continue
                raise OutputLockedError(
                    f"{self.path.parent.parent}: another run is writing this output (pid {owner.get('pid', '?')} "
                    f"on {owner.get('host', '?')}, started {owner.get('started_utc', '?')}: "
                    f"{owner.get('command', '')!s}). Wait for it to finish or use another --out; if that run "
                    f"is dead on another machine, delete {self.path}") from None
            with os.fdopen(fd, "w") as fh:
                json.dump(info, fh)
            return self
        raise OutputLockedError(f"{self.path}: could not take the lock; delete it if no run is active")

    def release(self) -> None:
        if self._owner().get("pid") == os.getpid():
            self.path.unlink(missing_ok=True)

    def __enter__(self) -> "OutputLock":
        return self.acquire()

    def __exit__(self, *exc) -> None:
        self.release()


def _pid_alive(pid: int) -> bool:
    if pid <= 0:
        return False
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True
