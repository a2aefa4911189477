"""Lab recordings in: tables a data-acquisition system writes, mapped to the stand's signals.

* :mod:`.units` -- units of the columns (s, ms; m, mm, um; rpm, Hz, rad/s; V with a
  sensitivity), converted once, here, at the edge.
* :mod:`.recording_map` -- which column is what (``--columns`` or a TOML map file), the
  machine's data (rotor mass, service speed), well-known column names recognised.
* :mod:`.table` -- reading CSV (any delimiter, decimal commas, header lines), Parquet and
  pandas HDF5 tables; checking them (time, gaps, NaN stretches, clipped channels).
* :mod:`.daq_export` -- a simulated recording written as a lab's DAQ export, with its truth.
"""
