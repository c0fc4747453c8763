"""Storage: netCDF results (:mod:`.netcdf`), atomic files (:mod:`.atomic`) and the output lock (:mod:`.lock`).

The schema of every variable lives in :mod:`pipeline.schema`.
"""

from ..schema import COMPONENTS, FLAG3, SCHEMA, apply_schema
from .atomic import (
    STATE_DIR,
    default_file_mode,
    publish,
    remove_stale_temporaries,
    replace_atomically,
    signals_held,
    staging_dir,
    write_bytes_atomic,
    write_csv_atomic,
    write_text_atomic,
)
from .lock import OutputLock
from .netcdf import FLOOR_GROUP, FloorRow, PulseSeries, open_results, ragged_dataset, ragged_rows, write_atomic

__all__ = ["COMPONENTS", "FLAG3", "FLOOR_GROUP", "SCHEMA", "STATE_DIR", "FloorRow", "OutputLock", "PulseSeries",
           "apply_schema",
           "default_file_mode", "publish", "signals_held", "staging_dir",
           "open_results", "ragged_dataset", "ragged_rows", "remove_stale_temporaries",
           "replace_atomically", "write_atomic", "write_bytes_atomic", "write_csv_atomic", "write_text_atomic"]
