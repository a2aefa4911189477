"""The ``stand`` command line.

    stand run SCENE.toml -o RUN.h5 [--json] [--method M] [--no-progress]
    stand accuracy SCENE.toml [--json] [--rtols 1e-4,1e-6,...] [--methods DOP853,Radau]
    stand theory SCENE.toml [--json] [--plot MAP.png] [--max-speed REV_PER_S]
    stand snapshot RUN.h5 [--instrument screen|strobe|rings] [--frame N] -o FRAME.png
    stand experiment SCENE.toml PROGRAMME [options] -o RUN.h5
    stand analyze RUN.h5|RUN.csv [--json] [--grade G] [--service-speed RPM]
    stand fit SCENE.toml DATA [--map MAP.toml] --free PATH[=LO..HI],... [-o FITTED.toml] [--json]
              [--report FIT.html]
    stand balance JOB.toml [--json] [--method M] [--influence FILE] [--save-influence FILE]
                  [-o REPORT.html] [--pdf REPORT.pdf]
    stand track FRAMES -o track.csv [--calibration RINGS.png] [--ring-radii R1,R2,...|RINGS.txt]
                [--roi X,Y,W,H] [--background median|DARK.png] [--exposure S]
    stand video RUN.h5 -o screen.mp4 [--screen NAME] [--qp 10]
    stand strobe FRAMES -o angles.csv [--weights N]
    stand warmup [--all]

Exit codes: 0 success; 1 the simulation stopped early (what was computed is
still written) or a computation ran out of its work budget (one line says which and
the budget); 2 invalid input (scene, arguments, files).

One BLAS thread per process: the command line's parallelism is processes (batch
and sweep workers), and the identification's matrices are small: on a busy
2-core machine OpenBLAS' threads made ``stand analyze`` 10x slower (1.1 s
instead of 0.08 s).  A value set in the environment is kept.
"""
from __future__ import annotations

import os

for _v in ("OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "BLIS_NUM_THREADS", "VECLIB_MAXIMUM_THREADS"):
    os.environ.setdefault(_v, "1")   # before numpy is imported (module docstring)

import argparse  # noqa: E402
import functools  # noqa: E402
import sys  # noqa: E402
from pathlib import Path  # noqa: E402


def build_parser() -> argparse.ArgumentParser:
    """The argument parser (stand.cli.parser) with the command handlers (stand.cli.simulation,
    .analysis, .images)."""
    from stand.cli import analysis, fitting, images, simulation
    from stand.cli.parser import build_parser as build

    return build({"accuracy": simulation.cmd_accuracy,
                  "analyze": analysis.cmd_analyze,
                  "balance": analysis.cmd_balance,
                  "daq": analysis.cmd_daq,
                  "experiment": simulation.cmd_experiment,
                  "fit": fitting.cmd_fit,
                  "influence": analysis.cmd_influence,
                  "report": analysis.cmd_report,
                  "run": simulation.cmd_run,
                  "snapshot": images.cmd_snapshot,
                  "stress": simulation.cmd_stress,
                  "strobe": images.cmd_strobe,
                  "sweep": simulation.cmd_sweep,
                  "theory": simulation.cmd_theory,
                  "track": images.cmd_track,
                  "video": images.cmd_video,
                  "warmup": simulation.cmd_warmup})


def _table_kind(path) -> str:
    p = str(path).lower()
    return "parquet" if p.endswith((".parquet", ".pq")) else "json" if p.endswith(".json") else "csv"


def _is_batch(source) -> bool:
    from stand.api.analysis import is_batch

    return is_batch(source)


def _guard(args) -> None:
    """Refuse outputs in a missing directory, outputs that are inputs and files of another kind
    (stand.io.guard), before any work."""
    from stand.io.guard import check_outputs

    g = lambda name: getattr(args, name, None)  # noqa: E731
    cmd = args.command
    inputs = [g("scene"), g("recording"), g("source"), g("calibration"), g("catalogue"), g("spec"),
              g("job"), g("influence"), g("data"), g("map")]
    out = g("output")
    outputs = [(g("json_file"), "json"), (g("plot"), "png"), (g("summary"), _table_kind(g("summary"))),
               (g("regime_map"), "png"), (g("critical_map"), "png"), (g("pdf"), "pdf")]
    kind = {"run": "hdf5", "experiment": "hdf5", "accuracy": "html", "report": "html",
            "stress": "html", "snapshot": "png", "track": "csv", "strobe": "csv", "daq": "csv",
            "sweep": "parquet", "analyze": _table_kind(out), "balance": "html",
            "fit": "toml"}.get(cmd)
    if cmd == "report" and g("recording") is not None and _is_batch(g("recording")):
        from stand.cli.analysis import batch_report_outputs

        summary, html_dir = batch_report_outputs(out, g("summary"))   # -o: a table or a folder
        outputs = [o for o in outputs if o[0] is not None and o[0] != g("summary")]
        if html_dir is not None and not Path(html_dir).resolve().parent.is_dir():
            raise FileNotFoundError(f"output directory of {html_dir!r} does not exist")
        if html_dir is None or Path(html_dir).is_dir() or Path(summary).parent != Path(html_dir):
            outputs.append((summary, _table_kind(summary)))    # not in a folder still to make
    elif out is not None and kind and not Path(out).is_dir():
        outputs.append((out, kind))
    if cmd == "run":
        outputs.append((g("checkpoint"), "npz"))
    if cmd == "balance":
        outputs.append((g("save_influence"), "toml"))
    if cmd == "fit":
        outputs.append((g("report"), "html"))
    for o, _ in outputs:    # fail before the work, not after it
        if o is not None and not Path(o).resolve().parent.is_dir():
            raise FileNotFoundError(f"output directory of {str(o)!r} does not exist")
    check_outputs(inputs, outputs, force=bool(g("force")))


def _naming_the_input(args, exc) -> str:
    """The error as one line that names the input (or, for a failed write, the output) it is about."""
    import errno

    out = getattr(args, "output", None)
    if isinstance(exc, OSError) and out and (exc.errno in (errno.EFBIG, errno.ENOSPC, errno.EROFS,
                                                            errno.EACCES, errno.EPERM, errno.EDQUOT)
                                             or "write" in str(exc).lower()):
        why = exc.strerror or " ".join(str(exc).split())
        return (f"cannot write {out}: {why}; nothing was written under that name (an existing "
                f"file is unchanged)")
    msg = " ".join(str(exc).split())
    src = next((getattr(args, k) for k in ("scene", "recording", "source", "spec", "catalogue", "job")
                if getattr(args, k, None)), None)
    if src is not None and Path(str(src)).name not in msg:
        msg = f"{src}: {msg}"
    return msg


def _one_line_errors(parser: argparse.ArgumentParser) -> argparse.ArgumentParser:
    """Argument errors as one line (docs/guarantees.md), not argparse's usage block:
    ``stand influence: error: the following arguments are required: --trial; see
    stand influence --help`` (exit 2), on the parser and every subcommand's."""
    def error(message, p=parser):
        p.exit(2, f"{p.prog}: error: {' '.join(str(message).split())}; see {p.prog} --help\n")

    parser.error = error
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for sub in action.choices.values():
                _one_line_errors(sub)
    return parser


@functools.cache
def _parser() -> argparse.ArgumentParser:
    """The parser, built once per process (about 10 ms for its 18 commands): a program or a
    test that calls :func:`main` many times parses with the same one (parsing changes it not)."""
    return _one_line_errors(build_parser())


def main(argv=None) -> int:
    from stand.errors import BudgetExceeded, SceneError

    args = _parser().parse_args(argv)
    try:
        _guard(args)
        return args.func(args)
    except (SceneError, ValueError, OSError) as exc:
        # OSError: missing files, permissions, a full disk or a file-size limit (EFBIG): the
        # outputs are written atomically, so what existed before is intact
        # TheoryError is a ValueError: out-of-scope scenes end here with their reason
        print(f"stand {args.command}: error: {_naming_the_input(args, exc)}", file=sys.stderr)
        return 2
    except BudgetExceeded as exc:
        # an iterative part ran out of its work budget (issue 34): one line, what and the budget
        print(f"stand {args.command}: stopped: {_naming_the_input(args, exc)}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print(f"stand {args.command}: interrupted", file=sys.stderr)
        return 130
    except MemoryError:      # advice about a scene only where the command simulates one
        simulates = args.command in ("run", "experiment", "accuracy", "sweep", "stress")
        print(f"stand {args.command}: error: " + (
            "not enough memory for this run (reduce run.duration * run.sample_rate or the number "
            "of weights)" if simulates else _naming_the_input(args, "not enough memory to read it")),
            file=sys.stderr)
        return 2
    except Exception as exc:  # last resort: a clear line, not a traceback
        print(f"stand {args.command}: internal error: {type(exc).__name__}: {exc} "
              "(please report this with the scene file)", file=sys.stderr)
        return 3
    finally:
        from stand.api.simulation import precompile_in_background

        precompile_in_background()


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
