"""A sweep over a rotor whose unbalance sits in a plane of its own (the grinding rotor: the
unbalance in plane "unbalance", the balls in "balancer") says "balanced" from the whole
rotor's static residual against the capacity of all its weights, not plane by plane."""
import math
import tomllib
from pathlib import Path

import numpy as np
import pytest

from stand.sweep import load_sweep, run_sweep

from _helpers import toml_text

ROOT = Path(__file__).resolve().parents[1]
SCENE = ROOT / "data_samples" / "scenes" / "family_grinding.toml"


def _grinding_spec(speeds, ball_mass=None, duration=12.0):
    """A simulate sweep over the held speed [rev/s] of family_grinding (instruments off,
    12 s at 100 Hz: the balls settle in ~5 s after the 3 s run-up at 35 rev/s)."""
    doc = tomllib.loads(SCENE.read_text())
    w = dict(doc["weights"][0])
    if ball_mass is not None:
        w["mass"] = ball_mass
    text = toml_text(base__scene=doc["scene"] | {"language": 2}, base__structure=doc["structure"],
                     base__weights=[w], base__drive=doc["drive"],
                     base__run=dict(duration=duration, sample_rate=100.0),
                     sweep=dict(name="grinding", compute=["simulate"]),
                     axis=[dict(key="speed", values=list(speeds))])
    return load_sweep(text), doc


def test_grinding_sweep_balanced_above_the_critical_speed_not_below(tmp_path):
    spec, doc = _grinding_spec([10.0, 35.0])
    df = run_sweep(spec, tmp_path / "g.parquet", scheduler="serial", progress=False)
    assert (df["status"] == "ok").all(), df["error"].tolist()
    S = 2 * doc["weights"][0]["mass"] * doc["weights"][0]["radius"]          # 4e-3 kg m
    # p.e0: the rotor's unbalance (2e-3 kg m, in its own plane) / S; before: the balancer
    # plane's own unbalance, 0
    np.testing.assert_allclose(df["p.e0"], doc["structure"]["unbalance"] / S, rtol=1e-12)
    below, above = df.iloc[0], df.iloc[1]
    # 35 rev/s (critical 17.3 rev/s): the balls cancel the unbalance, the whirl (7 um) is
    # well below 1 % of the eccentricity U / M = 2 mm the bare rotor whirls with above its
    # critical speed; before the fix: "side" (the balancer plane's residual, the balls'
    # own 0.5 S, read as the rotor's)
    assert above["sim.regime"] == "main"
    assert above["sim.residual"] < 1e-2
    e = doc["structure"]["unbalance"] / doc["structure"]["mass"]          # 2 mm
    assert above["sim.whirl_radius_m"] < 1e-2 * e
    # 10 rev/s, below the critical speed: the balls go to the heavy side and add to the
    # unbalance -- more than the bare rotor's 0.5 S (1.5 S once both sit on it); not balanced
    assert below["sim.regime"] != "main"
    assert below["sim.residual"] > 0.5


def test_too_light_balls_are_not_balanced(tmp_path):
    # balls of 2 g: capacity S = 0.8e-3 kg m < the 2e-3 kg m unbalance (e0 = 2.5): the static
    # residual cannot go below |U| - S = 1.5 S (triangle inequality); before the fix the
    # sweep read the balancer plane alone (0.98 S, the balls' own moment)
    spec, doc = _grinding_spec([35.0], ball_mass=0.002)
    df = run_sweep(spec, tmp_path / "g.parquet", scheduler="serial", progress=False)
    r = df.iloc[0]
    assert r["p.e0"] == pytest.approx(2.5, rel=1e-12)
    assert r["sim.residual"] >= 1.5 - 1e-9
    # after 12 s the balls still drift (0.2 rad over the window) and leave 1.55 S, 0.05 S
    # above the best they can do: not the maximally balanced motion, so not "main"
    assert r["sim.residual"] > 1.5 + 1e-2 and r["sim.regime"] != "main"


@pytest.mark.parametrize("a_over_S, balanced", [(0.05, False), (0.002, True)])
def test_couple_decides_where_the_weights_span_two_positions(a_over_S, balanced):
    # paper 003's two balancer planes at -0.15 m and 0.2 m (span L = 0.35 m), S = 4 x 2 g x
    # 0.1 m: opposite residuals +a, -a leave no static residual but a couple 0.35 a; the
    # verdict: |U_c| < balance_tol S L, i.e. a < 1e-2 S (the pair at the span's ends)
    from types import SimpleNamespace

    import stand
    from stand.sweep.compute import _balance

    scene = stand.load(ROOT / "data_samples" / "scenes" / "paper003_two_balancers.toml")
    S = 4 * 0.02 * 0.1
    a = np.array([[a_over_S * S * math.cos(0.3), a_over_S * S * math.sin(0.3)]])
    zero = np.zeros((1, 2))
    truth = {"residual/com": (zero, {}), "residual/unbalance1": (zero, {}),
             "residual/balancer1": (a, {}), "residual/balancer2": (-a, {})}
    psi, ok = _balance(SimpleNamespace(scene=scene, truth=truth), {"balance_tol": 1e-2})
    assert psi == 0.0 and ok is balanced
