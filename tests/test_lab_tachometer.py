"""Tachometer-only run-ups (issue 31, item 2): the rotor angle from the integrated
tachometer speed (held display corrected), the rigid-rotor model fitted with a free phase
constant -- f0, damping and |U| as with a keyphasor, no unbalance angle -- and notes that
say the tachometer was used (not "estimated from the vibration").

The record is the DAQ sample (data_samples/daq/daq_runup.csv, the stand's run-up with
its truth beside it) read with the tachometer and without the keyphasor.
"""
import json
from pathlib import Path

import pytest

from tests.test_lab_tables import run

DAQ = Path(__file__).resolve().parents[1] / "data_samples" / "daq"
TACHO_ONLY = ("time=time_ms[ms],x=disp_x_um[um],y=disp_y_um[um],speed=tacho_rpm[rpm]")


def test_tachometer_only_runup_identifies_the_rotor():
    truth = json.loads((DAQ / "daq_runup.truth.json").read_text())
    code, out, err = run("analyze", DAQ / "daq_runup.csv", "--json", "--columns", TACHO_ONLY,
                         "--map", DAQ / "daq_runup_no_speed.map.toml")
    assert code == 0, err
    doc = json.loads(out)
    assert doc["speed_source"].startswith("tachometer column 'tacho_rpm'")
    assert not doc["runup"]["speed_estimated"]
    notes = " ".join(doc["notes"])
    assert "no keyphasor or encoder" not in notes and "estimated from the vibration" not in notes
    # acceptance: f0 and critical speed within 1 %, |U| within 2 %
    assert doc["natural_frequency_hz"] == pytest.approx(truth["natural_frequency_hz"], rel=0.01)
    assert doc["critical_speed_hz"] == pytest.approx(truth["critical_speed_hz"], rel=0.01)
    assert doc["unbalance_gmm"] == pytest.approx(truth["unbalance_gmm"], rel=0.02)
    assert doc["unbalance_angle_deg"] is None          # a tachometer has no mark
    assert doc["unbalance_method"] == "rigid-rotor model fitted to the run-up"
