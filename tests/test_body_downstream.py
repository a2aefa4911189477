"""Body weights downstream (issue 16 items 5 and 7): the body_* sample scenes, the stress
cases of kind ``body_scene``, sweep axes over a body's keys and the experiment programmes
on planar scenes with body weights."""
from __future__ import annotations

import dataclasses
import io
import math
import re
import textwrap
from contextlib import redirect_stderr, redirect_stdout
from pathlib import Path

import numpy as np
import pytest

import stand
from stand.scene import experiments as ex
from stand.cli.main import main
from stand.reports.stress import load_catalogue, run_stress
from stand.reports.stress_catalogue import CatalogueError
from stand.sweep import SweepSpecError, load_sweep, run_sweep

ROOT = Path(__file__).resolve().parents[1]
SCENES = ROOT / "data_samples" / "scenes"
SWEEPS = ROOT / "data_samples" / "sweeps"

#: sample -> (|U| / (M e) at the end, tolerance): the outcomes stated in the files' comments
SAMPLES = {
    "body_two_axis_pendulum": (0.1711, 2e-3),   # ch. 6 main motion below the hinge, n = 0.1711
    "body_coupled_pair": (0.1667, 2e-4),        # ch. 7.1, e0 = 1.2 > 1: about M e - S = 0.2 S
    "body_damper": (0.1744, 2e-3),              # ch. 7.2 (7.54), n = 0.1744
    "body_liquid_float": (0.662, 2e-3),         # paper 001 lever: 1 - (r - 1) m2/m R^2/(R^2 - 1)
    "body_liquid_chamber": (0.623, 2e-3),       # thesis 002 lever with kappa
    "body_compare_balls": (0.0, 1e-6),          # two balls: exact balance
    "body_compare_liquid": (0.568, 2e-3),       # the thesis stand's chamber
}
#: scenes of the stress catalogue and the duration [s] they run with here (plumbing only)
STRESS_SCENES = {"body_stress_liquid_float_runup": 20.0, "body_stress_damper_singular": 12.0,
                 "body_stress_pendulum_fast": 5.0}


def _cli(*argv):
    out, err = io.StringIO(), io.StringIO()
    with redirect_stdout(out), redirect_stderr(err):
        code = main([str(a) for a in argv])
    return code, out.getvalue(), err.getvalue()


def _with_duration(src: Path, dst: Path, duration: float) -> Path:
    """A copy of a scene file with [run].duration replaced."""
    lines, table = [], None
    for line in src.read_text().splitlines():
        s = line.strip()
        if s.startswith("["):
            table = s.strip("[]").strip()
        if table == "run" and s.startswith("duration"):
            line = f"duration = {duration!r}"
        lines.append(line)
    dst.write_text("\n".join(lines) + "\n")
    return dst


# ------------------------------------------------------------------ samples
@pytest.mark.parametrize("name", sorted(SAMPLES))
def test_sample_runs_with_its_instruments_and_reaches_its_stated_outcome(name, tmp_path):
    path = SCENES / f"{name}.toml"
    text = path.read_text()
    assert text.startswith("#") and "Measured" in text, "the file opens with what it shows"
    assert "[instruments.screen]" in text and "[instruments.stroboscope]" in text
    rec = tmp_path / "run.h5"
    code, out, err = _cli("run", path, "-o", rec, "--no-progress")
    assert code == 0, out + err
    assert "Traceback" not in out + err
    r = stand.read(rec)
    assert r.shape("instruments/screen/frames")[1:] == (160, 160)
    assert r.shape("instruments/stroboscope/frames")[0] >= 3
    # the physics, without the instruments
    scene = stand.load(path)
    run = stand.run(dataclasses.replace(scene, instruments={}))
    assert run.stats.status == 0 and not run.notes, run.notes
    U = run.residual_unbalance()
    ratio = np.abs(U) / scene.rotor.unbalance
    want, tol = SAMPLES[name]
    assert ratio[-1] == pytest.approx(want, abs=tol)
    tail = run.t >= 0.7 * run.t[-1]               # settled well before the end
    assert np.max(np.abs(U[tail] - U[-1])) / scene.rotor.unbalance < 1e-3
    assert run.rotor_speed[-1] / (2 * math.pi) == pytest.approx(30.0)


def test_comparison_pair_shares_its_stand_and_names_each_other():
    a, b = (stand.load(SCENES / f"body_compare_{k}.toml") for k in ("balls", "liquid"))
    assert a.rotor == b.rotor and a.supports == b.supports
    np.testing.assert_array_equal(a.drive.programme, b.drive.programme)
    assert a.run.duration == b.run.duration
    assert "body_compare_liquid.toml" in (SCENES / "body_compare_balls.toml").read_text()
    assert "body_compare_balls.toml" in (SCENES / "body_compare_liquid.toml").read_text()
    assert a.balancer.count == 2 and not a.bodies
    assert [pb.kind for pb in b.bodies] == ["liquid_chamber"]


@pytest.mark.parametrize("name", sorted(STRESS_SCENES))
def test_stress_scenes_run_shortened(name, tmp_path):
    p = _with_duration(SCENES / f"{name}.toml", tmp_path / f"{name}.toml", STRESS_SCENES[name])
    code, out, err = _cli("run", p, "-o", tmp_path / "s.h5", "--no-progress")
    assert code == 0 and "Traceback" not in out + err, out + err


# ------------------------------------------------------------------ stress
def test_body_stress_cases_are_in_the_catalogue():
    cases = {c["name"]: c for c in load_catalogue()}
    want = {"body_liquid_float_runup_1e5": "runup_closed_form",
            "body_damper_singular_direction": "steady_theory",
            "body_two_axis_pendulum_R200": "steady_theory"}
    for name, check in want.items():
        assert cases[name]["kind"] == "body_scene" and cases[name]["check"] == check
        path = ROOT / cases[name]["params"]["path"]
        assert path.exists() and stand.load(path).bodies
    assert cases["body_two_axis_pendulum_R200"]["fast"]
    runup = stand.load(ROOT / cases["body_liquid_float_runup_1e5"]["params"]["path"])
    revs = 0.5 * (runup.drive.programme[0, 1] + runup.drive.programme[-1, 1]) * \
        runup.drive.programme[-1, 0] / (2 * math.pi)
    assert revs > 9.9e4
    damper = stand.load(ROOT / cases["body_damper_singular_direction"]["params"]["path"]).bodies[0]
    b = damper.body
    assert b.inertia == pytest.approx(b.mass * b.arm ** 2) and b.initial_tilt == pytest.approx(
        math.pi / 2)


def test_one_body_stress_case_runs_and_passes(tmp_path):
    doc = run_stress(cases=["body_two_axis_pendulum_R200"], json_path=tmp_path / "s.json")
    (c,) = doc["cases"]
    assert c["pass"], c["reason"]
    assert c["case_time_s"] <= c["time_budget_s"]
    d = c["details"]
    assert d["book_model"] == "two_axis" and d["book_params"]["R_omega"] == pytest.approx(200.0, 1e-3)
    assert c["error"] < 1e-6 and d["matched_ratio"] == pytest.approx(1.2528e-3, rel=1e-3)


def _catalogue(tmp_path, scene: str, check: str, extra: str = "") -> Path:
    p = tmp_path / "cat.toml"
    p.write_text(textwrap.dedent(f"""\
        [[case]]
        name = "c"
        kind = "body_scene"
        check = "{check}"
        tolerance = 1e-3
        time_budget_s = 60.0
        {extra}
        [case.params]
        path = "{scene}"
        """))
    return p


def test_body_scene_case_errors_and_validity(tmp_path):
    # a scene without body weights is a malformed case, naming the field
    cat = _catalogue(tmp_path, str(SCENES / "ball_runup.toml"), "steady_theory")
    with pytest.raises(CatalogueError, match="params.path.*no body weight"):
        run_stress(cat, cases=["c"])
    # the steady-motion check on a run that ends on the ramp: outside validity, said so
    short = _with_duration(SCENES / "body_two_axis_pendulum.toml", tmp_path / "p.toml", 12.0)
    doc = run_stress(_catalogue(tmp_path, str(short), "steady_theory"), cases=["c"])
    (c,) = doc["cases"]
    assert not c["pass"] and "not held over the last 30%" in c["outside_validity"]
    # the closed-form run-up does not apply to a damper
    doc = run_stress(_catalogue(tmp_path, str(short), "runup_closed_form"), cases=["c"])
    (c,) = doc["cases"]
    assert not c["pass"] and "closed-form run-up needs" in c["outside_validity"]


# ------------------------------------------------------------------ sweep
@pytest.mark.parametrize("whole", [False, pytest.param(True, marks=pytest.mark.full)],
                         ids=["extremes_at_30", "whole"])
def test_sample_sweep_over_the_fill_volume(tmp_path, whole):
    """The sample sweep; by default its two extreme volumes at 30 rev/s (2 of its 8 run-ups:
    every check below but the 15 rev/s group), the whole sweep under ``-m full``."""
    path = SWEEPS / "body_liquid_volume.toml"
    spec = load_sweep(path)
    assert spec.columns == ["weights[0].fill_volume", "speed"] and spec.n_points == 8
    if not whole:
        text = path.read_text()
        for old, new in (("[1.0e-4, 2.0e-4, 4.0e-4, 8.0e-4]", "[1.0e-4, 8.0e-4]"),
                         ("[15.0, 30.0]", "[30.0]"),
                         ('"../scenes/', f'"{SCENES.as_posix()}/')):
            assert old in text
            text = text.replace(old, new)
        spec = load_sweep(text)
        assert spec.n_points == 2
    df = run_sweep(spec, tmp_path / "vol.parquet", scheduler="serial", progress=False)
    assert (df["status"] == "ok").all(), df["error"].tolist()
    assert (df["sim.regime"] == "steady").all()
    assert (df["p.n"] == 1).all()
    df["ratio"] = df["sim.residual"] / df["p.e0"]
    for speed, g in df.groupby("speed"):
        g = g.sort_values("weights[0].fill_volume")
        assert np.all(np.diff(g["ratio"]) > 0), g["ratio"].tolist()   # less liquid, less left
        assert g["sim.whirl_radius_m"].max() == pytest.approx(g["sim.whirl_radius_m"].min(),
                                                               rel=1e-3)
    at30 = df[df["speed"] == 30.0].set_index("weights[0].fill_volume")["ratio"]
    assert at30[1e-4] == pytest.approx(0.594, abs=2e-3)
    assert at30[8e-4] == pytest.approx(0.698, abs=2e-3)
    small = df[df["weights[0].fill_volume"] == 1e-4]["sim.message"]
    assert small.str.contains("touched the wall").all()
    big = df[df["weights[0].fill_volume"] == 8e-4]["sim.message"]
    assert not big.str.contains("note:").any()
    # theory: the structure's critical speed, no book criterion for a body weight
    assert df["theory.main_stable"].isna().all()
    assert df["theory.critical_speeds_hz"].str.startswith("[").all()


def _spec(base: str, key: str, values, compute='["simulate"]') -> str:
    return (f'[sweep]\ncompute = {compute}\n[base]\nscene = "{base}"\n'
            f'[[axis]]\nkey = "{key}"\nvalues = {list(values)!r}\n')


@pytest.mark.parametrize("key, match", [
    ("weights[0].fill_volume", r"unknown key of weights\[0\] \(type 'two_axis_pendulum'\).*tilt_drag"),
    ("weights[0].tilt_dreg", r"did you mean 'tilt_drag'"),
    ("weights[2].arm", r"has 1 \[\[weights\]\] table\(s\)"),
    ("weights[0].dimensionless.R_m", r"gives SI keys, not the dimensionless sugar"),
    ("e0", r"sweep rotor\.eccentricity instead"),
])
def test_body_axis_keys_are_checked_early(key, match):
    base = SCENES / "body_two_axis_pendulum.toml"
    with pytest.raises(SweepSpecError, match=match):
        load_sweep(_spec(str(base), key, [0.1, 0.2]))


def test_body_axes_on_planar_and_structure_scenes(tmp_path):
    for key in ("weights[0].arm", "weights[0].tilt_drag", "weights[0].initial_tilt"):
        assert load_sweep(_spec(str(SCENES / "body_two_axis_pendulum.toml"), key, [0.1])).n_points == 1
    # a [structure] rotor with balls in one plane and a liquid chamber in the other
    scene = tmp_path / "mixed.toml"
    scene.write_text(textwrap.dedent("""\
        [scene]
        name = "mixed"
        [structure]
        type = "two_mass"
        body_mass = 2.0
        rotor_mass = 1.0
        body_stiffness = 1.0e4
        rotor_stiffness = 3.0e4
        body_damping = 20.0
        rotor_damping = 20.0
        unbalance = 2.0e-3
        [[weights]]
        plane = "balancer"
        type = "balls"
        count = 2
        mass = 0.01
        radius = 0.2
        drag = 0.5
        initial_angles = [60.0, 250.0]
        [[weights]]
        plane = "balancer"
        type = "liquid_chamber"
        chamber_radius = 0.1
        chamber_height = 0.02
        fill_volume = 1.0e-4
        [drive]
        type = "speed"
        programme = [[0.0, 0.0], [1.0, 14.0]]
        [run]
        duration = 2.0
        sample_rate = 100.0
        """))
    with pytest.raises(SweepSpecError, match=r"unknown key weights\[0\]\.fill_volume"):
        load_sweep(_spec(str(scene), "weights[0].fill_volume", [1e-4]))
    spec = load_sweep(_spec(str(scene), "weights[1].fill_volume", [1e-4, 2e-4], '["simulate", "theory"]'))
    df = run_sweep(spec, tmp_path / "m.parquet", scheduler="serial", progress=False)
    assert (df["status"] == "ok").all(), df["error"].tolist()
    assert (df["p.n"] == 3).all() and df["p.e0"].notna().all()
    assert df["sim.regime"].notna().all() and (df["sim.regime"] != "").all()
    assert df["theory.critical_speeds_hz"].str.startswith("[").all()


def test_theory_side_motions_refused_with_body_weights():
    text = _spec(str(SCENES / "body_damper.toml"), "weights[0].drag", [1e-3], '["theory"]')
    with pytest.raises(SweepSpecError, match="theory.side = true.*body weights \\(damper\\)"):
        load_sweep(text + "[theory]\nside = true\n")


# ------------------------------------------------------------------ experiments
def test_experiment_programmes_on_a_planar_scene_with_a_body(tmp_path):
    scene = stand.load(SCENES / "body_damper.toml")
    scene = dataclasses.replace(scene, instruments={})
    up = ex.programme(scene, "run-up", speed=30.0, rate=6.0, hold=5.0)
    run = stand.run(up)
    assert run.stats.status == 0 and run.rotor_speed[-1] == pytest.approx(30 * 2 * math.pi)
    # exponential coast-down as a programme on the generic kernel: speed e^-1 at time/5
    down = ex.programme(scene, "run-down", speed=30.0, time=10.0, exponential=True)
    run = stand.run(down)
    assert run.stats.status == 0
    k = np.argmin(np.abs(run.t - (10.0 + 2.0)))          # settle 10 s, then tau = 2 s
    assert run.rotor_speed[k] / (30 * 2 * math.pi) == pytest.approx(math.exp(-1.0), rel=1e-4)
    nf = ex.programme(scene, "natural-frequency", deflection=1e-3)
    assert stand.run(nf).stats.status == 0
    for name, opts in (("unbalance", dict(speed=30.0, at=1.0, eccentricity=1e-4)),
                       ("pressure", dict(speed=30.0, start=1.0, end=2.0, force=5.0))):
        why = ex.not_applicable(scene, name)
        assert why and "generic kernel" in why and "damper" in why
        with pytest.raises(ex.NotApplicable, match="perturbation"):
            ex.programme(scene, name, **opts)
    assert ex.not_applicable(scene, "run-up") is None
    family = stand.load(SCENES / "family_two_mass.toml")   # the generic kernel too
    assert ex.not_applicable(family, "run-up") is None
    assert "generic kernel" in ex.not_applicable(family, "pressure")


def test_experiment_command_on_a_body_scene(tmp_path):
    path = SCENES / "body_liquid_float.toml"
    code, out, err = _cli("experiment", path, "run-up", "--speed", "30", "--rate", "10",
                          "--hold", "5", "-o", tmp_path / "up.h5")
    assert code == 0 and "run-up" in out, out + err
    code, out, err = _cli("experiment", path, "run-down", "--speed", "30", "--time", "5",
                          "--exponential", "-o", tmp_path / "down.h5")
    assert code == 0, out + err
    code, out, err = _cli("experiment", path, "impact", "--speed", "30", "--at", "1",
                          "--velocity", "0.01", "-o", tmp_path / "imp.h5")
    assert code == 0 and (tmp_path / "imp.h5").exists(), out + err   # a blow: a state jump
    code, out, err = _cli("experiment", path, "pressure", "--speed", "30", "--at", "1",
                          "--end", "2", "--side-force", "5", "-o", tmp_path / "p.h5")
    assert "Traceback" not in out + err
    assert not (tmp_path / "p.h5").exists()
    text = out + err
    assert re.search(r"pressure on a scene with body weights \(liquid_float\).*perturbation", text)
    assert code == 0 and "not applicable:" in out
