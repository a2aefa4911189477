"""Run a sweep: compute the points in chunks on a local process pool or a Dask cluster
(:class:`stand.io.executor.Executor`), append each finished chunk to a checkpoint
directory (:mod:`.store`), combine at the end.

Re-running the same command reads the parts, skips every point whose id is
already there (ids are hashes of the base scene, the options and the point's
inputs: :meth:`SweepSpec.point_ids`) and computes the rest, and says so in one
line (:func:`resume_message`); ``fresh=True`` deletes the parts first.  A killed
sweep (even ``kill -9``) loses at most the chunks in flight.

A point that fails (invalid scene at that point, theory out of scope, solver
error ...) gets ``status = "error"`` and the message in ``error``; it never
stops the sweep, and it counts as finished (a resume does not retry it).

The per-point work is :mod:`.compute` (and :mod:`.theory_points`), the table's
columns :mod:`.schema`, the files :mod:`.store`; their public names are importable from
here as before.  The command (``stand sweep``) is :mod:`stand.cli.sweep`, through
:func:`stand.api.sweep.sweep`.
"""
from __future__ import annotations

import functools
import math
import sys
from pathlib import Path
from typing import Any, Callable, Optional, Union

import numpy as np
import pandas as pd

from stand.io.executor import Executor, progress_bar
from stand.io.jsonable import dumps
from stand.sweep.compute import compute_chunk
from stand.sweep.keys import SPECIAL_KEYS
from stand.sweep.schema import (COMMON_COLUMNS, RESULT_SCHEMA, SIMULATE_COLUMNS,  # noqa: F401
                     THEORY_COLUMNS, TIMING_COLUMNS, rows_to_frame)
from stand.sweep.spec import SweepSpec, load_sweep
from stand.sweep.store import (parts_dir, read_parts, read_results, remove_parts, write_part,
                    write_table)

__all__ = ["run_sweep", "compute_chunk", "read_results", "parts_dir", "RESULT_SCHEMA",
           "TIMING_COLUMNS", "rows_to_frame", "auto_chunk_size", "resume_message"]


def auto_chunk_size(n_points: int, workers: int, compute) -> int:
    """Points per task: about 4 tasks per worker (theory: 50-500 points; simulate: 1-50).

    Parameters
    ----------
    n_points : int
        Points to compute.
    workers : int
        Workers that share them.
    compute : sequence of str
        "theory" and/or "simulate".

    Returns
    -------
    int
    """
    per = math.ceil(n_points / max(1, 4 * workers))
    if "simulate" in compute:
        per = math.ceil(n_points / max(1, 8 * workers))
        return int(min(max(per, 1), 50))
    return int(min(max(per, 50), 500))


def _compute_task(payload: dict, task: tuple) -> list:
    """:func:`compute_chunk` of one task ``(indices, ids, points)`` (the executor's item)."""
    return compute_chunk(payload, *task)


def _task_order(spec: SweepSpec, points: np.ndarray) -> np.ndarray:
    """Point order for chunking: the speed axis varies fastest, so that a chunk holds
    whole speed lines (one scene parse, one vectorised stability batch and one set of
    critical speeds per line)."""
    cols = spec.columns
    if not cols:
        return np.arange(len(points))
    sp = [j for j, k in enumerate(cols) if k in SPECIAL_KEYS]
    others = [j for j in range(len(cols)) if j not in sp]
    order = others + sp                      # primary ... fastest
    return np.lexsort(tuple(points[:, j] for j in reversed(order)))  # stable: ties keep index order


def resume_message(output: Union[str, Path], done: int, total: int, stale: int = 0) -> Optional[str]:
    """The line that says what a sweep found in its checkpoint directory, or None.

    Parameters
    ----------
    output : path
        The final table; its parts are in ``<output>.parts/``.
    done : int
        Points of this sweep already in the parts.
    total : int
        Points of this sweep.
    stale : int
        Results in the parts that belong to no point of this sweep (another base
        scene, other options or axes): they are ignored.

    Returns
    -------
    str or None
        None when the parts hold nothing (a first run).

    Examples
    --------
    >>> resume_message("results.parquet", 120, 300)      # doctest: +SKIP
    'results.parquet is missing; resuming from 120 of 300 points in results.parquet.parts/ — use --fresh to recompute'
    """
    output = Path(output)
    pdir = f"{parts_dir(output)}/"
    if done:
        if not output.exists():
            return (f"{output} is missing; resuming from {done} of {total} points in {pdir} "
                    "\u2014 use --fresh to recompute")
        return (f"resuming: {done} of {total} points already done in {pdir} "
                "\u2014 use --fresh to recompute")
    if stale:
        return (f"{pdir} holds {stale} results of another sweep (other base scene, options or "
                f"axes): ignored, computing all {total} points \u2014 use --fresh to delete them")
    return None


def _stderr_line(line: str) -> None:
    print(f"sweep: {line}", file=sys.stderr, flush=True)


def run_sweep(spec: Union[SweepSpec, str, Path, dict], output: Union[str, Path], *,
              scheduler: Any = None, workers: Optional[int] = None,
              chunk_size: Optional[int] = None, fresh: bool = False, resume: bool = True,
              progress: bool = True, max_in_flight: Optional[int] = None,
              start_method: Optional[str] = None,
              log: Optional[Callable[[str], None]] = None) -> pd.DataFrame:
    """Run a sweep with checkpoints; return the final table.

    Parameters
    ----------
    spec : SweepSpec, path, TOML text or dict
        The sweep (see :mod:`stand.sweep.spec`).
    output : path
        Final table: ``*.parquet`` (default format) or ``*.h5``/``*.hdf5``.
        Finished chunks go to ``<output>.parts/`` as they complete.
    scheduler : None, "serial", "tcp://host:port" or dask.distributed.Client
        None: local process pool (``workers`` processes, default all cores;
        one worker or one task: in this process); "serial": in this process;
        an address or a Client: the same chunks are submitted to that Dask
        cluster (:class:`stand.io.executor.Executor`).
    workers : int, optional
        Local pool size (default ``os.cpu_count()``); with Dask only used to
        size the chunks (default: the cluster's thread count).
    chunk_size : int, optional
        Points per task; default ``spec.chunk_size`` or :func:`auto_chunk_size`.
    fresh : bool
        Start over: delete the stand's part files in ``<output>.parts/``
        (``part-*.parquet`` and stray ``.part-*.tmp``; nothing else there) and
        compute every point.  Default False: reuse the finished parts and say so
        (see ``log``).
    resume : bool
        Old spelling: ``resume=False`` is ``fresh=True``.
    progress : bool
        tqdm progress bar on stderr.
    max_in_flight : int, optional
        Chunks submitted but not finished at any time (default 2 x workers);
        bounds memory and what a kill can lose.
    start_method : {"fork", "spawn", "forkserver"}, optional
        Start method of the local pool; default "fork" when this process has
        one thread, else "spawn" (which, like "forkserver", needs the usual
        ``if __name__ == "__main__":`` guard in a calling script).
    log : callable, optional
        Receives the one line (:func:`resume_message`) when the parts already
        hold results: "resuming: 120 of 300 points already done in
        results.parquet.parts/ ...", or "results.parquet is missing; resuming
        from ..." when the final table is gone.  Default: printed on stderr
        after ``"sweep: "``.

    Returns
    -------
    pandas.DataFrame
        One row per point, in point order: ``point_index``, ``point_id``, the
        inputs (one column per axis key), ``status`` ("ok"/"error"), ``error``,
        ``wall_time_s`` [s], ``p.*`` (the point's parameters: for the planar
        rotor n, Rt, h, H, e0, R = omega/omega_1, f0_hz [Hz]) and the outputs
        ``theory.*`` and/or ``sim.*`` (see ``docs/sweep.md``).
        ``table.attrs["resumed_points"]``: points taken from earlier parts.
    """
    if not isinstance(spec, SweepSpec):
        spec = load_sweep(spec)
    output = Path(output)
    pdir = parts_dir(output)
    if fresh or not resume:
        remove_parts(pdir)
    pdir.mkdir(parents=True, exist_ok=True)

    points = spec.points()
    ids = spec.point_ids(points)
    id_set = set(ids)
    done, stale = set(), set()
    for fr in read_parts(pdir):
        for x in fr["point_id"].astype(object):
            (done if x in id_set else stale).add(x)
    line = resume_message(output, len(done), len(ids), len(stale))
    if line:
        (log or _stderr_line)(line)
    pending = [int(i) for i in _task_order(spec, points) if ids[i] not in done]

    with Executor(workers, scheduler, start_method=start_method) as ex:
        per = chunk_size or spec.chunk_size or auto_chunk_size(len(pending), ex.workers, spec.compute)
        chunks = [pending[i:i + per] for i in range(0, len(pending), per)]
        tasks = ((ch, [ids[i] for i in ch], points[ch].tolist()) for ch in chunks)
        bar = progress_bar(len(pending), enabled=progress, unit="pt", desc=f"sweep {spec.name}",
                           smoothing=0.1)
        try:
            for _, rows in ex.imap_unordered(functools.partial(_compute_task, spec.to_payload()),
                                             tasks, max_in_flight=max_in_flight,
                                             size_hint=len(chunks)):
                write_part(pdir, rows, spec)
                bar.update(len(rows))
        finally:
            bar.close()

    frames = [f for f in read_parts(pdir) if len(f)]
    table = pd.concat(frames, ignore_index=True) if frames else rows_to_frame([], spec)
    keep = np.fromiter((x in id_set for x in table["point_id"].astype(object)), bool, len(table))
    table = table[keep]
    table = table.drop_duplicates("point_id").sort_values("point_index", kind="stable")
    table = table.reset_index(drop=True)
    missing = len(ids) - len(table)
    if missing:  # pragma: no cover - every chunk is written before we get here
        raise RuntimeError(f"sweep: {missing} points have no result in {pdir}")
    write_table(table, output, {"sweep_name": spec.name, "fingerprint": spec.fingerprint(),
                                "axes": dumps(spec.columns), "compute": dumps(list(spec.compute))})
    table.attrs["resumed_points"] = len(done)
    return table
