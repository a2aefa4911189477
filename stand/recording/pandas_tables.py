"""Pandas tables in HDF5 files (``DataFrame.to_hdf``, lab recordings), read with h5py.

Nothing is unpickled: numeric columns only.  Used by :mod:`stand.lab.table`; HDF5 is opened
in :mod:`stand.recording`, nowhere else.
"""
from __future__ import annotations

from typing import Optional

import h5py

from stand.recording.layout import RecordingError

__all__ = ["pandas_table_key", "read_pandas_table"]


def pandas_table_key(path) -> Optional[str]:
    """The key of the first pandas table (``DataFrame.to_hdf``) in an HDF5 file, or None (a
    stand recording, or not readable: :func:`read_recording` names the problem)."""
    keys = []
    try:
        with h5py.File(path, "r") as f:
            if "format_version" in f.attrs or "time" in f:
                return None
            f.visititems(lambda n, o: keys.append(n) if "pandas_type" in o.attrs else None)
    except Exception:   # noqa: BLE001 -- a damaged file: the recording reader names the problem
        return None
    return keys[0] if keys else None


def _pickled_names(raw) -> list:
    """Column names pandas stores as a protocol-0 pickled list of strings, read as text: the
    arguments of its ``V`` (unicode) and ``S`` (str) opcodes; nothing is unpickled."""
    text = bytes(raw).decode("latin-1")
    names, i = [], 0
    while i < len(text):
        op = text[i]
        if op in "pgIFLVS":                       # opcodes with a line argument
            j = text.find("\n", i)
            j = len(text) if j < 0 else j
            arg = text[i + 1:j]
            if op == "V":
                names.append(arg.encode("latin-1").decode("raw_unicode_escape"))
            elif op == "S" and len(arg) >= 2 and arg[0] in "'\"":
                names.append(arg[1:-1])
            i = j + 1
        else:                                     # ( l a t . ) and others without arguments
            i += 1
    return names


def _fits(label: str, ds) -> None:
    """Refuse a dataset whose declared shape needs more than the memory budget to read (it and
    the columns taken from it: twice its bytes)."""
    from stand.io.guard import memory_budget

    need = 2.0 * ds.size * ds.dtype.itemsize
    if need > memory_budget():
        raise RecordingError(f"{label}: dataset '{ds.name}' declares shape {ds.shape} "
                             f"({need / 2 ** 30:.3g} GiB to read); the memory allows "
                             f"{memory_budget() / 2 ** 30:.3g} GiB")


def read_pandas_table(path, key: str):
    """A table written by ``DataFrame.to_hdf``, read with h5py: numeric columns only, nothing
    unpickled (pandas' own reader unpickles object columns: unsafe on a file from elsewhere).

    ``format="fixed"``: the ``block<i>_items`` / ``block<i>_values`` arrays;
    ``format="table"``: the fields of the ``table`` dataset (``data_columns=True``) and the
    ``values_block_<i>`` fields with their names.  Used by :mod:`stand.lab.table` (lab
    tables); HDF5 is opened here, in one module.

    Raises
    ------
    RecordingError
        No such key, not a DataFrame, no numeric column.
    """
    import pandas as pd

    label = str(path)
    cols = {}
    skipped = []
    with h5py.File(path, "r") as f:
        if key not in f:
            raise RecordingError(f"{label}: no key {key!r} in this HDF5 file")
        g = f[key]
        kind = g.attrs.get("pandas_type", b"")
        kind = kind.decode() if isinstance(kind, bytes) else str(kind)
        if kind == "frame":
            for i in range(int(g.attrs.get("nblocks", 0))):
                names = [n.decode() if isinstance(n, bytes) else str(n)
                         for n in g[f"block{i}_items"][()]]
                vals = g[f"block{i}_values"]
                if vals.dtype.kind not in "iufb" or vals.ndim != 2:
                    skipped += names                 # text (pickled object) columns
                    continue
                _fits(label, vals)
                a = vals[()]
                for j, n in enumerate(names):
                    cols[n] = a[:, j]
        elif kind == "frame_table":
            t = g["table"]
            _fits(label, t)
            data = t[()]
            for name in data.dtype.names:
                if name == "index":
                    continue
                a = data[name]
                if name.startswith("values_block_"):
                    names = _pickled_names(t.attrs.get(f"{name}_kind", b""))
                    if a.dtype.kind not in "iufb" or len(names) != (a.shape[1] if a.ndim == 2 else 1):
                        skipped.append(name)
                        continue
                    a = a.reshape(a.shape[0], -1)
                    for j, n in enumerate(names):
                        cols[n] = a[:, j]
                elif a.dtype.kind in "iufb" and a.ndim == 1:
                    cols[name] = a
                else:
                    skipped.append(name)
        else:
            raise RecordingError(f"{label}: {key!r} is a pandas {kind or 'object'}, not a DataFrame")
    if not cols:
        raise RecordingError(f"{label}: no numeric column in the pandas table {key!r}")
    df = pd.DataFrame(cols)
    df.attrs["skipped_columns"] = skipped
    return df
