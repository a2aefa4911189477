"""Property-based hardening of the recording readers (issue 10 item 5).

A valid small recording is written once, then mutated: truncated at random byte
offsets, datasets and groups deleted or replaced (other shapes, dtypes, a group
instead of a dataset), NaN/inf inserted, root and dataset attributes changed,
non-HDF5 bytes.  CSV inputs for ``stand analyze`` get missing columns, text in
numbers, NaN, unsorted and duplicate times, empty files.

Properties: ``read_recording`` returns a Recording or raises ``RecordingError``
naming the file; ``stand analyze`` (``stand.cli.main.main``) ends with exit code 0,
or 2 with one ``error:`` line naming the file -- never exit 3 (internal
error), never a traceback -- within a time bound.
"""
from __future__ import annotations

import io
import math
import shutil
import time
from contextlib import redirect_stderr, redirect_stdout
from pathlib import Path

import h5py
import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from stand.cli.main import main
from stand.recording.hdf5 import DATASETS, Recording, RecordingError, read_recording, write_recording
from stand.integrate.result import Run, SolverStats
from stand.scene.parse import load_scene

from _helpers import Properties, toml_text

FAST = settings(max_examples=120, deadline=20_000, derandomize=True, database=None,
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large,
                                       HealthCheck.function_scoped_fixture])
#: each property: an eighth of its examples by default, all under ``-m full`` (issue 43)
PROPS = Properties()
TIME_BOUND = 30.0  #: s, for one ``stand analyze`` of a small file

SCENE = toml_text(
    scene=dict(name="fuzz"), rotor=dict(mass=4.45, eccentricity=1e-4),
    supports=dict(stiffness=1613.09, damping=8.5577),
    balancer=dict(type="balls", count=2, mass=0.045, radius=0.08),
    drive=dict(type="speed", programme=[[0.0, 10.0]]), run=dict(duration=2.0, sample_rate=200.0))


def _trajectory(n=401, weights=2, rotating=True):
    t = np.linspace(0.0, 2.0, n)
    w = 2 * np.pi * 10.0 if rotating else 0.0
    phi = w * t
    z = 1e-4 * np.exp(1j * (phi + 0.3)) + (0 if rotating else 1e-4 * np.exp(-t) * np.cos(19 * t))
    wa = phi[:, None] + np.linspace(1.0, 2.0, weights)[None, :]
    names = [f"ball{j + 1}" for j in range(weights)]
    return Run(t=t, planes={"balancer": np.column_stack([z.real, z.imag])}, main_plane="balancer",
               rotor_angle=phi, rotor_speed=np.full(n, w),
               weights={nm: {"angle": wa[:, j], "speed": np.full(n, w)} for j, nm in enumerate(names)},
               weight_planes={nm: "balancer" for nm in names},
               stats=SolverStats(method="DOP853", rtol=1e-8, atol=1e-10, message="ok"),
               scene=load_scene(SCENE))


@pytest.fixture(scope="module")
def originals(tmp_path_factory):
    d = tmp_path_factory.mktemp("orig")
    out = {}
    for name, kw in (("rot", {}), ("free", {"rotating": False, "weights": 0})):
        out[name] = write_recording(_trajectory(**kw), d / f"{name}.h5")
    return out


def run_cli(*argv):
    """``stand.cli.main.main`` with captured output; returns (code, stdout, stderr, wall)."""
    out, err = io.StringIO(), io.StringIO()
    t0 = time.perf_counter()
    with redirect_stdout(out), redirect_stderr(err):
        code = main([str(a) for a in argv])
    return code, out.getvalue(), err.getvalue(), time.perf_counter() - t0


def check_analyze(path: Path):
    code, out, err, wall = run_cli("analyze", path, "--json")
    assert wall < TIME_BOUND, f"stand analyze took {wall:.1f} s"
    assert "Traceback" not in err and "Traceback" not in out
    assert code in (0, 2), f"exit {code}: {err}"
    if code == 2:
        assert err.startswith("stand analyze: error: "), err
        assert err.count("\n") == 1, f"more than one line: {err!r}"
        assert path.name in err, f"the file is not named: {err!r}"
    else:
        assert out.lstrip().startswith("{")
    return code, err


def check_read(path: Path):
    try:
        rec = read_recording(path)
    except RecordingError as exc:
        assert str(path) in str(exc), f"the file is not named: {exc}"
        return exc
    assert isinstance(rec, Recording)
    n = len(rec)
    for name in ("x", "y", "rotor_angle", "rotor_speed"):
        assert getattr(rec, name).shape == (n,)
    assert rec.weight_angle.shape == rec.weight_speed.shape == rec.relative_angle.shape
    assert rec.weight_angle.shape[0] == n
    return rec


# ---------------------------------------------------------------- HDF5: truncation, bytes
@PROPS(FAST)
@given(st.floats(0.0, 1.0), st.sampled_from(["rot", "free"]))
def test_truncated_recordings_are_clear_errors(originals, tmp_path_factory, frac, which):
    src = originals[which]
    blob = src.read_bytes()
    cut = int(frac * len(blob))
    assume(cut < len(blob))
    p = tmp_path_factory.mktemp("tr") / "cut.h5"
    p.write_bytes(blob[:cut])
    res = check_read(p)
    code, err = check_analyze(p)
    if isinstance(res, RecordingError):
        assert code == 2


@PROPS(settings(FAST, max_examples=60))
@given(st.binary(max_size=2000), st.sampled_from(["run.h5", "run.hdf5", "run", "run.csv"]))
def test_arbitrary_bytes_are_clear_errors(tmp_path_factory, blob, name):
    p = tmp_path_factory.mktemp("by") / name
    p.write_bytes(blob)
    if not name.endswith(".csv"):
        assert isinstance(check_read(p), RecordingError)
    code, _ = check_analyze(p)
    if not name.endswith(".csv"):
        assert code == 2


@PROPS(settings(FAST, max_examples=60))
@given(st.integers(0, 10 ** 9), st.binary(min_size=1, max_size=64))
def test_overwritten_bytes_in_the_data_are_clear_errors_or_read(originals, tmp_path_factory,
                                                                where, junk):
    blob = bytearray(originals["rot"].read_bytes())
    # keep the superblock (first 512 bytes): corrupting it is the truncation case
    i = 512 + where % max(1, len(blob) - 512 - len(junk))
    blob[i:i + len(junk)] = junk
    p = tmp_path_factory.mktemp("ow") / "flip.h5"
    p.write_bytes(bytes(blob))
    check_read(p)
    check_analyze(p)


# ---------------------------------------------------------------- HDF5: structure mutations
KEYS = list(DATASETS)
BAD_ARRAYS = st.sampled_from([
    "longer", "shorter", "2d", "3d", "scalar", "empty", "strings", "complex", "bool", "int",
    "nan", "inf", "group", "unsorted", "duplicate_times", "huge", "compound",
])


def _replacement(kind: str, a: np.ndarray):
    n = a.shape[0]
    if kind == "longer":
        return np.concatenate([a, a[:1]])
    if kind == "shorter":
        return a[:-1]
    if kind == "2d":
        return np.stack([a, a], axis=-1) if a.ndim == 1 else a[:, :, None].repeat(2, -1)[:, :, 0:2]
    if kind == "3d":
        return np.zeros((n, 2, 2))
    if kind == "scalar":
        return np.float64(1.0)
    if kind == "empty":
        return np.zeros((0,) + a.shape[1:])
    if kind == "strings":
        return np.array([b"x"] * n)
    if kind == "complex":
        return a.astype(complex)
    if kind == "bool":
        return a > 0
    if kind == "int":
        return (a * 1e6).astype(np.int64)
    if kind in ("nan", "inf"):
        b = a.astype(float).copy()
        b.flat[:: max(1, b.size // 7)] = np.nan if kind == "nan" else np.inf
        return b
    if kind == "unsorted":
        return a[::-1].copy()
    if kind == "duplicate_times":
        b = a.copy()
        b[1::2] = b[0::2][: b[1::2].shape[0]]
        return b
    if kind == "huge":
        return a * 1e300
    if kind == "compound":
        return np.zeros(n, dtype=[("a", "f8"), ("b", "i4")])
    raise AssertionError(kind)


def _mutate(path: Path, key: str, kind: str):
    with h5py.File(path, "r+") as f:
        a = f[key][()]
        del f[key]
        if kind == "group":
            f.create_group(key)
        else:
            f.create_dataset(key, data=_replacement(kind, a))


@PROPS(FAST)
@given(st.sampled_from(KEYS), BAD_ARRAYS, st.sampled_from(["rot", "free"]))
def test_changed_datasets_are_read_or_named(originals, tmp_path_factory, key, kind, which):
    p = tmp_path_factory.mktemp("ds") / "mut.h5"
    shutil.copy(originals[which], p)
    _mutate(p, key, kind)
    res = check_read(p)
    if isinstance(res, RecordingError):
        assert key in str(res), f"dataset {key!r} not named: {res}"
    elif kind in ("longer", "shorter", "3d", "scalar", "strings", "group", "compound") or (
            kind == "empty" and key in ("time", "shaft/x", "shaft/y")):
        pytest.fail(f"{key} as {kind} was accepted")
    code, err = check_analyze(p)
    if isinstance(res, RecordingError):
        assert code == 2


@PROPS(FAST)
@given(st.lists(st.sampled_from(KEYS + ["shaft", "rotor", "weights", "planes"]), min_size=1, max_size=4,
                unique=True), st.sampled_from(["rot", "free"]))
def test_deleted_datasets_and_groups_are_read_or_named(originals, tmp_path_factory, keys, which):
    p = tmp_path_factory.mktemp("del") / "del.h5"
    shutil.copy(originals[which], p)
    with h5py.File(p, "r+") as f:
        for k in keys:
            if k in f:
                del f[k]
    res = check_read(p)
    # shaft/x|y are links to planes/<main plane>/x|y: the shaft is lost only with the planes
    missing_required = any(k in keys for k in ("time", "planes"))
    if missing_required:
        assert isinstance(res, RecordingError) and "missing dataset" in str(res)
    else:
        assert isinstance(res, Recording)
        if "rotor/angle" in keys or "rotor" in keys:
            assert np.all(np.isnan(res.rotor_angle)) and res.notes
    check_analyze(p)


ATTR_VALUES = st.one_of(
    st.integers(-10, 10 ** 6), st.floats(allow_nan=True, allow_infinity=True),
    st.text(max_size=40).filter(lambda s: "\x00" not in s),  # h5py cannot store NUL
    st.binary(max_size=20).filter(lambda b: b"\x00" not in b), st.just(np.arange(3.0)),
    st.just(np.array([b"a", b"b"])), st.sampled_from(["{}", "[]", "null", "{\"a\": [1, 2]}", "{",
                                                      "[rotor]\nmass = -1\n", "[[[", SCENE,
                                                      SCENE.replace("4.45", "\"heavy\"")]),
)


@PROPS(FAST)
@given(st.sampled_from(["scene", "solver", "format", "format_version", "version", "scene_name",
                        "created"]), ATTR_VALUES, st.sampled_from(["rot", "free"]))
def test_changed_root_attributes_are_read_or_named(originals, tmp_path_factory, attr, value, which):
    p = tmp_path_factory.mktemp("at") / "attr.h5"
    shutil.copy(originals[which], p)
    with h5py.File(p, "r+") as f:
        f.attrs[attr] = value
    res = check_read(p)
    if isinstance(res, RecordingError):
        assert attr in str(res), f"attribute {attr!r} not named: {res}"
    check_analyze(p)


@PROPS(FAST)
@given(st.sampled_from(KEYS), st.sampled_from(["units", "description"]), ATTR_VALUES)
def test_changed_dataset_attributes_are_read(originals, tmp_path_factory, key, attr, value):
    p = tmp_path_factory.mktemp("da") / "dattr.h5"
    shutil.copy(originals["rot"], p)
    with h5py.File(p, "r+") as f:
        f[key].attrs[attr] = value
    res = check_read(p)
    if isinstance(res, RecordingError):
        assert key in str(res) or attr in str(res), res
    check_analyze(p)


def test_other_hdf5_files_and_paths(originals, tmp_path):
    empty = tmp_path / "empty.h5"
    with h5py.File(empty, "w"):
        pass
    exc = check_read(empty)
    assert isinstance(exc, RecordingError) and "time" in str(exc)
    assert check_analyze(empty)[0] == 2
    zero = tmp_path / "zero.h5"
    zero.write_bytes(b"")
    assert isinstance(check_read(zero), RecordingError)
    assert check_analyze(zero)[0] == 2
    d = tmp_path / "dir.h5"
    d.mkdir()
    assert isinstance(check_read(d), RecordingError)
    code, _, err, _ = run_cli("analyze", d)
    assert code == 2 and "dir.h5" in err
    with pytest.raises(FileNotFoundError):
        read_recording(tmp_path / "absent.h5")
    code, _, err, _ = run_cli("analyze", tmp_path / "absent.h5")
    assert code == 2 and "absent.h5" in err
    # the originals themselves: analysed to a result
    assert check_analyze(originals["rot"])[0] == 0
    assert check_analyze(originals["free"])[0] == 0


# ---------------------------------------------------------------- CSV inputs of stand analyze
def _csv_frame(n=400, rotating=True):
    t = np.linspace(0.0, 2.0, n)
    w = 2 * np.pi * 10.0
    z = 1e-4 * np.exp(1j * (w * t + 0.3)) if rotating else 1e-4 * np.exp(-t) * np.cos(19 * t)
    cols = {"t_s": t, "x_m": np.real(z), "y_m": np.imag(z) if rotating else 0 * t}
    if rotating:
        cols["rotor_angle_rad"] = w * t
    return cols


CSV_MUTATIONS = st.sampled_from([
    "drop_t", "drop_x", "drop_y", "text", "nan", "inf", "unsorted", "duplicate", "empty",
    "header_only", "one_row", "two_rows", "no_header", "semicolons", "huge", "bytes",
    "blank_lines", "extra_columns", "keyphasor", "keyphasor_text", "constant_time",
    "ragged", "quotes", "angle_nan",
])


def _write_csv(path: Path, cols: dict, mutation: str, data) -> None:
    cols = {k: np.array(v, dtype=object) for k, v in cols.items()}
    n = len(cols["t_s"])
    if mutation.startswith("drop_"):
        cols.pop({"drop_t": "t_s", "drop_x": "x_m", "drop_y": "y_m"}[mutation])
    elif mutation == "text":
        key = data.draw(st.sampled_from(list(cols)))
        cols[key][data.draw(st.integers(0, n - 1))] = data.draw(st.sampled_from(
            ["abc", "1,5", "--", "1e", "0x10", "True", " "]))
    elif mutation in ("nan", "inf", "huge", "angle_nan"):
        key = "rotor_angle_rad" if mutation == "angle_nan" and "rotor_angle_rad" in cols else \
            data.draw(st.sampled_from(list(cols)))
        idx = data.draw(st.lists(st.integers(0, n - 1), min_size=1, max_size=n))
        for i in idx:
            cols[key][i] = {"nan": math.nan, "angle_nan": math.nan, "inf": -math.inf,
                            "huge": 1e308}[mutation]
    elif mutation == "unsorted":
        perm = np.random.default_rng(data.draw(st.integers(0, 100))).permutation(n)
        cols["t_s"] = cols["t_s"][perm]
    elif mutation == "duplicate":
        cols["t_s"][1::2] = cols["t_s"][0::2][: len(cols["t_s"][1::2])]
    elif mutation == "constant_time":
        cols["t_s"][:] = 1.0
    elif mutation in ("one_row", "two_rows"):
        cols = {k: v[: 1 if mutation == "one_row" else 2] for k, v in cols.items()}
    elif mutation == "keyphasor":
        cols.pop("rotor_angle_rad", None)
        cols["keyphasor"] = np.array([1 if i % 20 == 0 else 0 for i in range(n)], dtype=object)
    elif mutation == "keyphasor_text":
        cols.pop("rotor_angle_rad", None)
        cols["keyphasor"] = np.array(["yes" if i % 20 == 0 else "" for i in range(n)], dtype=object)
    elif mutation == "extra_columns":
        cols["comment"] = np.array(["a,b" if i % 3 else "<script>" for i in range(n)], dtype=object)
    header = ",".join(cols)
    rows = [",".join(str(v) for v in row) for row in zip(*cols.values())]
    if mutation == "empty":
        text = ""
    elif mutation == "header_only":
        text = header + "\n"
    elif mutation == "no_header":
        text = "\n".join(rows) + "\n"
    elif mutation == "semicolons":
        text = "\n".join([header] + rows).replace(",", ";") + "\n"
    elif mutation == "blank_lines":
        text = "\n\n".join([header] + rows) + "\n"
    elif mutation == "ragged":
        text = "\n".join([header] + [r + ",1" * (i % 3) for i, r in enumerate(rows)]) + "\n"
    elif mutation == "quotes":
        text = "\n".join([header] + ['"' + r for r in rows]) + "\n"
    else:
        text = "\n".join([header] + rows) + "\n"
    if mutation == "bytes":
        path.write_bytes(text.encode()[:200] + b"\xff\xfe\x00\x81" + text.encode()[200:])
    else:
        path.write_text(text)


@PROPS(FAST)
@given(CSV_MUTATIONS, st.booleans(), st.data())
def test_csv_inputs_of_stand_analyze(tmp_path_factory, mutation, rotating, data):
    p = tmp_path_factory.mktemp("csv") / "run.csv"
    _write_csv(p, _csv_frame(rotating=rotating), mutation, data)
    code, err = check_analyze(p)
    if mutation in ("drop_t", "drop_x", "drop_y", "empty", "header_only", "no_header"):
        assert code == 2
    if mutation == "semicolons":     # a common DAQ delimiter: read like the commas (issue 19)
        assert code == 0, err
    if mutation.startswith("drop_"):
        col = {"drop_t": "t_s", "drop_x": "x_m", "drop_y": "y_m"}[mutation]
        assert col in err


@PROPS(settings(FAST, max_examples=60))
@given(st.lists(st.lists(st.one_of(st.floats(), st.integers(), st.text(max_size=4)),
                         min_size=3, max_size=4), max_size=30),
       st.sampled_from(["t_s,x_m,y_m", "t_s,x_m,y_m,rotor_angle_rad", "t_s,x_m,y_m,keyphasor"]))
def test_arbitrary_csv_rows(tmp_path_factory, rows, header):
    p = tmp_path_factory.mktemp("csvr") / "rows.csv"
    p.write_text("\n".join([header] + [",".join(str(v).replace("\n", " ") for v in r)
                                       for r in rows]) + "\n")
    check_analyze(p)


# ---------------------------------------------------------------- regressions found by this suite
def test_text_in_a_csv_number_names_file_column_and_row(tmp_path):
    """Was: 'error: could not convert string to float: 'abc'' (no file, no column)."""
    p = tmp_path / "txt.csv"
    p.write_text("t_s,x_m,y_m\n0,0,0\n0.1,abc,0\n")
    code, _, err, _ = run_cli("analyze", p)
    assert code == 2
    assert "txt.csv" in err and "'x_m'" in err and "row 2" in err and "'abc'" in err


def test_keyphasor_text_is_a_clear_error(tmp_path):
    p = tmp_path / "kp.csv"
    p.write_text("t_s,x_m,y_m,keyphasor\n0,0,0,yes\n0.1,0,0,\n")
    code, _, err, _ = run_cli("analyze", p)
    assert code == 2 and "kp.csv" in err and "'keyphasor'" in err


def test_csv_parse_error_is_one_line(tmp_path):
    """pandas' tokenizer message ends with a newline: the error was two lines."""
    p = tmp_path / "ragged.csv"
    p.write_text("t_s,x_m,y_m\n0,0,0\n0.1,0,0,7,8\n")
    code, _, err, _ = run_cli("analyze", p)
    assert code == 2 and err.count("\n") == 1 and "ragged.csv" in err


@pytest.mark.parametrize("rows", ["", "0,0,0,0\n"])
def test_fewer_than_two_samples_is_a_clear_error(tmp_path, rows):
    """One sample with a rotor angle was exit 3 (IndexError in np.gradient)."""
    p = tmp_path / "short.csv"
    p.write_text("t_s,x_m,y_m,rotor_angle_rad\n" + rows)
    code, _, err, _ = run_cli("analyze", p)
    assert code == 2 and "short.csv" in err and "at least 2" in err


def test_format_attribute_that_is_an_array(originals, tmp_path):
    """Was 'cannot read recording (truncated or corrupt file?): ValueError: The truth
    value of an array ... is ambiguous'; an array is simply not our format string."""
    p = tmp_path / "fmt.h5"
    shutil.copy(originals["rot"], p)
    with h5py.File(p, "r+") as f:
        f.attrs["format"] = np.arange(3.0)
    rec = read_recording(p)
    assert any("'format'" in n for n in rec.notes)


def test_values_near_the_float_limit_give_null_with_a_note(tmp_path):
    cols = _csv_frame()
    cols["x_m"] = cols["x_m"] * 1e308 * 1e4  # |x| ~ 1e308: finite, but sums overflow
    p = tmp_path / "huge.csv"
    p.write_text("t_s,x_m,y_m,rotor_angle_rad\n" + "\n".join(
        ",".join(repr(float(v)) for v in r) for r in zip(*cols.values())) + "\n")
    code, out, err, _ = run_cli("analyze", p, "--json")
    assert code == 0
    import json

    doc = json.loads(out)
    for k, v in doc.items():
        assert not (isinstance(v, float) and not math.isfinite(v))
    if doc["response_1x_m"] is None:
        assert any("response_1x_m: not finite" in n for n in doc["notes"])


test_property_with_all_its_examples = PROPS.full_test()
