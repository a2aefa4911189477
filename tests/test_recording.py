"""Tests for stand.recording.hdf5: HDF5 round trip, metadata, atomic writes, bad files."""
import json
import os

import h5py
import numpy as np
import pytest

from stand import __version__
from stand.recording.hdf5 import (FORMAT, FORMAT_VERSION, Recording, RecordingError,
                             read_recording, write_recording)
from stand.scene.parse import load_scene
from stand.integrate.result import SolverStats
from stand.integrate.simulate import simulate

from _helpers import toml_text

# two balls, omega_1 = 1 rad/s (natural_frequency default 1/(2 pi) Hz), R_omega = 3
TWO_BALLS = toml_text(
    scene=dict(name="two balls, recording test"),
    dimensionless=dict(n=2, Rt=0.01, h=0.5, H=0.1, e0=0.3),
    drive=dict(type="speed", programme_dimensionless=[[0.0, 3.0]]), run=dict(duration=20.0, sample_rate=100.0))

# rotor on supports, no [balancer] table -> Balancer() of type "none"
NO_BALANCER = toml_text(
    rotor=dict(mass=1.0, eccentricity=1e-3), supports=dict(stiffness=1.0, damping=0.1),
    drive=dict(type="speed", programme_dimensionless=[[0.0, 3.0]]), run=dict(duration=5.0, sample_rate=100.0))

UNITS = {
    "time": "s", "shaft/x": "m", "shaft/y": "m", "planes/balancer/x": "m", "planes/balancer/y": "m",
    "rotor/angle": "rad", "rotor/speed": "rad/s", "weights/ball1/angle": "rad",
    "weights/ball1/speed": "rad/s", "weights/ball2/angle": "rad", "weights/ball2/speed": "rad/s",
}
SOLVER_KEYS = {"method", "rtol", "atol", "n_steps", "n_rejected", "nfev", "wall_time",
               "status", "message"}


@pytest.fixture(scope="module")
def traj():
    return simulate(load_scene(TWO_BALLS))


@pytest.fixture(scope="module")
def traj_none():
    return simulate(load_scene(NO_BALANCER))


def test_round_trip_arrays_exact(traj, tmp_path):
    assert traj.success and len(traj.t) > 1000  # exercises the compressed path
    path = write_recording(traj, tmp_path / "run.h5")
    assert path == tmp_path / "run.h5" and path.is_file()
    rec = read_recording(path)
    assert isinstance(rec, Recording)
    for name in ("t", "x", "y", "rotor_angle", "rotor_speed", "weight_angle", "weight_speed"):
        a, b = getattr(rec, name), getattr(traj, name)
        assert a.dtype == np.float64 and a.shape == b.shape, name
        assert np.array_equal(a, b), name
    assert rec.weight_angle.shape == (len(traj.t), 2)
    assert np.array_equal(rec.relative_angle, traj.relative_angle)
    assert rec.notes == ()
    assert rec.units == {"t": "s", "x": "m", "y": "m", "rotor_angle": "rad",
                         "rotor_speed": "rad/s"}
    assert set(rec.weights) == {"ball1", "ball2"} and rec.weight_planes["ball2"] == "balancer"
    with pytest.raises(ValueError):
        rec.x[0] = 1.0  # read-only


def test_dataset_attributes_and_storage(traj, tmp_path):
    path = write_recording(traj, tmp_path / "run.h5")
    with h5py.File(path, "r") as f:
        for key, unit in UNITS.items():
            ds = f[key]
            assert ds.attrs["units"] == unit, key
            assert isinstance(ds.attrs["description"], str) and ds.attrs["description"], key
            assert ds.dtype == np.float64
            assert ds.compression == "gzip" and ds.compression_opts == 4 and ds.shuffle, key
            assert ds.chunks is not None
            if key != "time":   # the time axis is attached as a dimension scale
                assert ds.dims[0][0].name == "/time", key
        # shaft/x|y are links to the main plane's datasets, not copies
        assert f.get("shaft/x", getlink=True).path == "/planes/balancer/x"


def test_root_attributes(traj, tmp_path):
    path = write_recording(traj, tmp_path / "run.h5", extra_attrs={"operator": "test", "gain": 2.5})
    rec = read_recording(path)
    a = rec.attrs
    assert a["format"] == FORMAT == "autobalancer-stand recording"
    assert a["format_version"] == FORMAT_VERSION == 2
    assert a["structure"] == "planar" and a["main_plane"] == "balancer"
    assert a["version"] == rec.version == __version__
    assert a["scene_name"] == "two balls, recording test"
    assert a["created"].endswith("+00:00")
    assert a["operator"] == "test" and a["gain"] == 2.5
    # scene text round-trips and loads to the same scene
    assert rec.scene_text == TWO_BALLS
    scene = rec.scene
    assert scene.name == traj.scene.name
    assert scene.balancer.count == 2
    np.testing.assert_array_equal(scene.balancer.mass, traj.scene.balancer.mass)
    np.testing.assert_array_equal(scene.drive.programme, traj.scene.drive.programme)
    # solver statistics: JSON with plain types
    solver = json.loads(a["solver"])
    assert solver == rec.solver
    assert SOLVER_KEYS <= set(solver)
    assert solver["method"] == traj.stats.method
    assert solver["n_steps"] == traj.stats.n_steps and isinstance(solver["n_steps"], int)
    assert solver["status"] == 0


def test_solver_numpy_scalars_become_plain(traj, tmp_path):
    import dataclasses

    stats = SolverStats(**{**traj.stats, "n_steps": np.int64(7), "rtol": np.float32(1e-6),
                           "success": np.bool_(True), "nfev": np.int32(11)})
    t2 = dataclasses.replace(traj, stats=stats)
    solver = read_recording(write_recording(t2, tmp_path / "np.h5")).solver
    assert solver["n_steps"] == 7 and solver["nfev"] == 11 and solver["success"] is True
    assert solver["rtol"] == pytest.approx(1e-6)


def test_extra_attrs_cannot_override_reserved(traj, tmp_path):
    with pytest.raises(ValueError, match="format"):
        write_recording(traj, tmp_path / "run.h5", extra_attrs={"format": "x"})
    assert list(tmp_path.iterdir()) == []


def test_to_frame(traj, tmp_path):
    rec = read_recording(write_recording(traj, tmp_path / "run.h5"))
    df = rec.to_frame()
    assert list(df.columns) == ["t_s", "x_m", "y_m", "rotor_angle_rad", "rotor_speed_rad_s",
                                "ball1_angle_rad", "ball1_speed_rad_s",
                                "ball2_angle_rad", "ball2_speed_rad_s"]
    assert len(df) == len(traj.t)
    assert np.array_equal(df["x_m"].to_numpy(), traj.x)
    assert np.array_equal(df["ball2_speed_rad_s"].to_numpy(), traj.weight_speed[:, 1])


def test_no_balancer_writes_an_empty_weights_group(traj_none, tmp_path):
    assert traj_none.scene.balancer.type == "none"
    N = len(traj_none.t)
    path = write_recording(traj_none, tmp_path / "bare.h5")
    with h5py.File(path, "r") as f:
        assert isinstance(f["weights"], h5py.Group) and len(f["weights"]) == 0
    rec = read_recording(path)
    assert rec.weight_angle.shape == rec.weight_speed.shape == rec.relative_angle.shape == (N, 0)
    assert rec.n_weights == 0
    assert np.array_equal(rec.x, traj_none.x)
    assert list(rec.to_frame().columns) == ["t_s", "x_m", "y_m", "rotor_angle_rad",
                                            "rotor_speed_rad_s"]
    assert rec.notes == ()


def test_missing_directory_is_a_clear_error(traj, tmp_path):
    missing = tmp_path / "no" / "such"
    with pytest.raises(FileNotFoundError, match="directory") as info:
        write_recording(traj, missing / "run.h5")
    assert str(missing) in str(info.value)
    assert not (tmp_path / "no").exists()


def _tmp_files(directory):
    return [p.name for p in directory.iterdir() if p.name.endswith(".tmp")]


def test_atomic_write_dataset_failure_keeps_old_file(traj, traj_none, tmp_path, monkeypatch):
    target = tmp_path / "run.h5"
    write_recording(traj_none, target)
    before = target.read_bytes()
    calls = {"n": 0}
    real = h5py.Group.create_dataset

    def failing(self, name, *args, **kwargs):
        calls["n"] += 1
        if calls["n"] == 4:
            raise RuntimeError("disk full (simulated)")
        return real(self, name, *args, **kwargs)

    monkeypatch.setattr(h5py.Group, "create_dataset", failing)
    with pytest.raises(RuntimeError, match="simulated"):
        write_recording(traj, target)
    assert calls["n"] == 4  # failed mid-write
    assert target.read_bytes() == before
    assert _tmp_files(tmp_path) == []
    monkeypatch.undo()
    assert np.array_equal(read_recording(target).x, traj_none.x)


def test_atomic_write_open_failure_keeps_old_file(traj, traj_none, tmp_path, monkeypatch):
    target = tmp_path / "run.h5"
    write_recording(traj_none, target)
    before = target.read_bytes()

    def failing(*args, **kwargs):
        raise OSError("cannot create file (simulated)")

    monkeypatch.setattr(h5py, "File", failing)
    with pytest.raises(OSError, match="simulated"):
        write_recording(traj, target)
    monkeypatch.undo()
    assert target.read_bytes() == before
    assert _tmp_files(tmp_path) == []


def test_atomic_write_replace_failure_no_target(traj, tmp_path, monkeypatch):
    target = tmp_path / "run.h5"

    def failing(src, dst):
        raise OSError("rename failed (simulated)")

    monkeypatch.setattr(os, "replace", failing)
    with pytest.raises(OSError, match="simulated"):
        write_recording(traj, target)
    monkeypatch.undo()
    assert not target.exists()
    assert list(tmp_path.iterdir()) == []


def test_overwrite_replaces_file(traj, traj_none, tmp_path):
    target = tmp_path / "run.h5"
    write_recording(traj_none, target)
    write_recording(traj, target)
    assert read_recording(target).n_weights == 2
    assert _tmp_files(tmp_path) == []


def test_missing_dataset_named(traj, tmp_path):
    path = write_recording(traj, tmp_path / "run.h5")
    with h5py.File(path, "a") as f:
        del f["planes/balancer/y"]       # shaft/y is a link to it
    with pytest.raises(RecordingError, match="shaft/y") as info:
        read_recording(path)
    assert str(path) in str(info.value)


def test_wrong_length_named(traj, tmp_path):
    path = write_recording(traj, tmp_path / "run.h5")
    with h5py.File(path, "a") as f:
        del f["rotor/speed"]
        f["rotor/speed"] = np.zeros(len(traj.t) - 1)
    with pytest.raises(RecordingError, match="rotor/speed") as info:
        read_recording(path)
    assert str(path) in str(info.value) and "len(time)" in str(info.value)


def test_weight_column_mismatch(traj, tmp_path):
    """A format-1 style file whose weight matrices disagree on the number of weights."""
    path = write_recording(traj, tmp_path / "run.h5")
    with h5py.File(path, "a") as f:
        del f["weights"]
        f["weights/angle"] = np.zeros((len(traj.t), 2))
        f["weights/speed"] = np.zeros((len(traj.t), 3))
    with pytest.raises(RecordingError, match="weights/speed"):
        read_recording(path)


def test_non_hdf5_file(tmp_path):
    path = tmp_path / "notes.h5"
    path.write_text("this is not HDF5\n" * 100)
    with pytest.raises(RecordingError, match="not an HDF5 file") as info:
        read_recording(path)
    assert str(path) in str(info.value)
    empty = tmp_path / "empty.h5"
    empty.write_bytes(b"")
    with pytest.raises(RecordingError):
        read_recording(empty)


def test_truncated_file(traj, tmp_path):
    path = write_recording(traj, tmp_path / "run.h5")
    data = path.read_bytes()
    path.write_bytes(data[: len(data) // 2])
    with pytest.raises(RecordingError) as info:
        read_recording(path)
    assert str(path) in str(info.value)


@pytest.mark.parametrize("fraction", [0.05, 0.2, 0.5, 0.8, 0.95])
def test_truncated_at_various_points(traj, tmp_path, fraction):
    path = write_recording(traj, tmp_path / "run.h5")
    data = path.read_bytes()
    path.write_bytes(data[: int(len(data) * fraction)])
    with pytest.raises(RecordingError):
        read_recording(path)


def test_missing_file(tmp_path):
    with pytest.raises(FileNotFoundError):
        read_recording(tmp_path / "nope.h5")


def test_foreign_file_minimal(tmp_path):
    """A file from another tool: only time and shaft displacement, no metadata."""
    path = tmp_path / "logger.h5"
    t = np.linspace(0.0, 1.0, 11)
    with h5py.File(path, "w") as f:
        f["time"] = t
        f["shaft/x"] = np.sin(t).astype(np.float32)
        f["shaft/y"] = np.cos(t)
        f["shaft/x"].attrs["units"] = "m"
    rec = read_recording(path)
    assert np.array_equal(rec.t, t)
    assert np.array_equal(rec.x, np.sin(t).astype(np.float32).astype(np.float64))
    assert rec.rotor_angle.shape == (11,) and np.isnan(rec.rotor_angle).all()
    assert np.isnan(rec.rotor_speed).all()
    assert rec.weight_angle.shape == rec.weight_speed.shape == rec.relative_angle.shape == (11, 0)
    assert rec.solver == {} and rec.scene_text == "" and rec.version == ""
    assert any("rotor/angle" in n and "NaN" in n for n in rec.notes)
    assert any("time" in n and "units" in n for n in rec.notes)
    assert list(rec.to_frame().columns)[:5] == ["t_s", "x_m", "y_m", "rotor_angle_rad",
                                                "rotor_speed_rad_s"]
    assert rec.scene is None and any("scene" in n for n in rec.notes)


def test_foreign_file_with_weights_computes_relative_angle(tmp_path):
    path = tmp_path / "rig.h5"
    N = 5
    with h5py.File(path, "w") as f:
        f["time"] = np.arange(N, dtype=float)
        f["shaft/x"] = np.zeros(N)
        f["shaft/y"] = np.zeros(N)
        f["rotor/angle"] = np.arange(N, dtype=float)
        f["weights/angle"] = np.arange(N, dtype=float) * 2  # one weight, stored (N,)
    rec = read_recording(path)
    assert rec.weight_angle.shape == (N, 1)
    assert np.allclose(rec.relative_angle[:, 0], np.angle(np.exp(1j * np.arange(N))))
    assert np.isnan(rec.weight_speed).all()
    assert any("weights/speed" in n for n in rec.notes)
    assert any("relative_angle" in n for n in rec.notes)


def test_newer_format_version_rejected(traj, tmp_path):
    path = write_recording(traj, tmp_path / "run.h5")
    with h5py.File(path, "a") as f:
        f.attrs["format_version"] = 99
    with pytest.raises(RecordingError, match="format_version"):
        read_recording(path)


def test_named_screens_and_the_screen_option_list_the_same_groups(tmp_path):
    """One listing of a recording's screens: named_screens (positioned ones by default, the
    two-plane report) and screen_group_of's message (every named screen group)."""
    from stand.recording.read import named_screens, screen_group_of

    path = tmp_path / "screens.h5"
    with h5py.File(path, "w") as f:
        g = f.create_group("instruments")
        g.create_group("screen.front").attrs["axial_position_m"] = 0.1
        g.create_group("screen.side")              # a screen without an axial position
        g.create_dataset("screen.data", data=1.0)  # not a screen group
    assert named_screens(path) == ["front"]
    assert named_screens(path, positioned=False) == ["front", "side"]
    assert screen_group_of(path, "front") == "instruments/screen.front"
    with pytest.raises(ValueError, match="two screens, front and side, and no unnamed one"):
        screen_group_of(path)
    with pytest.raises(ValueError, match="give --screen front or --screen side"):
        screen_group_of(path, "rear")
    assert named_screens(tmp_path / "missing.h5") == []
