"""The ``stand`` command line: the README's main job and input errors."""
import json
import os
import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np
import pytest

from stand.cli.main import main

ROOT = Path(__file__).resolve().parents[1]
SCENES = ROOT / "data_samples" / "scenes"


def test_run_ball_runup_json_and_recording(tmp_path, capsys):
    out = tmp_path / "r.h5"
    rc = main(["run", str(SCENES / "ball_runup.toml"), "-o", str(out), "--json", "--no-progress"])
    assert rc == 0
    doc = json.loads(capsys.readouterr().out)
    for key in ("method", "rtol", "atol", "n_steps", "n_rejected", "nfev", "wall_time", "status", "message"):
        assert key in doc["solver"]
    assert doc["solver"]["status"] == 0
    # the balancing main motion is reached: ideal model, residual -> 0 (< 2 % of S)
    assert 0 <= doc["residual_unbalance"] < 0.02
    assert len(doc["weights_relative_angle_deg"]) == 2
    # balls at pi +- arccos(e0) from the heavy side, e0 = 0.5 -> +-120 deg
    assert sorted(abs(a) for a in doc["weights_relative_angle_deg"]) == pytest.approx([120, 120], abs=0.1)
    assert doc["whirl_radius_m"] >= 0
    with h5py.File(out, "r") as f:
        expected = {"time": "s", "shaft/x": "m", "shaft/y": "m", "rotor/angle": "rad",
                    "rotor/speed": "rad/s", "weights/ball1/angle": "rad",
                    "weights/ball2/speed": "rad/s"}
        for name, unit in expected.items():
            assert f[name].attrs["units"] == unit
            assert f[name].shape[0] == f["time"].shape[0]
        assert sorted(f["weights"]) == ["ball1", "ball2"]
        assert "ball_runup" in f.attrs["scene"]
        assert json.loads(f.attrs["solver"])["method"] == "DOP853"
        assert f.attrs["version"]
        t = f["time"][:]
        # exact sampling at 200 Hz
        assert np.allclose(np.diff(t), 1 / 200.0, rtol=0, atol=1e-12)


def test_run_bad_scene_exit_code_and_message(tmp_path, capsys):
    bad = tmp_path / "bad.toml"
    bad.write_text((SCENES / "no_balancer.toml").read_text().replace("mass = 4.45", "mass = -4.45"))
    rc = main(["run", str(bad), "-o", str(tmp_path / "x.h5")])
    assert rc == 2
    err = capsys.readouterr().err
    assert "rotor.mass" in err and "-4.45" in err and "kg" in err
    assert not (tmp_path / "x.h5").exists()


def test_run_missing_output_directory(tmp_path, capsys):
    rc = main(["run", str(SCENES / "no_balancer.toml"), "-o", str(tmp_path / "nope" / "x.h5")])
    assert rc == 2
    assert "nope" in capsys.readouterr().err


def test_accuracy_json_closed_form(capsys):
    rc = main(["accuracy", str(SCENES / "no_balancer.toml"), "--json", "--rtols", "1e-6,1e-10"])
    assert rc == 0
    rep = json.loads(capsys.readouterr().out)
    rows = rep["rows"]
    assert [r["rtol"] for r in rows] == [1e-6, 1e-10]
    # tighter tolerance -> smaller error; DOP853 at rtol 1e-10 is within ~1e-8 relative
    assert rows[1]["max_error_m"] < rows[0]["max_error_m"]
    assert rows[1]["relative_error"] < 1e-8
    assert all(r["nfev"] > 0 and r["wall_time_s"] > 0 for r in rows)


def test_console_script_entry_point(tmp_path):
    """The installed ``stand`` program (as in the README) runs."""
    exe = Path(sys.executable).with_name("stand")
    cmd = [str(exe)] if exe.exists() else [sys.executable, "-m", "stand.cli.main"]
    r = subprocess.run(cmd + ["run", str(SCENES / "no_balancer.toml"), "-o", str(tmp_path / "nb.h5")],
                       capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    assert (tmp_path / "nb.h5").exists()


def test_pure_python_fallback_path(tmp_path):
    """STAND_DISABLE_JIT=1 runs the same kernels without numba and agrees."""
    code = (
        "import numpy as np\n"
        "from stand.scene.model import SpeedDrive, RunSettings\n"
        "from stand.scene.parse import scene_from_dimensionless\n"
        "from stand.integrate.simulate import simulate\n"
        "import stand._jit as j\n"
        "assert not j.HAVE_NUMBA\n"
        "sc = scene_from_dimensionless(2, 0.01, 0.5, 0.1, 0.3, drive=SpeedDrive(np.array([[0.0, 3.0]])),"
        " run=RunSettings(5.0, 2.0, 1e-9, 1e-11))\n"
        "tr = simulate(sc)\n"
        "np.save(r'%s', tr.state)\n" % (tmp_path / "py.npy")
    )
    env = dict(os.environ, STAND_DISABLE_JIT="1")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=300)
    assert r.returncode == 0, r.stderr
    from stand.scene.model import RunSettings, SpeedDrive
    from stand.scene.parse import scene_from_dimensionless
    from stand.integrate.simulate import simulate
    sc = scene_from_dimensionless(2, 0.01, 0.5, 0.1, 0.3, drive=SpeedDrive(np.array([[0.0, 3.0]])),
                                  run=RunSettings(5.0, 2.0, 1e-9, 1e-11))
    compiled = simulate(sc).state
    py = np.load(tmp_path / "py.npy")
    # same algorithm, same arithmetic order: identical up to floating-point contraction
    assert np.max(np.abs(py - compiled)) < 1e-9


def test_output_that_is_not_a_regular_file_is_refused_before_the_run(tmp_path, capsys):
    fifo = tmp_path / "pipe.h5"
    os.mkfifo(fifo)
    rc = main(["run", str(SCENES / "no_balancer.toml"), "-o", str(fifo)])
    assert rc == 2
    assert "not a regular file" in capsys.readouterr().err
    assert not fifo.is_file() and fifo.exists()  # still the fifo
    rc = main(["run", str(SCENES / "no_balancer.toml"), "-o", str(tmp_path)])
    assert rc == 2 and "is a directory" in capsys.readouterr().err


@pytest.mark.parametrize("edit, key", [
    (("radius = 0.08 ", "radius = 1e200 "), "balancer.inertia"),
    (("count = 2", "count = 1000000000000"), "balancer.count"),
    (("duration = 40.0 ", "duration = 1e300 "), "run.duration"),
    (("[10.0, 15.0]", "[10.0, 1e200]"), "run.duration"),
    (("atol = 1e-10", "atol = 1e300"), "run.atol"),
    (("mass = 4.45 ", "mass = 1" + "0" * 400 + " "), "rotor.mass"),
])
def test_scenes_out_of_range_give_clear_errors(tmp_path, capsys, edit, key):
    bad = tmp_path / "bad.toml"
    bad.write_text((SCENES / "ball_runup.toml").read_text().replace(*edit, 1))
    rc = main(["run", str(bad), "-o", str(tmp_path / "x.h5")])
    err = capsys.readouterr().err
    assert rc == 2, err
    assert key in err and "Traceback" not in err


@pytest.mark.parametrize("duration, rate", [(0.7, 10.0), (1.1, 10.0), (40.0, 0.33), (3.0, 7.0)])
def test_last_sample_is_never_lost_to_rounding(duration, rate):
    from stand.integrate.simulate import sample_times
    t = sample_times(duration, rate)
    assert len(t) == int(np.floor(duration * rate + 1e-9)) + 1
    assert np.all(np.diff(t) > 0) and t[-1] <= duration
    if abs(duration * rate - round(duration * rate)) < 1e-9:
        assert t[-1] == duration
