"""Lab tables in (issue 19, items 1, 2 and 6): layouts, units, recognised names, speed sources
and the clear refusals / partial analyses of malformed tables.

The reference table is a rotor whirling at a constant 10 rev/s with a known 1X vector
(A = 50 um at 40 deg from the keyphasor mark), sampled at 1 kHz: its 1X amplitude and
speed are known exactly, so every layout and unit must give them back to the noise level.
"""
import html
import io
import json
import math
from contextlib import redirect_stderr, redirect_stdout

import numpy as np
import pandas as pd
import pytest

from stand.cli.main import main
from stand.lab.recording_map import MapError, parse_columns, read_map
from stand.lab.table import TableError, read_table

TWO_PI = 2 * math.pi
F, A, ANG = 10.0, 50e-6, math.radians(40.0)
FS, T = 1000.0, 3.0


def _frame(n_extra=0):
    t = np.arange(0, T, 1 / FS)
    phi = TWO_PI * F * t
    z = A * np.exp(1j * (phi + ANG))
    kp = np.where(np.mod(np.degrees(phi), 360.0) < 40.0, 5.0, 0.0)
    return pd.DataFrame({"time_ms": t * 1e3, "disp_x_um": z.real * 1e6 + 12.0,
                         "disp_y_um": z.imag * 1e6 - 7.0, "kp_V": kp,
                         "tacho_rpm": np.full(t.size, F * 60.0)})


def run(*argv):
    out, err = io.StringIO(), io.StringIO()
    with redirect_stdout(out), redirect_stderr(err):
        code = main([str(a) for a in argv])
    return code, out.getvalue(), err.getvalue()


def analyze_json(path, *extra):
    code, out, err = run("analyze", path, "--json", *extra)
    assert code == 0, err
    return json.loads(out), err


def _check_1x(doc):
    assert doc["speed_hz"] == pytest.approx(F, rel=1e-5)
    # keyphasor edges sampled at 1 kHz: the amplitude within the timing jitter's loss
    assert doc["response_1x_m"] == pytest.approx(A, rel=2e-3)


# ------------------------------------------------------------------ layouts and units
def test_recognised_names_are_reported(tmp_path):
    p = tmp_path / "daq.csv"
    _frame().to_csv(p, index=False)
    doc, err = analyze_json(p)
    _check_1x(doc)
    assert "columns recognised" in err and "time = column 'time_ms' [ms]" in err
    assert doc["input"]["columns"]["keyphasor"]["column"] == "kp_V"
    assert doc["speed_source"].startswith("keyphasor column 'kp_V'")


@pytest.mark.parametrize("sep,decimal", [(";", ","), ("\t", "."), ("\t", ","), (" ", ".")])
def test_delimiters_decimal_commas_and_header_lines(tmp_path, sep, decimal):
    p = tmp_path / "daq.txt"
    body = _frame().to_csv(sep=sep, decimal=decimal, index=False)
    p.write_text("Acquisition: bench 3\nSample rate: 1000 Hz\n\n" + body)
    doc, _ = analyze_json(p)
    _check_1x(doc)


def test_columns_option_with_units_and_volts(tmp_path):
    df = _frame()
    sens = 7.87e3                                    # V/m (7.87 V/mm)
    df["probe_x"] = df.pop("disp_x_um") * 1e-6 * sens   # volts
    df = df.rename(columns={"time_ms": "T", "disp_y_um": "chan2"})
    p = tmp_path / "lab.csv"
    df.to_csv(p, index=False)
    doc, err = analyze_json(p, "--columns",
                            "time=T[ms],x=probe_x[V, 7.87 V/mm],y=chan2[um],keyphasor=kp_V[V]")
    _check_1x(doc)
    assert "recognised" not in err
    assert doc["input"]["columns"]["x"] == {"column": "probe_x", "unit": "V",
                                            "sensitivity_v_per_mm": pytest.approx(7.87)}


def test_map_file_parquet_and_pandas_hdf5(tmp_path):
    df = _frame()
    m = tmp_path / "lab.toml"
    m.write_text('[columns]\ntime = "time_ms [ms]"\nx = "disp_x_um [um]"\ny = "disp_y_um [um]"\n'
                 'speed = {column = "tacho_rpm", unit = "rpm"}\n'
                 '[rotor]\nmass = "2 kg"\n')
    df.to_parquet(tmp_path / "lab.parquet")
    doc, _ = analyze_json(tmp_path / "lab.parquet", "--map", m)
    # a tachometer only: no mark, the 1X from the line, the speed still right
    assert doc["speed_hz"] == pytest.approx(F, rel=1e-5)
    assert doc["response_1x_m"] == pytest.approx(A, rel=1e-3)
    assert doc["unbalance_angle_deg"] is None
    pytest.importorskip("tables")                 # PyTables writes the file; we read it with h5py
    for fmt in ("fixed", "table"):
        df.assign(note="text").to_hdf(tmp_path / f"lab_{fmt}.h5", key="vibration", format=fmt)
        doc2, _ = analyze_json(tmp_path / f"lab_{fmt}.h5", "--map", m)
        assert doc2["response_1x_m"] == pytest.approx(doc["response_1x_m"], rel=1e-9)


def test_units_convert_once():
    m = parse_columns("time=t[us],x=a[mil],y=b[mm],speed=n[Hz]")
    assert m.columns["time"].si_factor("") == 1e-6
    assert m.columns["x"].si_factor("") == pytest.approx(25.4e-6)
    assert m.columns["speed"].si_factor("") == pytest.approx(TWO_PI)
    with pytest.raises(ValueError, match="x = column.*unit .rpm. is a speed unit"):
        parse_columns("x=a[rpm]").columns["x"].si_factor("x = column 'a'")
    with pytest.raises(MapError, match="unknown role 'z'"):
        parse_columns("z=a[m]")


def test_map_file_errors_name_the_key(tmp_path):
    m = tmp_path / "bad.toml"
    m.write_text('[rotor]\nmass = "12 furlong"\n')
    with pytest.raises(ValueError, match=r"bad\.toml: rotor\.mass = '12 furlong'.*unknown unit"):
        read_map(m)
    m.write_text('[columns]\nx = {col = "a"}\n')
    with pytest.raises(MapError, match=r"columns\.x: expected"):
        read_map(m)


def test_mapped_column_missing_suggests(tmp_path):
    p = tmp_path / "d.csv"
    _frame().to_csv(p, index=False)
    code, _, err = run("analyze", p, "--columns", "time=time_ms[ms],x=disp_x_uum[um],y=disp_y_um[um]")
    assert code == 2 and "disp_x_uum" in err and "did you mean 'disp_x_um'" in err


# ------------------------------------------------------------------ refusals (exit 2)
def test_no_time_column(tmp_path):
    p = tmp_path / "d.csv"
    _frame().drop(columns="time_ms").to_csv(p, index=False)
    code, _, err = run("analyze", p)
    assert code == 2 and err.count("\n") == 1
    assert "d.csv" in err and "no time column" in err and "disp_x_um" in err


def test_non_monotonic_time_names_column_and_rows(tmp_path):
    df = _frame()
    df.loc[1200, "time_ms"] = 1100.0
    p = tmp_path / "d.csv"
    df.to_csv(p, index=False)
    code, _, err = run("analyze", p)
    assert code == 2 and err.count("\n") == 1
    assert "'time_ms' (ms)" in err and "data rows 1200-1201" in err and "1199 -> 1100 ms" in err


def test_no_clean_stretch_is_refused(tmp_path):
    df = _frame()
    df.loc[::2, "disp_x_um"] = np.nan
    p = tmp_path / "d.csv"
    df.to_csv(p, index=False)
    code, _, err = run("analyze", p)
    assert code == 2 and "no stretch of 2 clean rows" in err and "'disp_x_um'" in err


# ------------------------------------------------------------------ partial analyses
def test_clipped_samples_are_censored_not_cut(tmp_path):
    """A knock triples the whirl for 0.3 s and the x channel's ADC saturates at +100 um: the
    clipped samples are censored (named once, the time base whole), the 1X taken without them."""
    df = _frame()
    sl = slice(2000, 2300)
    df.loc[sl, "disp_x_um"] = 12.0 + 3 * (df.loc[sl, "disp_x_um"] - 12.0)
    df["disp_x_um"] = df["disp_x_um"].clip(upper=100.0)
    p = tmp_path / "d.csv"
    df.to_csv(p, index=False)
    doc, err = analyze_json(p)
    assert doc["input"]["excluded"] == [] and doc["input"]["rows_used"] == [1, len(df)]
    assert len(doc["input"]["censored"]) == 1 and "'disp_x_um'" in doc["input"]["censored"][0]
    assert "clipped at 100 um" in doc["input"]["censored"][0]
    assert sum("clipped" in n for n in doc["notes"]) == 2    # the censoring, the steady 1X
    _check_1x(doc)


@pytest.mark.parametrize("case", ["gap", "nan"])
def test_partial_analysis_states_the_excluded_rows(tmp_path, case):
    df = _frame()
    if case == "gap":
        df = df.drop(index=range(2000, 2100)).reset_index(drop=True)
        reason, rows = "gap of 101 ms", "2000-2001"
    else:
        df.loc[1999:2098, "disp_y_um"] = np.nan
        reason, rows = "column 'disp_y_um': empty or NaN", "2000-2099"
    p = tmp_path / "d.csv"
    df.to_csv(p, index=False)
    doc, err = analyze_json(p)
    ex = doc["input"]["excluded"]
    assert any(reason in e["reason"] and (rows is None or e["rows"] == rows) for e in ex), ex
    used = doc["input"]["rows_used"]
    assert used[1] <= 2000 or used[0] > 2100
    assert f"excluded rows" in err and reason.split(":")[0] in err
    _check_1x(doc)                           # the rest is analysed
    # the report says it too
    code, _, err = run("report", p, "--json-file", tmp_path / "r.json", "-o", tmp_path / "r.html")
    assert code == 0, err
    rep = json.loads((tmp_path / "r.json").read_text())
    assert any(reason in e["reason"] for e in rep["analysis"]["input"]["excluded"])
    assert html.escape(reason.split(":")[0]) in (tmp_path / "r.html").read_text()


def test_binary_keyphasor_flags_keep_exact_times(tmp_path):
    t = np.arange(0, T, 1 / FS)
    phi = TWO_PI * F * t
    z = A * np.exp(1j * (phi + ANG))
    kp = np.zeros(t.size)
    kp[::100] = 1                              # the sample at each mark (10 rev/s at 1 kHz)
    p = tmp_path / "k.csv"
    pd.DataFrame({"t_s": t, "x_m": z.real, "y_m": z.imag, "keyphasor": kp}).to_csv(p, index=False)
    doc, _ = analyze_json(p)
    assert doc["response_1x_m"] == pytest.approx(A, rel=1e-9)


def test_read_table_is_the_one_reader():
    """stand analyze and stand report read tables through stand.lab.table (no second parser)."""
    import inspect

    from stand.analysis import identify, sources
    from stand.reports import balancing

    for mod in (identify, sources, balancing):
        assert "read_csv" not in inspect.getsource(mod)
    with pytest.raises(TableError):
        read_table(__file__)


def test_photogate_channel_of_a_free_decay(tmp_path):
    """The book's natural-frequency test (4.3): the period from the 1st to the 3rd pass of the
    beam over the photo-gate is the damped period (passes 1 and 3 cross in the same
    direction, so the gate's width cancels to first order in the damping)."""
    f0, zeta, fs = 3.0, 0.05, 5000.0
    t = np.arange(0, 1.5, 1 / fs)
    wd = TWO_PI * f0 * math.sqrt(1 - zeta ** 2)
    x = 3e-3 * np.exp(-zeta * TWO_PI * f0 * t) * np.cos(wd * t)
    gate = np.where(np.abs(x) < 0.25e-3, 4.8, 0.1)
    p = tmp_path / "decay.csv"
    pd.DataFrame({"t_s": t, "x_m": x, "y_m": 0 * t, "photogate_V": gate}).to_csv(p, index=False)
    doc, _ = analyze_json(p)
    pg = doc["photogate"]
    # edge timing: one sample (0.2 ms) in a 0.33 s period; the damping shifts the passes by
    # ~ (gate / amplitude) x zeta x period / 2 pi ~ 1e-4 of the period
    assert pg["frequency_hz"] == pytest.approx(wd / TWO_PI, rel=2e-3)
    assert doc["natural_frequency_hz"] == pytest.approx(f0, rel=1e-3)    # free decay fit


# ------------------------------------------------------------------ shape limits (issue 34)
def test_shape_limits_refuse_before_parsing(tmp_path, monkeypatch):
    """Too many columns, a too long line, a field over csv's limit and a table larger than the
    memory budget are refused with the file, the number and the limit, whatever the layout."""
    import stand.lab.table as table

    good = _frame().to_csv(index=False)
    head, body = good.split("\n", 1)
    cases = {
        "columns": (head + "," + ",".join(f"c{i}" for i in range(table.MAX_COLUMNS)) + "\n" + body,
                    f"{table.MAX_COLUMNS + len(head.split(','))} columns, over the limit of {table.MAX_COLUMNS}"),
        "line": (head + "\n" + "1" * (table.MAX_LINE_CHARS + 1) + "\n" + body,
                 f"line 2 has {table.MAX_LINE_CHARS + 1} characters, over the limit"),
        "field": (head + "\n" + '1,"' + "9" * 200_000 + '",2\n' + body, "field larger than"),
    }
    for name, (text, says) in cases.items():
        p = tmp_path / f"{name}.csv"
        p.write_text(text)
        with pytest.raises(TableError) as err:
            read_table(p)
        assert str(err.value).startswith(str(p)) and says in str(err.value), (name, str(err.value))
    # memory: rows x columns x CELL_BYTES against the budget (here made small)
    p = tmp_path / "big.csv"
    p.write_text(good)
    n_rows = len(body.strip().splitlines())
    from stand.lab import limits      # the limits every reader shares

    for mod in (table, limits):
        monkeypatch.setattr(mod, "_memory_budget", lambda: 4.0 * p.stat().st_size + 1)
    monkeypatch.setattr(limits, "CELL_BYTES", 4.0 * p.stat().st_size)
    with pytest.raises(TableError, match=rf"{n_rows} rows x {len(head.split(','))} columns would need"):
        read_table(p)
    monkeypatch.undo()
    assert read_table(p).t.size == n_rows
