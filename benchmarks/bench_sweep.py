"""Sweep throughput: points/s on 1 and 2 local workers, and the per-point overhead of
Dask against the local process pool.

    python benchmarks/bench_sweep.py [--points 4000] [--sims 600] [--sim-duration 2000]

Workloads (two balls, the base scene of data_samples/sweeps/ball_simulate_small.toml,
speed x unbalance):

* theory  -- main/QP stability and critical speeds over ``--points`` (speed x unbalance,
  as data_samples/sweeps/ball_theory_map.toml);
* simulate -- constant-speed runs (tau = 2000 by default, ~300-1900 revolutions,
  tens of ms each) classified by stand.analysis.regime.

The overhead row runs cheap theory points (no critical speeds) in small chunks (50
points per task) so that scheduling dominates: overhead per point = (wall x workers -
serial compute) / points.  Absolute numbers depend on the machine's load (a shared
2-core machine gives noisy speed-ups).

Every timed run's table is checked before its time is shown (``benchmarks/_peers.py``):
against the first run of the same workload (1 worker; for the overhead rows, the
serial run), the largest relative difference of its results (inputs, parameters,
theory and simulation outputs; timings left out; a different status, regime or
point set counts as infinite) must be at most ``TOL_REL``: the same points
computed on another scheduler give the same numbers.
"""
from __future__ import annotations

import argparse
import math
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _peers import check_peer  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
#: largest relative difference between two runs of the same points (scheduling only differs)
TOL_REL = 1e-9
#: the base scene of every workload: that of this sample (two balls, dimensionless form)
SAMPLE = ROOT / "data_samples" / "sweeps" / "ball_simulate_small.toml"


def base_scene(duration: float = 40.0) -> dict:
    """The sample's base scene document with run.duration = ``duration`` (tau)."""
    from stand.sweep import load_sweep

    base = load_sweep(SAMPLE).base
    base["run"]["duration"] = duration
    return base


def _axis(key: str, start: float, stop: float, num: int, **more) -> dict:
    return {"key": key, "start": start, "stop": stop, "num": num, **more}


def theory_spec(n_speed: int, n_e0: int, critical: bool = True) -> dict:
    return {"base": base_scene(), "sweep": {"compute": ["theory"]},
            "axis": [_axis("R_omega", 0.5, 10.0, n_speed, spacing="log"),
                     _axis("e0", 0.0, 1.0, n_e0)],
            "theory": {"critical_speeds": critical}}


def simulate_spec(n: int, duration: float = 400.0) -> dict:
    return {"base": base_scene(duration), "sweep": {"compute": ["simulate"]},
            "axis": [_axis("R_omega", 0.5, 6.0, max(2, n // 10)), _axis("e0", 0.05, 1.4, 10)]}


def table_difference(df, ref) -> float:
    """Largest relative difference of two sweep tables' results (timings left out); inf
    when the points, a status or any text column differ."""
    from stand.sweep import TIMING_COLUMNS

    if list(df["point_id"]) != list(ref["point_id"]) or list(df.columns) != list(ref.columns):
        return math.inf
    worst = 0.0
    for c in df.columns:
        if c in TIMING_COLUMNS or c == "sim.wall_s":
            continue
        a, b = df[c], ref[c]
        if a.dtype.kind in "fiu" and b.dtype.kind in "fiu":
            x, y = a.to_numpy(float), b.to_numpy(float)
            if not np.array_equal(np.isnan(x), np.isnan(y)):
                return math.inf
            ok = ~np.isnan(x)
            scale = np.maximum(np.abs(y[ok]), 1e-300)
            if ok.any():
                worst = max(worst, float(np.max(np.abs(x[ok] - y[ok]) / scale)))
        elif not a.astype(object).fillna("").equals(b.astype(object).fillna("")):
            return math.inf
    return worst


def timed(spec_doc: dict, tmp: Path, name: str, **kw) -> tuple:
    """(points, wall [s], serial compute [s], table) of one fresh run."""
    from stand.sweep import load_sweep, run_sweep

    spec = load_sweep(spec_doc)
    t0 = time.perf_counter()
    df = run_sweep(spec, tmp / f"{name}.parquet", fresh=True, progress=False, **kw)
    wall = time.perf_counter() - t0
    return len(df), wall, float(df["wall_time_s"].sum()), df


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--points", type=int, default=4000, help="theory points (default 4000)")
    ap.add_argument("--sims", type=int, default=600, help="simulated points (default 600)")
    ap.add_argument("--sim-duration", type=float, default=2000.0,
                    help="dimensionless duration of each simulated point (default 2000)")
    ap.add_argument("--no-dask", action="store_true")
    a = ap.parse_args()

    from stand.scene.parse import parse
    from stand.integrate.simulate import simulate

    simulate(parse(base_scene()))    # compile/load the integrator once
    n_e0 = 40
    n_speed = max(2, a.points // n_e0)
    rows = []
    with tempfile.TemporaryDirectory() as d:
        tmp = Path(d)
        for label, doc in (("theory", theory_spec(n_speed, n_e0)),
                           ("simulate", simulate_spec(a.sims, a.sim_duration))):
            ref = None
            for w in (1, 2):
                n, wall, work, df = timed(doc, tmp, f"{label}{w}", workers=w)
                ref = df if ref is None else ref
                peer = check_peer(f"{label}, {w} workers", table_difference(df, ref), TOL_REL)
                rows.append((f"{label}, local pool", w, n, wall, n / wall, 1e6 * wall / n, peer))
            if all(r[-1].valid for r in rows[-2:]):
                speedup = rows[-2][3] / rows[-1][3]
                rows.append((f"{label}: speed-up 2 vs 1 workers = {speedup:.2f}",))
            else:
                rows.append((f"{label}: speed-up not computed (the tables differ)",))

        cheap = theory_spec(max(2, 2000 // n_e0), n_e0, critical=False)
        n, wall_s, work, ref = timed(cheap, tmp, "serial", scheduler="serial")
        rows.append(("overhead: serial (no pool)", 1, n, wall_s, n / wall_s, 1e6 * wall_s / n,
                     check_peer("serial", 0.0, TOL_REL)))
        n, wall_l, _, df = timed(cheap, tmp, "pool", workers=2, chunk_size=50)
        over_l = (wall_l * 2 - work) / n
        rows.append(("overhead: local pool, 50 pts/task", 2, n, wall_l, n / wall_l, 1e6 * over_l,
                     check_peer("local pool", table_difference(df, ref), TOL_REL)))
        if not a.no_dask:
            from dask.distributed import Client, LocalCluster

            with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                              dashboard_address=None) as cluster, Client(cluster) as client:
                client.run(lambda: __import__("stand.sweep.compute"))   # import once per worker
                timed(cheap, tmp, "dask-warm", scheduler=client, chunk_size=50)
                n, wall_d, _, df = timed(cheap, tmp, "dask", scheduler=client, chunk_size=50)
            over_d = (wall_d * 2 - work) / n
            rows.append(("overhead: Dask LocalCluster, 50 pts/task", 2, n, wall_d, n / wall_d,
                         1e6 * over_d, check_peer("Dask", table_difference(df, ref), TOL_REL)))

    print(f"{'workload':44s} {'workers':>7s} {'points':>7s} {'wall s':>8s} {'points/s':>9s} "
          f"{'us/point':>9s}")
    for label, *rest in rows:
        if not rest:
            print(f"  {label}")
            continue
        w, n, wall, rate, us, peer = rest
        if peer.valid:
            print(f"{label:44s} {w:7d} {n:7d} {wall:8.2f} {rate:9.0f} {us:9.0f}")
        else:
            print(f"{label:44s} {w:7d} {n:7d} {peer.verdict}")
    print("(overhead rows: us/point = (wall x workers - serial compute) / points)")


if __name__ == "__main__":
    main()
