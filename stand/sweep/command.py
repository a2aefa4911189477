"""``stand sweep``: the command-line glue (:func:`add_sweep_arguments`, :func:`sweep_main`)."""
from __future__ import annotations

import time

from stand.io.jsonable import dumps
from stand.sweep.spec import SweepSpecError, load_sweep

__all__ = ["add_sweep_arguments", "sweep_main"]


def add_sweep_arguments(parser) -> None:
    """Add the arguments of ``stand sweep`` to an ``argparse`` (sub)parser.

    ``stand sweep SWEEP.toml -o results.parquet [--scheduler ADDRESS] [--workers N]
    [--chunk-size N] [--fresh] [--no-progress] [--regime-map PNG]
    [--critical-map PNG]``
    """
    parser.add_argument("spec", help="SWEEP.toml")
    parser.add_argument("-o", "--output", required=True,
                        help="results table: .parquet (default) or .h5; checkpoints in OUTPUT.parts/")
    parser.add_argument("--scheduler", default=None,
                        help="Dask scheduler address tcp://host:port (default: local process pool; "
                             "'serial': in this process)")
    parser.add_argument("--workers", type=int, default=None,
                        help="local worker processes (default: all cores)")
    parser.add_argument("--chunk-size", type=int, default=None, help="points per task")
    parser.add_argument("--fresh", "--no-resume", dest="fresh", action="store_true",
                        help="start over: delete the parts of an earlier run in OUTPUT.parts/ "
                             "and compute every point (default: resume, and say so)")
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    parser.add_argument("--regime-map", default=None, help="also draw the regime map (PNG)")
    parser.add_argument("--critical-map", default=None,
                        help="also draw the critical-speed map (PNG; theory sweeps)")
    parser.add_argument("--json", action="store_true", help="print the summary as JSON")


def sweep_main(args) -> int:
    """Entry point of ``stand sweep`` given parsed arguments.

    Parameters
    ----------
    args : argparse.Namespace
        Attributes (see :func:`add_sweep_arguments`): ``spec`` (path),
        ``output`` (path), and optionally ``scheduler`` (str or None),
        ``workers`` (int or None), ``chunk_size`` (int or None), ``fresh``,
        ``no_progress``, ``json`` (bool), ``regime_map``, ``critical_map``
        (PNG paths or None).

    Returns
    -------
    int
        0: every point succeeded; 1: the table was written but some points
        failed (``status = "error"``); 2: invalid sweep file (message on stderr).
        A resumed sweep says so on stderr first, e.g. ``stand sweep: resuming:
        120 of 300 points already done in results.parquet.parts/ — use --fresh
        to recompute``.
    """
    import sys

    from stand.sweep.run import run_sweep

    g = lambda name, default=None: getattr(args, name, default)  # noqa: E731
    try:
        spec = load_sweep(args.spec)
    except SweepSpecError as exc:
        print(f"stand sweep: {exc}", file=sys.stderr)
        return 2
    workers, chunk = g("workers"), g("chunk_size")
    for name, v in (("--workers", workers), ("--chunk-size", chunk)):
        if v is not None and v < 1:
            print(f"stand sweep: {name} = {v}: must be >= 1", file=sys.stderr)
            return 2
    t0 = time.perf_counter()
    table = run_sweep(spec, args.output, scheduler=g("scheduler"), workers=workers,
                      chunk_size=chunk, fresh=bool(g("fresh", False) or g("no_resume", False)),
                      progress=not g("no_progress", False),
                      log=lambda line: print(f"stand sweep: {line}", file=sys.stderr, flush=True))
    wall = time.perf_counter() - t0
    from stand.sweep import maps

    made = []
    if g("regime_map"):
        maps.regime_map(table, g("regime_map"), spec=spec)
        made.append(g("regime_map"))
    if g("critical_map"):
        maps.critical_speed_map(table, g("critical_map"), spec=spec)
        made.append(g("critical_map"))
    n_err = int((table["status"] != "ok").sum())
    summary = {"sweep": spec.name, "points": len(table), "failed": n_err, "output": str(args.output),
               "resumed_points": table.attrs.get("resumed_points", 0),
               "wall_time_s": wall, "points_per_s": len(table) / wall if wall > 0 else None,
               "maps": made}
    if g("json"):
        print(dumps(summary))
    else:
        print(f"{spec.name}: {len(table)} points ({n_err} failed) in {wall:.1f} s -> {args.output}")
    if n_err:      # exit 1: one line on stderr says why (as every command that stops early)
        first = " ".join(str(table.loc[table["status"] != "ok", "error"].iloc[0]).split())
        print(f"stand sweep: {n_err} of {len(table)} points failed (kept in {args.output} with "
              f"their error); first failure: {first}", file=sys.stderr)
    return 1 if n_err else 0
