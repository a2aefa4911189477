"""Read a lab table (CSV, Parquet, pandas HDF5) into SI signals, with its problems named.

:func:`read_table` is the one reader of tabular recordings (``stand analyze``,
``stand report``):

1. **File**: CSV/TSV/TXT with the delimiter sniffed (``, ; tab |`` or spaces)
   and decimal commas recognised; header lines before the table are skipped
   (``# key = value`` / ``key: value`` lines become metadata, e.g. the ring
   radii a ``stand track`` CSV carries); Parquet; an HDF5 table written by
   pandas (``DataFrame.to_hdf``, fixed or table format), read with h5py so that
   nothing is unpickled (numeric columns only).
2. **Map**: the recording map's columns (:mod:`.recording_map`), or the
   well-known names recognised; units converted to SI once.
3. **Checks**, each one line naming the column and the data rows (1-based,
   header excluded):

   * refused (:class:`TableError`, exit code 2): no time column, a time column
     that goes back, a table with no usable stretch;
   * excluded (the longest clean stretch is analysed; the rest is listed in
     ``excluded`` and stated in the report): gaps in time (a step above 1.5x
     the median), NaN or empty cells;
   * censored (kept in the time base, left out of the fit: ``censored``): clipped
     vibration samples, at the channel's rail (its extreme value held for >= 4 samples,
     :func:`dsp.artefacts.clipped`) or at or beyond the map's declared ADC ``range``.
"""
from __future__ import annotations

import csv
import io
import math
import re
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Optional

import numpy as np

from stand.lab.recording_map import ROLES, MapError, RecordingMap, recognise
from stand.lab.limits import CELL_BYTES, MAX_COLUMNS, TableError, _memory_budget, check_shape  # noqa: F401
from stand.lab.units import UnitError

__all__ = ["LabTable", "TableError", "read_table", "is_table_file", "is_table", "read_frame",
           "check_shape", "decode_text"]

TABLE_SUFFIXES = (".csv", ".tsv", ".txt", ".dat", ".parquet", ".pq", ".xlsx", ".xlsm", ".mat", ".tdms")
GAP_FACTOR = 1.5      #: a time step above this x the median step is a gap
MIN_ROWS = 2          #: fewest rows of a usable stretch
#: the shape limits of a table, checked before it is parsed (issue 34: a reader's work is
#: bounded by its input): a lab export has tens of channels, not thousands
MAX_LINE_CHARS = 1 << 20        #: one line of a text table [characters]


@dataclass
class LabTable:
    """A lab table in SI, reduced to its longest clean stretch.

    Attributes
    ----------
    path : str
    t : ndarray
        Times [s].
    signals : dict
        Role -> ndarray in SI (``x``, ``y`` [m], [m/s] or [m/s²] by ``quantity``;
        ``speed`` [rad/s]; ``angle`` [rad]; ``keyphasor``, ``photogate`` in the
        channel's volts).
    columns : dict
        Role -> :class:`ColumnSpec` used.
    recognised : list of str
        The choices made without a map (empty when everything was mapped).
    rows : (int, int)
        The data rows used (1-based, inclusive).
    excluded : list of dict
        ``{"rows": "a-b", "t_start_s", "t_end_s", "reason"}`` of every part left out.
    metadata : dict
        ``key = value`` header lines (strings).
    recording_map : RecordingMap
    quantity : str
        What ``x`` and ``y`` measure: ``length`` (displacement), ``velocity`` or
        ``acceleration``.
    censored : ndarray of bool or None
        Samples where ``x`` or ``y`` is clipped (bridged linearly in ``signals``, to be
        left out of any fit), with ``censored_what``, one line per channel.
    """

    path: str
    t: np.ndarray
    signals: dict
    columns: dict
    recognised: list = field(default_factory=list)
    rows: tuple = (1, 1)
    excluded: list = field(default_factory=list)
    metadata: dict = field(default_factory=dict)
    recording_map: RecordingMap = field(default_factory=RecordingMap)
    quantity: str = "length"
    censored: Optional[np.ndarray] = None
    censored_what: list = field(default_factory=list)

    def input_summary(self) -> dict:
        """What was read, JSON-able (``stand analyze``'s ``input``)."""
        return {"file": Path(self.path).name,
                "columns": {r: {"column": c.column, "unit": c.unit,
                                **({"sensitivity_v_per_mm": c.sensitivity_v_per_m * 1e-3}
                                   if c.sensitivity_v_per_m else {})}
                            for r, c in self.columns.items()},
                "map": self.recording_map.source if self.recording_map.columns else None,
                "recognised": list(self.recognised),
                "rows_used": list(self.rows), "excluded": list(self.excluded),
                "censored": list(self.censored_what),
                "vibration_quantity": self.quantity}


def is_table(path) -> bool:
    """A lab table rather than a stand recording: a table file by its name, or an HDF5 file
    holding a pandas table."""
    from stand.recording.hdf5 import pandas_table_key

    p = Path(path)
    return is_table_file(p) or (p.suffix.lower() in (".h5", ".hdf5", ".hdf") and p.is_file()
                                and pandas_table_key(p) is not None)


def is_table_file(path) -> bool:
    """A tabular recording by its name (an HDF5 file: :func:`stand.recording.hdf5.pandas_table_key`)."""
    return Path(path).suffix.lower() in TABLE_SUFFIXES


# ------------------------------------------------------------------ CSV layout
_META = re.compile(r"^\s*#?\s*([A-Za-z][\w .\-/()\[\]]*?)\s*[:=]\s*(.*?)\s*$")
_NUMBER = re.compile(r"^\s*[-+]?(\d+([.,]\d*)?|[.,]\d+)([eE][-+]?\d+)?\s*$")


def _fields(line: str, delim: Optional[str]) -> list:
    if delim is None:
        return line.split()
    try:
        return next(csv.reader([line], delimiter=delim))
    except csv.Error as exc:   # e.g. a field over csv's field limit: one clear line upstream
        raise TableError(f"a line that is not a table row ({exc})") from None


def _numeric_share(row) -> float:
    vals = [v for v in row if v.strip()]
    return sum(bool(_NUMBER.match(v)) for v in vals) / max(len(vals), 1)


def _sniff(lines: list):
    """(delimiter, field count) under which most of the lines are rows of numbers of one
    length (some text cells allowed: they are reported later, with their row)."""
    best = (0.0, ";", 0)
    for d in (";", "\t", ",", "|", None):
        rows = [_fields(ln, d) for ln in lines]
        lengths = [len(r) for r in rows]
        n = max(set(lengths), key=lengths.count)
        if n < 2:
            continue
        share = np.mean([_numeric_share(r) for r in rows if len(r) == n])
        score = lengths.count(n) / len(rows) * share
        if share >= 0.5 and score > best[0] + 1e-9:
            best = (score, d, n)
    return best[1], best[2]


def _layout(lines: list, rmap: RecordingMap, label: str):
    """(delimiter, decimal, header line index, metadata) of a CSV's first lines."""
    body = [ln for ln in lines if ln.strip()]
    if not body:
        raise TableError(f"{label}: empty file; at least 2 data rows are needed")
    tail = body[len(body) // 2:][:50] if len(body) > 4 else body
    delim, width = _sniff(tail)
    if rmap.delimiter is not None:
        delim = None if rmap.delimiter == " " else rmap.delimiter
        width = 0
    header = rmap.header_row - 1 if rmap.header_row else None
    if header is None:
        for i, ln in enumerate(lines):
            f = _fields(ln, delim)
            if len(f) >= 2 and (not width or len(f) == width) and _numeric_share(f) >= 0.5:
                header = i - 1
                break
        if header is None:
            raise TableError(f"{label}: no data rows (no line of numbers separated by "
                             f"{repr(delim) if delim else 'spaces'}); at least 2 are needed")
        while header >= 0 and not lines[header].strip():
            header -= 1
        if header < 0 or _numeric_share(_fields(lines[header], delim)) >= 0.5:
            raise TableError(f"{label}: no header line with the column names above the first "
                             f"data line ({header + 2})")
    decimal = rmap.decimal
    if decimal is None:
        sample = [v for ln in lines[header + 1:header + 50] for v in _fields(ln, delim)]
        decimal = "," if delim != "," and any(re.match(r"^\s*[-+]?\d+,\d+", v) for v in sample) \
            else "."
    meta = {}
    for ln in lines[:max(header, 0)]:
        m = _META.match(ln)
        if m:
            meta[m.group(1).strip()] = m.group(2).strip()
    return delim, decimal, header, meta


def read_frame(path, rmap: Optional[RecordingMap] = None):
    """The raw table as a DataFrame (every column, as read) and its header metadata."""
    import pandas as pd

    rmap = rmap or RecordingMap()
    p = Path(path)
    label = str(p)
    suffix = p.suffix.lower()
    try:
        if suffix in (".parquet", ".pq"):
            _check_parquet_shape(p, label)
            return pd.read_parquet(p), {}
        if suffix in (".h5", ".hdf5", ".hdf"):
            from stand.recording.hdf5 import pandas_table_key

            key = rmap.key or pandas_table_key(p)
            if key is None:
                raise TableError(f"{label}: no pandas table in this HDF5 file")
            from stand.recording.hdf5 import RecordingError, read_pandas_table

            try:
                return read_pandas_table(p, key), {}
            except RecordingError as exc:
                raise TableError(str(exc)) from None
    except ImportError as exc:
        raise TableError(f"{label}: reading it needs {exc.name or exc} (pip install pyarrow)") from None
    except (OSError, ValueError, KeyError) as exc:
        if isinstance(exc, TableError):
            raise
        raise TableError(f"{label}: not a readable table ({' '.join(str(exc).split())})") from None
    if suffix in (".xlsx", ".xlsm", ".mat", ".tdms"):
        from stand.lab.formats import read_other

        df, text = read_other(p, label, rmap.key)
        if df is not None:
            return df, {}
        return _frame_from_text(text, label, rmap)
    try:
        size = p.stat().st_size
        if 4.0 * size > _memory_budget():   # bytes, text, lines, cells: ~4 copies of the file
            raise TableError(f"{label}: {size / 2 ** 30:.1f} GiB of text, over the limit of "
                             f"{_memory_budget() / 4 / 2 ** 30:.1f} GiB for a text table; split it "
                             f"or convert it to Parquet")
        raw = p.read_bytes()
    except OSError as exc:
        raise TableError(f"{label}: cannot read ({exc.strerror or exc})") from None
    return _frame_from_text(decode_text(raw, label), label, rmap)


def decode_text(raw: bytes, label: str) -> str:
    """The text of a table's bytes: UTF-16 (by its byte-order mark, or by the NUL bytes of
    ASCII text in UTF-16 without one), UTF-8 (with or without BOM), else Windows-1252."""
    if raw[:2] in (b"\xff\xfe", b"\xfe\xff"):
        encs = ("utf-16",)
    else:
        head = raw[:4096]
        even, odd = head[0::2].count(0), head[1::2].count(0)
        encs = (("utf-16-le",) if odd > 0.3 * len(head) / 2 > even else
                ("utf-16-be",) if even > 0.3 * len(head) / 2 > odd else ())
        encs += ("utf-8-sig", "cp1252", "latin-1")
    for enc in encs:
        try:
            text = raw.decode(enc)
        except UnicodeDecodeError:
            continue
        if "\x00" in text:
            raise TableError(f"{label}: binary data, not a text table (NUL characters in the "
                             f"{enc} text); a table is read from CSV/TSV/TXT in UTF-8 or UTF-16, "
                             f"Parquet, HDF5, Excel, MATLAB or TDMS")
        return text.lstrip("\ufeff")
    raise TableError(f"{label}: not a text table in UTF-8, UTF-16 or Windows-1252")


def _frame_from_text(text: str, label: str, rmap: RecordingMap):
    """The CSV layout rules (module docstring) on a table's text."""
    import pandas as pd

    lines = text.splitlines()
    longest = max(range(len(lines)), key=lambda i: len(lines[i]), default=0)
    if lines and len(lines[longest]) > MAX_LINE_CHARS:
        raise TableError(f"{label}: line {longest + 1} has {len(lines[longest])} characters, over "
                         f"the limit of {MAX_LINE_CHARS} for a line of a table")
    try:
        delim, decimal, header, meta = _layout(lines[:400], rmap, label)
    except TableError as exc:
        msg = str(exc)
        raise TableError(msg if msg.startswith(label) else f"{label}: {msg}") from None
    if not any(ln.strip() for ln in lines[header + 1:]):
        raise TableError(f"{label}: 0 data rows; at least {MIN_ROWS} are needed")
    width = max((len(_fields(ln, delim)) for ln in lines[header:header + 50] if ln.strip()),
                default=0)
    check_shape(label, width, len(lines) - header - 1)
    try:
        df = pd.read_csv(io.StringIO("\n".join(lines[header:])), sep=delim if delim else r"\s+",
                         decimal=decimal, skipinitialspace=True, engine="c" if delim else "python")
    except Exception as exc:  # pandas parse errors of any kind -> one clear line
        raise TableError(f"{label}: not a readable table ({' '.join(str(exc).split())})") from None
    df.columns = [str(c).strip() for c in df.columns]
    df.attrs["first_data_line"] = header + 2
    return df, meta


def _check_parquet_shape(p: Path, label: str) -> None:
    """The shape limits of a Parquet file from its footer, before it is read."""
    try:
        import pyarrow.parquet as pq
    except ImportError:
        return                       # read_parquet says what is missing
    try:
        meta = pq.read_metadata(p)
    except Exception as exc:  # noqa: BLE001 -- any footer error: one clear line
        raise TableError(f"{label}: not a readable Parquet file ({' '.join(str(exc).split())})") \
            from None
    check_shape(label, meta.num_columns, meta.num_rows)


# ------------------------------------------------------------------ checks
def _runs(mask) -> list:
    """[(start, stop)) of the True runs of a boolean array."""
    m = np.concatenate(([0], np.asarray(mask, np.int8), [0]))
    d = np.flatnonzero(np.diff(m))
    return list(zip(d[::2].tolist(), d[1::2].tolist()))


def _rows(a, b) -> str:
    return f"{a + 1}-{b}" if b - a > 1 else f"{a + 1}"


def read_table(path, recording_map: Optional[RecordingMap] = None,
               require=("x", "y")) -> LabTable:
    """Read a lab table into SI signals on its longest clean stretch (module docstring).

    Parameters
    ----------
    path : str or Path
    recording_map : RecordingMap, optional
        Columns and layout.  With a map that names columns, exactly those are
        used; without, the well-known names are recognised
        (:func:`.recording_map.recognise`) and the choices listed in ``recognised``.
    require : tuple of str
        Roles that must be present besides ``time``.

    Raises
    ------
    TableError
        One line naming the file, the column (with its unit) and the rows.
    """
    import pandas as pd

    rmap = recording_map or RecordingMap()
    label = str(path)
    df, meta = read_frame(path, rmap)
    names = list(df.columns)
    cols = {}
    from stand.lab.formats import resolve_column

    for role, spec in rmap.columns.items():
        full = resolve_column(spec.column, names, grouped=bool(df.attrs.get("grouped")))
        if full is not None and full != spec.column:
            spec = replace(spec, column=full)
        if full is None:
            from stand.io.validate import suggest

            raise TableError(f"{label}: {role} = column {spec.column!r} ({rmap.source}) is not in "
                             f"the table; {suggest(spec.column, names)}its columns: "
                             f"{', '.join(names)}")
        cols[role] = spec
    recognised = []
    if not cols:
        grouped = bool(df.attrs.get("grouped"))          # MATLAB / TDMS: group/channel
        bare = [n.rsplit("/", 1)[-1] if grouped else n for n in names]
        found, recognised = recognise(bare)
        full = dict(zip(bare, names))
        found = {r: replace(c, column=full[c.column]) for r, c in found.items()}
        cols.update(found)
    for role, eg, unit in (("time", "t_s, time_ms", "s"), ("x", "x_m, disp_x_um", "um"),
                           ("y", "y_m, disp_y_um", "um")):
        if role in cols or (role != "time" and role not in require):
            continue
        what = "time" if role == "time" else f"{role} displacement"
        how = (f"the map {rmap.source} names none" if rmap.columns else
               f"no well-known name such as {eg}")
        raise TableError(f"{label}: no {what} column ({how}; columns: {', '.join(names)}); "
                         f"map one with --columns {role}=COLUMN[{unit}]")
    # numbers in SI
    sig = {}
    for role, spec in cols.items():
        if spec.unit is None:
            from stand.lab.recording_map import DEFAULT_UNIT
            from stand.lab.units import unit_from_name, ROLE_QUANTITY

            unit = unit_from_name(spec.column, ROLE_QUANTITY[role])
            for q in (("velocity", "acceleration") if role in ("x", "y") else ()):
                unit = unit or unit_from_name(spec.column, q)
            if unit is None:
                raise TableError(f"{label}: {role} = column {spec.column!r}: no unit; give it, e.g. "
                                 f"--columns {role}={spec.column}[{DEFAULT_UNIT[role]}]")
            spec = cols[role] = replace(spec, unit=unit)
        try:
            k = spec.si_factor(f"{role} = column {spec.column!r}")
        except (UnitError, MapError) as exc:
            raise TableError(f"{label}: {exc}") from None
        raw = df[spec.column]
        num = pd.to_numeric(raw, errors="coerce")
        text = (num.isna() & raw.notna() & (raw.astype(str).str.strip() != "")).to_numpy()
        if text.any():
            i = int(np.argmax(text))
            raise TableError(f"{label}: column {spec.column!r} ({spec.unit}), data row {i + 1}: "
                             f"{str(raw.iloc[i])[:40]!r} is not a number")
        sig[role] = num.to_numpy(float) * (1.0 if role in ("keyphasor", "photogate") else k)
    quantity = _vibration_quantity(cols, label)
    t = sig.pop("time")
    tcol = cols["time"]
    n = t.size
    if n < MIN_ROWS:
        raise TableError(f"{label}: {n} data rows; at least {MIN_ROWS} are needed")
    # time must not go back (NaN times are excluded below)
    fin_t = np.flatnonzero(np.isfinite(t))
    back = np.flatnonzero(np.diff(t[fin_t]) <= 0)
    if back.size:
        i, j = int(fin_t[back[0]]), int(fin_t[back[0] + 1])
        scale = 1.0 / tcol.si_factor("time")
        raise TableError(f"{label}: column {tcol.column!r} ({tcol.unit}): time does not increase at "
                         f"data rows {i + 1}-{j + 1} ({t[i] * scale:.6g} -> {t[j] * scale:.6g} "
                         f"{tcol.unit}); {back.size} such place(s). Sort the table or split it")
    bad = np.zeros(n, bool)
    reasons, clip = [], {}
    for role in ["time"] + [r for r in ROLES if r in sig]:
        v = t if role == "time" else sig[role]
        spec = cols[role]
        nan = ~np.isfinite(v)
        for a, b in _runs(nan):
            reasons.append((a, b, f"column {spec.column!r}: empty or NaN"))
        bad |= nan
        if role in ("x", "y"):
            from dsp.artefacts import clipped

            k = spec.si_factor("")
            clip[role] = clipped(v, rail=None if spec.rail is None else np.multiply(spec.rail, k))
    # a gap in time is judged on the rows that have a time: rows whose other columns are
    # empty are excluded as such above, they are no gap in the time column
    good = np.flatnonzero(np.isfinite(t))
    cut = np.zeros(n, bool)                  # rows that start again after a gap in time
    if good.size >= 2:
        dt = np.diff(t[good])
        step = float(np.median(dt))
        for k in np.flatnonzero(dt > GAP_FACTOR * step):
            a, b = int(good[k]), int(good[k + 1])
            cut[b] = True
            reasons.append((a, b + 1, f"column {tcol.column!r}: gap of "
                                      f"{(t[b] - t[a]) / tcol.si_factor('time'):.6g} {tcol.unit} "
                                      f"(median step {step / tcol.si_factor('time'):.6g} {tcol.unit})"))
    # the longest clean stretch: clean rows, no gap inside (stretches numbered, the largest kept)
    ok = ~bad
    start = ok & (np.concatenate(([True], bad[:-1])) | cut)
    number = np.cumsum(start) * ok
    sizes = np.bincount(number)
    sizes[0] = 0
    rows_best = np.flatnonzero(number == int(np.argmax(sizes))) if sizes.max() > 0 else np.zeros(0, int)
    a, b = (int(rows_best[0]), int(rows_best[-1]) + 1) if rows_best.size else (0, 0)
    if b - a < MIN_ROWS:
        why = "; ".join(f"rows {_rows(x, y)}: {r}" for x, y, r in reasons[:3])
        raise TableError(f"{label}: no stretch of {MIN_ROWS} clean rows ({why})")
    excluded = []
    if a > 0 or b < n:
        for x, y, r in sorted(reasons):
            excluded.append({"rows": _rows(x, y), "t_start_s": _finite(t, x),
                             "t_end_s": _finite(t, y - 1), "reason": r})
        if a > 0:
            excluded.append({"rows": _rows(0, a), "t_start_s": _finite(t, 0),
                             "t_end_s": _finite(t, a - 1), "reason": "before the longest clean stretch"})
        if b < n:
            excluded.append({"rows": _rows(b, n), "t_start_s": _finite(t, b),
                             "t_end_s": _finite(t, n - 1), "reason": "after the longest clean stretch"})
    cens, what = _censored(t[a:b], sig, clip, cols, a, b)
    return LabTable(path=label, t=t[a:b], signals={r: v[a:b] for r, v in sig.items()},
                    columns=cols, recognised=recognised, rows=(a + 1, b), excluded=excluded,
                    metadata=meta, recording_map=rmap, quantity=quantity, censored=cens,
                    censored_what=what)


def _censored(t, sig, clip, cols, a, b):
    """The clipped samples of x and y within rows a:b: ``(mask or None, one line per
    channel)``; the channels bridged over them in ``sig`` (in place)."""
    from dsp.artefacts import filled

    mask, what = np.zeros(b - a, bool), []
    for role, m in clip.items():
        m = m[a:b]
        if m.any():
            spec, v = cols[role], sig[role]
            k = spec.si_factor("")
            lv = np.unique(v[a:b][m]) / k
            what.append(f"column {spec.column!r}: {int(m.sum())} samples clipped at "
                        f"{', '.join(f'{x:.6g}' for x in lv[:4])}{' ...' if lv.size > 4 else ''} "
                        f"{spec.unit} ({len(_runs(m))} runs, {t[m][0]:.6g}-{t[m][-1]:.6g} s)")
            mask |= m
    if not mask.any():
        return None, []
    for role in clip:
        sig[role][a:b] = filled(t, sig[role][a:b], mask)
    return mask, what


def _vibration_quantity(cols, label) -> str:
    """What x and y measure (displacement ``length``, ``velocity``, ``acceleration``): one
    quantity for both."""
    qs = {r: cols[r].quantity() for r in ("x", "y") if r in cols}
    if len(set(qs.values())) > 1:
        raise TableError(f"{label}: x = column {cols['x'].column!r} [{cols['x'].unit}] is a "
                         f"{qs['x']}, y = column {cols['y'].column!r} [{cols['y'].unit}] a "
                         f"{qs['y']}; both probes must measure the same quantity")
    return next(iter(qs.values()), "length")


def _finite(t, i):
    v = float(t[i])
    return v if math.isfinite(v) else None
