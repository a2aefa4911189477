"""``stand fit`` (issue 39): time against the number of free values and the record length, and
the calibration of its ± over noise seeds.

Every record is written by the independent reference tests/oracles/two_ball_stand.py (its own
equations, scipy's integrator, its own TTL keyphasor; 2 um probe noise at 1 kHz) -- the
universal stand, run up 0 -> 15 rev/s over 40 % of the record, then held -- and fitted from
the lab's template (stiffness +12 %, damping x1.8, eccentricity x0.7, unbalance angle +35 deg,
ball drag x2.5; with friction the template's friction x1.5).

    python benchmarks/bench_fit.py                 # (a) time vs values, (b) vs length, (c) 24 seeds
    python benchmarks/bench_fit.py --part c --seeds 24 --friction-seeds 8 --json fit.json
    python benchmarks/bench_fit.py --quick         # small: 10-s records, 4 seeds

(a) and (b) fit with the default pool (all cores); (c) runs the fits themselves on a pool of
2 processes, each fit serial.  z = (estimate - truth) / std, angles wrapped.
"""
from __future__ import annotations

import argparse
import json
import math
import sys
import tempfile
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))

FIVE = ["supports.stiffness", "supports.damping", "rotor.eccentricity", "rotor.unbalance_angle",
        "balancer.drag"]
FRICTION = ["rotor.eccentricity", "rotor.unbalance_angle", "balancer.drag", "balancer.friction"]
KEY = {"supports.stiffness": "stiffness", "supports.damping": "damping",
       "rotor.eccentricity": "eccentricity", "rotor.unbalance_angle": "unbalance_angle",
       "balancer.drag": "drag", "balancer.friction": "friction"}


def _stand(duration, friction=0.0):
    from oracles.two_ball_stand import Stand

    return Stand(programme=[[0.0, 0.0], [0.4 * duration, 15.0]], friction=friction)


def one_fit(args):
    """Write one reference record, fit it; returns {path: (value, std, identifiable)}, stats."""
    import stand
    from oracles.two_ball_stand import PERTURBED, record, template_scene, write_record

    seed, duration, free, friction, workers = args
    truth = _stand(duration, friction)
    perturb = {KEY[p]: PERTURBED.get(KEY[p], 1.5) for p in free if KEY[p] in PERTURBED
               or KEY[p] == "friction"}
    with tempfile.TemporaryDirectory() as tmp:
        rec = record(truth, duration=duration, seed=seed)
        csv, m = write_record(rec, truth, Path(tmp) / f"r{seed}.csv")
        tmpl = template_scene(truth, Path(tmp) / "t.toml", duration=duration, perturb=perturb)
        t0 = time.perf_counter()
        fit = stand.fit(tmpl, csv, ",".join(free), recording_map=m, workers=workers)
        wall = time.perf_counter() - t0
    out = {}
    for p in free:
        d = fit["parameters"][p]
        tv = getattr(truth, KEY[p])
        err = ((d["value"] - tv + 180.0) % 360.0 - 180.0) if d["unit"] == "deg" else d["value"] - tv
        out[p] = dict(err=err, rel=(err / tv if d["unit"] != "deg" else None), std=d["std"],
                      z=err / d["std"] if d["std"] and math.isfinite(d["std"]) else None,
                      identifiable=d["identifiable"])
    return dict(seed=seed, values=out, wall=wall, sims=fit["fit"]["simulations"],
                chi2=fit["fit"]["chi2_dof"])


def part_a(duration):
    print(f"\n(a) fit time against the number of free values ({duration:g}-s record, 1 kHz, "
          "x and y, default pool)")
    print(f"{'values':>7} {'wall [s]':>9} {'simulations':>12} {'ms/sim':>8}  chi2/dof")
    rows = []
    for k in range(1, 6):
        r = one_fit((0, duration, FIVE[:k], 0.0, None))
        rows.append(dict(values=k, **{x: r[x] for x in ("wall", "sims", "chi2")}))
        print(f"{k:>7} {r['wall']:>9.1f} {r['sims']:>12} {1e3 * r['wall'] / r['sims']:>8.1f}  {r['chi2']:.3g}")
    r = one_fit((0, duration, FIVE + ["balancer.friction"], 3e-3, None))
    rows.append(dict(values=6, friction=True, **{x: r[x] for x in ("wall", "sims", "chi2")}))
    print(f"{'6 (fr.)':>7} {r['wall']:>9.1f} {r['sims']:>12} {1e3 * r['wall'] / r['sims']:>8.1f}  {r['chi2']:.3g}")
    return rows


def part_b(lengths):
    print("\n(b) fit time against the record length (5 values, default pool)")
    print(f"{'length [s]':>10} {'wall [s]':>9} {'simulations':>12}  chi2/dof")
    rows = []
    for d in lengths:
        r = one_fit((0, d, FIVE, 0.0, None))
        rows.append(dict(length=d, **{x: r[x] for x in ("wall", "sims", "chi2")}))
        print(f"{d:>10g} {r['wall']:>9.1f} {r['sims']:>12}  {r['chi2']:.3g}")
    return rows


def _table(results, free, title):
    print(f"\n{title}")
    print(f"{'value':<24} {'RMS(z)':>7} {'|z|<2':>6} {'max |err|':>11} {'not ident.':>10}")
    rows = {}
    for p in free:
        zs = np.array([r["values"][p]["z"] for r in results if r["values"][p]["z"] is not None])
        errs = [abs(r["values"][p]["err"] if p.endswith("angle") else r["values"][p]["rel"])
                for r in results]
        bad = sum(not r["values"][p]["identifiable"] for r in results)
        rms = float(np.sqrt(np.mean(zs ** 2))) if zs.size else float("nan")
        cov = float(np.mean(np.abs(zs) < 2)) if zs.size else float("nan")
        unit = " deg" if p.endswith("angle") else ""
        mx = max(errs)
        print(f"{p:<24} {rms:>7.2f} {100 * cov:>5.0f}% "
              f"{(f'{mx:.3g}{unit}' if unit else f'{100 * mx:.3g} %'):>11} {bad:>10}")
        rows[p] = dict(rms_z=rms, within_2=cov, max_abs_err=mx, not_identifiable=bad)
    walls = [r["wall"] for r in results]
    print(f"wall per fit (serial, 2 at a time): median {np.median(walls):.1f} s, "
          f"max {max(walls):.1f} s; chi2/dof median {np.median([r['chi2'] for r in results]):.3g}")
    return rows


def part_c(seeds, friction_seeds, duration):
    with ProcessPoolExecutor(2) as pool:
        res = list(pool.map(one_fit, [(s, duration, FIVE, 0.0, 1) for s in range(seeds)]))
        fr = list(pool.map(one_fit, [(100 + s, duration, FRICTION, 3e-3, 1)
                                     for s in range(friction_seeds)])) if friction_seeds else []
    out = {"five": _table(res, FIVE, f"(c) calibration over {seeds} seeds ({duration:g}-s record, "
                                     "5 values)"), "runs": res}
    if fr:
        out["friction"] = _table(fr, FRICTION, f"    with rolling friction 3e-3, {friction_seeds} "
                                               "seeds (4 values)")
        out["friction_runs"] = fr
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--part", default="abc", help="any of a, b, c")
    ap.add_argument("--seeds", type=int, default=24)
    ap.add_argument("--friction-seeds", type=int, default=8)
    ap.add_argument("--duration", type=float, default=25.0)
    ap.add_argument("--quick", action="store_true", help="10-s records, 4 seeds, 2 with friction")
    ap.add_argument("--json", default=None, help="write the numbers to this file")
    a = ap.parse_args(argv)
    if a.quick:
        a.seeds, a.friction_seeds, a.duration = 4, 2, 10.0
    out = {}
    if "a" in a.part:
        out["a"] = part_a(a.duration)
    if "b" in a.part:
        out["b"] = part_b([10.0, 25.0, 50.0] if not a.quick else [10.0, 20.0])
    if "c" in a.part:
        out["c"] = part_c(a.seeds, a.friction_seeds, a.duration)
    if a.json:
        Path(a.json).write_text(json.dumps(out, indent=1, default=float))


if __name__ == "__main__":
    main()
