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

__all__ = ["expand_sources", "is_batch_source", "run_batch", "analyze_row", "summary_columns",
           "write_table"]

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
        ``file``, ``status`` ("ok"/"error"), ``error`` and the columns of the document of
        :func:`stand.analysis.identify.analyze` (:func:`summary_columns`).
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
    row.update(summary_columns(doc))
    return row


#: documents of the analysis shown in the summary by some of their fields:
#: ``field -> {key of the document: column}``; the other keys are left out
NESTED_COLUMNS = {
    "iso_grade": {"class": "iso_grade", "grade_mm_s": "iso_grade_mm_s",
                  "grade_mm_s_std": "iso_grade_mm_s_std", "target_mm_s": "iso_target_mm_s",
                  "passed": "iso_passed", "permissible_gmm": "iso_permissible_gmm",
                  "service_speed_rpm": "iso_service_speed_rpm", "mass_kg": "iso_mass_kg"},
    "programme": {"kind": "programme"},
}
#: documents and tables of the analysis that have no column: ``runup`` is the Bode table
#: (arrays) and its resonance / model fit, whose answer is already in the columns
#: ``critical_speed_hz``, ``critical_speed_hz_std``, ``critical_speed_method``; the lists
#: (``notes``, ``components``, ``critical_speeds_hz``, ``settling``) are tables of their own
#: (``stand analyze FILE --json``)
NO_COLUMN = ("runup", "notes", "components", "critical_speeds_hz", "settling", "regime_timeline")
#: the other documents of the analysis (their scalar fields as ``<key>_<field>``); None in an
#: analysis that lacks them, which gives no column
DOCUMENTS = ("stationary_stretch", "vibration_1x", "ring_reading", "reduction", "input",
             "photogate")


def summary_columns(doc) -> dict:
    """The summary row's columns of one analysis document (:func:`stand.analysis.identify.analyze`).

    Scalars keep their key; the documents of :data:`NESTED_COLUMNS` give their named
    fields (``iso_grade``: the grade class, e.g. ``"G 2.5"``, with ``iso_grade_mm_s``,
    ``iso_passed``, ...; ``programme``: its kind, e.g. ``"run-up + constant"``); any other
    document gives its scalar fields as ``<key>_<field>`` (``reduction_factor``,
    ``stationary_stretch_t_start_s``, ...); :data:`NO_COLUMN` and lists are left out.
    A document that is None in this analysis gives no column (its columns are empty only in
    the rows of the files that lack it).

    Parameters
    ----------
    doc : mapping
        The analysis document.

    Returns
    -------
    dict
    """
    row = {}
    for k, v in doc.items():
        if k in NO_COLUMN or isinstance(v, (list, tuple)):
            continue
        if isinstance(v, dict):
            names = NESTED_COLUMNS.get(k)
            for f, x in v.items():
                scalar = isinstance(x, (int, float, str, bool)) or x is None
                if names is not None and f in names:
                    row[names[f]] = x
                elif names is None and scalar:
                    row[f"{k}_{f}"] = x
        elif v is not None and isinstance(v, (int, float, str, bool)):
            row[k] = v
        elif v is None and k not in NESTED_COLUMNS and k not in DOCUMENTS:
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
