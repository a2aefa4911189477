"""Bounded work on every command (issue 34): conditioning limits at load, work budgets
during the computation, one line on stderr for either."""
from __future__ import annotations

import io
import re
import time
from contextlib import redirect_stderr, redirect_stdout
from pathlib import Path

import numpy as np
import pytest

import stand
from stand.errors import Budget, BudgetExceeded, SceneError

ROOT = Path(__file__).resolve().parents[1]
TWO_SCREENS = (ROOT / "data_samples" / "scenes" / "paper003_two_screens.toml").read_text()


def _scene(tmp_path: Path, **edits) -> Path:
    text = TWO_SCREENS
    for key, value in edits.items():
        text, n = re.subn(rf"(?m)^{key} = .*$", f"{key} = {value!r}", text, count=1)
        assert n == 1, key
    p = tmp_path / "scene.toml"
    p.write_text(text)
    return p


def _cli(*argv) -> tuple:
    from stand.cli.main import main

    out, err = io.StringIO(), io.StringIO()
    t0 = time.perf_counter()
    with redirect_stdout(out), redirect_stderr(err):
        code = main([str(a) for a in argv])
    return code, [ln for ln in err.getvalue().splitlines() if ln.strip()], time.perf_counter() - t0


def test_ill_conditioned_rigid_rotor_refused_by_every_command(tmp_path):
    """The issue's case: [structure] mass = 1e30, A = 1e-30 made theory, accuracy --fast and
    sweep hang; now every command refuses it at load, naming the keys and the limit."""
    p = _scene(tmp_path, mass=1e30, A=1e-30)
    spec = tmp_path / "sweep.toml"
    spec.write_text(f'[base]\nscene = "{p.name}"\n[[axis]]\nkey = "speed"\nvalues = [5.0, 20.0]\n')
    for argv in (["run", p, "-o", tmp_path / "r.h5"], ["theory", p], ["accuracy", p, "--fast"],
                 ["experiment", p, "constant", "-o", tmp_path / "e.h5", "--duration", "1"],
                 ["sweep", spec, "-o", tmp_path / "s.parquet"]):
        code, lines, wall = _cli(*argv)
        assert code == 2 and len(lines) == 1, (argv[0], code, lines)
        assert "structure.A = 1e-30 kg m^2" in lines[0] and "limit 1e+08" in lines[0], lines
        assert wall < 10.0, (argv[0], wall)


@pytest.mark.parametrize("edits, words", [
    ({"mass": 1e20}, ["structure.mass = 1e+20 kg", "span a factor"]),
    ({"c1": 1e30, "c2": 1e30}, ["structure.c1 = 1e+30 N/m", "sqrt(K/M)"]),
    ({"stiffness_damping": 1e20}, ["structure.stiffness_damping = 1e+20 s", "damping rate"]),
])
def test_conditioning_limits_name_keys_values_units(tmp_path, edits, words):
    with pytest.raises(SceneError) as info:
        stand.load(_scene(tmp_path, **edits))
    msg = str(info.value)
    assert "\n" not in msg and all(w in msg for w in words), msg


@pytest.mark.parametrize("params", [
    # a CD-drive rotor: 15 g, A ~ 1e-5 kg m^2, stiff bearings 1 cm apart
    dict(mass=0.015, A=1e-5, C=1.8e-5, l1=0.005, l2=0.005, c1=1e6, c2=1e6),
    # a turbine rotor of 1e5 kg on its bearings
    dict(mass=1e5, A=2e5, C=5e4, l1=3.0, l2=3.0, c1=2e9, c2=2e9, stiffness_damping=1e-4),
])
def test_real_machines_lie_inside_the_limits(params):
    from stand.model.rotors.spatial import spatial_scene_rotor
    from stand.scene.conditioning import (MAX_MASS_CONDITION, MAX_RATE, MAX_RATE_SPREAD,
                                          conditioning)

    m = conditioning(spatial_scene_rotor(**params), top_speed=2 * np.pi * 500)
    assert max(m["rate_K"], m["rate_D"], m["rate_G"]) < MAX_RATE / 100
    assert m["mass_condition"] < MAX_MASS_CONDITION and m["rate_spread"] < MAX_RATE_SPREAD / 100


def test_budget_counts_and_stops():
    b = Budget("a scan", 3)
    b.spend(3)
    with pytest.raises(BudgetExceeded, match="a scan ran out of its budget of 3 evaluations"):
        b.spend()
    assert issubclass(BudgetExceeded, RuntimeError)


def test_generalised_criterion_bisection_is_bounded(monkeypatch):
    """A count of non-negative eigenvalues that flickers from round-off at every level used to
    make the bisection explode (2^43 evaluations); the budget stops it within a second."""
    import stand.model.rotors.structure as st

    rotor = stand.load(ROOT / "data_samples" / "scenes" / "paper003_two_screens.toml").linear_rotor()
    rng = np.random.default_rng(0)
    monkeypatch.setattr(st, "_positive_count", lambda r, p, om: rng.integers(0, 2, np.size(om)))
    t0 = time.perf_counter()
    with pytest.raises(BudgetExceeded, match="generalised criterion's bisection"):
        st.generalised_working_ranges(rotor, ["balancer1", "balancer2"], 1.0, 1e3)
    assert time.perf_counter() - t0 < 10.0


def test_accuracy_ladder_budget_stops_with_one_line(tmp_path):
    text = (ROOT / "data_samples" / "scenes" / "ball_runup.toml").read_text()
    text = re.sub(r"(?m)^duration = .*$", "duration = 2.0\nmax_steps = 20", text, count=1)
    p = tmp_path / "s.toml"
    p.write_text(text)
    code, lines, wall = _cli("accuracy", p, "--fast")
    assert code == 1 and len(lines) == 1, (code, lines)
    assert "step budget" in lines[0] and "4 x run.max_steps = 20" in lines[0], lines


def test_floquet_scan_is_bounded(monkeypatch):
    """The Floquet scan's flows spend one budget; a tiny budget stops the theory (exit 1)."""
    import stand.theories.rotors as th

    scene = stand.load(ROOT / "data_samples" / "scenes" / "family_two_mass.toml")
    monkeypatch.setattr(th, "FLOQUET_BUDGET", 1000)
    with pytest.raises(BudgetExceeded, match="Floquet scan .* budget of 1000 state-steps"):
        th.family_theory(scene)
