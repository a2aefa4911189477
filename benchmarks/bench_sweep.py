"""Sweep throughput: points/s on 1 and 2 local workers, and the per-point overhead of
Dask against the local process pool.

    python benchmarks/bench_sweep.py [--points 4000] [--sims 600] [--sim-duration 2000]

Workloads (the universal stand's ball balancer, speed x unbalance):

* theory  -- main/QP stability and critical speeds (data_samples/sweeps/ball_theory_map.toml
  cut to ``--points``);
* simulate -- constant-speed runs (tau = 2000 by default, ~300-1900 revolutions,
  tens of ms each) classified by stand.regime.

The overhead row runs cheap theory points (no critical speeds) in small chunks (50
points per task) so that scheduling dominates: overhead per point = (wall x workers -
serial compute) / points.  Absolute numbers depend on the machine's load (a shared
2-core machine gives noisy speed-ups).
"""
from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

BASE = """
[base.dimensionless]
n = 2
Rt = 0.01
h = 0.3
H = 0.3
e0 = 0.5
initial_angles = [150.0, 210.0]
[base.drive]
type = "speed"
programme_dimensionless = [[0.0, 3.0]]
[base.run]
duration = 40.0
sample_rate = 5.0
"""


def theory_spec(n_speed: int, n_e0: int, critical: bool = True) -> str:
    return BASE + f"""
[sweep]
compute = ["theory"]
[[axis]]
key = "R_omega"
start = 0.5
stop = 10.0
num = {n_speed}
spacing = "log"
[[axis]]
key = "e0"
start = 0.0
stop = 1.0
num = {n_e0}
[theory]
critical_speeds = {"true" if critical else "false"}
"""


def simulate_spec(n: int, duration: float = 400.0) -> str:
    return BASE.replace("duration = 40.0", f"duration = {duration}") + f"""
[sweep]
compute = ["simulate"]
[[axis]]
key = "R_omega"
start = 0.5
stop = 6.0
num = {max(2, n // 10)}
[[axis]]
key = "e0"
start = 0.05
stop = 1.4
num = 10
"""


def timed(spec_text: str, tmp: Path, name: str, **kw) -> tuple:
    from stand.sweep import load_sweep, run_sweep

    spec = load_sweep(spec_text)
    t0 = time.perf_counter()
    df = run_sweep(spec, tmp / f"{name}.parquet", resume=False, progress=False, **kw)
    wall = time.perf_counter() - t0
    return len(df), wall, float(df["wall_time_s"].sum())


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--points", type=int, default=4000, help="theory points (default 4000)")
    ap.add_argument("--sims", type=int, default=600, help="simulated points (default 600)")
    ap.add_argument("--sim-duration", type=float, default=2000.0,
                    help="dimensionless duration of each simulated point (default 2000)")
    ap.add_argument("--no-dask", action="store_true")
    a = ap.parse_args()

    from stand.scene_file import load_scene
    from stand.simulate import simulate

    simulate(load_scene(BASE.replace("[base.", "[")))    # compile/load the integrator once
    n_e0 = 40
    n_speed = max(2, a.points // n_e0)
    rows = []
    with tempfile.TemporaryDirectory() as d:
        tmp = Path(d)
        for label, text in (("theory", theory_spec(n_speed, n_e0)),
                            ("simulate", simulate_spec(a.sims, a.sim_duration))):
            for w in (1, 2):
                n, wall, work = timed(text, tmp, f"{label}{w}", workers=w)
                rows.append((f"{label}, local pool", w, n, wall, n / wall, 1e6 * wall / n))
            speedup = rows[-2][3] / rows[-1][3]
            rows.append((f"{label}: speed-up 2 vs 1 workers = {speedup:.2f}", None, None, None,
                         None, None))

        cheap = theory_spec(max(2, 2000 // n_e0), n_e0, critical=False)
        n, wall_s, work = timed(cheap, tmp, "serial", scheduler="serial")
        rows.append(("overhead: serial (no pool)", 1, n, wall_s, n / wall_s, 1e6 * wall_s / n))
        n, wall_l, _ = timed(cheap, tmp, "pool", workers=2, chunk_size=50)
        over_l = (wall_l * 2 - work) / n
        rows.append(("overhead: local pool, 50 pts/task", 2, n, wall_l, n / wall_l, 1e6 * over_l))
        if not a.no_dask:
            from dask.distributed import Client, LocalCluster

            with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                              dashboard_address=None) as cluster, Client(cluster) as client:
                client.run(lambda: __import__("stand.sweep.run"))   # import once per worker
                timed(cheap, tmp, "dask-warm", scheduler=client, chunk_size=50)
                n, wall_d, _ = timed(cheap, tmp, "dask", scheduler=client, chunk_size=50)
            over_d = (wall_d * 2 - work) / n
            rows.append(("overhead: Dask LocalCluster, 50 pts/task", 2, n, wall_d, n / wall_d,
                         1e6 * over_d))

    print(f"{'workload':44s} {'workers':>7s} {'points':>7s} {'wall s':>8s} {'points/s':>9s} "
          f"{'us/point':>9s}")
    for label, w, n, wall, rate, us in rows:
        if w is None:
            print(f"  {label}")
            continue
        print(f"{label:44s} {w:7d} {n:7d} {wall:8.2f} {rate:9.0f} {us:9.0f}")
    print("(overhead rows: us/point = (wall x workers - serial compute) / points)")


if __name__ == "__main__":
    main()
