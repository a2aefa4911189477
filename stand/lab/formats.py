"""The files DAQ systems write, as one DataFrame of named columns: Excel, MATLAB, NI TDMS.

Each reader goes through a well-kept library (no hand-written parser) and checks the
table's shape (:func:`stand.lab.limits.check_shape`: columns, memory budget) before the
cells are read where the format tells the shape up front:

* Excel ``.xlsx`` / ``.xlsm``: :func:`pandas.read_excel` with openpyxl (optional
  dependency, ``pip install openpyxl``); the sheet is the map's ``key`` or the first one.
  The cells become text rows and go through the CSV layout rules (header lines above
  the column names are skipped, ``key: value`` lines kept as metadata).
* MATLAB ``.mat``: v5 / v7 by :func:`scipy.io.loadmat`, v7.3 (HDF5) by h5py.  Every
  numeric vector is a column named by its variable; a struct's fields are
  ``struct/field``; a matrix of N rows and k columns gives ``name/1`` ... ``name/k``.
* NI TDMS ``.tdms``: npTDMS (optional dependency, ``pip install npTDMS``); channels
  are ``group/channel``.  A waveform channel (``wf_increment``) without a time channel
  in the file adds ``time_s`` from its increment.

Where a format has groups, a column is named ``group/channel``; its bare name works
when it is unique (:func:`resolve_column`).
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

__all__ = ["READERS", "FORMATS_READ", "read_other", "resolve_column", "bare_aliases"]

#: suffix -> format name of the readers here
READERS = {".xlsx": "Excel", ".xlsm": "Excel", ".mat": "MATLAB", ".tdms": "NI TDMS"}
#: the formats ``stand analyze`` reads, for the message of an unrecognised file
FORMATS_READ = ("stand recording (.h5, HDF5)", "CSV/TSV/TXT/DAT (UTF-8, UTF-8 with BOM, UTF-16, "
                "Windows-1252)", "Parquet (.parquet)", "pandas HDF5 table (.h5)",
                "Excel (.xlsx)", "MATLAB (.mat v5, v7.3)", "NI TDMS (.tdms)")


def _error(msg):
    from stand.lab.limits import TableError

    return TableError(msg)


def _need(module: str, package: str, label: str):
    import importlib

    try:
        return importlib.import_module(module)
    except ImportError:
        raise _error(f"{label}: reading it needs the optional package {package} "
                     f"(pip install {package})") from None


def bare_aliases(names) -> dict:
    """``{bare name: full name}`` of ``group/channel`` names whose bare name is unique."""
    bare = {}
    for n in names:
        b = str(n).rsplit("/", 1)[-1]
        bare.setdefault(b, []).append(n)
    return {b: v[0] for b, v in bare.items() if len(v) == 1 and v[0] != b}


def resolve_column(name: str, names, grouped: bool = True) -> str | None:
    """The table's column for ``name``: itself, or the ``group/channel`` whose bare name it is
    (when unique); None otherwise."""
    if name in names:
        return name
    return bare_aliases(names).get(name) if grouped else None


def _frame(columns: dict, label: str):
    """A DataFrame of equal-length 1-D columns; the longest length wins and shorter
    channels are padded with NaN (the table's checks then name them)."""
    import pandas as pd

    from stand.lab.limits import check_shape

    cols = {k: np.asarray(v, float).ravel() for k, v in columns.items()}
    cols = {k: v for k, v in cols.items() if v.size > 1}
    if not cols:
        raise _error(f"{label}: no numeric vector (a column of at least 2 numbers) in the file")
    n = max(v.size for v in cols.values())
    check_shape(label, len(cols), n)
    out = {}
    for k, v in cols.items():
        if v.size < n:
            v = np.concatenate((v, np.full(n - v.size, np.nan)))
        out[k] = v
    df = pd.DataFrame(out)
    df.attrs["grouped"] = True
    return df


# ------------------------------------------------------------------ Excel
EXCEL_ROWS, EXCEL_COLUMNS = 1_048_576, 16_384   #: Excel's own sheet limits
#: largest unzipped / zipped size of a workbook member: real sheets compress 3-20x; a member
#: above this ratio and :data:`ZIP_RATIO_FROM` bytes unzipped is a zip bomb
ZIP_RATIO, ZIP_RATIO_FROM = 100.0, 8 << 20
PROGRESS_AFTER_S = 2.0     #: a read that lasts longer shows a progress bar on stderr


def _check_zip(p: Path, label: str) -> None:
    """Refuse a workbook whose members unzip far beyond a real sheet, before any parse."""
    import zipfile

    from stand.lab.limits import _memory_budget

    try:
        with zipfile.ZipFile(p) as z:
            infos = z.infolist()
    except (zipfile.BadZipFile, OSError, ValueError) as exc:
        raise _error(f"{label}: not a readable Excel workbook ({' '.join(str(exc).split())})") \
            from None
    for i in infos:
        ratio = i.file_size / max(i.compress_size, 1)
        if (i.file_size > ZIP_RATIO_FROM and ratio > ZIP_RATIO) or i.file_size > _memory_budget():
            raise _error(f"{label}: member {i.filename} unzips to {i.file_size} bytes from "
                         f"{i.compress_size} (ratio {ratio:.0f}, a real sheet's is under "
                         f"{ZIP_RATIO:.0f}; memory allows {_memory_budget():.3g} bytes): "
                         f"refused as a zip bomb")


def _cell_text(cell) -> str:
    """A cell as pandas writes it: empty or an error -> "", a number in its shortest exact form."""
    v = cell.value
    return "" if v is None or cell.data_type == "e" else str(v)


def _quoted(text: str) -> str:
    """A CSV field as pandas writes it (quoted when it holds ``;``, a quote or a newline)."""
    return '"' + text.replace('"', '""') + '"' if any(c in text for c in ';"\n\r') else text


def excel_text(p: Path, label: str, sheet=None) -> str:
    """The sheet's cells as ``;``-separated text rows (for the CSV layout rules).

    Bounded before the work: the zip members' sizes and ratios (:func:`_check_zip`), the
    sheet's declared dimension against Excel's limits and the memory budget, then a
    streaming read (openpyxl ``read_only``) that stops at :data:`EXCEL_ROWS` rows.
    """
    from stand.io.executor import progress_bar
    from stand.lab.limits import TableError, check_shape

    _check_zip(p, label)
    openpyxl = _need("openpyxl", "openpyxl", label)
    try:
        wb = openpyxl.load_workbook(p, read_only=True, data_only=True, keep_links=False)
    except Exception as exc:  # noqa: BLE001 -- a broken workbook: one clear line
        raise _error(f"{label}: not a readable Excel workbook ({' '.join(str(exc).split())})") \
            from None
    try:
        names = wb.sheetnames
        name = sheet if sheet is not None else names[0]
        if name not in names:
            raise _error(f"{label}: no sheet {name!r} (sheets: {', '.join(names)})")
        ws = wb[name]
        rows, cols = ws.max_row or 0, ws.max_column or 0
        if rows > EXCEL_ROWS or cols > EXCEL_COLUMNS:
            raise _error(f"{label}: sheet {name!r} declares {rows} rows x {cols} columns, over "
                         f"Excel's limit of {EXCEL_ROWS} x {EXCEL_COLUMNS}")
        check_shape(label, cols, rows)
        ws.reset_dimensions()     # the declared dimension may be wrong: read what is there
        out, width, last = [], 0, 0      # (row as text, its cells); widest row; last with data
        bar = progress_bar(rows or EXCEL_ROWS, unit="rows", desc=f"reading {p.name}",
                           delay=PROGRESS_AFTER_S, leave=False)
        try:
            for row in ws.rows:
                cells = [_cell_text(c) for c in row]
                while cells and not cells[-1]:
                    cells.pop()
                if len(out) >= EXCEL_ROWS or len(cells) > EXCEL_COLUMNS:
                    over = ("rows", EXCEL_ROWS) if len(out) >= EXCEL_ROWS else ("columns",
                                                                                EXCEL_COLUMNS)
                    raise _error(f"{label}: sheet {name!r} has more than {over[1]} {over[0]}, "
                                 f"over Excel's limit")
                out.append((";".join(map(_quoted, cells)), len(cells)))
                if cells:
                    last, width = len(out), max(width, len(cells))
                if len(out) % 65536 == 0:     # a sheet whose dimension lied: still bounded
                    check_shape(label, width, len(out))
                bar.update(1)
        finally:
            bar.close()
    except Exception as exc:  # noqa: BLE001 -- a malformed sheet's XML: one clear line
        if isinstance(exc, TableError):
            raise
        raise _error(f"{label}: not a readable Excel sheet ({' '.join(str(exc).split())})") \
            from None
    finally:
        wb.close()
    return "".join(text + ";" * (width - max(n, 1)) + "\n" for text, n in out[:last])


# ------------------------------------------------------------------ MATLAB
def _mat_columns(name, v, out):
    """Numeric vectors of a loadmat value (struct fields recursively)."""
    if isinstance(v, np.ndarray) and v.dtype.names:          # a struct array
        if v.size == 1:
            for f in v.dtype.names:
                _mat_columns(f"{name}/{f}", v[f].reshape(-1)[0], out)
        return
    if isinstance(v, np.ndarray) and v.dtype == object and v.size == 1:
        _mat_columns(name, v.reshape(-1)[0], out)
        return
    a = np.asarray(v)
    if a.dtype.kind not in "fiub" or a.ndim > 2 or a.size < 2:
        return
    if a.ndim == 2 and min(a.shape) > 1:                      # rows are samples
        if a.shape[0] < a.shape[1]:
            a = a.T
        for j in range(a.shape[1]):
            out[f"{name}/{j + 1}"] = a[:, j]
        return
    out[name] = a.ravel()


def _mat73_columns(f, out, label):
    """Numeric datasets of a MATLAB v7.3 (HDF5) file; MATLAB stores them transposed.  Their
    declared shapes are checked against the memory budget before any is read."""
    import h5py

    from stand.lab.limits import check_shape

    found = []

    def visit(path, obj):
        if not isinstance(obj, h5py.Dataset) or path.startswith("#"):
            return
        if obj.dtype.kind not in "fiu" or obj.ndim > 2 or obj.size < 2:
            return
        cls = obj.attrs.get("MATLAB_class", b"double")
        if (cls.decode("ascii", "replace") if isinstance(cls, bytes) else str(cls)) in ("char",
                                                                                       "cell"):
            return
        found.append((path, obj))

    f.visititems(visit)
    check_shape(label, sum(min(o.shape) if o.ndim == 2 else 1 for _, o in found),
                max((max(o.shape) for _, o in found), default=0))
    for path, obj in found:
        a = obj[()]
        _mat_columns(path, a.T if a.ndim == 2 else a, out)


def read_mat(p: Path, label: str):
    import h5py

    from stand.lab.limits import TableError

    out = {}
    if h5py.is_hdf5(str(p)):
        try:
            with h5py.File(p, "r") as f:
                _mat73_columns(f, out, label)
        except Exception as exc:  # noqa: BLE001 -- h5py's errors on a damaged file: one line
            if isinstance(exc, TableError):
                raise
            raise _error(f"{label}: not a readable MATLAB v7.3 file "
                         f"({' '.join(str(exc).split())})") from None
    else:
        import scipy.io

        try:
            info = scipy.io.whosmat(str(p))
            from stand.lab.limits import check_shape

            check_shape(label, len(info), max((int(np.prod(s[1])) for s in info), default=0))
            data = scipy.io.loadmat(str(p), squeeze_me=False, struct_as_record=True)
        except Exception as exc:  # noqa: BLE001 -- MatReadError and the like: one clear line
            if isinstance(exc, TableError):
                raise
            raise _error(f"{label}: not a readable MATLAB file ({' '.join(str(exc).split())})") \
                from None
        for k, v in data.items():
            if not k.startswith("__"):
                _mat_columns(k, v, out)
    return _frame(out, label)


# ------------------------------------------------------------------ TDMS
TDMS_CHUNK = 1 << 20       #: samples read at a time (the progress bar's step)


def read_tdms(p: Path, label: str):
    """The numeric channels of a TDMS file; the declared lengths are checked against the
    memory budget before any data is read, and a long read shows a progress bar (bytes)."""
    import logging

    from stand.io.executor import progress_bar
    from stand.lab.limits import TableError, check_shape

    nptdms = _need("nptdms", "npTDMS", label)
    from nptdms.log import log_manager

    level = log_manager.log_level
    log_manager.set_level(logging.ERROR)     # its warnings: the refusal says it all
    try:
        with nptdms.TdmsFile.open(p) as f:
            chans = [(g.name, c) for g in f.groups() for c in g.channels()
                     if c.data_type is not None and np.dtype(c.dtype).kind in "fiu"]
            check_shape(label, len(chans), max((len(c) for _, c in chans), default=0))
            out, inc = {}, None
            bar = progress_bar(sum(len(c) * np.dtype(c.dtype).itemsize for _, c in chans) or 1,
                               unit="B", unit_scale=True, desc=f"reading {p.name}",
                               delay=PROGRESS_AFTER_S, leave=False)
            try:
                for g, c in chans:
                    n, size = len(c), np.dtype(c.dtype).itemsize
                    parts = []
                    for i in range(0, n, TDMS_CHUNK):
                        parts.append(c[i:min(i + TDMS_CHUNK, n)])
                        bar.update(parts[-1].size * size)
                    out[f"{g}/{c.name}"] = np.concatenate(parts) if parts else np.zeros(0)
                    if inc is None and "wf_increment" in c.properties:
                        inc = (float(c.properties["wf_increment"]),
                               float(c.properties.get("wf_start_offset", 0.0)), n)
            finally:
                bar.close()
    except TableError:
        raise
    except Exception as exc:  # noqa: BLE001 -- any npTDMS error: one clear line
        raise _error(f"{label}: not a readable TDMS file ({' '.join(str(exc).split())})") from None
    finally:
        log_manager.set_level(level)
    has_time = any(k.rsplit("/", 1)[-1].lower().startswith(("time", "t_")) for k in out)
    if inc is not None and not has_time and inc[0] > 0:
        out["time_s"] = inc[1] + inc[0] * np.arange(inc[2])
    return _frame(out, label)


def read_other(p: Path, label: str, key=None):
    """``(DataFrame, None)`` of a MATLAB or TDMS file, ``(None, text)`` of an Excel sheet."""
    suffix = p.suffix.lower()
    if suffix in (".xlsx", ".xlsm"):
        return None, excel_text(p, label, key)
    if suffix == ".mat":
        return read_mat(p, label), None
    return read_tdms(p, label), None
