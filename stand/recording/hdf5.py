"""Recordings: one HDF5 layout for every scene, written atomically, read back with checks.

The public names of the recording modules, in one place (imports elsewhere use this module):

* :mod:`.layout` -- the layout (dataset and group names, units, root attributes),
  :class:`RecordingError`;
* :mod:`.write`  -- :func:`write_recording` (``stand.save``), with :mod:`.write_instruments`;
* :mod:`.read`   -- :func:`read_recording` (``stand.read``) and :class:`Recording`;
* :mod:`.pandas_tables` -- pandas tables in HDF5 files (lab recordings);
* :mod:`.legacy` -- files written before the one layout;
* :mod:`.sweep_table` -- the other HDF5 layout: a sweep's final table.
"""
from __future__ import annotations

from stand.recording.layout import (DATASETS, FORMAT, FORMAT_VERSION, REQUIRED,  # noqa: F401
                                    RESERVED_ATTRS, RecordingError)
from stand.recording.pandas_tables import pandas_table_key, read_pandas_table
from stand.recording.read import Recording, read_recording
from stand.recording.write import write_recording

__all__ = ["FORMAT", "FORMAT_VERSION", "DATASETS", "Recording", "RecordingError",
           "read_recording", "write_recording", "pandas_table_key",
           "read_pandas_table"]
