"""Storage: netCDF results (:mod:`.netcdf`), atomic files (:mod:`.atomic`), output sets published as one unit
(:mod:`.sets`), the output lock (:mod:`.lock`) and the refusal of anything planted under the output (:mod:`.guard`).

The schema of every variable lives in :mod:`pipeline.schema`.
"""

from ..schema import COMPONENTS, FLAG3, SCHEMA, apply_schema
from .atomic import (
    STATE_DIR,
    default_file_mode,
    remove_stale_temporaries,
    replace_atomically,
    write_bytes_atomic,
    write_csv_atomic,
    write_text_atomic,
)
from .guard import check_output_tree
from .lock import OutputLock
from .netcdf import FLOOR_GROUP, FloorRow, PulseSeries, open_results, ragged_dataset, ragged_rows, write_atomic
from .sets import (
    Family,
    carry,
    describe,
    output_names,
    publish,
    publish_staged,
    removed_unless_published,
    signals_held,
    staging_dir,
)

__all__ = ["COMPONENTS", "FLAG3", "FLOOR_GROUP", "SCHEMA", "STATE_DIR", "Family", "FloorRow", "OutputLock",
           "PulseSeries", "apply_schema", "carry", "check_output_tree", "describe",
           "default_file_mode", "publish", "publish_staged", "signals_held", "staging_dir",
           "open_results", "output_names", "ragged_dataset", "ragged_rows", "remove_stale_temporaries",
           "removed_unless_published",
           "replace_atomically", "write_atomic", "write_bytes_atomic", "write_csv_atomic", "write_text_atomic"]
