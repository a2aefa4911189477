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


def _check_truth(doc, truth):
    assert doc["natural_frequency_hz"] == pytest.approx(truth["natural_frequency_hz"], rel=0.005)
    assert doc["damping_ratio"] == pytest.approx(truth["damping_ratio"], rel=0.05)
    assert doc["unbalance_gmm"] == pytest.approx(truth["unbalance_gmm"], rel=0.02)
    assert doc["critical_speed_hz"] == pytest.approx(truth["critical_speed_hz"], rel=0.01)
    assert doc["unbalance_angle_deg"] == pytest.approx(truth["unbalance_angle_deg"], abs=2.0)


def test_bode_table_gives_its_truth():
    truth = json.loads((DAQ / "bode_table.truth.json").read_text())
    code, out, err = run("analyze", DAQ / "bode_table.csv", "--json", "--map", DAQ / "bode_table.map.toml")
    assert code == 0, err
    _check_truth(json.loads(out), truth)


def test_acc_runup_gives_its_truth_and_its_report_the_same_numbers_in_g_um_and_mm_s(monkeypatch):
    """The accelerometer run-up, its one identification (10-15 s CPU) asserted three ways:
    ``stand analyze`` finds the truth; ``stand report`` presents the analysis' numbers
    (tests/test_report_chain.check_same_numbers: the run-up table of that module's chain,
    the report a view of the analysis computed once for both commands); the report states
    the 1X in g, as displacement in um and as ISO 20816 velocity in mm/s, the numbers of the
    analysis (not an acceleration labelled um)."""
    import math

    from stand.analysis import identify
    from stand.reports.balancing_page import vibration_rows
    from tests.test_report_chain import _memoized_analysis, check_same_numbers

    monkeypatch.setattr(identify, "analyze", _memoized_analysis(identify.analyze))
    path, rmap = DAQ / "acc_runup.csv", DAQ / "acc_runup.map.toml"
    docs = []
    for command in ("analyze", "report"):
        code, out, err = run(command, path, "--map", rmap, "--json")
        assert code == 0, err
        docs.append(json.loads(out))
    analysis, report = docs
    _check_truth(analysis, json.loads((DAQ / "acc_runup.truth.json").read_text()))
    assert check_same_numbers(analysis, report) > 10
    vib = report["balancing_quality"]["vibration_1x"]
    assert vib["quantity"] == "acceleration" and vib["unit"] == "g"
    # the 1X acceleration a = w^2 d of the displacement d, in g (9.80665 m/s²)
    w = 2 * math.pi * report["balancing_quality"]["residual_speed_hz"]
    d = report["balancing_quality"]["response_1x_m"]
    assert vib["peak"] == pytest.approx(w * w * d / 9.80665, rel=1e-9)
    assert vib["velocity_rms_mm_s"] == pytest.approx(w * d / math.sqrt(2) * 1e3, rel=1e-9)
    assert 30e-6 < d < 80e-6                      # a displacement of tens of µm, not 1.36 m
    rows = dict(vibration_rows(report["balancing_quality"]))
    assert any(v.endswith(" g") for v in rows.values()), rows
    assert any(v.endswith("mm/s") for v in rows.values()), rows
