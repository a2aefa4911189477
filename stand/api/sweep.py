"""The API of ``stand sweep``: a parameter sweep (theory and/or simulation) on a process pool or
a Dask cluster, with its maps (:mod:`stand.sweep`, docs/sweep.md)."""
from __future__ import annotations

import time

__all__ = ["sweep"]


def sweep(spec, output, *, scheduler=None, workers=None, chunk_size=None, fresh: bool = False,
          progress: bool = True, log=None, regime_map=None, critical_map=None):
    """Run a sweep file and write its results table (with resumable parts beside it).

    Parameters
    ----------
    spec : str or os.PathLike
        ``SWEEP.toml`` (:func:`stand.sweep.load_sweep`).
    output : str or os.PathLike
        Results table: ``.parquet`` or ``.h5``; checkpoints in ``OUTPUT.parts/``.
    scheduler : str, optional
        Dask scheduler address, ``"serial"`` (this process), or None (local processes).
    workers, chunk_size : int, optional
        Local worker processes and points per task (each >= 1).
    fresh : bool
        Delete an earlier run's parts and compute every point (default: resume).
    progress : bool
        Progress bar on stderr.
    log : callable, optional
        Receives one line per event (e.g. a resumed sweep).
    regime_map, critical_map : path, optional
        Also draw these maps (PNG).

    Returns
    -------
    (pandas.DataFrame, dict)
        The table (one row per point, ``status`` "ok" or "error") and the summary: ``sweep``,
        ``points``, ``failed``, ``output``, ``resumed_points``, ``wall_time_s`` [s],
        ``points_per_s`` [1/s], ``maps`` (the PNGs written).

    Raises
    ------
    stand.sweep.SweepSpecError
        An invalid sweep file (a ValueError naming the key).
    """
    from stand.sweep import maps
    from stand.sweep.run import run_sweep
    from stand.sweep.spec import load_sweep

    for name, v in (("workers", workers), ("chunk_size", chunk_size)):
        if v is not None and v < 1:
            raise ValueError(f"{name} = {v}: must be >= 1")
    sp = load_sweep(spec)
    t0 = time.perf_counter()
    table = run_sweep(sp, output, scheduler=scheduler, workers=workers, chunk_size=chunk_size,
                      fresh=fresh, progress=progress, log=log)
    wall = time.perf_counter() - t0
    made = []
    for path, draw in ((regime_map, maps.regime_map), (critical_map, maps.critical_speed_map)):
        if path:
            draw(table, path, spec=sp)
            made.append(path)
    summary = {"sweep": sp.name, "points": len(table), "failed": int((table["status"] != "ok").sum()),
               "output": str(output), "resumed_points": table.attrs.get("resumed_points", 0),
               "wall_time_s": wall, "points_per_s": len(table) / wall if wall > 0 else None,
               "maps": made}
    return table, summary
