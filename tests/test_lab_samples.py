"""The samples of issue 31 (item 5), written by the stand with the truth beside them:
data_samples/daq/acc_runup.csv (the daq_runup run-up measured by accelerometers in g,
with the keyphasor; ``stand daq --quantity acceleration``) and data_samples/daq/
bode_table.csv (the steady 1X table of the slow run-up bode_runup.toml, ``stand daq
--bode``), analysed by the README's commands.  Acceptance tolerances: f0 0.5 %, zeta 5 %,
|U| 2 %, critical speed 1 %.
"""
import json
from pathlib import Path

import pytest

from tests.test_lab_tables import run

DAQ = Path(__file__).resolve().parents[1] / "data_samples" / "daq"


@pytest.mark.parametrize("name", ["acc_runup", "bode_table"])
def test_sample_gives_its_truth(name):
    truth = json.loads((DAQ / f"{name}.truth.json").read_text())
    code, out, err = run("analyze", DAQ / f"{name}.csv", "--json", "--map", DAQ / f"{name}.map.toml")
    assert code == 0, err
    doc = json.loads(out)
    assert doc["natural_frequency_hz"] == pytest.approx(truth["natural_frequency_hz"], rel=0.005)
    assert doc["damping_ratio"] == pytest.approx(truth["damping_ratio"], rel=0.05)
    assert doc["unbalance_gmm"] == pytest.approx(truth["unbalance_gmm"], rel=0.02)
    assert doc["critical_speed_hz"] == pytest.approx(truth["critical_speed_hz"], rel=0.01)
    assert doc["unbalance_angle_deg"] == pytest.approx(truth["unbalance_angle_deg"], abs=2.0)
