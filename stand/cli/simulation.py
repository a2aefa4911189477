"""Commands that simulate or predict: ``stand run``, ``accuracy``, ``experiment``, ``theory``,
``sweep``, ``stress``, ``warmup``.  Each parses nothing (stand.cli.parser did), calls the
library and prints."""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from stand.cli.common import print_json, say_not_applicable

__all__ = ["cmd_run", "cmd_accuracy", "cmd_experiment", "cmd_theory", "cmd_sweep", "cmd_stress", "cmd_warmup"]


def cmd_run(args) -> int:
    from stand.api import load, run, save
    from stand.io.atomic import check_output_path

    scene = load(args.scene)
    out = check_output_path(args.output)  # before the run, not after it
    res = run(scene, method=args.method, progress=not args.no_progress and sys.stderr.isatty(),
              checkpoint=args.checkpoint)
    save(res, out)
    final = res.final or {}
    doc = {"scene": scene.name, "structure": scene.structure_type, "output": str(out),
           "solver": res.solver, **final, "final": final, "notes": list(res.notes)}
    if args.json:
        print_json(doc)
    else:
        st = res.stats
        print(f"{scene.name} ({scene.structure_type}): {st.message} [{st.method}, {st.n_steps} steps, "
              f"{st.nfev} RHS evaluations, {st.wall_time:.2f} s] -> {out}")
        if final:
            ru = final.get("residual_unbalance")
            print(f"  t = {final['time_s']:.6g} s, speed {final['rotor_speed_rev_per_s']:.4g} rev/s, "
                  f"plane {final['main_plane']} whirl radius {final['whirl_radius_m']:.4g} m"
                  + (f", residual unbalance {100 * ru:.3g} % of S" if ru is not None else ""))
        for n in res.notes:
            print(f"  note: {n}")
    if not res.stats.success:
        print(f"stand run: {res.stats.message}", file=sys.stderr)
        return 1
    return 0


def cmd_accuracy(args) -> int:
    from stand.integrate.accuracy import DEFAULT_RTOLS, FAST_REFERENCE_RTOL, FAST_RTOLS, accuracy
    from stand.scene.parse import load_scene

    scene = load_scene(args.scene)
    rtols = FAST_RTOLS if args.fast else DEFAULT_RTOLS
    if args.rtols:
        try:
            rtols = tuple(float(v) for v in args.rtols.split(","))
        except ValueError:
            raise ValueError(f"--rtols = {args.rtols!r}: must be a comma-separated list of numbers")
        if not all(0 < r < 1 for r in rtols):
            raise ValueError(f"--rtols = {args.rtols!r}: each tolerance must be in (0, 1)")
    methods = args.methods.split(",") if args.methods else None
    steps = None
    if args.rk4_steps:
        try:
            steps = tuple(float(v) for v in args.rk4_steps.split(","))
        except ValueError:
            raise ValueError(f"--rk4-steps = {args.rk4_steps!r}: comma-separated steps in s") from None
        if not all(v > 0 for v in steps):
            raise ValueError(f"--rk4-steps = {args.rk4_steps!r}: steps must be > 0 (s)")
    if methods:
        from stand.scene.model import METHODS
        bad = [m for m in methods if m not in METHODS and m != "RK4"]
        if bad:
            raise ValueError(f"--methods: unknown {', '.join(bad)}; valid: {', '.join(METHODS)}, RK4")
    if args.output or args.json_file:
        from stand.reports.accuracy_report import accuracy_report

        for o in (args.output, args.json_file):
            if o and not Path(o).resolve().parent.is_dir():
                raise FileNotFoundError(f"output directory of {o!r} does not exist")

        doc = accuracy_report(scene, rtols=rtols if args.rtols else (1e-4, 1e-6, 1e-8, 1e-10),
                              methods=methods, rk4_steps=steps, html_path=args.output,
                              json_path=args.json_file)
        if args.json:
            print_json(doc)
        else:
            rec = doc["recommended"]
            print(f"{scene.name}: {len(doc['runs'])} runs against {doc['reference']['name']}; "
                  f"recommended: {rec.get('method')} "
                  + (f"rtol {rec['rtol']:g}" if rec.get("rtol") else f"step {rec.get('step_s')}")
                  + (f" ({rec['relative_error']:.2g} relative error, {rec['wall_time_s']:.3g} s)"
                     if rec.get("relative_error") is not None else "")
                  + ("" if rec.get("reached") else " -- the target was not reached")
                  + (f" -> {args.output}" if args.output else ""))
        return 0
    rep = accuracy(scene, rtols=rtols, methods=methods, rk4_steps=steps,
                   reference_rtol=FAST_REFERENCE_RTOL if args.fast else None)
    if args.json:
        print_json(rep.to_dict())
    else:
        print(rep.table())
    return 0


def cmd_experiment(args) -> int:
    from stand.scene.experiments import PROGRAMMES, not_applicable, programme
    from stand.instruments.pipeline import run_with_instruments
    from stand.api import save
    from stand.io.atomic import check_output_path
    from stand.scene.parse import load_scene

    base = load_scene(args.scene)
    out = check_output_path(args.output)
    why = not_applicable(base, args.programme)
    if why:
        return say_not_applicable("experiment", why)
    p = args.programme
    # the builders' arguments (stand.scene.experiments.PROGRAMMES) from the command's flags
    opts = dict(speed=args.speed, rate=args.rate, hold=args.hold, band=args.band,
                duration=args.change_time if p == "unbalance" else args.duration, time=args.time,
                exponential=args.exponential, at=args.at, start=args.at,
                eccentricity=args.eccentricity, angle_deg=args.angle, velocity=args.velocity,
                end=args.end, force=args.side_force, stiffness=args.stiffness,
                deflection=args.deflection)
    flag = {"start": "at", "force": "side-force", "angle_deg": "angle"}
    for k in PROGRAMMES[p][1]:
        if opts[k] is None:
            raise ValueError(f"stand experiment {p}: --{flag.get(k, k)} is required")
    sc = programme(base, p, **opts)
    res = run_with_instruments(sc, progress=sys.stderr.isatty())
    save(res, out, attrs={"experiment": {
        "programme": p, **{k: v for k, v in vars(args).items() if k != "func" and v is not None}}})
    st = res.stats
    print(f"{sc.name} / {p}: {st.message} [{st.method}, {st.wall_time:.2f} s] -> {out}")
    if not st.success:   # exit 1: one line on stderr says why (as stand run)
        print(f"stand experiment: {st.message}", file=sys.stderr)
        return 1
    return 0


def cmd_theory(args) -> int:
    from stand.api import load
    from stand.theories.scene import theory, theory_lines

    scene = load(args.scene)
    if args.plot and not Path(args.plot).resolve().parent.exists():
        raise FileNotFoundError(f"plot directory {str(Path(args.plot).parent)!r} does not exist")
    doc = theory(scene, max_speed=args.max_speed, floquet=not args.no_floquet)
    if args.plot:
        if doc["kind"] == "chapter5":
            from stand.theories.planar.speedmap import plot_speed_map, scene_theory

            plot_speed_map(scene_theory(scene, R_max=args.max_speed * 2 * np.pi / scene.natural_frequency
                                        if args.max_speed else None), args.plot)
        else:
            doc["not_applicable"].append("--plot: the speed map is drawn for the chapter-5 planar "
                                         "rotor with weights only")
    if args.json:
        print_json(doc)
        return 0
    for line in theory_lines(doc):
        print(line)
    if args.plot and doc["kind"] == "chapter5":
        print(f"speed map written to {args.plot}")
    return 0


def cmd_sweep(args) -> int:
    from stand.sweep import sweep_main

    return sweep_main(args)


def cmd_stress(args) -> int:
    from stand.reports.stress import DEFAULT_CATALOGUE, run_stress

    for o in (args.output, args.json_file):
        if o and not Path(o).resolve().parent.is_dir():
            raise FileNotFoundError(f"output directory of {o!r} does not exist")
    cases = None
    if args.cases:
        cases = "fast" if args.cases == "fast" else [c.strip() for c in args.cases.split(",")]
    doc = run_stress(args.catalogue or DEFAULT_CATALOGUE, cases=cases, html_path=args.output,
                     json_path=args.json_file, progress=sys.stderr.isatty())
    if args.json:
        print_json(doc)
    else:
        for c in doc["cases"]:
            print(f"  {'PASS' if c.get('pass') else 'FAIL'}  {c.get('name')}: {c.get('reason', '')}")
        s = doc["summary"]
        print(f"stand stress: {s.get('n_passed')} of {s.get('n_cases')} cases passed "
              f"in {s.get('total_time_s', 0):.0f} s"
              + (f" -> {args.output}" if args.output else ""))
    return 0 if doc["summary"].get("all_passed") else 1


def cmd_warmup(args) -> int:
    from stand.cli.warmup import warmup

    warmup(every_kind=args.all)
    return 0
