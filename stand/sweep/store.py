"""A sweep's files: the checkpoint parts and the final table.

Layout of the results of ``run_sweep(spec, "results.parquet")``::

    results.parquet              # final combined table (written last, atomically)
    results.parquet.parts/       # one Parquet file per finished chunk
        part-000000500-3f9c...parquet

Every file is written through :func:`stand.io.atomic.atomic_path` (a temporary
``.<name>.*.tmp`` beside it, fsync, ``os.replace``), so a killed sweep leaves
only complete files plus at most a few stray temporaries, which
:func:`read_parts` deletes.
"""
from __future__ import annotations

import uuid
import warnings
from pathlib import Path
from typing import Union

import pandas as pd

from stand.io.atomic import atomic_path
from stand.sweep.schema import rows_to_frame

__all__ = ["parts_dir", "read_results", "read_parts", "write_part", "write_table", "remove_parts"]


def parts_dir(output: Union[str, Path]) -> Path:
    """Checkpoint directory of an output file: ``<output>.parts``."""
    return Path(str(output) + ".parts")


def _write_parquet(df: pd.DataFrame, path: Path) -> None:
    with atomic_path(path) as tmp:
        df.to_parquet(tmp, index=False)


def write_table(table: pd.DataFrame, output: Union[str, Path], attrs: dict) -> None:
    """Write the final table: HDF5 for ``*.h5``/``*.hdf5`` (``attrs`` on the file), else Parquet.

    Parameters
    ----------
    table : pandas.DataFrame
    output : path
    attrs : dict
        Strings stored as HDF5 file attributes (sweep name, fingerprint, ...).
    """
    output = Path(output)
    if output.suffix.lower() in (".h5", ".hdf5"):
        from stand.recording.sweep_table import write_sweep_table

        write_sweep_table(table, output, attrs)
    else:
        _write_parquet(table, output)


def read_results(path: Union[str, Path]) -> pd.DataFrame:
    """Read a sweep's final table (``.parquet`` or ``.h5``/``.hdf5``).

    Parameters
    ----------
    path : path

    Returns
    -------
    pandas.DataFrame
    """
    path = Path(path)
    if path.suffix.lower() in (".h5", ".hdf5"):
        from stand.recording.sweep_table import read_sweep_table

        return read_sweep_table(path)
    return pd.read_parquet(path)


#: names of the files the stand writes in a checkpoint directory: the parts, and the
#: temporaries of :func:`stand.io.atomic.atomic_path` a kill may leave behind
_PART_GLOB = "part-*.parquet"
_TMP_GLOB = ".part-*.tmp"


def remove_parts(pdir: Path) -> int:
    """Delete the stand's files in a checkpoint directory (``--fresh``).

    Only ``part-*.parquet`` and the stray temporaries ``.part-*.tmp`` are removed;
    any other file stays, and so does the directory itself.

    Parameters
    ----------
    pdir : path
        The checkpoint directory (:func:`parts_dir`); absent is fine.

    Returns
    -------
    int
        Number of part files removed (temporaries not counted).
    """
    pdir = Path(pdir)
    if not pdir.is_dir():
        return 0
    removed = 0
    for pattern in (_PART_GLOB, _TMP_GLOB):
        for f in pdir.glob(pattern):
            if f.is_file() and not f.is_symlink():
                f.unlink()
                removed += pattern == _PART_GLOB
    return removed


def read_parts(pdir: Path) -> list:
    """All complete part tables of a checkpoint directory; stray temporary files are removed."""
    frames = []
    if not pdir.is_dir():
        return frames
    for tmp in pdir.glob(_TMP_GLOB):
        try:
            tmp.unlink()
        except OSError:
            pass
    for f in sorted(pdir.glob(_PART_GLOB)):
        try:
            frames.append(pd.read_parquet(f))
        except Exception as exc:  # cannot happen with atomic writes; keep going anyway
            warnings.warn(f"sweep: skipping unreadable part {f.name}: {exc}")
    return frames


def write_part(pdir: Path, rows: list, spec) -> None:
    """One finished chunk as ``part-<first index>-<random>.parquet`` in ``pdir``."""
    df = rows_to_frame(rows, spec)
    first = int(df["point_index"].min()) if len(df) else 0
    _write_parquet(df, pdir / f"part-{first:09d}-{uuid.uuid4().hex[:8]}.parquet")
