"""Calibration of the stated uncertainties on the image, track and line paths (issue 30).

The paths of :mod:`bench_uncertainty` that are not a run-up: each function
``path(seed, workdir) -> {quantity: z or None}`` draws one noise realisation of a
closed-form truth, runs the stand's estimator as a lab does and returns
z = (estimate − truth) / std of every reported quantity with a ±.  :data:`PATHS`
maps the path names to them (merged into ``bench_uncertainty``'s registry).

* ``lines``: :func:`dsp.lines.refine_frequencies` on two complex exponentials
  (7.3 Hz, |a| = 1 and 23.1 Hz, |a| = 0.3; 200 samples/s for 10 s) in complex white
  noise of E|n|² = 0.5² -- frequencies and |a| of both lines;
* ``lines-close``: the same with the second line 0.8 / T above the first (closer than
  a main lobe: the sequential search and the joint fit);
* ``sinusoids``: two real sinusoids (7.3 Hz, A = 1 and 23.1 Hz, A = 0.3) in real white
  noise of std 0.5: four lines (+- pairs), each sinusoid's f and A = 2 |a|;
* ``precession``: ``stand analyze``'s quasi-periodic step
  (:func:`dsp.quasiperiodic.decompose`, Hann search, unweighted polish) on a precession
  line Omega = 4.1 Hz (|a| 1.0) and a nutation line omega = 21.7 Hz (|a| 0.4, the rotor
  speed) with an offset -- Omega, omega, both amplitudes and phases;
* ``track-rings``: a ``stand track --calibration`` CSV (:func:`track_csv`): the spot
  drawing a circle of known radius on the screen, read with px noise and a ring scale
  [mm/px] that carries its own calibration error (common to all frames), through
  ``stand analyze``: the circle's radius, the unbalance interpolated between the rings
  and the ISO grade;
* ``two-plane``: two screens' tracks written from the closed form
  z_k(t) = Z_k e^{i phi(t)} + noise with Z from a chosen pair of plane unbalances
  through the stand's own receptance (taken as exact), through
  ``stand analyze RUN.h5 --tracks``: each plane's correction (g mm and angle).
"""
from __future__ import annotations

import io
import json
import math
from contextlib import redirect_stderr, redirect_stdout
from pathlib import Path

import numpy as np

TWO_PI = 2 * math.pi


def _z(est, truth, std):
    return None if est is None or not std else (est - truth) / std


def _zang(est_rad, truth_rad, std_rad):
    """z of an angle: the wrapped difference."""
    if est_rad is None or not std_rad:
        return None
    return (math.remainder(est_rad - truth_rad, TWO_PI)) / std_rad


def _cli(args):
    """``stand ARGS --json`` in this process: the JSON document."""
    from stand.cli.main import main

    out, err = io.StringIO(), io.StringIO()
    with redirect_stdout(out), redirect_stderr(err):
        code = main(args)
    if code != 0:
        raise RuntimeError(err.getvalue())
    return json.loads(out.getvalue())


# ------------------------------------------------------------------------ lines
#: two complex exponentials in complex white noise (sigma: sqrt(E|n|^2))
LINES = {"fs_hz": 200.0, "duration_s": 10.0, "f_hz": (7.3, 23.1), "a": (1.0, 0.3 * np.exp(1j)),
         "sigma": 0.5}


def _lines_signal(seed, f_hz, a, fs_hz, duration_s, sigma, offset=0j):
    rng = np.random.default_rng(seed)
    t = np.arange(int(round(fs_hz * duration_s))) / fs_hz
    z = offset + sum(ak * np.exp(TWO_PI * 1j * fk * t) for fk, ak in zip(f_hz, a))
    n = sigma / math.sqrt(2) * (rng.standard_normal(t.size) + 1j * rng.standard_normal(t.size))
    return t, z + n


def lines(seed, workdir=None, *, close=False, **kw):
    """z of f and |a| of both lines (:func:`dsp.lines.refine_frequencies`)."""
    from dsp.lines import refine_frequencies

    p = {**LINES, **kw}
    if close:
        p["f_hz"] = (p["f_hz"][0], p["f_hz"][0] + 0.8 / p["duration_s"])
    t, z = _lines_signal(seed, **p)
    c = refine_frequencies(t, z, 2)
    out = {}
    for k, (f, a) in enumerate(zip(p["f_hz"], p["a"])):       # match by frequency
        j = int(np.argmin(np.abs(c.frequency_hz - f)))
        out[f"f{k + 1}"] = _z(c.frequency_hz[j], f, c.frequency_hz_std[j])
        out[f"A{k + 1}"] = _z(abs(c.amplitude[j]), abs(a), c.amplitude_std[j])
    return out


def lines_close(seed, workdir=None, **kw):
    return lines(seed, workdir, close=True, **kw)


#: two real sinusoids A cos(2 pi f t + p) in real white noise of std sigma
SINUSOIDS = {"fs_hz": 200.0, "duration_s": 10.0, "f_hz": (7.3, 23.1), "A": (1.0, 0.3),
             "phase": (0.3, -1.0), "sigma": 0.5}


def sinusoids(seed, workdir=None, **kw):
    """z of f and A of both sinusoids: a real signal's lines come in +- pairs (4 lines
    fitted); each sinusoid read from its positive line, A = 2 |a|."""
    from dsp.lines import refine_frequencies

    p = {**SINUSOIDS, **kw}
    rng = np.random.default_rng(seed)
    t = np.arange(int(round(p["fs_hz"] * p["duration_s"]))) / p["fs_hz"]
    x = sum(A * np.cos(TWO_PI * f * t + ph) for f, A, ph in zip(p["f_hz"], p["A"], p["phase"]))
    c = refine_frequencies(t, x + p["sigma"] * rng.standard_normal(t.size), 4)
    out = {}
    for k, (f, A) in enumerate(zip(p["f_hz"], p["A"])):
        j = int(np.argmin(np.abs(c.frequency_hz - f)))
        out[f"f{k + 1}"] = _z(c.frequency_hz[j], f, c.frequency_hz_std[j])
        out[f"A{k + 1}"] = _z(2 * abs(c.amplitude[j]), A, 2 * c.amplitude_std[j])
    return out


#: precession + nutation (the rotor speed) + an offset, as ``stand analyze`` decomposes
PRECESSION = {"fs_hz": 200.0, "duration_s": 10.0, "f_hz": (4.1, 21.7),
              "a": (1.0 * np.exp(0.4j), 0.4 * np.exp(-2.0j)), "sigma": 0.5, "offset": 0.2 + 0.1j}


def precession(seed, workdir=None, **kw):
    """z of Omega, omega, their amplitudes and phases (:func:`dsp.quasiperiodic.decompose`
    with the arguments of ``stand analyze``)."""
    from dsp import quasiperiodic as qpd

    p = {**PRECESSION, **kw}
    t, z = _lines_signal(seed, **p)
    fP, fN = p["f_hz"]
    dec = qpd.decompose(t, z, rotor_speed_hz=fN, polish="rect")
    tr = 0.5 * (t[0] + t[-1])               # the decomposition's amplitudes are at mid-record
    aP, aN = (ak * np.exp(TWO_PI * 1j * fk * tr) for fk, ak in zip(p["f_hz"], p["a"]))
    P, N = dec.precession, dec.nutation
    return {"Omega": _z(dec.precession_hz, fP, dec.precession_std_hz),
            "omega": _z(dec.nutation_hz, fN, dec.nutation_std_hz),
            "A_Omega": _z(dec.precession_amplitude_m, abs(aP), dec.precession_amplitude_std_m),
            "A_omega": _z(dec.nutation_amplitude_m, abs(aN), dec.nutation_amplitude_std_m),
            "phase_Omega": _zang(P.phase_rad, np.angle(aP), P.phase_std_rad),
            "phase_omega": _zang(N.phase_rad, np.angle(aN), N.phase_std_rad)}


PATHS = {"lines": lines, "lines-close": lines_close, "sinusoids": sinusoids,
         "precession": precession}


# ------------------------------------------------------------------ track + rings
#: the laser spot drawing a circle on the screen, filmed at 50 frames/s, read with px
#: noise; the rings of zones 0..16 every 0.6 mm (S = 7200 g mm), the ring scale 0.1 mm/px
#: stated with a 0.3 % calibration uncertainty; a 2 kg rotor at 1500 rpm for the grade
TRACK = {"radius_mm": 4.1, "ring_step_mm": 0.6, "capacity_gmm": 7200.0, "scale_mm_per_px": 0.1,
         "scale_rel_std": 3e-3, "noise_px": 2.0, "frames": 300, "frame_rate_hz": 50.0,
         "spot_hz": 12.3, "optical_gain": 6.0, "mass_kg": 2.0, "service_rpm": 1500.0}


def track_truth(p=None) -> dict:
    """The closed-form truth of :data:`TRACK`: circle radius [mm], unbalance [g mm] (linear
    between equally spaced rings: r / step x S / 16) and the ISO grade G [mm/s]."""
    p = {**TRACK, **(p or {})}
    U = p["radius_mm"] / p["ring_step_mm"] * p["capacity_gmm"] / 16.0
    w = p["service_rpm"] * TWO_PI / 60.0
    return {"radius_mm": p["radius_mm"], "U_gmm": U, "G_mm_s": U * w / (1000.0 * p["mass_kg"])}


def track_csv(seed, workdir, **kw):
    """A ``stand track --calibration`` CSV of :data:`TRACK` for one draw, and its map.

    The spot's centre [px] is drawn with Gaussian noise ``noise_px`` on each axis; the
    ring scale written is the true one times (1 + e), e ~ N(0, scale_rel_std) -- one
    draw per track, as one ring calibration serves every frame -- and stated with that
    std; the columns in mm and m follow from the written scale, as ``stand track``
    computes them."""
    import pandas as pd

    from stand.analysis.tracking import write_track_csv

    p = {**TRACK, **kw}
    rng = np.random.default_rng(seed)
    s0 = p["scale_mm_per_px"]
    s = s0 * (1.0 + p["scale_rel_std"] * rng.standard_normal())        # the calibration's
    n = int(p["frames"])
    t = np.arange(n) / p["frame_rate_hz"]
    th = TWO_PI * p["spot_hz"] * t + 0.7
    uc, vc = 160.0, 150.0                                       # the ring centre [px]
    r_px = p["radius_mm"] / s0
    u = uc + 0.8 + r_px * np.cos(th) + p["noise_px"] * rng.standard_normal(n)   # a circle a
    v = vc - 0.5 - r_px * np.sin(th) + p["noise_px"] * rng.standard_normal(n)   # bit off-centre
    X, Y = (u - uc) * s, -(v - vc) * s                          # [mm] through the stated scale
    g = p["optical_gain"]
    df = pd.DataFrame({"frame": np.arange(n), "time": t, "u_px": u, "v_px": v,
                       "u_std_px": p["noise_px"], "v_std_px": p["noise_px"], "ok": True,
                       "x_mm": X, "y_mm": Y, "scale_mm_per_px": s, "t_s": t,
                       "x_m": X * 1e-3 / g, "y_m": Y * 1e-3 / g})
    radii = np.arange(17) * p["ring_step_mm"] * 1e-3
    df.attrs["preamble"] = {"source": "closed-form circle", "optical_gain": repr(g),
                            "ring_radii_m": ",".join(repr(float(r)) for r in radii),
                            "capacity_gmm": repr(p["capacity_gmm"]), "exposure_s": "0.0",
                            "scale_mm_per_px": repr(s),
                            "scale_std_mm_per_px": repr(s * p["scale_rel_std"])}
    csv = Path(workdir) / f"track_{seed}.csv"
    write_track_csv(df, csv)
    rmap = csv.with_suffix(".map.toml")
    rmap.write_text(f'[rotor]\nmass = "{p["mass_kg"]} kg"\n'
                    f'service_speed = "{p["service_rpm"]} rpm"\n')
    return csv, rmap


def track_rings(seed, workdir, **kw):
    """z of the circle radius, the unbalance interpolated between the rings and the ISO
    grade of ``stand analyze TRACK.csv --map MAP``."""
    csv, rmap = track_csv(seed, workdir, **kw)
    d = _cli(["analyze", str(csv), "--json", "--map", str(rmap)])
    tr = track_truth(kw)
    ring, iso = d.get("ring_reading") or {}, d.get("iso_grade") or {}
    return {"radius": _z(ring.get("circle_radius_mm"), tr["radius_mm"],
                         ring.get("circle_radius_mm_std")),
            "U": _z(d.get("unbalance_gmm"), tr["U_gmm"], d.get("unbalance_gmm_std")),
            "G": _z(iso.get("achieved_grade_mm_s"), tr["G_mm_s"], iso.get("achieved_grade_mm_s_std"))}


PATHS["track-rings"] = track_rings


# ---------------------------------------------------------------------- two planes
#: the paper-003 rotor of data_samples/scenes/paper003_two_screens.toml run for 1 s at
#: 30 rev/s (the recording gives the rotor angle, the screens' positions and the model's
#: receptance); the tracks: 97 frames/s of each screen, the closed-form axis points of the
#: plane unbalances U1, U2 [kg m] with circular Gaussian noise (per axis, m)
TWO_PLANE = {"U": (2.0e-3 * np.exp(0.7j), 0.8e-3 * np.exp(3.5j)), "frame_rate_hz": 97.0,
             "noise_m": 3e-6}
SCENE_2P = Path(__file__).resolve().parents[1] / "data_samples" / "scenes" / \
    "paper003_two_screens.toml"


def two_plane_recording(workdir) -> Path:
    """``stand run`` of the two-screen scene shortened to 1 s (once per ``workdir``)."""
    from stand.cli.main import main

    rec = Path(workdir) / "two_plane_run.h5"
    if not rec.exists():
        text = SCENE_2P.read_text().replace("duration = 5.0", "duration = 1.0") \
            .replace("[[0.0, 30.0], [5.0, 30.0]]", "[[0.0, 30.0], [1.0, 30.0]]") \
            .replace("start_time = 2.5", "start_time = 0.0")
        scene = Path(workdir) / "two_plane.toml"
        scene.write_text(text)
        with redirect_stdout(io.StringIO()), redirect_stderr(io.StringIO()):
            if main(["run", str(scene), "-o", str(rec), "--no-progress"]) != 0:
                raise RuntimeError("stand run of the two-plane scene failed")
    return rec


def two_plane_tracks(seed, workdir, **kw):
    """The two screens' tracks of one draw: ``(recording, [csv, csv], truth U [kg m])``.

    The stand's own chain taken as exact (the model's receptance H at the drive's speed,
    the axis line (4.2) through the screens): the screens' rotor-frame phasors are
    Z = L^-1 H U, each frame sees Z e^{i phi(t)} (shortened by the exposure's blur as the
    stand divides it out) plus noise."""
    import json as _json

    import pandas as pd

    from stand.analysis.two_plane import _correction_planes, _forward
    from stand.integrate.coupled import with_locked_weights
    from stand.recording.hdf5 import read_recording

    p = {**TWO_PLANE, **kw}
    rec_path = two_plane_recording(workdir)
    rec = read_recording(rec_path)
    scene = rec.scene
    planes = _correction_planes(scene)
    t_rec = np.asarray(rec.t, float)
    phi_rec = np.unwrap(np.asarray(rec.rotor_angle, float))
    omega = TWO_PI * 30.0
    rotor = with_locked_weights(scene.linear_rotor(), scene.weights, scene.bodies)
    H = np.array([[_forward(rotor.unbalance_response(omega, pj, at=pi)) for pj, _ in planes]
                  for pi, _ in planes])
    U = np.asarray(p["U"], complex)
    P = H @ U
    names = ("screen.front", "screen.rear")
    d = [float(rec.dataset_attrs(f"instruments/{n}")["axial_position_m"]) for n in names]
    L = np.array([[(d[1] - a) / (d[1] - d[0]), (a - d[0]) / (d[1] - d[0])] for _, a in planes])
    Z = np.linalg.solve(L, P)
    rng = np.random.default_rng(seed)
    t = np.arange(0.05, t_rec[-1] - 0.01, 1.0 / p["frame_rate_hz"])
    phi = np.interp(t, t_rec, phi_rec)
    csvs = []
    for name, z0 in zip(names, Z):
        expo = float(_json.loads(rec.dataset_attrs(f"instruments/{name}")
                                 .get("settings", "{}")).get("exposure", 0.0))
        h = 0.5 * omega * expo
        z = z0 * (math.sin(h) / h if h else 1.0) * np.exp(1j * phi) \
            + p["noise_m"] * (rng.standard_normal(t.size) + 1j * rng.standard_normal(t.size))
        csv = Path(workdir) / f"two_plane_{name}_{seed}.csv"
        pd.DataFrame({"t_s": t, "x_m": z.real, "y_m": z.imag, "ok": True,
                      "screen": name}).to_csv(csv, index=False)
        csvs.append(csv)
    return rec_path, csvs, U


def two_plane(seed, workdir, **kw):
    """z of each plane's correction (g mm, angle) of ``stand analyze RUN.h5 --tracks``."""
    rec, csvs, U = two_plane_tracks(seed, workdir, **kw)
    doc = _cli(["analyze", str(rec), "--tracks", *map(str, csvs), "--json"])
    out = {}
    for k, (row, u) in enumerate(zip(doc["planes"], U), start=1):
        out[f"U{k}"] = _z(row["unbalance_gmm"], abs(u) * 1e6, row["unbalance_gmm_std"])
        sa = row.get("angle_deg_std")
        out[f"angle{k}"] = _zang(math.radians(row["angle_deg"]), float(np.angle(u)),
                                 math.radians(sa) if sa else None)
    return out


PATHS["two-plane"] = two_plane

# ---------------------------------------------------------------- camera artefacts (issue 42)
from _uncertainty_camera import PATHS as _CAMERA_PATHS  # noqa: E402  (lens, JPEG, flicker)

PATHS.update(_CAMERA_PATHS)
