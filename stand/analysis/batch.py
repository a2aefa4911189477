"""Batch processing of recordings: `stand analyze` / `stand report` on a folder
or a glob, in parallel, with one summary table (issue 10 item 4).

Files are processed by :class:`stand.io.executor.Executor`: a local process pool
(all cores by default) or, with ``scheduler="tcp://host:port"``, a
dask.distributed cluster -- the same function either way.  A file that fails
gives a row with ``status = "error"`` and its message; the others go on.  The
summary is written atomically (CSV, or Parquet when the name ends in
``.parquet``).
"""
from __future__ import annotations

import functools
import glob
from pathlib import Path
from typing import Callable, Optional

from stand.io.executor import Executor, ItemError, error_text
from stand.io.atomic import atomic_path

__all__ = ["expand_sources", "is_batch_source", "run_batch", "analyze_row", "write_table"]

EXTENSIONS = (".h5", ".hdf5", ".csv")


def is_batch_source(source: str) -> bool:
    """Whether ``source`` names several recordings: a directory or a glob pattern.

    Parameters
    ----------
    source : str
        A path or a pattern with ``*``, ``?`` or ``[``.

    Returns
    -------
    bool
    """
    return Path(source).is_dir() or any(c in str(source) for c in "*?[")


def expand_sources(source: str) -> list:
    """Sorted recording files of a directory (``*.h5``, ``*.hdf5``, ``*.csv``) or a glob.

    Parameters
    ----------
    source : str
        A directory or a glob pattern.

    Returns
    -------
    list of str

    Raises
    ------
    FileNotFoundError
        Nothing matches.
    """
    p = Path(source)
    if p.is_dir():
        files = [str(f) for f in sorted(p.iterdir()) if f.suffix.lower() in EXTENSIONS and f.is_file()]
    else:
        files = sorted(f for f in glob.glob(str(source)) if Path(f).is_file())
    if not files:
        raise FileNotFoundError(f"{source!r}: no recordings (*.h5, *.hdf5, *.csv) found")
    return files


def analyze_row(path: str, grade: float = 6.3, service_speed_rpm: Optional[float] = None,
                recording_map=None, *, grade_mm_s: Optional[float] = None) -> dict:
    """One summary row of ``stand analyze`` for ``path`` (never raises).

    Parameters
    ----------
    path : str
        A recording.
    grade : float
        Target ISO 21940-11 balance grade G [mm/s] (``grade_mm_s``: its old name, deprecated).
    service_speed_rpm : float, optional
        Service speed [rpm].
    recording_map : stand.lab.recording_map.RecordingMap, optional
        Columns of lab tables.

    Returns
    -------
    dict
        ``file``, ``status`` ("ok"/"error"), ``error`` and the scalar fields of
        :func:`stand.analysis.identify.analyze`.
    """
    from stand.analysis.identify import analyze
    from stand.io.result import renamed

    grade = renamed(grade, grade_mm_s, "grade_mm_s", "grade", "analyze_row")
    row = {"file": path, "status": "ok", "error": ""}
    try:
        doc = analyze(path, grade=grade, service_speed_rpm=service_speed_rpm,
                      recording_map=recording_map)
    except Exception as exc:   # a bad file must not stop the batch: reported in its row
        row.update(status="error", error=error_text(exc))
        return row
    for k, v in doc.items():
        if isinstance(v, (int, float, str, bool)) or v is None:
            row[k] = v
    return row


def _error_row(failed: ItemError) -> dict:
    """The row of a file whose call raised (the function did not make its own)."""
    return {"file": str(failed.item), "status": "error", "error": failed.error}


def run_batch(files, func: Callable = analyze_row, *, workers: Optional[int] = None,
              scheduler: Optional[str] = None, progress: bool = False, **kwargs):
    """Apply ``func(path, **kwargs) -> dict`` to every file (:class:`stand.io.executor.Executor`).

    Parameters
    ----------
    files : iterable of str
        Recording paths (:func:`expand_sources`).
    func : callable
        A picklable function (module level) returning one summary row; default
        :func:`analyze_row`.
    workers : int, optional
        Local worker processes (default: all cores; 1: in this process).
    scheduler : str, optional
        A dask.distributed scheduler address ``tcp://host:port`` instead of the
        local pool.
    progress : bool
        Progress bar on stderr (when tqdm is installed).
    **kwargs
        Passed to ``func``.

    Returns
    -------
    pandas.DataFrame
        One row per file, in the order of ``files``; a file whose call raised
        gets ``status = "error"`` and the message in ``error``.
    """
    import pandas as pd

    files = list(files)
    call = functools.partial(func, **kwargs) if kwargs else func
    with Executor(workers, scheduler) as ex:
        rows = ex.map(call, files, progress=progress, unit="file", errors="capture")
    return pd.DataFrame([_error_row(r) if isinstance(r, ItemError) else r for r in rows])


def write_table(df, path) -> Path:
    """Write the summary atomically (:func:`stand.io.atomic.atomic_path`): CSV, Parquet for
    ``*.parquet`` / ``*.pq``, or JSON for ``*.json`` (a list of rows, missing values null).

    Raises
    ------
    FileNotFoundError
        The output directory does not exist.
    """
    path = Path(path)
    with atomic_path(path) as tmp:
        if path.suffix.lower() in (".parquet", ".pq"):
            df.to_parquet(tmp, index=False)
        elif path.suffix.lower() == ".json":
            from stand.io.jsonable import dumps

            Path(tmp).write_text(dumps(df.to_dict("records"), indent=1) + "\n", encoding="utf-8")
        else:
            df.to_csv(tmp, index=False)
    return path
