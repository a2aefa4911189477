"""The files DAQ systems write (issue 31, item 4): Excel, MATLAB v5 / v7.3, NI TDMS and
CSV in UTF-8 / UTF-8 with BOM / UTF-16 give the same table, hence the same numbers; a
refused or unusual file is one clear line with exit code 2.

The reference is the constant-speed whirl of ``test_lab_tables`` (10 rev/s, a 1X vector
of 50 um at 40 deg from the keyphasor mark): every format must give back its CSV's
numbers exactly (the same cells), and the known 1X to the keyphasor's timing jitter.
"""
import json

import numpy as np
import pytest

from tests.test_lab_tables import A, F, _frame, run

MAP_COLUMNS = "time=time_ms[ms],x=disp_x_um[um],y=disp_y_um[um],keyphasor=kp_V[V]"


def _analyze(path, columns=MAP_COLUMNS):
    code, out, err = run("analyze", path, "--json", "--columns", columns)
    assert code == 0, err
    return json.loads(out)


def _same(doc, ref):
    assert doc["speed_hz"] == pytest.approx(ref["speed_hz"], rel=1e-12)
    assert doc["response_1x_m"] == pytest.approx(ref["response_1x_m"], rel=1e-9)
    assert doc["speed_hz"] == pytest.approx(F, rel=1e-5)
    assert doc["response_1x_m"] == pytest.approx(A, rel=2e-3)


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    p = tmp_path_factory.mktemp("csv") / "daq.csv"
    _frame().to_csv(p, index=False, float_format="%.17g")
    return _analyze(p)


@pytest.mark.parametrize("encoding", ["utf-8-sig", "utf-16", "utf-16-le"])
def test_csv_encodings(tmp_path, reference, encoding):
    p = tmp_path / "daq.csv"
    text = _frame().to_csv(index=False, float_format="%.17g", sep="\t")
    p.write_bytes(text.encode(encoding))       # utf-16-le: no byte-order mark
    _same(_analyze(p), reference)


def test_xlsx(tmp_path, reference):
    pytest.importorskip("openpyxl", reason="Excel is read through openpyxl (optional)")
    import pandas as pd

    p = tmp_path / "daq.xlsx"
    with pd.ExcelWriter(p, engine="openpyxl") as w:        # a header line above the names
        pd.DataFrame([["rig: test stand 1"]]).to_excel(w, index=False, header=False)
        _frame().to_excel(w, index=False, startrow=2)
    _same(_analyze(p), reference)


def test_mat_v5_struct_fields(tmp_path, reference):
    import scipy.io

    df = _frame()
    p = tmp_path / "daq.mat"
    scipy.io.savemat(p, {"daq": {c: df[c].to_numpy()[:, None] for c in df.columns}})
    # struct fields are group/channel; the bare names work because they are unique
    _same(_analyze(p), reference)
    _same(_analyze(p, MAP_COLUMNS.replace("=time_ms", "=daq/time_ms")), reference)


def test_mat_v73(tmp_path, reference):
    import h5py

    df = _frame()
    p = tmp_path / "daq.mat"
    with h5py.File(p, "w", userblock_size=512) as f:        # MATLAB's -v7.3 layout
        for c in df.columns:
            d = f.create_dataset(c, data=df[c].to_numpy()[None, :])   # stored transposed
            d.attrs["MATLAB_class"] = np.bytes_("double")
    with open(p, "r+b") as fh:
        fh.write(b"MATLAB 7.3 MAT-file".ljust(116))
    _same(_analyze(p), reference)


def test_tdms_groups_and_waveform_time(tmp_path, reference):
    nptdms = pytest.importorskip("nptdms", reason="TDMS is read through npTDMS (optional)")
    df = _frame()
    p = tmp_path / "daq.tdms"
    dt = 1e-3
    chans = [nptdms.ChannelObject("Vibration", c, df[c].to_numpy(),
                                  properties={"wf_increment": dt, "wf_start_offset": 0.0})
             for c in ("disp_x_um", "disp_y_um", "kp_V")]
    with nptdms.TdmsWriter(p) as w:
        w.write_segment([nptdms.GroupObject("Vibration")] + chans)
    doc = _analyze(p, "x=Vibration/disp_x_um[um],y=disp_y_um[um],keyphasor=kp_V[V],time=time_s[s]")
    _same(doc, reference)


# ------------------------------------------------------------------ refusals: one line, exit 2
def _refused(path, *extra):
    code, out, err = run("analyze", path, *extra)
    assert code == 2, (code, err)
    lines = [ln for ln in err.strip().splitlines() if ln.strip()]
    assert len(lines) == 1, err
    return lines[0]


def test_unknown_format_lists_the_formats(tmp_path):
    p = tmp_path / "scope.wfm"
    p.write_bytes(b"\x89WFM\x00\x01binary")
    line = _refused(p)
    for name in ("CSV", "UTF-16", "Excel", "MATLAB", "TDMS", "Parquet", "HDF5"):
        assert name in line


def test_binary_file_with_a_table_suffix(tmp_path):
    p = tmp_path / "daq.csv"
    p.write_bytes(bytes(range(256)) * 8)
    assert "not a text table" in _refused(p) or "no data rows" in _refused(p)


def test_broken_workbook(tmp_path):
    p = tmp_path / "daq.xlsx"
    p.write_bytes(b"PK\x03\x04 not really a zip")
    line = _refused(p)
    assert "daq.xlsx" in line and ("Excel" in line or "openpyxl" in line)


def test_broken_mat_and_tdms(tmp_path):
    for name, data in (("daq.mat", b"garbage" * 20), ("short.mat", b"garbagegarbage"),
                       ("daq.tdms", b"garbage" * 20)):
        p = tmp_path / name
        p.write_bytes(data)
        line = _refused(p)
        assert name in line


def test_missing_role_in_a_grouped_file(tmp_path):
    import scipy.io

    df = _frame()
    p = tmp_path / "daq.mat"
    scipy.io.savemat(p, {"a": {"x": df["disp_x_um"].to_numpy()}, "b": {"x": df["disp_y_um"].to_numpy()},
                         "time_ms": df["time_ms"].to_numpy()})
    line = _refused(p, "--columns", "time=time_ms[ms],x=x[um],y=b/x[um]")
    assert "'x'" in line and "a/x" in line         # ambiguous bare name: the full names listed
