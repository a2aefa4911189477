"""Batch processing of recordings: `stand analyze` / `stand report` on a folder
or a glob, in parallel, with one summary table (issue 10 item 4).

Files are processed by a local process pool (all cores by default) or, with
``scheduler="tcp://host:port"``, by a dask.distributed cluster -- the same
function either way.  A file that fails gives a row with ``status = "error"``
and its message; the others go on.  The summary is written atomically (CSV,
or Parquet when the name ends in ``.parquet``).
"""
from __future__ import annotations

import glob
import os
from pathlib import Path
from typing import Callable, Optional

__all__ = ["expand_sources", "is_batch_source", "run_batch", "analyze_row", "write_table"]

EXTENSIONS = (".h5", ".hdf5", ".csv")


def is_batch_source(source: str) -> bool:
    """A directory or a glob pattern (several recordings)."""
    return Path(source).is_dir() or any(c in str(source) for c in "*?[")


def expand_sources(source: str) -> list:
    """Sorted recording files of a directory (``*.h5``, ``*.hdf5``, ``*.csv``) or a glob."""
    p = Path(source)
    if p.is_dir():
        files = [str(f) for f in sorted(p.iterdir()) if f.suffix.lower() in EXTENSIONS and f.is_file()]
    else:
        files = sorted(f for f in glob.glob(str(source)) if Path(f).is_file())
    if not files:
        raise FileNotFoundError(f"{source!r}: no recordings (*.h5, *.hdf5, *.csv) found")
    return files


def analyze_row(path: str, grade_mm_s: float = 6.3, service_speed_rpm: Optional[float] = None) -> dict:
    """One summary row of `stand analyze` for ``path`` (never raises)."""
    from .identify import analyze

    row = {"file": path, "status": "ok", "error": ""}
    try:
        doc = analyze(path, grade_mm_s=grade_mm_s, service_speed_rpm=service_speed_rpm)
    except Exception as exc:   # a bad file must not stop the batch: reported in its row
        row.update(status="error", error=f"{type(exc).__name__}: {exc}")
        return row
    for k, v in doc.items():
        if isinstance(v, (int, float, str, bool)) or v is None:
            row[k] = v
    return row


def _chunks(items, n):
    for i in range(0, len(items), n):
        yield items[i:i + n]


def _run_chunk(func, paths, kwargs):
    return [func(p, **kwargs) for p in paths]


def run_batch(files, func: Callable = analyze_row, *, workers: Optional[int] = None,
              scheduler: Optional[str] = None, progress: bool = False, **kwargs):
    """Apply ``func(path, **kwargs) -> dict`` to every file; returns a pandas DataFrame
    (one row per file, in the order of ``files``)."""
    import pandas as pd

    files = list(files)
    rows = {}
    bar = None
    if progress:
        try:
            from tqdm import tqdm
            bar = tqdm(total=len(files), unit="file")
        except ImportError:
            pass
    if scheduler:
        from dask.distributed import Client, as_completed

        with Client(scheduler) as client:
            futs = {client.submit(func, f, pure=False, **kwargs): f for f in files}
            for fut in as_completed(futs):
                rows[futs[fut]] = fut.result()
                if bar is not None:
                    bar.update(1)
    elif (workers or os.cpu_count() or 1) == 1 or len(files) == 1:
        for f in files:
            rows[f] = func(f, **kwargs)
            if bar is not None:
                bar.update(1)
    else:
        from concurrent.futures import ProcessPoolExecutor, as_completed as done

        with ProcessPoolExecutor(max_workers=workers) as ex:
            futs = {ex.submit(func, f, **kwargs): f for f in files}
            for fut in done(futs):
                rows[futs[fut]] = fut.result()
                if bar is not None:
                    bar.update(1)
    if bar is not None:
        bar.close()
    return pd.DataFrame([rows[f] for f in files])


def write_table(df, path) -> Path:
    """Write the summary atomically: CSV, or Parquet for ``*.parquet``."""
    import tempfile

    path = Path(path)
    if not path.resolve().parent.is_dir():
        raise FileNotFoundError(f"output directory of {str(path)!r} does not exist")
    fd, tmp = tempfile.mkstemp(dir=str(path.resolve().parent), prefix=f".{path.name}.", suffix=".tmp")
    os.close(fd)
    try:
        if path.suffix.lower() == ".parquet":
            df.to_parquet(tmp, index=False)
        else:
            df.to_csv(tmp, index=False)
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)
    return path
