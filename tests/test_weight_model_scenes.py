"""[weight_model] scenes: stand theory / stand run for every weight type of issue 8."""
import json

import numpy as np
import pytest

from stand.theories.scene import model_theory
from stand.scene.parse import load_scene as load_weight_model
import stand
from stand.cli.main import main
from stand.scene.model import SceneError

S = "data_samples/scenes/weight_{}.toml"


@pytest.mark.parametrize("kind", ["two_axis", "gravity_pair", "damper", "liquid_float",
                                  "liquid_chamber"])
def test_theory_json(kind, capsys):
    assert main(["theory", S.format(kind), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["type"] == kind


@pytest.mark.parametrize("kind", ["two_axis", "gravity_pair"])
def test_run_ends_on_a_stable_steady_motion_of_the_theory(kind, tmp_path):
    """The weight's tilt angle phi at the end of the run equals the phi of one
    of the steady motions the theory calls stable (within 1e-3 rad)."""
    out = tmp_path / "r.h5"
    assert main(["run", S.format(kind), "-o", str(out)]) == 0
    rec = stand.read(out)
    phi_end = rec.coordinates["state/phi"][0][-1]
    stable = [m["phi"] for m in model_theory(load_weight_model(S.format(kind)))["steady_motions"]
              if m["stable"]]
    assert min(abs(phi_end - p) for p in stable) < 1e-3


def test_liquid_float_run_peak_matches_the_closed_form(tmp_path):
    out = tmp_path / "r.h5"
    assert main(["run", S.format("liquid_float"), "-o", str(out)]) == 0
    rec = stand.read(out)
    delta = np.hypot(rec.x, rec.y).max() / 1e-4
    th = model_theory(load_weight_model(S.format("liquid_float")))["runup_extrema"]
    assert delta == pytest.approx(th["delta_star_over_e"], rel=2e-3)   # sampled at 2.25 ms


def test_bad_weight_model_scene(tmp_path):
    p = tmp_path / "b.toml"
    p.write_text('[weight_model]\ntype = "damper"\nR_m = "x"\n')
    with pytest.raises(SceneError, match="R_m"):
        load_weight_model(p)
    p.write_text('[weight_model]\ntype = "nope"\n')
    with pytest.raises(SceneError, match="valid"):
        load_weight_model(p)
    # the quasi-static liquid chamber runs too (its rotor with the quasi-static residual)
    assert main(["run", S.format("liquid_chamber"), "-o", str(tmp_path / "c.h5")]) == 0


@pytest.mark.parametrize("kind", ["two_axis", "gravity_pair", "damper", "liquid_float"])
def test_book_oracle_run_agrees_with_the_run(kind):
    """The book's own right-hand side (tests/oracles) run on the same scene gives the same
    state columns as the package's run (the generic composition on the compiled kernel):
    two integrations of the same equations at rtol 1e-10 (1e-12 for the SI liquid float)."""
    import dataclasses

    from oracles.book_run import run_book_oracle

    sc = load_weight_model(S.format(kind))
    sc = dataclasses.replace(sc, run=dataclasses.replace(
        sc.run, duration=min(sc.run.duration, 20.0 if kind != "liquid_float" else 0.05)))
    tol = (1e-10, 1e-13) if kind != "liquid_float" else (1e-12, 1e-16)   # SI: lengths ~1e-5 m
    a = stand.run(sc, rtol=tol[0], atol=tol[1])
    b = run_book_oracle(sc, rtol=tol[0], atol=tol[1])
    assert a.success and b.stats.success
    for name, (col, unit) in b.coordinates.items():
        ref = np.max(np.abs(col)) + 1e-300
        assert np.max(np.abs(a.coordinates[name][0] - col)) / ref < 1e-6, name
