"""Recordings: :mod:`.hdf5` gathers the public names of :mod:`.layout` (the one HDF5 layout for
every scene, its group and dataset names), :mod:`.write` (written atomically; the instruments'
output by :mod:`.write_instruments`), :mod:`.read` (read back with checks),
:mod:`.pandas_tables` (pandas tables in HDF5 lab files), :mod:`.legacy` (files written
before the one layout) and :mod:`.sweep_table` (a sweep's final table).  The only code of the
stand that writes HDF5."""
