"""stand analyze: recordings (HDF5 or CSV) in, journal numbers out, scored against the truth."""
import json
import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from stand.cli.main import main

SCENES = Path(__file__).resolve().parents[1] / "data_samples" / "scenes"
KEYS = ("natural_frequency_hz", "damping_ratio", "unbalance_gmm", "unbalance_angle_deg", "iso_grade",
        "components", "precession_hz", "nutation_hz", "petals", "shape", "critical_speeds_hz", "regime")


def _json(capsys, *argv):
    assert main(list(argv)) == 0
    return json.loads(capsys.readouterr().out)


def test_unbalance_of_the_rotor_without_balancer_at_supercritical_speed(tmp_path, capsys):
    out = tmp_path / "nb.h5"
    assert main(["experiment", str(SCENES / "no_balancer.toml"), "constant", "--speed", "15",
                 "--duration", "30", "-o", str(out)]) == 0
    capsys.readouterr()
    doc = _json(capsys, "analyze", str(out), "--json", "--grade", "6.3", "--service-speed", "900")
    assert set(KEYS) <= set(doc)
    # truth: M e = 4.45 kg * 0.80899 mm = 3600 g mm at the reference mark
    assert doc["unbalance_gmm"] == pytest.approx(3600.0, rel=0.01)
    assert abs(doc["unbalance_angle_deg"]) < 0.5
    g = doc["iso_grade"]
    # G = U Omega / (1000 m) = 3600 * 94.25 / 4450 = 76 mm/s -> class G 100, fails G 6.3
    assert g["achieved_grade_mm_s"] == pytest.approx(3600 * 900 * 2 * math.pi / 60 / 1000 / 4.45, rel=0.01)
    assert g["passed"] is False


def test_natural_frequency_of_the_free_decay(tmp_path, capsys):
    out = tmp_path / "nf.h5"
    assert main(["run", str(SCENES / "natural_frequency.toml"), "-o", str(out)]) == 0
    capsys.readouterr()
    doc = _json(capsys, "analyze", str(out), "--json")
    f0 = math.sqrt(1613.09 / 4.54) / (2 * math.pi)
    assert doc["natural_frequency_hz"] == pytest.approx(f0, rel=1e-3)
    assert doc["damping_ratio"] == pytest.approx(8.5577 / (2 * math.sqrt(1613.09 * 4.54)), rel=1e-2)


def test_stuck_balls_components(tmp_path, capsys):
    out = tmp_path / "st.h5"
    assert main(["run", str(SCENES / "ball_stuck.toml"), "-o", str(out)]) == 0
    capsys.readouterr()
    doc = _json(capsys, "analyze", str(out), "--json")
    f1 = 3.0  # ball_stuck: natural_frequency = 3 Hz, R_omega = 3
    assert doc["nutation_hz"] == pytest.approx(3 * f1, rel=5e-4)
    assert doc["precession_hz"] == pytest.approx(0.96135 * f1, rel=5e-4)  # Table 5.1-B
    # (5.181) Omega_1 < omega_1: 3.9 % below the scene's f1, so the f0 note applies
    assert "the stuck weights' precession 2.88407 Hz lies 3.9 % below the natural frequency 3 Hz " \
           "(the scene's): Omega_1 < omega_1 (5.181), a lower bound for f0, not f0" in doc["notes"]
    assert doc["petals"] == 2 and doc["shape"] == "curtate"
    assert doc["regime"] == "quasi-periodic"


def test_csv_input_and_errors(tmp_path, capsys):
    t = np.arange(0, 10, 1e-3)
    w = 2 * np.pi * 10.0
    z = 1e-4 * np.exp(1j * (w * t + 0.3))
    pd.DataFrame({"t_s": t, "x_m": z.real, "y_m": z.imag, "rotor_angle_rad": w * t}).to_csv(
        tmp_path / "r.csv", index=False)
    doc = _json(capsys, "analyze", str(tmp_path / "r.csv"), "--json")
    assert doc["speed_hz"] == pytest.approx(10.0, rel=1e-9)
    assert doc["unbalance_gmm"] is None and any("scene" in n for n in doc["notes"])
    pd.DataFrame({"t_s": t, "x_m": z.real}).to_csv(tmp_path / "bad.csv", index=False)
    assert main(["analyze", str(tmp_path / "bad.csv")]) == 2
    assert "y_m" in capsys.readouterr().err
    assert main(["analyze", str(tmp_path / "missing.h5")]) == 2
