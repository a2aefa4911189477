"""``stand sweep``: its arguments (:func:`add_sweep_arguments`) and the command (:func:`sweep_main`),
which calls :func:`stand.api.sweep.sweep` and prints."""
from __future__ import annotations

import sys

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
    """Entry point of ``stand sweep`` given parsed arguments (:func:`add_sweep_arguments`).

    Returns
    -------
    int
        0: every point succeeded; 1: the table was written but some points
        failed (``status = "error"``); 2: invalid sweep file or option (message on stderr).
        A resumed sweep says so on stderr first, e.g. ``stand sweep: resuming:
        120 of 300 points already done in results.parquet.parts/ — use --fresh
        to recompute``.
    """
    from stand.api.sweep import sweep
    from stand.cli.common import print_json

    try:
        table, summary = sweep(args.spec, args.output, scheduler=args.scheduler,
                               workers=args.workers, chunk_size=args.chunk_size, fresh=args.fresh,
                               progress=not args.no_progress, regime_map=args.regime_map,
                               critical_map=args.critical_map,
                               log=lambda line: print(f"stand sweep: {line}", file=sys.stderr,
                                                      flush=True))
    except ValueError as exc:     # an invalid sweep file or option: the message names it
        print(f"stand sweep: {exc}", file=sys.stderr)
        return 2
    n_err = summary["failed"]
    if args.json:
        print_json(summary)
    else:
        print(f"{summary['sweep']}: {len(table)} points ({n_err} failed) in "
              f"{summary['wall_time_s']:.1f} s -> {args.output}")
    if n_err:      # exit 1: one line on stderr says why (as every command that stops early)
        first = " ".join(str(table.loc[table["status"] != "ok", "error"].iloc[0]).split())
        print(f"stand sweep: {n_err} of {len(table)} points failed (kept in {args.output} with "
              f"their error); first failure: {first}", file=sys.stderr)
    return 1 if n_err else 0
