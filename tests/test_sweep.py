"""Parameter sweeps (stand.sweep): spec errors, theory and simulate sweeps, process pool
and Dask execution, checkpoint/kill/resume."""
import argparse
import json
import math
import os
import signal
import subprocess
import sys
import textwrap
import time
import warnings
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from stand.cli.sweep import add_sweep_arguments, sweep_main
from stand.sweep import (TIMING_COLUMNS, SweepSpecError, load_sweep,
                         parts_dir, read_results, run_sweep)
from stand.sweep.maps import critical_speed_map, regime_map
from stand.theories.planar import main_motion as mm

from _helpers import toml_text, wait_for

ROOT = Path(__file__).resolve().parents[1]
SWEEPS = ROOT / "data_samples" / "sweeps"


def _spec_text(body: str, duration: float = 30.0) -> str:
    """A sweep over a two-ball dimensionless base scene, then body (dedented)."""
    base = toml_text(
        base__dimensionless=dict(n=2, Rt=0.01, h=0.3, H=0.3, e0=0.5, initial_angles=[150.0, 210.0]),
        base__drive=dict(type="speed", programme_dimensionless=[[0.0, 3.0]]),
        base__run=dict(duration=duration, sample_rate=5.0))
    return base + textwrap.dedent(body)


def _same(a: pd.DataFrame, b: pd.DataFrame) -> None:
    drop = [c for c in TIMING_COLUMNS if c in a.columns]
    pd.testing.assert_frame_equal(a.drop(columns=drop), b.drop(columns=drop))


# ------------------------------------------------------------------ spec
@pytest.mark.parametrize("body, match", [
    ("[sweep]\ncompute = ['theroy']\n", r"sweep\.compute\[0\] = \"theroy\": did you mean 'theory'"),
    ("[[axis]]\nkey = 'rotor.eccentricity'\nvalues = [1.0]\n", r"axis\[0\]\.key = \"rotor\.eccentricity\": the base scene is \[dimensionless\]"),
    ("[[axis]]\nkey = 'dimensionless.eo'\nvalues = [1.0]\n", r"unknown key dimensionless\.eo: did you mean 'e0'"),
    ("[[axis]]\nkey = 'R_omega'\nstart = 1.0\nstop = 2.0\nnum = 1\n", r"axis\[0\]\.num = 1: must be an integer >= 2"),
    ("[[axis]]\nkey = 'R_omega'\nstart = 0.0\nstop = 2.0\nnum = 5\nspacing = 'log'\n", r"axis\[0\]\.start, stop .* log grid needs start > 0"),
    ("[[axis]]\nkey = 'R_omega'\nvalues = [1.0]\nstart = 1.0\nstop = 2.0\nnum = 3\n", r"axis\[0\]: give exactly one of"),
    ("[[axis]]\nkey = 'e0'\nrandom = 'uniform'\nlow = 0.0\nhigh = 1.0\ncount = 10\n", r"axis\[0\]\.seed: missing"),
    ("[[axis]]\nkey = 'e0'\nrandom = 'gauss'\nlow = 0.0\nhigh = 1.0\ncount = 10\nseed = 1\n", r"axis\[0\]\.random = \"gauss\""),
    ("[[axis]]\nkey = 'e0'\nvalues = [0.1, 'x']\n", r"axis\[0\]\.values\[1\] = \"x\": must be a number"),
    ("[[axis]]\nkey = 'omega'\nvalues = [1.0]\n", r"axis\[0\]\.key = \"omega\""),
    ("[[axis]]\nkey = 'e0'\nvalues = [0.1]\nstep = 2\n", r"unknown key axis\[0\]\.step"),
    ("[[axis]]\nkey = 'e0'\nvalues = [0.1]\n[[axis]]\nkey = 'e0'\nvalues = [0.2]\n", r"axis\[1\]\.key = \"e0\": the same key as axis\[0\]"),
    ("[sweep]\ncombine = 'zip'\n[[axis]]\nkey = 'e0'\nvalues = [0.1]\n[[axis]]\nkey = 'h'\nvalues = [0.2, 0.3]\n", r"every axis needs the same number"),
    ("[simulate]\nwindow = 2.0\n", r"simulate\.window = 2\.0: must be <= 1"),
    ("[theory]\nside = 1\n", r"theory\.side = 1: must be true or false"),
    ("[sweeps]\nname = 'x'\n", r"unknown table \[sweeps\]: did you mean 'sweep'"),
])
def test_bad_spec_names_the_field(body, match):
    with pytest.raises(SweepSpecError, match=match):
        load_sweep(_spec_text(body))


def test_bad_base_scene_and_missing_file(tmp_path):
    with pytest.raises(SweepSpecError, match=r"\[base\] scene: dimensionless\.Rt = 0\.7"):
        load_sweep(_spec_text("").replace("Rt = 0.01", "Rt = 0.7"))
    with pytest.raises(SweepSpecError, match=r"missing table \[base\]"):
        load_sweep("[sweep]\nname = 'x'\n")
    f = tmp_path / "s.toml"
    f.write_text("[base]\nscene = 'nowhere.toml'\n")
    with pytest.raises(SweepSpecError, match=r"s\.toml: base\.scene = \"nowhere\.toml\": cannot read"):
        load_sweep(f)
    with pytest.raises(SweepSpecError, match="sweep file not found"):
        load_sweep(tmp_path / "absent.toml")


# a seeded log grid x a seeded random axis: 3 x 4 points
SEEDED_AXES = """
[sweep]
seed = 7
[[axis]]
key = "R_omega"
start = 1.0
stop = 100.0
num = 3
spacing = "log"
[[axis]]
key = "e0"
random = "uniform"
low = 0.0
high = 1.0
count = 4
"""


def test_axes_grids_random_and_ids():
    spec = load_sweep(_spec_text(SEEDED_AXES))
    assert spec.n_points == 12
    pts = spec.points()
    np.testing.assert_allclose(np.unique(pts[:, 0]), [1.0, 10.0, 100.0])
    again = load_sweep(_spec_text(SEEDED_AXES))
    np.testing.assert_array_equal(pts, again.points())        # seeded: reproducible
    ids = spec.point_ids()
    assert len(set(ids)) == 12 and ids == again.point_ids()
    changed = load_sweep(_spec_text(SEEDED_AXES).replace("h = 0.3", "h = 0.4"))
    assert not set(changed.point_ids()) & set(ids)          # other base scene: other ids


# ------------------------------------------------------------------ theory
@pytest.mark.parametrize("num", [pytest.param(100, marks=pytest.mark.full), 10],
                         ids=["10k points", "100 points"])
def test_theory_sweep_10k_points_under_a_minute_and_band_structure(tmp_path, num):
    """10^4 points (speed x unbalance) of the universal stand's ball balancer on the local
    pool (all cores) in < 60 s; the main/QP stability at sampled points equals
    is_stable / the QP escape speed, and the band structure of scene_theory.  The default
    run sweeps the same map on a 10 x 10 grid (the same code paths: pool, table, maps; every
    point checked against is_stable, 10 speeds on each of the two band lines) without a time
    limit (the theory sweep's throughput is benchmarks/bench_sweep.py's); ``-m full``: the
    100 x 100 map and its time limit."""
    from stand.scene.parse import load_scene, parse_scene
    from stand.sweep.spec import point_scene_dict
    from stand.theories.planar.speedmap import scene_theory

    text = (SWEEPS / "ball_theory_map.toml").read_text().replace("num = 100", f"num = {num}")
    text = text.replace('"../scenes/', f'"{(SWEEPS.parent / "scenes").as_posix()}/')
    spec = load_sweep(text)
    n = num * num
    assert spec.n_points == n
    out = tmp_path / "map.parquet"
    t0 = time.perf_counter()
    df = run_sweep(spec, out, progress=False)
    wall = time.perf_counter() - t0
    print(f"{n}-point theory sweep: {wall:.1f} s")
    if num == 100:                 # the time limit of the full map only (a loaded CI machine)
        assert wall < 60.0
    assert len(df) == n and (df["status"] == "ok").all()
    _same(read_results(out), df)
    assert list(df["point_index"]) == list(range(n))

    # pointwise: is_stable and the escape speed at 300 random points (all of a small map)
    rng = np.random.default_rng(0)
    for i in rng.choice(len(df), min(300, n), replace=False):
        r = df.iloc[i]
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            ok = mm.is_stable(r["p.R"], r["p.Rt"], r["p.h"], r["p.H"], r["theory.d"])
        assert bool(r["theory.main_stable"]) == ok
        assert bool(r["theory.qp_stable"]) == (r["p.R"] < 1 + 2 * r["p.Rt"] / (r["p.h"] * r["p.H"]))
        assert r["p.e0"] == pytest.approx(r["e0"], rel=1e-9, abs=1e-12)
        assert r["p.R"] == pytest.approx(r["R_omega"], rel=1e-12)

    # band structure: at two unbalances, every sampled speed away from a band edge has the
    # main/QP stability of the scene_theory band that contains it
    base = load_scene(ROOT / "data_samples" / "scenes" / "ball_runup.toml")
    e0s = np.unique(df["e0"])
    for e0 in (e0s[30 * num // 100], e0s[85 * num // 100]):
        line = df[df["e0"] == e0]
        sc = parse_scene(point_scene_dict(spec.base, ["e0"], [e0]))
        th = scene_theory(sc, R_max=12.0, n_grid=40)
        edges = [b.R_to for b in th.bands[:-1]]
        checked = 0
        for _, r in line.iterrows():
            R = r["p.R"]
            if any(abs(R - e) < 1e-3 * e for e in edges):
                continue
            band = next(b for b in th.bands if b.R_from <= R <= b.R_to)
            assert bool(r["theory.main_stable"]) == ("main" in band.motions), (e0, R, band)
            assert bool(r["theory.qp_stable"]) == ("quasi-periodic" in band.motions), (e0, R, band)
            checked += 1
        assert checked > 0.9 * num
        # the stable band of the main motion starts at the first critical speed
        crit = json.loads(line["theory.critical_speeds_R"].iloc[0])
        main_crit = [c.R for c in th.critical_speeds if c.motion == "main"]
        np.testing.assert_allclose(crit, main_crit, rtol=1e-9)
    assert base.natural_frequency > 0

    png1, png2 = tmp_path / "regimes.png", tmp_path / "critical.png"
    regime_map(df, png1, spec=spec)
    critical_speed_map(df, png2, spec=spec)
    assert png1.stat().st_size > 5000 and png2.stat().st_size > 5000


def test_theory_with_side_motions_matches_scene_theory(tmp_path):
    """theory.side = true: the full set of stable motions equals scene_theory's band."""
    from stand.scene.parse import parse_scene
    from stand.sweep.spec import point_scene_dict
    from stand.theories.planar.speedmap import scene_theory

    spec = load_sweep(_spec_text(toml_text(
        sweep=dict(compute=["theory"]),
        axis=[dict(key="R_omega", values=[0.6, 0.97, 1.2, 2.5, 6.0, 12.0]),
              dict(key="e0", values=[0.4, 1.3])],
        theory=dict(side=True),
    )).replace("h = 0.3", "h = 0.05").replace("H = 0.3", "H = 0.05"))
    df = run_sweep(spec, tmp_path / "side.parquet", scheduler="serial", progress=False)
    assert (df["status"] == "ok").all()
    for e0 in (0.4, 1.3):
        sc = parse_scene(point_scene_dict(spec.base, ["e0"], [e0]))
        th = scene_theory(sc, R_max=15.0, n_grid=60)
        for _, r in df[df["e0"] == e0].iterrows():
            band = next(b for b in th.bands if b.R_from <= r["p.R"] <= b.R_to)
            got = set(filter(None, r["theory.stable_motions"].split(";")))
            assert got == set(band.motions), (e0, r["p.R"], got, band.motions)


def test_failing_points_do_not_stop_the_sweep_and_hdf5_output(tmp_path):
    spec = load_sweep(_spec_text(toml_text(
        sweep=dict(compute=["theory"]),
        axis=[dict(key="dimensionless.Rt", values=[0.01, 0.7, 0.02]),
              dict(key="R_omega", values=[2.0, 3.0])],
    )))
    out = tmp_path / "t.h5"
    df = run_sweep(spec, out, scheduler="serial", progress=False)
    bad = df[df["dimensionless.Rt"] == 0.7]
    assert (bad["status"] == "error").all() and len(bad) == 2
    assert bad["error"].str.contains(r"dimensionless\.Rt = 0\.7").all()
    assert (df[df["dimensionless.Rt"] != 0.7]["status"] == "ok").all()
    _same(read_results(out), df)
    # the CLI entry point: exit 1 when some points failed, 2 for a bad spec
    p = argparse.ArgumentParser()
    add_sweep_arguments(p)
    f = tmp_path / "s.toml"
    f.write_text(spec_text := _spec_text("""
        [[axis]]
        key = "dimensionless.Rt"
        values = [0.01, 0.7]
    """))
    args = p.parse_args([str(f), "-o", str(tmp_path / "c.parquet"), "--no-progress",
                         "--workers", "1", "--regime-map", str(tmp_path / "r.png")])
    assert sweep_main(args) == 1
    assert (tmp_path / "c.parquet").exists() and (tmp_path / "r.png").exists()
    f.write_text(spec_text.replace("values = [0.01, 0.7]", "values = []"))
    assert sweep_main(args) == 2


def test_physical_base_e0_H_h_conversions(tmp_path):
    """Bare e0, h, H on a physical scene are converted to rotor/balancer/support fields."""
    spec = load_sweep(toml_text(
        base=dict(scene=(ROOT / "data_samples" / "scenes" / "ball_runup.toml").as_posix()),
        sweep=dict(combine="zip"),
        axis=[dict(key="e0", values=[0.3, 0.8]), dict(key="h", values=[0.1, 0.5]),
              dict(key="H", values=[0.2, 0.05]), dict(key="speed", values=[9.0, 15.0])]))
    df = run_sweep(spec, tmp_path / "p.parquet", scheduler="serial", progress=False)
    assert (df["status"] == "ok").all()
    np.testing.assert_allclose(df["p.e0"], [0.3, 0.8], rtol=1e-12)
    np.testing.assert_allclose(df["p.h"], [0.1, 0.5], rtol=1e-12)
    np.testing.assert_allclose(df["p.H"], [0.2, 0.05], rtol=1e-12)
    np.testing.assert_allclose(df["p.R"] * df["p.f0_hz"], [9.0, 15.0], rtol=1e-12)


# ------------------------------------------------------------------ any scene kind
TWO_MASS = """
[base.scene]
name = "family_two_mass_short"
[base.structure]
type = "two_mass"
body_mass = 2.0
rotor_mass = 1.0
body_stiffness = 1.0e4
rotor_stiffness = 3.0e4
body_damping = 20.0
rotor_damping = 20.0
unbalance = 2.0e-3
[[base.weights]]
plane = "balancer"
type = "balls"
count = 2
mass = 0.01
radius = 0.2
drag = 0.5
initial_angles = [60.0, 250.0]
[base.drive]
type = "speed"
programme = [[0.0, 0.0], [1.0, 14.0]]
[base.run]
duration = 4.0
sample_rate = 100.0
"""


def test_structure_base_scene_swept_over_a_structure_parameter(tmp_path):
    """A [structure] base scene (data_samples/scenes/family_two_mass.toml, shortened) swept
    over structure.rotor_stiffness: theory (engineering criterion of stand.theory) and
    simulation; keys that only the planar rotor has are refused by name."""
    from stand.scene.parse import parse
    from stand.theories.scene import theory
    from stand.sweep.spec import point_scene_dict

    spec = load_sweep(TWO_MASS + """
        [sweep]
        compute = ["theory", "simulate"]
        [[axis]]
        key = "structure.rotor_stiffness"
        values = [2.0e4, 3.0e4]
    """)
    assert spec.kind == "rotor" and spec.n_points == 2
    df = run_sweep(spec, tmp_path / "two_mass.parquet", scheduler="serial", progress=False)
    assert (df["status"] == "ok").all(), df["error"].tolist()
    _same(read_results(tmp_path / "two_mass.parquet"), df)
    for _, r in df.iterrows():
        sc = parse(point_scene_dict(spec.base, spec.columns, [r["structure.rotor_stiffness"]]))
        doc = theory(sc, floquet=False)
        assert r["p.f0_hz"] == pytest.approx(min(doc["natural_frequencies_hz_at_rest"]), rel=1e-9)
        assert r["p.R"] * r["p.f0_hz"] == pytest.approx(14.0, rel=1e-12)     # the held speed
        crit = doc["engineering_criterion"]["balancer"]["critical_speeds_hz"]
        np.testing.assert_allclose(json.loads(r["theory.critical_speeds_hz"]), crit, rtol=1e-9)
        assert r["theory.n_critical"] == len(crit)
        assert bool(r["theory.main_stable"])      # 14 rev/s lies in the first working range
    assert df["sim.success"].all()
    assert set(df["sim.regime"]) <= {"main", "side", "quasi-periodic", "transient"}
    assert (df["sim.nfev"] > 0).all() and np.isfinite(df["sim.residual"]).all()

    with pytest.raises(SweepSpecError, match=r"axis\[0\]\.key = \"R_omega\": .*\[structure\] scene.*"
                                             r"sweep \"speed\""):
        load_sweep(TWO_MASS + "[[axis]]\nkey = 'R_omega'\nvalues = [1.0]\n")
    with pytest.raises(SweepSpecError, match=r"unknown key structure\.rotor_stifness: did you mean"):
        load_sweep(TWO_MASS + "[[axis]]\nkey = 'structure.rotor_stifness'\nvalues = [1.0]\n")
    book = f"[base]\nscene = \"{(ROOT / 'data_samples' / 'scenes' / 'weight_damper.toml').as_posix()}\"\n"
    with pytest.raises(SweepSpecError, match=r"sweep\.compute = \"theory\": .*\[weight_model\]"):
        load_sweep(book + "[[axis]]\nkey = 'weight_model.h'\nvalues = [0.2]\n")


# ------------------------------------------------------------------ simulate on Dask
@pytest.fixture(scope="module")
def warm_jit():
    """Compile (or load) the integrator once here, so that worker processes find the
    numba cache on disk instead of compiling concurrently."""
    from stand.scene.parse import load_scene
    from stand.integrate.simulate import simulate

    simulate(load_scene(_spec_text("").replace("[base.", "[")))


def test_simulate_sweep_200_points_on_dask_localcluster(tmp_path, warm_jit):
    from dask.distributed import Client, LocalCluster

    spec = load_sweep(_spec_text("""
        [sweep]
        compute = ["simulate"]
        [[axis]]
        key = "R_omega"
        start = 0.5
        stop = 6.0
        num = 4
        [[axis]]
        key = "e0"
        start = 0.05
        stop = 1.4
        num = 20
    """, duration=40.0))
    # 4 speeds (0.5, 2.33, 4.17, 6) x 20 unbalances: two speeds far above resonance, 8
    # balanceable unbalances each (the check below needs more than 10 such points)
    assert spec.n_points == 80
    # one worker process: the tasks still travel to another process through the scheduler
    # (the 80 runs take 0.5 s of CPU; a second worker process only doubled the start-up's)
    with LocalCluster(n_workers=1, threads_per_worker=1, processes=True,
                      dashboard_address=None) as cluster:
        t0 = time.perf_counter()
        df = run_sweep(spec, tmp_path / "dask.parquet", scheduler=cluster.scheduler_address,
                       progress=False)
        print(f"80 simulations on a 1-worker LocalCluster: {time.perf_counter() - t0:.1f} s")
    assert len(df) == 80 and (df["status"] == "ok").all()
    assert set(df["sim.regime"]) <= {"main", "side", "quasi-periodic", "transient"}
    assert df["sim.success"].all()
    # far above resonance with a balanceable unbalance the balls balance the rotor
    hi = df[(df["p.R"] > 4) & (df["p.e0"] > 0.3) & (df["p.e0"] < 0.9)]
    assert len(hi) > 10 and (hi["sim.regime"] == "main").mean() > 0.8
    # beyond capacity: never "balanced" to zero
    assert (df.loc[df["p.e0"] > 1.05, "sim.residual"] > 0.04).all()
    # the same points in this process: identical table (up to timings); the local process
    # pool meets the same sweeps in the 400-point map and the kill-and-resume test (its
    # uninterrupted reference: in this process)
    local = run_sweep(spec, tmp_path / "local.parquet", scheduler="serial", progress=False)
    _same(df, local)


# ------------------------------------------------------------------ kill and resume
KILL_SPEC = """
[sweep]
compute = ["theory"]
[[axis]]
key = "R_omega"
start = 0.5
stop = 8.0
num = 12
spacing = "log"
[[axis]]
key = "e0"
start = 0.05
stop = 1.2
num = 10
[theory]
side = true
"""


def test_kill_minus_9_then_resume_equals_uninterrupted(tmp_path):
    spec_file = tmp_path / "kill.toml"
    spec_file.write_text(_spec_text(KILL_SPEC))
    out = tmp_path / "killed.parquet"
    code = (f"from stand.sweep import run_sweep; run_sweep({str(spec_file)!r}, {str(out)!r}, "
            f"workers=2, chunk_size=5, progress=False)")
    proc = subprocess.Popen([sys.executable, "-c", code], cwd=ROOT, start_new_session=True,
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    pdir = parts_dir(out)
    try:
        if not wait_for(lambda: pdir.is_dir() and len(list(pdir.glob("part-*.parquet"))) >= 4,
                        proc, timeout_s=120, poll_s=0.01):
            assert proc.poll() is None, proc.stderr.read().decode()
            pytest.fail("no part files within 120 s")
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)    # the sweep and its worker processes
        proc.wait()
    assert proc.returncode == -signal.SIGKILL, "the sweep finished before it was killed"
    assert not out.exists()                      # the final table is never half-written
    parts = list(pdir.glob("part-*.parquet"))
    done = pd.concat([pd.read_parquet(p) for p in parts])   # every part is complete
    # 120 points in 24 parts of 5 (the kill after 4 parts): some done, not all
    assert 20 <= len(done) < 120 and done["point_id"].is_unique

    resumed = run_sweep(spec_file, out, workers=2, chunk_size=5, progress=False)
    # the uninterrupted sweep in this process (the pool's start-up, ~2 s CPU a worker, spared):
    # the resumed table, made by the pool before and after the kill, equals it
    fresh = run_sweep(spec_file, tmp_path / "fresh.parquet", scheduler="serial", chunk_size=5,
                      progress=False)
    assert len(resumed) == 120 and (resumed["status"] == "ok").all()
    _same(resumed, fresh)
    _same(read_results(out), fresh)
    # the points finished before the kill were not recomputed
    kept = resumed.set_index("point_id").loc[done["point_id"], "wall_time_s"]
    np.testing.assert_array_equal(kept.to_numpy(), done["wall_time_s"].to_numpy())
    # a second resume does nothing and gives the same table
    t0 = time.perf_counter()
    again = run_sweep(spec_file, out, workers=2, progress=False)
    assert time.perf_counter() - t0 < 10
    _same(again, fresh)
