"""Instruments on any plane of any rotor (issue 17, part 1): screens, stroboscopes, probes
and keyphasors on rotor-family scenes, on a named plane or on an axis point of a tilting
rotor ((4.2): the laser along the shaft axis), recovered by ``stand track``."""
from __future__ import annotations

import dataclasses
import glob
from pathlib import Path

import h5py
import numpy as np
import pandas as pd
import pytest

import stand
from stand.cli.main import main
from stand.scene.placement import axis_plane_name, placement_of
from stand.scene.model import SceneError

ROOT = Path(__file__).resolve().parents[1]
SAMPLES = sorted(glob.glob(str(ROOT / "data_samples/scenes/family_*.toml")))


def _short(path, duration):
    sc = stand.load(path)
    return dataclasses.replace(sc, run=dataclasses.replace(sc.run, duration=duration))


@pytest.mark.parametrize("path", SAMPLES, ids=lambda p: Path(p).stem)
def test_every_family_sample_has_a_screen_and_a_stroboscope(path):
    sc = stand.load(path)
    # [structure] type = "planar" reads into the chapter-5 planar Scene (issue 40)
    assert sc.kind == ("planar" if sc.structure_type == "planar" else "rotor")
    assert {"screen", "stroboscope"} <= set(sc.instruments)
    p = placement_of(sc.instruments["screen"])
    assert p.plane is None or p.plane in sc.planes


def test_track_recovers_the_axis_point_of_the_spatial_rotor(tmp_path):
    """family_spatial: the screen at 0.5 m films the axis point x + d beta, y - d alpha;
    `stand track` finds it within 0.05 px RMS of the truth, and the truth is the axis
    point of the run."""
    src = ROOT / "data_samples/scenes/family_spatial.toml"
    text = src.read_text().replace("duration = 30.0", "duration = 8.0")
    scene_path = tmp_path / "spatial.toml"
    scene_path.write_text(text)
    rec, csv = tmp_path / "run.h5", tmp_path / "track.csv"
    assert main(["run", str(scene_path), "-o", str(rec), "--no-progress"]) == 0
    assert main(["track", str(rec), "-o", str(csv)]) == 0
    df = pd.read_csv(csv, comment="#")
    with h5py.File(rec) as f:
        g = f["instruments/screen"]
        assert g.attrs["plane"] == axis_plane_name(0.5) and g.attrs["axial_position_m"] == 0.5
        truth = f["truth/screen/centre_px"][:]
        inside = f["truth/screen/in_frame"][:]
        cm = f["truth/screen/centre_m"][:]
        texp = f["truth/screen/exposure_time"][:]
        assert f["instruments/stroboscope/frames"].shape[0] >= 2
        assert f["instruments/screen/ring_radius"].shape == (21,)
    ok = inside & df["ok"].to_numpy().astype(bool)
    assert ok.sum() >= 6
    err = np.hypot(df["u_px"].to_numpy()[ok] - truth[ok, 0], df["v_px"].to_numpy()[ok] - truth[ok, 1])
    assert np.sqrt(np.mean(err ** 2)) < 0.05
    # the screen's truth is the axis point at d = 0.5 m: (x + d beta, y - d alpha) * gain
    run = stand.run(stand.load(scene_path))
    sim = run.scene.linear_rotor()
    assert axis_plane_name(0.5) in sim.planes
    q = np.column_stack([run.coordinates[f"structure/{c.partition(' [')[0]}"][0]
                         for c in sim.coords])
    x, y, a, b = q.T
    k = 3
    i = int(np.searchsorted(run.t, texp[k].mean()))
    # the exposure lasts 2 ms; compare with the nearest recorded sample loosely, and exactly
    # with the run's axis plane (same map)
    np.testing.assert_allclose(run.planes[axis_plane_name(0.5)][:, 0], x + 0.5 * b, atol=1e-15)
    np.testing.assert_allclose(run.planes[axis_plane_name(0.5)][:, 1], y - 0.5 * a, atol=1e-15)
    assert np.isfinite(cm[k]).all() and i < run.t.size


def test_screen_on_another_plane_films_that_plane(tmp_path):
    """two_mass with the screen on the housing ("body"): the spot follows planes["body"]."""
    src = ROOT / "data_samples/scenes/family_two_mass.toml"
    text = src.read_text().replace('plane = "balancer"         # the rotor;',
                                   'plane = "body"         # the housing;')
    text = text.replace("duration = 40.0", "duration = 4.0")
    p = tmp_path / "tm.toml"
    p.write_text(text)
    sc = stand.load(p)
    assert placement_of(sc.instruments["screen"]).plane == "body"
    run = stand.run(sc)
    path = stand.save(run, tmp_path / "tm.h5")
    with h5py.File(path) as f:
        assert f["instruments/screen"].attrs["plane"] == "body"
        cm = f["truth/screen/centre_m"][:]
        texp = f["truth/screen/exposure_time"][:]
        gain = 1.0
    # the exposure sub-samples of the run (run.extra) in the body plane, averaged per frame
    F, K = texp.shape
    body = run.extra.planes["body"][:F * K].reshape(F, K, 2).mean(axis=1)
    np.testing.assert_allclose(run.extra.t[:F * K].reshape(F, K), texp, atol=1e-12)
    np.testing.assert_allclose(cm, gain * body, atol=1e-12)
    assert not np.allclose(cm, gain * run.extra.planes["balancer"][:F * K].reshape(F, K, 2)
                           .mean(axis=1), atol=1e-6)


def test_placement_errors_are_clear(tmp_path):
    base = (ROOT / "data_samples/scenes/family_two_mass.toml").read_text()
    bad = base.replace('plane = "balancer"         # the rotor;', 'plane = "shaft"  #')
    with pytest.raises(SceneError, match=r'instruments.screen.plane = "shaft": not a plane.*body'):
        _load(tmp_path, bad)
    na = base.replace('plane = "balancer"         # the rotor;', 'axial_position = 0.3  #')
    with pytest.raises(SceneError, match="axial_position = 0.3: not applicable: the two-mass"):
        _load(tmp_path, na)
    both = base.replace('plane = "balancer"         # the rotor;',
                        'plane = "body"\naxial_position = 0.3  #')
    with pytest.raises(SceneError, match="not both"):
        _load(tmp_path, both)
    flex = (ROOT / "data_samples/scenes/family_flexible.toml").read_text().replace(
        "axial_position = 0.3 ", "axial_position = 1.3 ")
    with pytest.raises(SceneError, match="strictly between the supports"):
        _load(tmp_path, flex)


def _load(tmp_path, text):
    p = tmp_path / "s.toml"
    p.write_text(text)
    return stand.load(p)


def test_family_rings_are_the_locked_rotor_response():
    """Rings on a family scene: the locked-weights steady response; on the planar family
    sample they equal the planar closed form of the same rotor."""
    from stand.instruments.rings import family_ring_radii, ring_radii

    import tomllib

    from stand.scene.structure_tables import parse_family_scene

    path = ROOT / "data_samples/scenes/family_planar.toml"
    # the generic structure of the sample (stand.load reads it into the planar Scene)
    fam = parse_family_scene(tomllib.loads(path.read_text()))
    assert fam.kind == "rotor" and stand.load(path).kind == "planar"
    r = family_ring_radii(fam, cam=fam.instruments["screen"])
    assert r[0] == 0 and np.all(np.diff(r) > 0)
    np.testing.assert_allclose(r, r[1] * np.arange(21), rtol=1e-12)
    assert np.array_equal(r, ring_radii(fam, cam=fam.instruments["screen"]))
    planar = stand.load(path)
    np.testing.assert_allclose(ring_radii(planar, cam=planar.instruments["screen"]), r,
                               rtol=1e-12)
    # the planar closed form (rings.ring_radii of a planar scene) of the same rotor
    p = fam.structure.params
    w = float(fam.drive.programme[-1, 1])
    b = fam.weights[0].balancer
    Ms = p["mass"] + float(np.sum(b.mass))
    X = w * w / (p["stiffness_x"] - Ms * w * w + 1j * w * p["damping_x"])
    Y = -1j * w * w / (p["stiffness_y"] - Ms * w * w + 1j * w * p["damping_y"])
    A, B = 0.5 * (X + 1j * Y), 0.5 * (np.conj(X) + 1j * np.conj(Y))
    gain = fam.instruments["screen"].gain
    assert r[1] == pytest.approx(gain * b.capacity / 16 * (abs(A) + abs(B)), rel=1e-9)


def test_probes_on_a_named_plane(tmp_path):
    text = (ROOT / "data_samples/scenes/family_two_mass.toml").read_text()
    text = text.replace("duration = 40.0", "duration = 2.0")
    text += '\n[instruments.probes]\nplane = "body"\nsample_rate = 200.0\n'
    sc = _load(tmp_path, text)
    run = stand.run(sc)
    path = stand.save(run, tmp_path / "p.h5")
    with h5py.File(path) as f:
        g = f["instruments/probes"]
        assert g.attrs["plane"] == "body"
        disp = g["displacement"][:]
        t = g["time"][:]
        ang = g["angles"][:]
    body = run.planes["body"]
    i = np.searchsorted(run.t, t)
    i = np.clip(i, 0, run.t.size - 1)
    exact = np.abs(run.t[i] - t) < 1e-12
    expect = body[i, 0, None] * np.cos(ang) + body[i, 1, None] * np.sin(ang)
    np.testing.assert_allclose(disp[exact], expect[exact], atol=1e-12)


def test_book_models_still_refuse_instruments():
    from stand.instruments.pipeline import run_with_instruments

    sc = stand.load(ROOT / "data_samples/scenes/weight_two_axis.toml")
    sc = dataclasses.replace(sc, instruments=dict(stand.load(
        ROOT / "data_samples/scenes/family_planar.toml").instruments))
    with pytest.raises(SceneError, match="book weight model"):
        run_with_instruments(sc)
