"""Results as netCDF4 files: atomic writes, CF ragged arrays, opening results.

Variable attributes come from :mod:`pipeline.schema`.
"""

from __future__ import annotations

from pathlib import Path
from typing import Hashable

import numpy as np
import xarray as xr

from ..errors import ResultsError
from ..schema import PULSE_SERIES
from .atomic import replace_atomically


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
    # the time of each sample from the start of its series (record start times are often unknown: AT2 files)
    time = (np.concatenate([np.arange(np.size(r[first])) * float(r["dt"]) for r in rows]) if rows
            else np.zeros(0))
    coords = {"time": (("sample",), time, {"units": "s", "long_name": "time since the first sample of the series",
                                           "axis": "T"})}
    return xr.Dataset(data, coords=coords, attrs={"Conventions": "CF-1.11", "featureType": "timeSeries"})


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
    return ragged_dataset("record_id", "record", rows, PULSE_SERIES)


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
