"""stand analyze / report: each note says the true reason, each line is labelled by what it is,
one name per JSON quantity and one word per regime (the audit of the samples)."""
import json
import math
import re
from pathlib import Path

import h5py
import numpy as np
import pytest

from stand.cli.main import main

from _helpers import toml_text

ROOT = Path(__file__).resolve().parents[1]
SCENES, DAQ = ROOT / "data_samples" / "scenes", ROOT / "data_samples" / "daq"
RUNUP_COLUMNS = "time=time_ms[ms],x=disp_x_um[um],y=disp_y_um[um],keyphasor=kp_V[V]"


def _out(capsys, *argv):
    assert main([str(a) for a in argv]) == 0
    return capsys.readouterr().out


def _json(capsys, *argv):
    return json.loads(_out(capsys, *argv, "--json"))


def _run(capsys, scene, h5, *extra):
    _out(capsys, "run", scene, "-o", h5, *extra)
    return h5


#: 60 rev/s sampled at 100 Hz, no weights
FAST_BARE = toml_text(scene=dict(name="fast_bare"), rotor=dict(mass=1.0, eccentricity=1.0e-4),
                      supports=dict(stiffness=1.0e4, damping=10.0),
                      drive=dict(type="speed", programme=[[0.0, 60.0], [3.0, 60.0]]),
                      run=dict(duration=3.0, sample_rate=100.0))


def test_a_rotor_faster_than_half_the_sample_rate_says_so(tmp_path, capsys):
    """60 rev/s sampled at 100 Hz: 0.6 revolution per sample, the sampled angle aliases; the
    note says it with the numbers, not 'no scene' nor dsp's 't: too short'."""
    scene = tmp_path / "fast_bare.toml"
    scene.write_text(FAST_BARE)
    doc = _json(capsys, "analyze", _run(capsys, scene, tmp_path / "f.h5"))
    notes = doc["notes"]
    assert "1X: the record samples 100 Hz, below twice the 60 rev/s speed (from 0 s on): no 1X" \
        in notes
    assert doc["speed_hz"] is None and doc["unbalance_gmm"] is None
    assert not any(n.startswith("no scene in the recording") or "too short" in n for n in notes)
    assert any(n.startswith("unbalance: no steady 1X") for n in notes)
    assert "regime: the recording's scene has no weights: there is no regime of weights" in notes
    # the speed programme is the recorded speed's (60 rev/s held), not the aliased angle's
    assert doc["programme"]["kind"] == "constant"


def test_weightless_scene_counts_balls_and_bodies():
    """The one test behind 'the recording's scene has no weights' (precession line, regime):
    known and without balls or body weights; a scene with only a body weight has weights."""
    from stand.analysis.sources import weightless_scene
    from stand.scene.parse import load_scene

    assert weightless_scene(load_scene(SCENES / "no_balancer.toml"))
    assert not weightless_scene(None)
    assert not weightless_scene(load_scene(SCENES / "ball_runup.toml"))
    body = load_scene(SCENES / "body_two_axis_pendulum.toml")
    assert body.n_weights == 0 and body.bodies and not weightless_scene(body)


#: the universal stand's balls passing half the sample rate: 10 rev/s (half of 20 Hz) at 1.905 s
FAST_BALLS = toml_text(
    scene=dict(name="fast_balls"), rotor=dict(mass=4.45, eccentricity=8.0899e-4),
    supports=dict(stiffness=1613.09, damping=8.5577),
    balancer=dict(type="balls", count=2, mass=0.045, radius=0.08, drag=0.16965,
                  initial_angles=[150.0, 210.0]),
    drive=dict(type="speed", programme=[[0.0, 0.0], [4.0, 21.0]]),      # [s, rev/s]
    run=dict(duration=6.0, sample_rate=20.0))


def test_the_regime_is_classified_where_the_record_samples_fast_enough(tmp_path, capsys):
    """Balls on a rotor passing half the sample rate (10 rev/s at 20 Hz, at t = 1.905 s, the
    first sample beyond at 1.95 s): the regime windows end there, the regime at the end of
    the record is not claimed."""
    scene = tmp_path / "fast_balls.toml"
    scene.write_text(FAST_BALLS)
    h5 = tmp_path / "fb.h5"
    _out(capsys, "run", scene, "-o", h5)
    doc = _json(capsys, "analyze", h5)
    assert doc["regime"] is None
    assert any(n.startswith("regime: the record samples 20 Hz, below twice the 21 rev/s speed "
                            "(from 1.95 s on)") and "classified before 1.95 s only" in n
               for n in doc["notes"])
    res = stand_analyze(h5)
    assert res["regime_timeline"] and max(w["t_end_s"] for w in res["regime_timeline"]) < 1.95


def stand_analyze(path):
    import stand

    return stand.analyze(str(path))


def test_a_record_ending_in_a_run_down_says_so(tmp_path, capsys):
    h5 = tmp_path / "rd.h5"
    _out(capsys, "experiment", SCENES / "ball_runup.toml", "run-down", "--speed", "20",
         "--time", "20", "-o", h5)
    notes = _json(capsys, "analyze", h5)["notes"]
    one_x = [n for n in notes if n.startswith("1X: ")]
    assert len(one_x) == 1 and one_x[0].startswith("1X: the record ends in a run-down (")
    assert "holds 1 sample; a steady 1X needs at least 3: no 1X" in one_x[0]
    assert not any("no scene" in n or "too short, 1 samples" in n for n in notes)


def test_a_family_rotor_with_weights_has_its_regime(tmp_path, capsys):
    """family_grinding records weights/ball1|2/angle: the regime is classified.  Its
    unbalance sits in a plane of its own ("unbalance") and the balls in "balancer": the
    static residual is their sum (either plane alone is no residual), tiny at the end against
    the ring of zone 1 of the capacity (S / 16): 'main' (balanced), as the run's summary and
    the sweep say.  (An earlier version read the balls' plane alone, 0.5 S: 'side'.)"""
    h5 = _run(capsys, SCENES / "family_grinding.toml", tmp_path / "g.h5")
    doc = _json(capsys, "analyze", h5)
    with h5py.File(h5) as f:
        U = sum(np.asarray(f[f"truth/residual/{p}"])[-1] for p in f["truth/residual"])
        S = float(f["truth/capacity"][()])
    assert math.hypot(*U) / S < 1e-3 / 16                # balanced: the planes' sum ~ 0
    assert doc["regime"] == "main"
    notes = doc["notes"]
    assert not any("needs the weights' angles" in n or "no scene" in n for n in notes)
    assert any(n.startswith("unbalance: the 1X is turned into an unbalance with the planar "
                            "rotor's model") and "the 'grinding' structure" in n for n in notes)


def test_a_line_of_a_rotor_without_weights_is_no_precession(tmp_path, capsys):
    """influence_reference (a flexible shaft, no weights): its 22.19 Hz line is the free
    whirl at the first critical speed (22.2 Hz, the scene's comment), not a stuck weights'
    precession; no note compares it with f0."""
    h5 = _run(capsys, SCENES / "influence_reference.toml", tmp_path / "i.h5")
    doc = _json(capsys, "analyze", h5)
    assert doc["precession_hz"] is None and doc["nutation_hz"] is None
    assert doc["strongest_other_line_hz"] == pytest.approx(22.2, rel=0.01)
    assert not any("lower bound for f0" in n for n in doc["notes"])
    text = _out(capsys, "analyze", h5)
    assert "Strongest orbit line besides the 1X: 22." in text and "recession" not in text


def test_synchronous_weights_make_no_precession(tmp_path, capsys):
    """ball_friction: the balls turn with the rotor (15 rev/s); the 14.989 Hz line beside the
    1X is no stuck weights' precession and lies nowhere near f0 = 3 Hz: no f0 note."""
    h5 = _run(capsys, SCENES / "ball_friction.toml", tmp_path / "bf.h5")
    doc = _json(capsys, "analyze", h5)
    assert doc["precession_hz"] is None
    assert doc["strongest_other_line_hz"] == pytest.approx(14.989, abs=0.005)
    assert not any("lower bound for f0" in n for n in doc["notes"])
    assert any("is no stuck weights' precession: the weights turn at 15" in n
               and "with the rotor (synchronous)" in n for n in doc["notes"])


def test_the_specific_unbalance_and_its_angle_are_shown_without_a_mass(capsys):
    """daq_runup without the map's mass: the text shows the specific unbalance e [g mm / kg]
    and the angle the JSON holds (truth 40 g mm/kg at 30 deg)."""
    import stand
    from stand.cli.analysis import _analysis_lines      # the text `stand analyze` prints

    # (one analysis, its JSON form and its text: the CLI prints _analysis_lines of it)
    doc = stand.analyze(DAQ / "daq_runup.csv", columns=RUNUP_COLUMNS).to_dict()
    text = "\n".join(_analysis_lines(doc))
    e = re.search(r"Specific unbalance e: ([\d.]+) ± ([\d.]+) g·mm/kg", text)
    a = re.search(r"Unbalance angle \(from the mark\): ([\d.]+) ± ([\d.]+)", text)
    assert e and a, text
    assert float(e[1]) == pytest.approx(doc["specific_unbalance_gmm_per_kg"], abs=float(e[2]))
    assert float(a[1]) == pytest.approx(doc["unbalance_angle_deg"], abs=float(a[2]))
    truth = json.loads((DAQ / "daq_runup.truth.json").read_text())
    assert abs(float(e[1]) - truth["specific_unbalance_um"]) < 5 * float(e[2]) + 0.01
    assert abs(float(a[1]) - truth["unbalance_angle_deg"]) < 5 * float(a[2]) + 0.01


def test_one_name_for_the_achieved_and_the_required_grade(tmp_path, capsys):
    """daq_lab: analyze's iso_grade and the report's iso_21940_11 name the grade the rotor
    achieves achieved_grade_mm_s and the one required required_grade_mm_s, the same values."""
    csv, m = DAQ / "daq_lab.csv", DAQ / "daq_lab.map.toml"
    r = _json(capsys, "report", csv, "--map", m, "--grade", "6.3")
    a = r["analysis"]["iso_grade"]      # analyze's iso_grade, as the report embeds it
    iso = r["balancing_quality"]["iso_21940_11"]
    # the old keys, kept with their old meanings (docs/results.md)
    assert a["grade_mm_s"] == a["achieved_grade_mm_s"] and a["target_mm_s"] == 6.3
    assert iso["grade_mm_s"] == 6.3
    assert a["required_grade_mm_s"] == iso["required_grade_mm_s"] == 6.3
    assert iso["achieved_grade_mm_s"] == a["achieved_grade_mm_s"] != 6.3


def test_analyze_and_report_say_the_same_regime(tmp_path, capsys):
    """ball_runup ends with the balls balancing the rotor: 'balanced' in both."""
    from stand.io.labels import REGIME_NAMES

    h5 = _run(capsys, SCENES / "ball_runup.toml", tmp_path / "b.h5")
    doc = _json(capsys, "analyze", h5)
    assert doc["regime"] == "main"                   # dsp.regime's name in the JSON
    text = _out(capsys, "analyze", h5)
    rep = _json(capsys, "report", h5)
    assert rep["dynamics"]["final_regime"] == REGIME_NAMES["main"] == "balanced"
    assert "  Regime: balanced\n" in text and "main" not in text


def _track(path, t, nan_rows=()):
    x = 1e-4 * np.cos(2 * np.pi * 3.0 * t)
    y = 1e-4 * np.sin(2 * np.pi * 3.0 * t)
    x[list(nan_rows)] = np.nan
    y[list(nan_rows)] = np.nan
    rows = ["t_s,x_m,y_m"] + [",".join("" if math.isnan(v) else f"{v:.9g}" for v in r)
                              for r in zip(t, x, y)]
    path.write_text("\n".join(rows) + "\n")
    return path


def test_empty_rows_are_no_time_gap(tmp_path, capsys):
    """Frames without a spot (x, y empty) on a regular time base: 'empty or NaN', no gap in
    time; a real gap in t_s is still one."""
    t = np.arange(200) * 0.01
    doc = _json(capsys, "analyze", _track(tmp_path / "a.csv", t, nan_rows=range(3, 10)))
    ex = [n for n in doc["notes"] if n.startswith("excluded rows")]
    assert "excluded rows 4-10: column 'x_m': empty or NaN" in ex
    assert not any("gap" in n for n in ex)
    t_gap = np.delete(t, range(3, 10))
    doc = _json(capsys, "analyze", _track(tmp_path / "b.csv", t_gap))
    assert any("column 't_s': gap of 0.08 s" in n for n in doc["notes"])


def test_a_continuous_encoder_column_is_not_folded():
    """An angle column already continuous with 7.5 revolutions per sample (a camera's frames
    at 2 Hz on a 15 rev/s rotor): its speed is 15 rev/s, not an alias."""
    from dsp.speed_channels import angle_from_encoder

    t = np.arange(40) * 0.5
    ra = angle_from_encoder(t, 2 * np.pi * 15.0 * t)
    assert np.allclose(ra.speed_rad_s, 2 * np.pi * 15.0, rtol=1e-12)
    wrapped = angle_from_encoder(t[:8] * 0.01, np.mod(2 * np.pi * 15.0 * t[:8] * 0.01, 2 * np.pi))
    assert np.allclose(wrapped.speed_rad_s, 2 * np.pi * 15.0, rtol=1e-9)   # still unwrapped


def test_a_lab_orbit_keeps_its_precession_and_nutation(tmp_path, capsys):
    """A lab record has no weights' angles: the orbit is all there is, so its quasi-periodic
    lines are identified as the precession and nutation (dsp.quasiperiodic), as before the
    stuck-weights check -- that check applies only where the weights' angles are recorded
    or the recording's scene has no weights.  Orbit of the ball_stuck kind: precession at
    0.96135 f1 (Table 5.1-B, f1 = 3 Hz), nutation at the rotor speed 9 Hz, noise 1 um."""
    import pandas as pd

    t = np.arange(0.0, 20.0, 1e-3)
    fP, fN = 0.96135 * 3.0, 9.0
    rng = np.random.default_rng(5)
    z = (1e-4 * np.exp(2j * np.pi * fP * t) + 3e-5 * np.exp(1j * (2 * np.pi * fN * t + 0.4))
         + 1e-6 * (rng.standard_normal(t.size) + 1j * rng.standard_normal(t.size)))
    p = tmp_path / "lab_orbit.csv"
    pd.DataFrame({"t_s": t, "x_m": z.real, "y_m": z.imag,
                  "rotor_angle_rad": 2 * np.pi * fN * t}).to_csv(p, index=False)
    doc = _json(capsys, "analyze", p)
    assert doc["precession_hz"] == pytest.approx(fP, rel=1e-4)
    assert doc["nutation_hz"] == pytest.approx(fN, rel=1e-4)
    assert doc["precession_amplitude_m"] == pytest.approx(1e-4, rel=0.02)


def test_a_slow_stretch_after_an_aliased_one_keeps_its_1x(tmp_path, capsys):
    """Sampled at 200 Hz, a rotor first at 150 rev/s (aliased: above 100 Hz), then held at
    10 rev/s for 20 s: the steady stretch at the end is properly sampled and gives its 1X
    (amplitude 50 um), not the 'no 1X' of the aliased start."""
    import pandas as pd

    fs = 200.0
    t = np.arange(0.0, 30.0, 1.0 / fs)
    f = np.where(t < 5.0, 150.0, np.where(t < 10.0, 150.0 - 28.0 * (t - 5.0), 10.0))
    phi = 2 * np.pi * np.cumsum(f) / fs
    z = 5e-5 * np.exp(1j * (phi + 0.3))
    p = tmp_path / "slow_after_fast.csv"
    pd.DataFrame({"t_s": t, "x_m": z.real, "y_m": z.imag, "rotor_angle_rad": phi}).to_csv(
        p, index=False)
    doc = _json(capsys, "analyze", p)
    assert doc["speed_hz"] == pytest.approx(10.0, rel=1e-3)
    assert doc["response_1x_m"] == pytest.approx(5e-5, rel=1e-3)
    assert not any(n.startswith("1X:") and "no 1X" in n for n in doc["notes"])


def test_a_trace_of_unresolved_circles_states_its_bound(tmp_path):
    """A `stand track --trace` CSV whose circles are all unresolved (radius below 3 spot
    sigmas: a balanced rotor's still spot) gives no unbalance, and says the upper bound its
    frames read (the largest of ``unbalance_max_gmm``), not nothing."""
    import stand

    rows = "\n".join(f"{k},{8 + 0.5 * k},0.001,-0.002,3.0,2.0,unresolved,,,True,{210.0 + k}"
                     for k in range(6))
    p = tmp_path / "trace.csv"
    p.write_text("# ring_radii_m = 0.0,0.001,0.002,0.003\n# capacity_gmm = 7200.0\n"
                 "frame,time,x_mm,y_mm,radius_px,spot_sigma_px,flags,radius_mm,radius_std_mm,ok,"
                 "unbalance_max_gmm\n" + rows + "\n")
    a = stand.analyze(str(p)).to_dict()
    assert a.get("unbalance_gmm") is None
    assert any("below 215 g·mm" in n for n in a["notes"]), a["notes"]



def test_a_lab_line_within_the_resolution_of_the_1x_is_no_precession(tmp_path, capsys):
    """The video sample's orbit (its exposure-averaged truth through the camera's gain: the
    universal stand balancing itself at 12 rev/s, no speed channel) over its steady stretch of
    2.48 s (1/T = 0.40 Hz) holds a line at 11.94 Hz beside the 1X at 12.003 Hz: the 1X still
    changing, not resolved from it -- no precession or nutation (it had been printed as the
    stuck weights' precession with a nutation at 11.97 Hz), the line kept as the strongest
    other line with a note.  (A lab orbit with a precession at 0.32 of the rotor speed keeps
    both: test_a_lab_orbit_keeps_its_precession_and_nutation.)"""
    import pandas as pd

    video = Path(__file__).resolve().parents[1] / "data_samples" / "video"
    tr = pd.read_csv(video / "screen_truth.csv", comment="#")
    gain, pitch, exposure = 6.0, 1e-4, 0.016          # the sample's camera (its preamble)
    p = tmp_path / "orbit.csv"
    pd.DataFrame({"t_s": tr["time_s"] + exposure / 2,
                  "x_m": (tr["u_px"] - 127.5) * pitch / gain,
                  "y_m": -(tr["v_px"] - 127.5) * pitch / gain}).to_csv(p, index=False)
    doc = _json(capsys, "analyze", p)
    T = doc["stationary_stretch"]["duration_s"]
    assert doc["precession_hz"] is None and doc["nutation_hz"] is None
    assert abs(doc["strongest_other_line_hz"] - doc["speed_hz"]) < 1 / T
    assert any("resolution 1/T" in n for n in doc["notes"]), doc["notes"]
