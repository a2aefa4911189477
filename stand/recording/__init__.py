"""Recordings: :mod:`.hdf5` (one HDF5 layout for every scene, written atomically, read back with
checks) and :mod:`.legacy` (files written before the one layout)."""
