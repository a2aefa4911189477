"""The second HDF5 layout of stand/recording: a sweep's final table (``stand sweep ... -o R.h5``).

One dataset per column under ``/results`` (the column order as JSON in its ``columns``
attribute; strings as variable-length UTF-8; pandas' nullable ``boolean`` / ``Int64`` as
float64 with NaN for missing, their dtype in the dataset's ``dtype`` attribute), the sweep's
strings (name, fingerprint, ...) as file attributes.  Written atomically by the one HDF5
writer (:func:`stand.recording.write.open_for_writing`).  Recordings of one run are
:mod:`.write` / :mod:`.read`.
"""
from __future__ import annotations

import json
from pathlib import Path
from typing import Union

import h5py
import numpy as np
import pandas as pd

from stand.io.jsonable import dumps
from stand.recording.write import open_for_writing

__all__ = ["write_sweep_table", "read_sweep_table"]

#: pandas' nullable dtypes stored as float64 with NaN for missing
_NULLABLE = ("boolean", "Int64")


def write_sweep_table(df: pd.DataFrame, path: Union[str, Path], attrs: dict) -> None:
    """Write a sweep's table to ``path`` (HDF5, atomically).

    Parameters
    ----------
    df : pandas.DataFrame
    path : path
    attrs : dict
        Strings stored as HDF5 file attributes (sweep name, fingerprint, ...).
    """
    with open_for_writing(Path(path), df.memory_usage(deep=True).sum()) as f:
        g = f.create_group("results")
        for k, v in attrs.items():
            f.attrs[k] = v
        g.attrs["columns"] = dumps(list(df.columns))
        for c in df.columns:
            col = df[c]
            if col.dtype == "string" or col.dtype == object:
                g.create_dataset(c, data=np.array(col.fillna("").astype(str), dtype=object),
                                 dtype=h5py.string_dtype())
            elif str(col.dtype) in _NULLABLE:
                g.create_dataset(c, data=col.astype("float64").to_numpy(na_value=np.nan))
                g[c].attrs["dtype"] = str(col.dtype)
            else:
                g.create_dataset(c, data=col.to_numpy())


def read_sweep_table(path: Union[str, Path]) -> pd.DataFrame:
    """Read a table written by :func:`write_sweep_table`.

    Parameters
    ----------
    path : path

    Returns
    -------
    pandas.DataFrame
        The columns in their written order and dtypes.
    """
    with h5py.File(path, "r") as f:
        g = f["results"]
        cols = json.loads(g.attrs["columns"])
        data = {}
        for c in cols:
            ds = g[c]
            kind = ds.attrs.get("dtype")
            if h5py.check_string_dtype(ds.dtype) is not None:
                data[c] = pd.array([s.decode() if isinstance(s, bytes) else s for s in ds[()]],
                                   dtype="string")
            elif kind in _NULLABLE:
                vals = [None if np.isnan(v) else (bool(v) if kind == "boolean" else int(v))
                        for v in ds[()]]
                data[c] = pd.array(vals, dtype=kind)
            else:
                data[c] = ds[()]
    return pd.DataFrame(data, columns=cols)
