"""Every sensor quantity (issue 31, item 1): accelerometers (g, keyphasor) and velocity
pickups (mm/s, tachometer only) through ``stand analyze --map``, against an independent
reference (scipy solve_ivp of the rigid rotor's equation, tests/_rotor_reference.py),
not the stand's simulator.

Acceptance: f0 within 0.5 %, zeta within 5 %, |U| within 2 %, critical speed within 1 %;
the same accelerometer table as .xlsx, .mat and .tdms gives the numbers of its CSV.
Noise: 2 % of each channel's RMS, white (the fit's residual; its effect on f0 and zeta
is ~1e-4, far inside the tolerances).
"""
import json
import math

import numpy as np
import pandas as pd
import pytest

from stand.lab.recording_map import MapError, parse_columns
from tests._rotor_reference import TWO_PI, runup
from tests.test_lab_tables import run

G_N = 9.80665


@pytest.fixture(scope="module")
def reference():
    """4 -> 24 rev/s in 12 s, 3 s at 24 rev/s, 250 samples/s (3750 samples, 10 per
    revolution at the top; 6000 at 400 samples/s, 29 000 at 1 kHz over 24 + 5 s before):
    the accelerometer run-up's f0 within 0.07 %, zeta 0.5 %, |U| 0.11 %, its angle 0.08 deg,
    the 1X 0.09 % (400 samples/s: 0.05 %, 0.5 %, 0.11 %, 1.0 deg, 0.04 %; 1 kHz: 0.02 %,
    0.2 %, 0.08 %), the velocity run-up's 0.09 %, 0.2 %, 0.17 %: noise-limited, 6 x or more
    inside the acceptance, for a third of the CPU at 400; the hold is 9 decay times
    (1 / zeta w0 = 0.33 s) long, the 1X at 24 rev/s steady."""
    return runup(fs=250.0, t_ramp=12.0, t_hold=3.0)


def _noisy(z, rng, share=0.02):
    s = share * np.std(z)
    return z + s * (rng.standard_normal(z.size) + 1j * rng.standard_normal(z.size))


def _accelerometer_frame(ref):
    d, _ = ref
    rng = np.random.default_rng(7)
    a = _noisy(d["acc"], rng) / G_N
    kp = np.where(np.mod(d["phi"], TWO_PI) < 1.5, 5.0, 0.0)     # 1.5 rad: 2 samples at 24 rev/s
    return pd.DataFrame({"time_s": d["t"], "acc_x_g": a.real, "acc_y_g": a.imag, "kp_V": kp})


def _velocity_frame(ref):
    d, _ = ref
    rng = np.random.default_rng(8)
    v = _noisy(d["v"], rng) * 1e3
    # a tachometer display updated every 0.1 s with the mean speed of the gate before
    t, gate = d["t"], 0.1
    k = np.floor(t / gate).astype(int)
    rev = d["phi"] / TWO_PI
    edges = np.arange(k.max() + 2) * gate
    rev_at = np.interp(edges, t, rev)
    mean_rps = np.diff(rev_at) / gate
    rpm = np.where(k >= 1, mean_rps[np.maximum(k - 1, 0)], mean_rps[0]) * 60.0
    return pd.DataFrame({"time_s": t, "vel_x_mm_s": v.real, "vel_y_mm_s": v.imag, "tacho": rpm})


ACC_MAP = """
[columns]
time = "time_s [s]"
x = "acc_x_g [g]"
y = "acc_y_g [g]"
keyphasor = "kp_V [V]"
[rotor]
mass = "6 kg"
"""
VEL_MAP = """
[columns]
time = "time_s [s]"
x = "vel_x_mm_s [mm/s pk]"
y = "vel_y_mm_s [mm/s pk]"
speed = "tacho [rpm]"
[rotor]
mass = "6 kg"
"""


def _analyze(path, map_path):
    code, out, err = run("analyze", path, "--json", "--map", map_path)
    assert code == 0, err
    return json.loads(out)


def _check(doc, truth, angle=True):
    assert doc["natural_frequency_hz"] == pytest.approx(truth["f0_hz"], rel=0.005)
    assert doc["damping_ratio"] == pytest.approx(truth["zeta"], rel=0.05)
    assert doc["unbalance_gmm"] == pytest.approx(truth["e_m"] * truth["mass_kg"] * 1e6, rel=0.02)
    assert doc["critical_speed_hz"] == pytest.approx(truth["critical_hz"], rel=0.01)
    if angle:
        assert doc["unbalance_angle_deg"] == pytest.approx(math.degrees(truth["beta_rad"]), abs=2.0)


def _steady_displacement(truth, f):
    r = f / truth["f0_hz"]
    return truth["e_m"] * r * r / abs(1 - r * r + 2j * truth["zeta"] * r)


@pytest.fixture(scope="module")
def acc_csv(tmp_path_factory, reference):
    tmp = tmp_path_factory.mktemp("acc")
    p = tmp / "acc.csv"
    _accelerometer_frame(reference).to_csv(p, index=False, float_format="%.12g")
    (tmp / "acc.map.toml").write_text(ACC_MAP)
    return p, tmp / "acc.map.toml", _analyze(p, tmp / "acc.map.toml")


def test_accelerometer_runup_with_keyphasor(acc_csv, reference):
    _, truth = reference
    doc = acc_csv[2]
    _check(doc, truth)
    assert doc["input"]["vibration_quantity"] == "acceleration"
    vib = doc["vibration_1x"]
    disp = _steady_displacement(truth, 24.0)
    assert doc["response_1x_m"] == pytest.approx(disp, rel=0.01)      # reported as displacement
    w = TWO_PI * 24.0
    assert vib["unit"] == "g" and vib["peak"] == pytest.approx(disp * w * w / G_N, rel=0.01)
    assert vib["velocity_rms_mm_s"] == pytest.approx(disp * w / math.sqrt(2) * 1e3, rel=0.01)
    assert any("bearing housings" in n for n in doc["notes"])


def test_velocity_runup_tachometer_only(tmp_path, reference):
    _, truth = reference
    p = tmp_path / "vel.csv"
    _velocity_frame(reference).to_csv(p, index=False, float_format="%.12g")
    (tmp_path / "vel.map.toml").write_text(VEL_MAP)
    doc = _analyze(p, tmp_path / "vel.map.toml")
    assert doc["speed_source"].startswith("tachometer")
    _check(doc, truth, angle=False)
    assert doc["vibration_1x"]["quantity"] == "velocity"


def _analysis_input(path, map_path):
    """What ``stand analyze PATH --map MAP`` hands to the identification
    (stand.analysis.sources.read_source): the arrays, the rotor angle, what was read."""
    from stand.analysis.sources import read_source
    from stand.lab.recording_map import read_map

    d = read_source(path, read_map(map_path))
    tab, angle = d["table"], d["angle"]
    arrays = dict(t=d["t"], x=d["x"], y=d["y"], phi=d["phi"], speed=angle.speed_rad_s,
                  acceleration=angle.acceleration_rad_s2,
                  **{f"signal_{k}": v for k, v in tab.signals.items()})
    said = dict(quantity=d["quantity"], speed_how=d["speed_how"], notes=d["notes"],
                censored=d["censored"], channel_filter=d["channel_filter"], rows=tab.rows,
                excluded=tab.excluded, columns=sorted(tab.columns),
                units={k: (c.quantity(), c.si_factor(k)) for k, c in tab.columns.items()})
    return arrays, said


@pytest.mark.parametrize("fmt", ["xlsx", "mat", "tdms"])
def test_accelerometer_table_in_other_formats(acc_csv, reference, tmp_path, fmt):
    """The same table as .xlsx, .mat or .tdms gives the numbers of its CSV: ``stand analyze``
    reads each into exactly the arrays (times, SI channels, the keyphasor's rotor angle, its
    speed and acceleration) and the notes of the CSV (every number the CSV's analysis
    reports, checked against the reference in test_accelerometer_runup_with_keyphasor, is a
    deterministic function of them; the identification is not run again per format)."""
    csv_path, map_path, ref_doc = acc_csv
    df = pd.read_csv(csv_path)
    p = tmp_path / f"acc.{fmt}"
    if fmt == "xlsx":
        pytest.importorskip("openpyxl", reason="Excel is read through openpyxl (optional)")
        df.to_excel(p, index=False)
    elif fmt == "mat":
        import scipy.io

        scipy.io.savemat(p, {c: df[c].to_numpy() for c in df.columns})
    else:
        nptdms = pytest.importorskip("nptdms", reason="TDMS is read through npTDMS (optional)")
        with nptdms.TdmsWriter(p) as w:
            w.write_segment([nptdms.ChannelObject("daq", c, df[c].to_numpy()) for c in df.columns])
    arrays, said = _analysis_input(p, map_path)
    ref_arrays, ref_said = _analysis_input(csv_path, map_path)
    if fmt == "tdms":       # a TDMS channel is named with its group
        said["speed_how"] = said["speed_how"].replace("'daq/kp_V'", "'kp_V'")
    assert said == ref_said
    assert sorted(arrays) == sorted(ref_arrays) and arrays["phi"] is not None
    assert arrays["signal_x"].size == len(df)     # every row read (the angle's: between pulses)
    for key, ref in ref_arrays.items():      # float64 written and read exactly in every format
        np.testing.assert_array_equal(arrays[key], ref, err_msg=key)


# ------------------------------------------------------------------ units and refusals
@pytest.mark.parametrize("spec, quantity, factor", [
    ("x=a[g]", "acceleration", G_N), ("x=a[m/s²]", "acceleration", 1.0),
    ("x=v[mm/s]", "velocity", 1e-3), ("x=v[in/s rms]", "velocity", 25.4e-3),
    ("x=d[um pk-pk]", "length", 1e-6),
    ("x=a[mV, 100 mV/g]", "acceleration", 1e-3 / 0.1 * G_N),
    ("x=v[V, 4 mV/(mm/s)]", "velocity", 1.0 / 4.0),     # 4 mV/(mm/s) = 4 V/(m/s)
    ("x=d[V, 7.87 V/mm]", "length", 1e-3 / 7.87),
])
def test_units_of_every_quantity(spec, quantity, factor):
    c = parse_columns(spec).columns["x"]
    assert c.quantity() == quantity
    assert c.si_factor("x") == pytest.approx(factor, rel=1e-12)


def _refused(*argv):
    code, out, err = run(*argv)
    assert code == 2, (code, err)
    lines = [ln for ln in err.strip().splitlines() if ln.strip()]
    assert len(lines) == 1, err
    return lines[0]


@pytest.mark.parametrize("columns, says", [
    ("time=time_s[s],x=acc_x_g[rpm],y=acc_y_g[g]", ["'rpm' is a speed unit", "acc_x_g"]),
    ("time=time_s[s],x=acc_x_g[g],y=acc_y_g[um]", ["acceleration", "same quantity"]),
    ("time=time_s[s],x=acc_x_g[mV],y=acc_y_g[mV]", ["sensitivity", "mV/g"]),
    ("time=time_s[s],x=acc_x_g[g]", ["no y displacement column"]),
], ids=["wrong quantity", "mixed quantities", "volts without sensitivity", "missing role"])
def test_bad_sensor_columns_are_refused(tmp_path, reference, columns, says):
    """A unit of the wrong quantity, x and y of different quantities, volts without a
    sensitivity, a missing role: one line naming what is wrong, exit 2."""
    p = tmp_path / "acc.csv"
    _accelerometer_frame(reference).iloc[:2000].to_csv(p, index=False)
    line = _refused("analyze", p, "--columns", columns)
    assert all(w in line for w in says), line


def test_bad_sensitivity_is_a_map_error():
    with pytest.raises(MapError, match="sensitivity"):
        parse_columns("x=a[V, 100 mV/furlong]").columns["x"].si_factor("x")
