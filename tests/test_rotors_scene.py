"""Rotor-family scene files ([structure] + [[weights]]) and their CLI paths."""
import json
import math

import h5py
import numpy as np
import pytest

from stand.cli.main import main
from stand.integrate.coupled import PlaneWeights, simulate_coupled
from stand.model.rotors.planar_supports import planar_critical_speeds, planar_rotor
from stand.scene.structure_tables import parse_family_scene
from stand.scene.parse import load_scene
from stand.scene.model import SceneError

SAMPLE = "data_samples/scenes/family_planar.toml"


def test_sample_loads_and_theory_matches_the_closed_form(capsys):
    """[structure] type = "planar" is the chapter-5 planar rotor (one Scene for both spellings,
    issue 40): its theory is chapter 5's, whose critical speeds are (2.29)."""
    sc = load_scene(SAMPLE)
    assert sc.structure_type == "planar" and sc.kind == "planar"
    assert len(sc.weights) == 1 and sc.weights[0].balancer.count == 2
    assert main(["theory", SAMPLE, "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    crit = [c["hz"] for c in doc["critical_speeds_hz"] if "(2.29)" in c["source"]]
    # (2.29) with the locked balls' mass; light damping moves the edges by O(zeta^2)
    M = sc.rotor.mass + 2 * 0.045
    closed = np.array(planar_critical_speeds(M, 1613.09, 3226.18)) / (2 * math.pi)
    np.testing.assert_allclose(crit, closed, rtol=0.01)
    assert doc["stable_bands"][-1]["motions"] == ["main (engineering criterion)"]


def test_run_writes_a_recording(tmp_path):
    text = open(SAMPLE).read().replace("duration = 30.0", "duration = 2.0")
    p = tmp_path / "short.toml"
    p.write_text(text)
    out = tmp_path / "r.h5"
    assert main(["run", str(p), "-o", str(out)]) == 0
    with h5py.File(out) as f:
        assert f["time"].shape == f["shaft/x"].shape == f["planes/balancer/x"].shape == (401,)
        assert f["weights/ball2/angle"].shape == (401,)
        assert f.attrs["structure"] == "planar" and f.attrs["main_plane"] == "balancer"


def _doc(**structure):
    return {"structure": {"type": "planar", "mass": 1.0, "stiffness_x": 100.0, **structure},
            "drive": {"type": "speed", "programme": [[0.0, 1.0]]},
            "run": {"duration": 1.0, "sample_rate": 10.0}}


def test_bad_scenes_name_the_field():
    with pytest.raises(SceneError, match=r"structure\.stiffnes: not a parameter.*stiffness_x"):
        parse_family_scene(_doc(stiffnes=1.0))
    with pytest.raises(SceneError, match=r"mass"):
        parse_family_scene(_doc(mass=-1.0))
    with pytest.raises(SceneError, match="unknown rotor type"):
        parse_family_scene({**_doc(), "structure": {"type": "rotor9"}})
    d = _doc()
    d["weights"] = [{"plane": "nowhere", "type": "balls", "count": 2, "mass": 0.01, "radius": 0.1}]
    with pytest.raises(SceneError, match=r'weights\[0\]\.plane = "nowhere".*balancer'):
        parse_family_scene(d)
    d["weights"] = [{"plane": "balancer", "type": "balls", "count": 2, "mass": -0.01, "radius": 0.1}]
    with pytest.raises(SceneError, match=r"weights\[0\]\.mass"):
        parse_family_scene(d)


def test_gravity_only_where_the_axis_is_not_vertical():
    """Horizontal axis (g along -y): the static sag is -(M + m) g / c_y, and a
    pendulum-free ball at rest hangs at the bottom; a vertical axis has no
    gravity terms at all (the generalised gravity force is zero)."""
    from stand.scene.model import Balancer

    g = 9.81
    c = 4.0e4
    ball = Balancer(type="balls", mass=np.array([0.05]), radius=np.array([0.1]),
                    drag=np.array([5.0]), inertia=np.array([0.05 * 0.01]),
                    initial_angles=np.array([0.3]), initial_speeds=np.zeros(1))
    rot = planar_rotor(2.0, c, damping_x=40.0, g=(0.0, -g))
    run = simulate_coupled(rot, [PlaneWeights("balancer", ball)], [[0.0, 0.0]], 20.0, 10.0)
    assert run.success
    y_end = run.planes["balancer"][-1, 1]
    assert y_end == pytest.approx(-(2.0 + 0.05) * g / c, rel=1e-4)
    # the ball (rotor at rest, phi = 0) settles at the bottom: angle -90 deg
    assert math.remainder(run.weight_angle[-1, 0] + math.pi / 2, 2 * math.pi) == pytest.approx(0, abs=1e-3)
    vertical = planar_rotor(2.0, c)
    assert not vertical.gravity.any() and not vertical.gravity_plane.any()
