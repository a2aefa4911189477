"""The ``stand`` command line.

    stand run SCENE.toml -o RUN.h5 [--json] [--method M] [--no-progress]
    stand accuracy SCENE.toml [--json] [--rtols 1e-4,1e-6,...] [--methods DOP853,Radau]

Exit codes: 0 success; 1 the simulation stopped early (what was computed is
still written); 2 invalid input (scene, arguments, files).
"""
from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np


def _jsonable(o):
    if isinstance(o, dict):
        return {k: _jsonable(v) for k, v in o.items()}
    if isinstance(o, (list, tuple)):
        return [_jsonable(v) for v in o]
    if isinstance(o, np.generic):
        return o.item()
    if isinstance(o, float) and not np.isfinite(o):
        return None
    return o


def _cmd_run(args) -> int:
    from .recording import write_recording
    from .scene_file import load_scene
    from .simulate import simulate

    scene = load_scene(args.scene)
    out = Path(args.output)
    if not out.parent.exists():
        raise FileNotFoundError(f"output directory {str(out.parent)!r} does not exist")
    traj = simulate(scene, method=args.method, progress=not args.no_progress and sys.stderr.isatty())
    write_recording(traj, out)
    summ = traj.summary()
    final = summ.get("final") or {}
    doc = {"scene": scene.name, "output": str(out), "solver": summ["solver"], **final, "final": final}
    if args.json:
        print(json.dumps(_jsonable(doc), indent=2))
    else:
        st = traj.stats
        print(f"{scene.name}: {st.message} [{st.method}, {st.n_steps} steps, {st.nfev} RHS evaluations, "
              f"{st.wall_time:.2f} s] -> {out}")
        if final:
            ru = final.get("residual_unbalance")
            print(f"  t = {final['time_s']:.6g} s, speed {final['rotor_speed_rev_per_s']:.4g} rev/s, "
                  f"whirl radius {final['whirl_radius_m']:.4g} m"
                  + (f", residual unbalance {100 * ru:.3g} % of S" if ru is not None else ""))
    if not traj.stats.success:
        print(f"stand run: {traj.stats.message}", file=sys.stderr)
        return 1
    return 0


def _cmd_accuracy(args) -> int:
    from .accuracy import DEFAULT_RTOLS, accuracy
    from .scene_file import load_scene

    scene = load_scene(args.scene)
    rtols = DEFAULT_RTOLS
    if args.rtols:
        try:
            rtols = tuple(float(v) for v in args.rtols.split(","))
        except ValueError:
            raise ValueError(f"--rtols = {args.rtols!r}: must be a comma-separated list of numbers")
        if not all(0 < r < 1 for r in rtols):
            raise ValueError(f"--rtols = {args.rtols!r}: each tolerance must be in (0, 1)")
    methods = args.methods.split(",") if args.methods else None
    rep = accuracy(scene, rtols=rtols, methods=methods)
    if args.json:
        print(json.dumps(_jsonable(rep.to_dict()), indent=2))
    else:
        print(rep.table())
    return 0


def build_parser() -> argparse.ArgumentParser:
    from .simulate import METHODS

    p = argparse.ArgumentParser(prog="stand", description="Virtual autobalancer test stand")
    sub = p.add_subparsers(dest="command", required=True)
    r = sub.add_parser("run", help="simulate a scene and write an HDF5 recording")
    r.add_argument("scene", help="scene file (TOML)")
    r.add_argument("-o", "--output", required=True, help="recording to write (HDF5)")
    r.add_argument("--json", action="store_true", help="print a JSON summary")
    r.add_argument("--method", choices=METHODS, default=None, help="override run.method")
    r.add_argument("--no-progress", action="store_true", help="no progress bar")
    r.set_defaults(func=_cmd_run)
    a = sub.add_parser("accuracy", help="error against run time over tolerances and methods")
    a.add_argument("scene", help="scene file (TOML)")
    a.add_argument("--json", action="store_true", help="print JSON instead of a table")
    a.add_argument("--rtols", default=None, help="comma-separated relative tolerances")
    a.add_argument("--methods", default=None, help="comma-separated methods (default: automatic)")
    a.set_defaults(func=_cmd_accuracy)
    return p


def main(argv=None) -> int:
    from .scene import SceneError

    args = build_parser().parse_args(argv)
    try:
        return args.func(args)
    except (SceneError, ValueError, FileNotFoundError, PermissionError, IsADirectoryError) as exc:
        print(f"stand {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(f"stand {args.command}: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
