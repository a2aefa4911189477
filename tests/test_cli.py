"""The ``stand`` command line: the README's main job and input errors."""
import json
import os
import re
import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np
import pytest

from stand.cli.main import main

ROOT = Path(__file__).resolve().parents[1]
SCENES = ROOT / "data_samples" / "scenes"


@pytest.fixture(scope="module", autouse=True)
def _analysis_computed_once():
    """The identification of a recording (stand.analysis.identify.analyze, seconds for the lab
    run-up) computed once per (recording, arguments) in this module and a deep copy handed to
    each caller: ``stand analyze``, ``analyze --json`` and ``stand report`` of one recording
    each check their own printing and serialisation of the same numbers (the analysis itself:
    test_lab_daq.py, test_report_chain.py).  Its callers import it at call time."""
    import copy

    from stand.analysis import identify

    cache = {}
    original = identify.analyze

    def once(*args, **kwargs):
        key = repr((args, sorted(kwargs.items())))
        if key not in cache:
            cache[key] = original(*args, **kwargs)
        return copy.deepcopy(cache[key])

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(identify, "analyze", once)
        yield cache


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


# ---------------------------------------------------------------- what the commands print (issue 40)
DAQ = ROOT / "data_samples" / "daq"
CAMERAS = ROOT / "data_samples" / "recordings" / "stand_cameras.h5"


def _nothing_without_a_meaning(text: str) -> None:
    """No Python None, no "+-" beside "±", no float noise as a ± (``8.9e-15``)."""
    assert "None" not in text and "+-" not in text and "warning(s)" not in text, text
    assert not re.search(r"\de-1\d", text), text


def test_numbers_resolved_and_round_off():
    """One formatter: a ± below 1e-9 of the value is round-off (not shown); a value below its
    rounded ± is "below resolution", and :func:`resolved` says so too (the CLI then shows no
    angle for it)."""
    from stand.io.numbers import resolved, with_uncertainty

    assert with_uncertainty(12.0, 8.9e-15, "rev/s") == "12 rev/s"
    assert with_uncertainty(0.03, 0.033, "g·mm").startswith("below resolution")
    assert not resolved(0.03, 0.033) and not resolved(None, 1.0)
    assert resolved(0.034, 0.033) and resolved(240.0, 0.88) and resolved(12.0, None)
    # the edge: u rounds to 2 digits (0.0335 -> 0.034), as the text shows it
    assert not resolved(0.0339, 0.0335)
    assert with_uncertainty(0.0339, 0.0335).startswith("below resolution")


@pytest.fixture(scope="module")
def lab_runup(tmp_path_factory):
    """(CSV, map) of a short lab run-up and hold: the exact rigid rotor of
    tests/_rotor_reference.py (f0 12 Hz, 240 g·mm on 6 kg), 4 -> 24 rev/s in 8 s then 2 s at
    24 rev/s, 250 samples/s (2 500 rows), 2 µm probe noise, a keyphasor; at 1560 rpm it fails
    G6.3.  What the commands print is checked on it; the DAQ sample's own analysis (30 000
    rows, 6 s of CPU) in test_lab_daq.py."""
    from tests._rotor_reference import runup

    d, _ = runup(fs=250.0, t_ramp=8.0, t_hold=2.0)
    rng = np.random.default_rng(3)
    z = d["z"] + 2e-6 * (rng.standard_normal(d["t"].size) + 1j * rng.standard_normal(d["t"].size))
    kp = np.where(np.mod(d["phi"], 2 * np.pi) < 1.5, 5.0, 0.0)     # 1.5 rad: >= 2 samples
    tmp = tmp_path_factory.mktemp("lab_runup")
    np.savetxt(tmp / "runup.csv", np.column_stack((d["t"], z.real * 1e6, z.imag * 1e6, kp)),
               delimiter=",", fmt="%.12g", header="time_s,x_um,y_um,kp_V", comments="")
    (tmp / "runup.map.toml").write_text(
        '[columns]\ntime = "time_s [s]"\nx = "x_um [um]"\ny = "y_um [um]"\nkeyphasor = "kp_V [V]"\n'
        '\n[rotor]\nmass = "6 kg"\nservice_speed = "1560 rpm"\n')
    return tmp / "runup.csv", tmp / "runup.map.toml"


def test_analyze_prints_labels_units_and_the_json_numbers(capsys, lab_runup):
    """``stand analyze`` of a lab run-up prints each value by its label (stand.io.labels) in
    the label's unit, rounded to its ±: the 1X in µm equals the JSON's metres x 1e6 to half
    the last digit shown (GUM 7.2.6 rounding), and nothing the analysis did not give."""
    from stand.io.labels import label

    args = ["analyze", str(lab_runup[0]), "--map", str(lab_runup[1])]
    assert main(args + ["--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert main(args) == 0
    out = capsys.readouterr().out
    _nothing_without_a_meaning(out)
    m = re.search(re.escape(label("response_1x_m")) + r": (\d+\.(\d+)) ± (\d+\.\d+) µm", out)
    assert m, out
    half_digit = 0.5 * 10.0 ** -len(m.group(2))
    assert float(m.group(1)) == pytest.approx(doc["response_1x_m"] * 1e6, abs=half_digit)
    assert float(m.group(3)) == pytest.approx(doc["response_1x_m_std"] * 1e6, abs=half_digit)
    assert f"{label('unbalance_gmm')}: " in out and " g·mm" in out
    assert label("unbalance_angle_deg") in out       # resolved: 240 ± 0.9 g·mm
    assert doc["petals"] is None and label("petals") not in out   # not given: not printed


def test_analyze_shows_no_angle_of_an_unbalance_below_resolution(capsys):
    """The simulator's balanced run: the unbalance is below its numerical ±, so its angle
    (and the vibration velocity of that 1X) are not printed; the regime changes carry a ±
    only where it is above round-off."""
    from stand.io.labels import label

    assert main(["analyze", str(CAMERAS), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["unbalance_gmm"] < doc["unbalance_gmm_std"]
    assert main(["analyze", str(CAMERAS)]) == 0
    out = capsys.readouterr().out
    _nothing_without_a_meaning(out)
    assert f"{label('unbalance_gmm')}: below resolution" in out
    assert label("unbalance_angle_deg") not in out and " deg" not in out
    changes = re.findall(label("regime_change") + r": \w+ -> \w+ at ([^\n]+)", out)
    assert len(changes) == len(doc["critical_speeds_hz"]) > 0


def test_report_names_its_warnings(tmp_path, capsys, lab_runup):
    """``stand report`` says which warnings it gave (each message, as in the JSON), not
    "1 warning(s)"."""
    js = tmp_path / "r.json"
    assert main(["report", str(lab_runup[0]), "--map", str(lab_runup[1]),
                 "-o", str(tmp_path / "r.html"), "--json-file", str(js)]) == 0
    cap = capsys.readouterr()
    warnings = json.loads(js.read_text())["warnings"]
    assert warnings, "the run-up fails G6.3: a warning expected"
    for w in warnings:
        assert f"stand report: warning: {w['message']}" in cap.err
    n = len(warnings)
    assert f"; {n} warning{'s' if n != 1 else ''} (above)" in cap.out
    _nothing_without_a_meaning(cap.out + cap.err)


def test_snapshot_of_a_frame_without_the_spot_says_so(tmp_path, capsys):
    """stand_cameras.h5's frames 4-8 show no spot (the brightest pixel is noise): the
    snapshot warns naming the frame and why; a frame with the whole spot gives no warning,
    one whose spot runs past the border (simulator truth, frames 9-10) says so."""
    import cv2

    out = tmp_path / "f.png"
    assert main(["snapshot", str(CAMERAS), "--frame", "5", "-o", str(out)]) == 0
    err = capsys.readouterr().err
    img = cv2.imread(str(out), cv2.IMREAD_UNCHANGED)
    assert int(img.max()) - float(np.median(img)) < 20       # black: noise only (DN)
    assert "stand snapshot: warning: frame 5 " in err and "off the screen" in err
    assert main(["snapshot", str(CAMERAS), "--frame", "12", "-o", str(out)]) == 0
    img = cv2.imread(str(out), cv2.IMREAD_UNCHANGED)
    assert int(img.max()) - float(np.median(img)) > 50       # the spot (DN above background)
    assert "warning" not in capsys.readouterr().err
    # a warning exactly where the simulator's truth has the spot's path leave the image
    with h5py.File(CAMERAS) as f:
        inside = f["truth/screen/in_frame"][:]
    for k in (3, 4, 9, 10, 11):
        assert main(["snapshot", str(CAMERAS), "--frame", str(k), "-o", str(out)]) == 0
        warned = f"stand snapshot: warning: frame {k} " in capsys.readouterr().err
        assert warned == (not inside[k]), k


def test_balance_prints_an_exact_cancellation_as_zero(capsys):
    """Two planes, two readings: the corrections cancel the readings exactly, so the predicted
    residual is round-off (~1e-14 mm/s) and printed as 0, not as a number; the ± in
    the text are the JSON's, by the one formatter."""
    from stand.io.numbers import with_uncertainty

    job = str(ROOT / "data_samples" / "balance" / "bk_17_227.toml")
    assert main(["balance", job, "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert all(abs(r["after"]) < 1e-9 * abs(r["before"]) for r in doc["residuals"])
    assert main(["balance", job]) == 0
    out = capsys.readouterr().out
    _nothing_without_a_meaning(out)
    assert out.count(f"-> 0 {doc['vibration_unit']}") == len(doc["residuals"]) == 2
    c = doc["corrections"]["P1"]
    assert f"P1: {with_uncertainty(c['mass'], c['mass_std'], doc['mass_unit'])} @ " in out
