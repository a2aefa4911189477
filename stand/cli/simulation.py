"""Commands that simulate or predict: ``stand run``, ``accuracy``, ``experiment``, ``theory``,
``sweep``, ``stress``, ``warmup``.  Each parses nothing (stand.cli.parser did), calls the
API (:mod:`stand.api`, :mod:`stand.api.simulation`) and prints."""
from __future__ import annotations

import sys

from stand.cli.common import print_json, say_not_applicable, shown

__all__ = ["cmd_run", "cmd_accuracy", "cmd_experiment", "cmd_theory", "cmd_sweep", "cmd_stress", "cmd_warmup"]


def _numbers(text, option: str, what: str) -> tuple:
    """A comma-separated list of numbers of an option, or one line naming the option."""
    try:
        return tuple(float(v) for v in text.split(","))
    except ValueError:
        raise ValueError(f"{option} = {text!r}: must be a comma-separated list of {what}") from None


def cmd_run(args) -> int:
    from stand.api import load, run, save
    from stand.io.atomic import check_output_path
    from stand.io.numbers import plain

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
            ru, cpl = final.get("residual_unbalance"), final.get("residual_couple_g_mm2")
            off = final.get("static_offset_m") or 0.0
            print(f"  t = {plain(final['time_s'], 's', 6)}, speed "
                  f"{plain(final['rotor_speed_rev_per_s'], 'rev/s')}, plane {final['main_plane']} "
                  f"whirl radius {shown({'final_whirl_m': final['whirl_radius_m']}, 'final_whirl_m')}"
                  # a static offset (gravity sag) larger than the whirl is worth a word (not a
                  # sub-nanometre one: round-off of a rotor at rest, below any probe)
                  + (f" about a static offset of {shown({'final_whirl_m': off}, 'final_whirl_m')}"
                     if off > max(final["whirl_radius_m"], 1e-9) else "")
                  + (f", residual unbalance {plain(100 * ru, '% of S', 3)} (static)"
                     if ru is not None else "")
                  + (f", couple {plain(cpl, 'g·mm²', 3)}" if cpl is not None else ""))
        for n in res.notes:
            print(f"  note: {n}")
    if not res.stats.success:
        print(f"stand run: {res.stats.message}", file=sys.stderr)
        return 1
    return 0


def cmd_accuracy(args) -> int:
    from stand.api import load
    from stand.api.simulation import accuracy

    scene = load(args.scene)
    rtols = _numbers(args.rtols, "--rtols", "numbers") if args.rtols else None
    if rtols and not all(0 < r < 1 for r in rtols):
        raise ValueError(f"--rtols = {args.rtols!r}: each tolerance must be in (0, 1)")
    steps = _numbers(args.rk4_steps, "--rk4-steps", "steps in s") if args.rk4_steps else None
    if steps and not all(v > 0 for v in steps):
        raise ValueError(f"--rk4-steps = {args.rk4_steps!r}: steps must be > 0 (s)")
    methods = args.methods.split(",") if args.methods else None
    rep = accuracy(scene, rtols=rtols, methods=methods, rk4_steps=steps, fast=args.fast,
                   duration=args.duration,
                   html_path=args.output, json_path=args.json_file)
    if args.json:
        print_json(rep if isinstance(rep, dict) else rep.to_dict())
    elif not (args.output or args.json_file):
        print(rep.table())
    else:
        rec = rep["recommended"]
        print(f"{scene.name}: {len(rep['runs'])} runs against {rep['reference']['name']}; "
              f"recommended: {rec.get('method')} "
              + (f"rtol {rec['rtol']:g}" if rec.get("rtol") else f"step {rec.get('step_s')} s")
              + (f" ({rec['relative_error']:.2g} relative error, {rec['wall_time_s']:.3g} s)"
                 if rec.get("relative_error") is not None else "")
              + ("" if rec.get("reached") else " -- the target was not reached")
              + (f" -> {args.output}" if args.output else ""))
    return 0


def cmd_experiment(args) -> int:
    from stand.api.simulation import experiment, required_options
    from stand.errors import NotApplicable

    p = args.programme
    # the builders' arguments (stand.scene.experiments.PROGRAMMES) from the command's flags
    opts = dict(speed=args.speed, rate=args.rate, hold=args.hold, band=args.band,
                duration=args.change_time if p == "unbalance" else args.duration, time=args.time,
                exponential=args.exponential, at=args.at, start=args.at,
                eccentricity=args.eccentricity, angle_deg=args.angle, velocity=args.velocity,
                end=args.end, force=args.side_force, stiffness=args.stiffness,
                deflection=args.deflection)
    flag = {"start": "at", "force": "side-force", "angle_deg": "angle"}
    for k in required_options(p):
        if opts[k] is None:
            raise ValueError(f"stand experiment {p}: --{flag.get(k, k)} is required")
    record = {k: v for k, v in vars(args).items() if k != "func" and v is not None}
    try:
        res, sc = experiment(args.scene, p, args.output, progress=sys.stderr.isatty(),
                             record=record, **opts)
    except NotApplicable as exc:
        return say_not_applicable("experiment", str(exc))
    st = res.stats
    print(f"{sc.name} / {p}: {st.message} [{st.method}, {st.wall_time:.2f} s] -> {args.output}")
    if not st.success:   # exit 1: one line on stderr says why (as stand run)
        print(f"stand experiment: {st.message}", file=sys.stderr)
        return 1
    return 0


def cmd_theory(args) -> int:
    from stand.api import load, theory
    from stand.api.simulation import speed_map, theory_text

    scene = load(args.scene)
    doc = theory(scene, max_speed=args.max_speed, floquet=not args.no_floquet)
    if args.plot:
        if doc["kind"] == "chapter5":
            speed_map(scene, args.plot, max_speed=args.max_speed)
        else:
            doc["not_applicable"].append("--plot: the speed map is drawn for the chapter-5 planar "
                                         "rotor with weights only")
    if args.json:
        print_json(doc)
        return 0
    for line in theory_text(doc):
        print(line)
    if args.plot and doc["kind"] == "chapter5":
        print(f"speed map written to {args.plot}")
    return 0


def cmd_sweep(args) -> int:
    from stand.cli.sweep import sweep_main

    return sweep_main(args)


def cmd_stress(args) -> int:
    from stand.api.simulation import stress

    cases = None
    if args.cases:
        cases = "fast" if args.cases == "fast" else [c.strip() for c in args.cases.split(",")]
    doc = stress(args.catalogue, cases=cases, html_path=args.output, json_path=args.json_file,
                 progress=sys.stderr.isatty())
    if args.json:
        print_json(doc)
    else:
        for c in doc["cases"]:
            print(f"  {'PASS' if c.get('pass') else 'FAIL'}  {c.get('name')}"
                  + (f": {c['reason']}" if c.get("reason") else ""))
        s = doc["summary"]
        print(f"stand stress: {s.get('n_passed')} of {s.get('n_cases')} cases passed "
              f"in {s.get('total_time_s', 0):.0f} s"
              + (f" -> {args.output}" if args.output else ""))
    return 0 if doc["summary"].get("all_passed") else 1


def cmd_warmup(args) -> int:
    from stand.api.warmup import warmup

    warmup(every_kind=args.all)
    return 0
