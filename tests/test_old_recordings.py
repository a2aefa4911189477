"""Recordings written before the one layout still open, analyse and report.

``tests/data/v1_*.h5`` were written by the stand at commit afd4e0a (before the
one-stand change): a planar recording (format_version 1: ``shaft/x|y``,
``weights/angle`` matrices), a rotor-family file (``planes/<p>`` (N, 2)) and a
weight-model file (a ``state`` matrix).
"""
from pathlib import Path

import numpy as np
import pytest

import stand
from stand.cli.main import main

DATA = Path(__file__).resolve().parent / "data"


def test_format_1_planar_recording_reads_with_its_scene():
    rec = stand.read(DATA / "v1_planar.h5")
    assert rec.format_version == 1 and rec.main_plane == "shaft"
    assert rec.n_weights == 2 and set(rec.weights) == {"weight1", "weight2"}
    # the balls start at 150 / 210 deg from the mark (ball_runup.toml)
    np.testing.assert_allclose(np.degrees(rec.relative_angle[0]), [150.0, -150.0], atol=1e-9)
    assert rec.scene is not None and rec.scene.kind == "planar"
    assert rec.t[-1] == pytest.approx(3.0) and np.all(np.isfinite(rec.x))


def test_family_recording_reads_every_plane():
    rec = stand.read(DATA / "v1_family.h5")
    assert set(rec.planes) >= {"balancer", "body"} and rec.main_plane == "balancer"
    np.testing.assert_array_equal(rec.x, rec.planes["balancer"][:, 0])
    assert rec.scene is not None and rec.scene.structure_type == "two_mass"
    assert any("rotor-family" in n for n in rec.notes)
    assert "structure/x1" in rec.coordinates and rec.coordinates["structure/x1"][1] == "m"


def test_weight_model_recording_reads_its_shaft():
    rec = stand.read(DATA / "v1_weight_model.h5")
    assert rec.main_plane == "balancer" and np.all(np.isfinite(rec.x))
    assert any("weight-model" in n for n in rec.notes)


@pytest.mark.parametrize("name", [pytest.param("v1_planar.h5", marks=pytest.mark.full),
                                  "v1_family.h5", "v1_weight_model.h5"])
def test_old_recordings_analyse_and_report(name, tmp_path, capsys):
    """The planar one under ``-m full`` (its report computes ball_runup's whole speed map,
    7 s of CPU): its old layout is read in test_format_1_planar_recording_reads_with_its_scene,
    and the two other cases here take an old file through `stand analyze` and `stand report`."""
    path = DATA / name
    assert main(["analyze", str(path)]) == 0
    assert main(["report", str(path), "-o", str(tmp_path / "r.html"),
                 "--json-file", str(tmp_path / "r.json")]) == 0
    assert (tmp_path / "r.html").stat().st_size > 1000
    out = capsys.readouterr().out
    assert "report ->" in out


def test_xarray_sees_the_time_axis_of_every_group(tmp_path):
    """time is an HDF5 dimension scale attached to every channel (netCDF-4 readers see it)."""
    xr = pytest.importorskip("xarray")
    pytest.importorskip("h5netcdf")
    scene = stand.load(str(DATA.parents[1] / "data_samples/scenes/no_balancer.toml"))
    import dataclasses

    scene = dataclasses.replace(scene, run=dataclasses.replace(scene.run, duration=1.0))
    path = stand.save(stand.run(scene), tmp_path / "r.h5")
    for group, names in (("planes/balancer", {"x", "y"}), ("rotor", {"angle", "speed"})):
        ds = xr.open_dataset(path, engine="h5netcdf", group=group, phony_dims="access",
                             decode_timedelta=False)
        assert set(ds.data_vars) == names and dict(ds.sizes) == {"time": 201}
    root = xr.open_dataset(path, engine="h5netcdf", phony_dims="access", decode_timedelta=False)
    np.testing.assert_array_equal(root["time"].values, stand.read(path).t)
