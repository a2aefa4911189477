"""``stand fit``: parse, call :func:`stand.api.fit`, print (the command line stays thin)."""
from __future__ import annotations

import math
import sys
from pathlib import Path


def _lines(fit) -> list:
    """Each fitted value with its ± (rounded to it), the fit's chi^2, then the comparison."""
    from stand.io.numbers import with_uncertainty

    out = []
    for p, d in fit["parameters"].items():
        if not d["identifiable"]:
            out.append(f"  {p} = {d['value']:.6g} {d['unit']}: not identifiable"
                       + (f" ({d['note']})" if d.get("note") else ""))
        else:
            out.append(f"  {p} = {with_uncertainty(d['value'], d['std'], d['unit'], resolution=False)}"
                       + (f" ({d['note']})" if d.get("note") else ""))
    f = fit["fit"]
    out.append(f"  chi2/dof {f['chi2_dof']:.3g}, residual RMS {f['rms_residual']:.3g} "
               f"{f['rms_residual_unit']} (noise {f['noise_std']:.3g} {f['noise_std_unit']}), "
               f"{f['simulations']} simulations in {f['wall_time_s']:.1f} s")
    rows = [r for r in fit.get("comparison") or [] if r.get("measured") is not None
            or r.get("predicted") is not None]
    if rows:
        out.append("  theory against experiment (measured | fitted model):")
    for r in rows:
        unit = "" if r["unit"] == "1" else r["unit"]
        m = "n/a" if r.get("measured") is None else with_uncertainty(
            r["measured"], r.get("measured_std"), unit, resolution=False)
        p = "n/a" if r.get("predicted") is None else with_uncertainty(
            r["predicted"], r.get("predicted_std"), unit, resolution=False)
        ds = r.get("difference_sigma")
        out.append(f"    {r['quantity']}: {m} | {p}"
                   + (f" ({ds:+.1f} sigma)" if ds is not None and math.isfinite(ds) else ""))
    return out


def cmd_fit(args) -> int:
    from stand.api import fit as fit_scene
    from stand.api.analysis import fit_report
    from stand.cli.common import print_json

    for what, path in (("scene", args.scene), ("record", args.data)):
        if not Path(path).exists():
            raise FileNotFoundError(f"{what} not found: {path}")
    progress = (lambda s: print(s, file=sys.stderr, flush=True)) if not args.no_progress else False
    fit = fit_scene(args.scene, args.data, args.free, recording_map=args.map, columns=args.columns,
                    workers=args.workers, scheduler=args.scheduler, progress=progress)
    written = []
    if args.output:
        written.append(fit.write_scene(args.output, inputs=(args.scene, args.data, args.map)))
    if args.json_file:
        from stand.io.atomic import write_text

        write_text(args.json_file, fit.to_json(indent=2))
        written.append(args.json_file)
    if args.report:
        fit_report(fit, args.report)
        written.append(args.report)
    if args.json:
        print_json(fit)
        return 0
    print(f"{args.data} fitted to {args.scene}:")
    for line in _lines(fit):
        print(line)
    for n in fit.get("notes") or []:
        print(f"  note: {n}")
    for w in written:
        print(f"  wrote {w}")
    return 0
