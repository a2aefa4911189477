"""`stand analyze` of a stand recording reads its displacement probes as a lab would
(issue 30): x, y solved from the probes' projections, and on the scene-model route (rotors
with weights) the probes' runout dealt with in the 1X's ±."""
from __future__ import annotations

import math

import numpy as np
import pytest

import stand
from stand.recording.probes import probes_xy


def test_probes_at_any_two_angles_give_x_and_y():
    """s_i = x cos a_i + y sin a_i at 30 and 150 deg: the 2x2 solve returns x, y to
    rounding; parallel probes cannot, and say so."""
    rng = np.random.default_rng(3)
    x, y = rng.normal(size=50), rng.normal(size=50)
    a = np.radians([30.0, 150.0])
    sig = np.column_stack([x * np.cos(ai) + y * np.sin(ai) for ai in a])
    xs, ys = probes_xy(sig, a)
    assert np.max(np.abs(xs - x)) < 1e-12 and np.max(np.abs(ys - y)) < 1e-12
    notes = []
    assert probes_xy(sig, np.radians([30.0, 210.0]), notes) is None
    assert "do not span the plane" in notes[0]


SCENE = """[scene]
name = "balls_probes"
[rotor]
mass = 4.45
eccentricity = 8.0899e-4
unbalance_angle = 0.0
[supports]
stiffness = 1613.09
damping = 8.5577
[balancer]
type = "balls"
count = 2
mass = 0.045
radius = 0.08
drag = 0.16965
initial_angles = [150.0, 210.0]
[drive]
type = "speed"
programme = [[0.0, 0.0], [6.0, 15.0]]
[run]
duration = 14.0
sample_rate = 200.0
rtol = 1e-8
atol = 1e-10
"""
PROBES = """[instruments.probes]
sample_rate = 200.0
noise_rms = 0.5e-6
runout = 5.0e-6
angles = [0.0, 90.0]
seed = 4
"""


@pytest.fixture(scope="module")
def ball_runs():
    return (stand.analyze(stand.run(stand.load(SCENE + PROBES))),
            stand.analyze(stand.run(stand.load(SCENE))))


def test_balls_probes_runout_is_in_the_1x_std(ball_runs):
    """The balls balance the rotor (the shaft's own 1X ~0): the probes' 1X is their 5 um
    runout.  With no slow roll in the record the stated runout goes into the 1X's ± (a
    vector of 5 um at an unknown angle): the probes' 1X lies within 2 std of the shaft's,
    and the unbalance within 2 std of the shaft state's; without the runout in the ± the
    probes' 1X (~5 um, std ~0.01 um) would be hundreds of std off."""
    p, s = ball_runs
    assert any("analysed the displacement probes" in n for n in p["notes"])
    assert any("stated 1X runout 5 µm" in n for n in p["notes"])
    assert p["response_1x_m_std"] >= 5e-6
    assert abs(p["response_1x_m"] - s["response_1x_m"]) < 2 * p["response_1x_m_std"]
    assert abs(p["unbalance_gmm"] - s["unbalance_gmm"]) < 2 * p["unbalance_gmm_std"]


def test_balls_critical_speed_has_a_std(ball_runs):
    """The resonance route (no model fit with weights): the critical speed has a std, with
    the damping unknown (half the sweep-limited lag in it); the shaft state's and the
    probes' critical speeds agree within it."""
    p, s = ball_runs
    for d in (p, s):
        assert d["critical_speed_hz_std"] is not None and d["critical_speed_hz_std"] > 0
        assert "damping" in d["critical_speed_method"]
    assert abs(p["critical_speed_hz"] - s["critical_speed_hz"]) < 2 * p["critical_speed_hz_std"]
    assert any("no displacement probes" in n for n in s["notes"])
