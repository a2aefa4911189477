"""Instruments see the body weights (issue 16, item 4).

Oracles:
* the stroboscope draws a two-axis pendulum's bob at its centre of mass,
  ``arm sin(tilt) (-sin angle, cos angle)`` from the shaft point: `stand strobe`
  reads the bob's direction back from the frames within 1 deg of the truth
  recorded at the flashes (and its apparent radial offset within a pixel);
* the liquid's crescent is the chamber disc minus the free-surface disc, so
  the first moment of the liquid's brightness about the chamber centre is
  ``-(contrast) pi r^2 s`` (``s`` the free-surface offset): the drawn surface
  sits where the truth says; the crescent's centroid is the liquid's centre of
  mass (``kappa = r^2/(R^2 - r^2)``);
* the screen camera films the shaft's spot whatever the weights: `stand track`
  finds it where the truth says;
* the instruments that need the shaft velocity get it from the generic
  kernel's state (finite differences of the recorded x agree).
"""
import json
import math
from types import SimpleNamespace

import h5py
import numpy as np
import pandas as pd
import pytest

from stand.cli.main import main
from stand.instruments.strobe_readings import body_looks, strobe_angles
from stand.instruments.strobe_render import LEVEL_FLOAT, LEVEL_INTERIOR, render_strobe_frames
from stand.scene.strobe_settings import Stroboscope
from stand.instruments.timing import shaft_velocity, wrap
from stand.scene.parse import load_scene
from stand.integrate.simulate import simulate

BASE = """
[scene]
name = "{name}"
[rotor]
mass = 3.0
eccentricity = 2.0e-4
[supports]
stiffness_x = 3.0e4
stiffness_y = 3.0e4
damping_x = 20.0
damping_y = 20.0
{weights}
[drive]
type = "speed"
programme = [[0.0, 0.0], [1.5, 25.0]]
[run]
duration = 3.0
sample_rate = 500.0
[instruments.stroboscope]
flash_angle = 90.0
slot_width = 0.003
slot_radius = 0.12
frame_every = 3
width = 160
height = 160
pixel_pitch = 1.6e-3
seed = 2
{extra}
"""
PENDULUM = """
[[weights]]
type = "two_axis_pendulum"
mass = 0.1
arm = 0.03
inertia_tilt = 1.2e-4
inertia_axial = 1.0e-4
tilt_drag = 2e-4
turn_drag = 2e-4
initial_tilt = 5.0
"""
DAMPER = """
[[weights]]
type = "damper"
mass = 0.1
arm = 0.03
inertia = 1.2e-4
drag = 2e-4
initial_tilt = 20.0
"""
CHAMBER = """
[[weights]]
type = "liquid_chamber"
chamber_radius = 0.08
chamber_height = 0.02
fill_volume = 1.5e-4
relaxation_time = 0.01
"""
FLOAT = """
[[weights]]
type = "liquid_float"
liquid_mass = 0.3
chamber_radius = 0.08
float_radius = 0.06
"""
SCREEN = """
[instruments.screen]
gain = 2.0
pixel_pitch = 2.5e-4
width = 96
height = 96
frame_rate = 4.0
exposure = 0.01
spot_diameter = 1.2e-3
peak = 4000.0
background = 8.0
read_noise = 1.0
bit_depth = 8
seed = 1
"""
PITCH = 1.6e-3


def _scene_file(tmp_path, name, weights, extra=""):
    path = tmp_path / f"{name}.toml"
    path.write_text(BASE.format(name=name, weights=weights, extra=extra))
    return path


def _run(tmp_path, name, weights, extra=""):
    scene = _scene_file(tmp_path, name, weights, extra)
    out = tmp_path / f"{name}.h5"
    assert main(["run", str(scene), "-o", str(out), "--no-progress"]) == 0
    return out


@pytest.fixture(scope="module")
def pendulum(tmp_path_factory):
    """The two-axis pendulum with a stroboscope and a screen camera, recorded."""
    return _run(tmp_path_factory.mktemp("pendulum"), "pendulum", PENDULUM, SCREEN)


# ---------------------------------------------------------------- stroboscope: pendulum
def test_strobe_reads_the_pendulums_bob_back_within_a_degree(pendulum, tmp_path):
    csv = tmp_path / "angles.csv"
    assert main(["strobe", str(pendulum), "-o", str(csv)]) == 0
    df = pd.read_csv(csv)
    with h5py.File(pendulum) as f:
        g = f["instruments/stroboscope"]
        drawn = json.loads(g.attrs["weights"])
        t = f["truth/stroboscope/two_axis1"]
        truth = {k: t[k][:, 0] for k in ("relative_azimuth", "radius", "angle", "tilt", "azimuth")}
        flash = g["flash_time"][:, 0]
        n_frames = g["frames"].shape[0]
        assert "relative_angle" not in f["truth/stroboscope"]     # no balls
    assert [w["name"] for w in drawn] == ["two_axis1"] and drawn[0]["drawn"] == "pendulum"
    assert drawn[0]["arm_m"] == 0.03 and drawn[0]["housing_radius_m"] == pytest.approx(0.0375)
    assert len(df) == n_frames >= 10
    np.testing.assert_allclose(df["time"], flash)
    # the truth is the centre of mass: arm sin(tilt) (-sin angle, cos angle)
    np.testing.assert_allclose(truth["radius"], 0.03 * np.abs(np.sin(truth["tilt"])), atol=1e-12)
    np.testing.assert_allclose(wrap(truth["azimuth"] - truth["angle"]),
                               np.where(np.sin(truth["tilt"]) > 0, 1, -1) * math.pi / 2,
                               atol=1e-9)
    # read back: every bob at least 4 px from the shaft point, within 1 deg
    seen = df["ok"].to_numpy(bool) & (truth["radius"] / PITCH > 4.0)
    assert seen.sum() >= 8
    err = wrap(np.radians(df["two_axis1_deg"].to_numpy()) - truth["relative_azimuth"])[seen]
    assert np.max(np.abs(np.degrees(err))) < 1.0
    # the reported uncertainty is honest (a few sigma) and the offset is read within a pixel
    assert np.all(np.abs(np.degrees(err)) < 5 * df["two_axis1_std_deg"][seen] + 0.3)
    np.testing.assert_allclose(df["two_axis1_radius_mm"][seen], truth["radius"][seen] * 1e3,
                               atol=PITCH * 1e3)
    # the mark at the flash angle
    np.testing.assert_allclose(df["mark_deg"][df["ok"]], 90.0, atol=0.5)


def test_strobe_truth_matches_the_run_at_the_flashes(tmp_path):
    """strobe_angles / render_strobe_frames on the Run: the bodies' truth is the run's
    coordinates at the flash instants; the frame draws the bob there."""
    scene = load_scene(_scene_file(tmp_path, "p", PENDULUM))
    run = simulate(scene)
    strobe = dict(scene.instruments)["stroboscope"]
    r = strobe_angles(run, strobe, 2.0, 3.0)
    assert r.t.size >= 20
    assert r.weight_angle.shape == (r.t.size, 0)                # the body is not a ball
    b = r.bodies["two_axis1"]
    # the same run sampled at the flash instants themselves (dense output, no interpolation)
    exact = simulate(scene, extra_times=r.t).extra.weights["two_axis1"]
    np.testing.assert_allclose(b["angle"], exact["angle"], atol=1e-5)
    np.testing.assert_allclose(b["tilt"], exact["tilt"], atol=1e-5)
    az = np.arctan2(np.sin(exact["tilt"]) * np.cos(exact["angle"]),
                    -np.sin(exact["tilt"]) * np.sin(exact["angle"]))
    assert np.max(np.abs(wrap(b["relative_azimuth"] - (az - r.rotor_angle)))) < 1e-4
    f = next(render_strobe_frames(run, strobe, 2.5, 3.0))
    d = f.bodies["two_axis1"]
    cx, cy = f.centre_px[0]
    np.testing.assert_allclose(d["px"][0], [cx + d["offset_x"][0] / strobe.pixel_pitch,
                                            cy - d["offset_y"][0] / strobe.pixel_pitch])
    # the rod: bright half-way between the pivot and the bob
    u, v = (np.array([cx, cy]) + d["px"][0]) / 2
    assert f.image[int(round(v)), int(round(u))] / 255 > 0.5


def test_strobe_snapshot_and_screen_of_a_body_scene(pendulum, tmp_path):
    import cv2

    for inst in ("strobe", "screen", "rings"):
        png = tmp_path / f"{inst}.png"
        assert main(["snapshot", str(pendulum), "--instrument", inst, "--frame", "-1",
                     "-o", str(png)]) == 0
        assert cv2.imread(str(png), cv2.IMREAD_GRAYSCALE).size > 0
    with h5py.File(pendulum) as f:
        assert f["truth/capacity"][()] == pytest.approx(0.1 * 0.03)       # m l of the body
        assert f["instruments/screen/ring_radius"].shape == (21,)
        truth_px = f["truth/screen/centre_px"][:]
        inside = f["truth/screen/in_frame"][:]
    csv = tmp_path / "track.csv"
    assert main(["track", str(pendulum), "-o", str(csv)]) == 0
    df = pd.read_csv(csv, comment="#")
    good = inside & df["ok"].to_numpy(bool)
    assert good.sum() >= 10
    err = np.hypot(df["u_px"] - truth_px[:, 0], df["v_px"] - truth_px[:, 1])[good]
    assert np.max(err) < 0.5


# ---------------------------------------------------------------- damper and liquids
def test_damper_renders_and_its_truth_is_recorded(tmp_path):
    out = _run(tmp_path, "damper", DAMPER)
    with h5py.File(out) as f:
        assert f["instruments/stroboscope/frames"].shape[0] >= 10
        t = f["truth/stroboscope/damper1"]
        n = np.stack([t[k][:] for k in ("n_x", "n_y", "n_z")], axis=-1)
        np.testing.assert_allclose(np.linalg.norm(n, axis=-1), 1.0, atol=1e-12)
        np.testing.assert_allclose(t["offset_x"][:], 0.03 * n[..., 0], atol=1e-15)
        np.testing.assert_allclose(t["radius"][:], 0.03 * np.hypot(n[..., 0], n[..., 1]))
        assert t["relative_azimuth"].attrs["units"] == "rad"
        drawn = json.loads(f["instruments/stroboscope"].attrs["weights"])
    assert drawn[0]["type"] == "damper" and drawn[0]["drawn"] == "pendulum"
    csv = tmp_path / "d.csv"
    assert main(["strobe", str(out), "-o", str(csv)]) == 0
    assert "damper1_deg" in pd.read_csv(csv)


@pytest.mark.parametrize("weights, name", [(CHAMBER, "chamber"), (FLOAT, "float")])
def test_liquid_renders_as_a_crescent_with_its_truth(tmp_path, weights, name):
    extra = "read_noise = 0.0\nfull_well = 0.0\n"   # [instruments.stroboscope] noiseless
    scene_path = _scene_file(tmp_path, name, weights)
    scene_path.write_text(scene_path.read_text().replace("seed = 2\n", "seed = 2\n" + extra, 1))
    out = tmp_path / f"{name}.h5"
    assert main(["run", str(scene_path), "-o", str(out), "--no-progress"]) == 0
    scene = load_scene(scene_path)
    (lk,) = body_looks(scene)
    with h5py.File(out) as f:
        frames = f["instruments/stroboscope/frames"][:]
        t = f["truth/stroboscope/liquid1"]
        lx, ly, sx, sy = (t[k][:, 0] for k in ("liquid_x", "liquid_y", "surface_x", "surface_y"))
        centre = f["truth/stroboscope/centre_px"][:, 0]
        surf_px = t["px"][:, 0]
        assert json.loads(f["instruments/stroboscope"].attrs["weights"])[0]["drawn"] == "crescent"
        assert f["truth/capacity"][()] == pytest.approx(lk.mass * lk.kappa * (lk.chamber_radius
                                                                              - lk.surface_radius))
    # the free surface is -liquid / kappa from the chamber centre (the lever: on the bearing axis)
    np.testing.assert_allclose(sx, -lx / lk.kappa, atol=1e-3 * np.max(np.abs(lx)) / lk.kappa)
    np.testing.assert_allclose(sy, -ly / lk.kappa, atol=1e-3 * np.max(np.abs(ly)) / lk.kappa)
    np.testing.assert_allclose(surf_px, centre + np.column_stack([sx, -sy]) / PITCH, atol=1e-9)
    # the drawing: the free-surface disc is the only non-liquid part of the chamber
    for k in range(frames.shape[0]):
        s_px = _surface_offset_px(frames[k].astype(float) / 255, centre[k], lk, name)
        np.testing.assert_allclose(s_px, [sx[k] / PITCH, -sy[k] / PITCH], atol=0.05)


def _surface_offset_px(img, centre, lk, name):
    """Free-surface centre from the chamber centre (column, row) [px] from a noiseless frame.

    Inside the chamber (R - 3 px) the frame is liquid but on the free-surface disc (air,
    or the float): the first moment of (image - liquid level) about the chamber centre is
    -(contrast) pi r^2 s, with no contribution from the liquid nor from the cut.
    """
    R, r = lk.chamber_radius / PITCH, lk.surface_radius / PITCH
    inside = LEVEL_INTERIOR if name != "float" else LEVEL_FLOAT
    H, W = img.shape
    V, U = np.mgrid[0:H, 0:W]
    d = np.hypot(U - centre[0], V - centre[1])
    ref = np.median(img[(d > R - 6) & (d < R - 3)])            # the liquid's level, quantised
    sel = d < R - 3
    w = img[sel] - ref
    m = np.array([np.sum(w * (U[sel] - centre[0])), np.sum(w * (V[sel] - centre[1]))])
    return -m / ((ref - inside) * math.pi * r * r)


def test_crescent_of_a_large_offset_points_at_the_liquids_centre_of_mass(tmp_path):
    """A synthetic run with the free surface 6 px off the chamber centre: the liquid's
    pixels have their centroid at the liquid's centre of mass (kappa times the offset,
    reversed), in the fixed frame of the picture."""
    scene = load_scene(_scene_file(tmp_path, "c", CHAMBER))
    (lk,) = body_looks(scene)
    t = np.linspace(0.0, 1.0, 201)
    w = 2 * math.pi * 10.0
    s = np.array([6.0, -4.0]) * PITCH                     # free surface from the chamber centre
    liquid = -lk.kappa * s
    run = SimpleNamespace(t=t, x=0 * t, y=0 * t, rotor_angle=w * t, rotor_speed=w + 0 * t,
                          scene=scene, weights={"liquid1": {"liquid_x": liquid[0] + 0 * t,
                                                            "liquid_y": liquid[1] + 0 * t}},
                          weight_angle=np.zeros((t.size, 0)), weight_speed=np.zeros((t.size, 0)))
    strobe = Stroboscope(flash_angle=0.3, width=160, height=160, pixel_pitch=PITCH,
                         shaft_motion=False, read_noise=0.0, full_well=0.0)
    f = next(render_strobe_frames(run, strobe, 0.2, 1.0))
    cu, cv = f.centre_px[0]
    np.testing.assert_allclose(f.bodies["liquid1"]["px"][0], [cu + 6.0, cv + 4.0])
    s_px = _surface_offset_px(f.image.astype(float) / 255, (cu, cv), lk, "chamber")
    np.testing.assert_allclose(s_px, [6.0, 4.0], atol=0.05)
    # the crescent's centroid, kappa (-s), is the liquid's centre of mass of the truth
    np.testing.assert_allclose(f.bodies["liquid1"]["liquid_x"], liquid[0], rtol=1e-12)
    np.testing.assert_allclose(-lk.kappa * s_px * PITCH, [liquid[0], -liquid[1]],
                               atol=0.05 * lk.kappa * PITCH)


# ---------------------------------------------------------------- shaft velocity
def test_shaft_velocity_of_a_body_run_from_the_generic_state(tmp_path):
    run = simulate(load_scene(_scene_file(tmp_path, "v", PENDULUM)))
    vx, vy = shaft_velocity(run)
    gx, gy = np.gradient(run.x, run.t), np.gradient(run.y, run.t)
    scale = np.max(np.hypot(vx, vy))
    assert scale > 0
    assert np.max(np.abs(vx - gx)[2:-2]) < 0.05 * scale
    assert np.max(np.abs(vy - gy)[2:-2]) < 0.05 * scale
