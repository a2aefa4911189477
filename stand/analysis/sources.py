"""The first step of ``stand analyze``: a recording's channels as arrays.

Whatever the source -- a :class:`stand.Run` in memory, a :class:`stand.Recording`, a
stand recording file, or a lab table (CSV, Parquet, pandas HDF5, read by
:func:`stand.lab.table.read_table` with its recording map) -- :func:`read_source`
returns one dict: ``t`` [s], ``x``, ``y`` [m], ``phi`` (the rotor angle [rad] or None),
``weights`` (weight angles [rad] or None), ``scene`` (the planar scene whose model
turns a 1X response into an unbalance, or None), ``notes``, ``angle`` (a
:class:`dsp.speed.RotorAngle` or None), ``speed_how`` (where the speed comes from),
``table`` (the lab table or None), ``quantity`` (what x and y measure: ``length``,
``velocity`` [m/s] or ``acceleration`` [m/s²]; a Run's are ``length``), and for a Run or
recording ``mass_kg`` (the scene's total mass when the run-up model is fitted),
``probes`` (the displacement probes analysed, or None), ``rotor_speed`` (the recorded
rotor speed [rad/s] on ``t``, or None: it tells a rotor turning half a revolution or more
per sample, whose sampled angle no longer shows its speed; :func:`undersampled`) and
``residual_ratio`` (a rotor of the family: its planes' recorded residual over S_p / 16,
:func:`_residual_ratio`).  A recording with displacement probes is analysed through them, as a lab would (:func:`from_run`); without, through the
simulator's noise-free shaft state.  :func:`whirls` tells whether a record without a
speed channel comes from a spinning shaft.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

__all__ = ["read_source", "from_table", "from_run", "whirls", "no_weights", "undersampled",
           "undersampled_words", "weightless_scene"]

TWO_PI = 2 * math.pi


def read_source(path, recording_map=None):
    """The arrays of a Run, a Recording, a stand recording file or a lab table."""
    from stand.lab.table import is_table
    from stand.recording.hdf5 import read_recording
    from stand.integrate.result import Run

    if isinstance(path, Run):
        return from_run(path)
    p = Path(path)
    if is_table(p):
        from stand.lab.bode_table import is_bode_map, read_bode_table

        if is_bode_map(recording_map):
            return dict(bode=read_bode_table(p, recording_map), notes=[])
        return from_table(p, recording_map)
    _refuse_unknown(p)
    d = from_run(read_recording(p))
    if recording_map is not None and recording_map.columns:   # e.g. a folder of mixed files
        d["notes"].append("the recording map applies to tables; this stand recording carries "
                          "its own channels (map ignored)")
    return d


def _refuse_unknown(p: Path) -> None:
    """A file that is neither a table by its name nor HDF5: one line listing what is read."""
    import h5py

    from stand.lab.formats import FORMATS_READ
    from stand.lab.table import TableError

    if not p.is_file():
        return                                   # the recording reader says what is missing
    try:
        hdf5 = h5py.is_hdf5(str(p))
    except OSError:
        return
    if not hdf5:
        raise TableError(f"{p}: not a format that is read (suffix {p.suffix or 'none'!r}, no HDF5 "
                         f"signature); stand analyze reads: {'; '.join(FORMATS_READ)}")


def from_table(p, recording_map):
    """A lab table (:func:`stand.lab.table.read_table`) and its rotor angle."""
    from stand.lab.speed_source import rotor_angle_of
    from stand.lab.table import read_table

    tab = read_table(p, recording_map)
    notes = _excluded_notes(tab.excluded)
    if tab.censored is not None:
        notes.append(f"clipped samples censored ({int(tab.censored.sum())}, "
                     f"{100 * tab.censored.mean():.2g} %: left out of the model fit and of the "
                     "1X per revolution, the time base kept): " + "; ".join(tab.censored_what))
    angle, how = rotor_angle_of(tab, notes)
    t, x, y, cens = tab.t, tab.signals["x"], tab.signals["y"], tab.censored
    phi = None
    if angle is not None and angle.referenced:
        c = angle.covered
        if not c.all():
            notes.append(f"samples outside the first and last keyphasor pulse left out "
                         f"({int((~c).sum())})")
        t, x, y, phi = t[c], x[c], y[c], angle.angle_rad[c]
        cens = None if cens is None else cens[c]
        from dataclasses import replace

        angle = replace(angle, angle_rad=angle.angle_rad[c], speed_rad_s=angle.speed_rad_s[c],
                        acceleration_rad_s2=angle.acceleration_rad_s2[c],
                        covered=np.ones(int(c.sum()), bool))
    if tab.quantity != "length":
        notes.append(_SUPPORT_MODEL)
    flt = {tab.columns[r].filter for r in ("x", "y") if r in tab.columns}
    if len(flt) > 1:
        from stand.lab.table import TableError

        said = [tab.columns[r].filter for r in ("x", "y")]
        raise TableError(f"{p}: x and y declare different filters ({said[0] and said[0].describe()}"
                         f" / {said[1] and said[1].describe()}); both probes go through one filter")
    return dict(t=t, x=x, y=y, phi=phi, kp=None, weights=None, scene=None, notes=notes,
                angle=angle, speed_how=how, table=tab, quantity=tab.quantity, censored=cens,
                channel_filter=flt.pop() if flt else None)


def _excluded_notes(excluded) -> list:
    """One note per kind of excluded rows (the reason without its numbers), with the
    count and the rows' range."""
    import re

    kinds = {}
    for e in excluded:
        kinds.setdefault(re.sub(r"-?\d[\d.e+-]*", "#", e["reason"]), []).append(e)
    notes = []
    for es in kinds.values():
        if len(es) == 1:
            notes.append(f"excluded rows {es[0]['rows']}: {es[0]['reason']}")
        else:
            notes.append(f"excluded rows {es[0]['rows']} ... {es[-1]['rows']} ({len(es)} places): "
                         f"{es[0]['reason']} ...")
    return notes


_SUPPORT_MODEL = ("velocity / acceleration channels: taken as the motion of the rotor's centre "
                  "(the rigid rotor on isotropic supports, the sensors on bearing housings that "
                  "move with the journal: no relative motion between shaft and housing); the "
                  "model's response is differentiated to the channel's quantity, nothing is "
                  "integrated")


def from_run(rec):
    """The arrays of a Run or Recording; the scene only where the model parts apply (the
    planar rotor of chapter 5).

    With displacement probes (``instruments/probes`` of a recording, ``run.instruments
    ["probes"]`` in memory) the record is analysed as a lab would: the probes' own time
    base and signals (x, y solved from the probes' projections, with their noise,
    quantisation and runout) and the rotor angle of the recording's encoder (``rotor/angle``
    interpolated onto the probe times).  A planar rotor without weights then goes through
    the run-up model fit like a lab table (``scene`` None, the scene's total mass as
    ``mass_kg``; its f0 and damping only as a cross-check in ``notes``).  Without probes the
    simulator's shaft state (``shaft/x``, ``shaft/y``) is analysed, noise-free.
    """
    from stand.recording.probes import probe_channels, probes_xy

    rscene = rec.scene
    scene = rscene if getattr(rscene, "kind", None) == "planar" else None
    notes = list(rec.notes)
    t = np.asarray(rec.t)
    phi = rec.rotor_angle if np.all(np.isfinite(rec.rotor_angle)) else None
    w = rec.weight_angle if rec.weight_angle.size and np.all(np.isfinite(rec.weight_angle)) else None
    x, y = np.asarray(rec.x), np.asarray(rec.y)
    ws = np.asarray(getattr(rec, "rotor_speed", np.zeros(0)), float)
    ws = ws if ws.shape == t.shape and np.all(np.isfinite(ws)) else None
    ratio = _residual_ratio(rec, rscene)
    pr = probe_channels(rec)
    xy = None if pr is None else probes_xy(pr["signal"], pr["angles"], notes)
    mass = None
    if xy is not None and pr["time"].size > 1:
        tp = pr["time"]
        if phi is not None:
            from scipy.interpolate import CubicSpline

            ph = np.unwrap(np.asarray(phi, float))
            try:
                phi = CubicSpline(t, ph)(tp)
            except ValueError:                  # times not strictly increasing
                phi = np.interp(tp, t, ph)
        if w is not None:
            wa = np.unwrap(np.asarray(w, float), axis=0).reshape(t.size, -1)
            w = np.column_stack([np.interp(tp, t, c) for c in wa.T]).reshape((tp.size,) +
                                                                                 np.shape(w)[1:])
        if ws is not None:
            ws = np.interp(tp, t, ws)
        if ratio is not None:
            ratio = np.interp(tp, t, ratio)
        t, (x, y) = tp, xy
        deg = ", ".join(f"{math.degrees(a):g}" for a in pr["angles"])
        plane = f" in plane {pr['plane']!r}" if pr.get("plane") else ""
        notes.append(f"analysed the displacement probes (instruments/probes{plane}: "
                     f"{len(pr['angles'])} probes at {deg} deg, {t.size} samples at "
                     f"{1.0 / float(np.median(np.diff(t))):.6g} samples/s; x, y solved from the "
                     "probes' projections, with their noise, quantisation and runout) and the "
                     "rotor angle of the recording's encoder (rotor/angle interpolated onto the "
                     "probe times), as a lab would; not the simulator's shaft state")
        if scene is not None and no_weights(scene):
            mass = float(scene.total_mass)
            s = scene.supports
            notes.append(f"the recording's scene says f0 = {scene.natural_frequency / TWO_PI:.6g} Hz, "
                         f"zeta = {c_over_ccrit(scene):.4g} (cross-check only: f0, zeta and the "
                         "unbalance are fitted to the probes)" if s.stiffness_x > 0 else
                         "the recording's scene has no support stiffness (no cross-check)")
            scene = None                        # the run-up model is fitted, as on a lab table
    elif pr is None:
        notes.append("no displacement probes in the recording: the simulator's shaft state "
                     "(shaft/x, shaft/y) is analysed, noise-free; its ± are numerical only "
                     "(add [instruments.probes] to the scene to see what a lab sees)")
    angle = None
    if phi is not None and t.size > 1:
        from dsp.speed import RotorAngle

        # the simulator's encoder is exact (no count quantum for a spline to average, as
        # dsp.speed.angle_from_encoder does for a lab's encoder column): central differences
        # are exact on the drive programme's quadratic angle, O(N) on long records, and
        # follow its acceleration steps (the spline with a knot every 8 revolutions left f0
        # +4e-4 and zeta -0.45 % at a ramp -> hold corner; its dense design matrix grows as
        # samples x revolutions)
        ph = np.unwrap(np.asarray(phi, float))
        wr = np.gradient(ph, t)
        angle = RotorAngle(ph, wr, np.gradient(wr, t), np.ones(t.size, bool), "rotor angle",
                           referenced=True)
    return dict(t=t, x=x, y=y, phi=phi, kp=None, weights=w, scene=scene, notes=notes,
                angle=angle, speed_how="the recording's rotor angle" if phi is not None
                else "no rotor angle", table=None, rec_scene=rscene, mass_kg=mass,
                rotor_speed=ws, residual_ratio=ratio,
                probes=pr if xy is not None else None, truth=_truth(rec), rings=_rings(rec),
                scene_name=str((getattr(rec, "attrs", None) or {}).get("scene_name")
                               or getattr(rscene, "name", "") or ""),
                solver=dict(getattr(rec, "solver", None) or getattr(rec, "stats", None) or {}),
                channel_filter=_probe_filter(rscene) if xy is not None else None,
                censored=_clipped_probes(t, x, y, notes) if xy is not None else None)


def _residual_ratio(rec, scene):
    """A rotor of the family with weights: its static residual unbalance (every plane's
    ``truth/residual/<plane>`` summed: :func:`stand.integrate.residual.static_residual`,
    the rule of the run's summary and the sweep) [kg m] over the ring of zone 1 of the
    capacity of all its weights, S / 16 (``(N,)``, below 1: balanced), or None (a planar
    rotor, no weights, no truth).  A plane alone is no residual where the unbalance sits in
    a plane of its own (grinding, spatial)."""
    from stand.integrate.residual import static_residual

    weights = getattr(scene, "weights", None) or ()
    if getattr(scene, "kind", None) in (None, "planar") or not weights:
        return None
    S = scene.weights_capacity()
    try:
        U = static_residual(rec)
    except (AttributeError, TypeError, ValueError):
        return None
    if U is None or not S > 0 or np.shape(U) != (np.size(rec.t),):
        return None
    return np.abs(U) / (S / 16)


def _clipped_probes(t, x, y, notes):
    """The probes' clipped samples (at their ADC range), bridged in x and y (in place) and
    returned as the censoring mask, or None."""
    from dsp.artefacts import clipped, filled

    m = clipped(x) | clipped(y)
    if not m.any():
        return None
    x[:], y[:] = filled(t, x, m), filled(t, y, m)
    notes.append(f"clipped probe samples censored ({int(m.sum())}, {t[m][0]:.6g}-{t[m][-1]:.6g} "
                 "s: left out of the model fit and of the 1X per revolution, the time base kept)")
    return m


def _probe_filter(scene):
    """The probes' DAQ filter the scene declares (``[instruments.probes] filter``), or None."""
    from stand.instruments.probes import channel_filter

    probes = (getattr(scene, "instruments", None) or {}).get("probes")
    return None if probes is None else channel_filter(probes)


def _truth(rec):
    """``(t [s], static residual unbalance [kg m], complex)`` of a simulated run with weights
    and instruments, or None: what the identified residual is checked against.

    The static residual is the vector sum over all planes of the unbalances and the
    weights' static moments (:func:`stand.integrate.residual.static_residual`): a rotor whose
    unbalance sits in a plane of its own (grinding, spatial) has it in
    ``truth/residual/<its plane>``, not with the balls.  A recording holds the truth when it
    was written with instruments (``truth/residual_unbalance``); its per-plane datasets give
    the sum (recordings written before the sum was stored there hold the main plane's
    residual alone in ``truth/residual_unbalance``: read only when the per-plane ones are
    absent).  A run in memory: as its recording would hold (instruments present).
    """
    from stand.integrate.residual import static_residual

    t = np.asarray(rec.t)
    if hasattr(rec, "shape"):                       # a Recording: the stored truth
        shape = rec.shape("truth/residual_unbalance")
        if shape is None or len(shape) != 2 or shape[0] != t.size:
            return None
        if not any(k.startswith("residual/") for k in rec.truth):   # a planar recording
            tr = np.asarray(rec.dataset("truth/residual_unbalance"), float)
            return t, tr[:, 0] + 1j * tr[:, 1]
    elif not getattr(rec, "instruments", None):  # as its recording: truth with the instruments
        return None
    scene = rec.scene
    if getattr(scene, "kind", None) not in ("planar", "rotor"):
        return None
    if scene.kind == "planar" and not getattr(scene.balancer, "count", 0):
        return None
    try:
        psi = static_residual(rec)
    except (AttributeError, ValueError, IndexError):
        return None
    psi = None if psi is None else np.asarray(psi)
    return (t, psi) if psi is not None and psi.shape == t.shape else None


def _rings(rec):
    """The screen's calibration rings of a recording or a run in memory: ``{"radius_m",
    "gain", "offset_m", "test_speed_rad_s"}`` (the screen's optical gain and offset, the
    speed the rings were drawn for), or None."""
    import json

    if hasattr(rec, "shape"):
        if rec.shape("instruments/screen/ring_radius") is None:
            return None
        radius = np.asarray(rec.dataset("instruments/screen/ring_radius"), float)
        attrs = rec.dataset_attrs("instruments/screen")
        try:
            st = json.loads(attrs.get("settings", "{}"))
        except (TypeError, ValueError):
            st = {}
        ts = attrs.get("ring_test_speed_rad_s", None)
    else:
        outputs = getattr(rec, "instruments", None)
        if not outputs or "screen" not in outputs or outputs["screen"].rings is None:
            return None
        from stand.instruments.pipeline import settings_dict

        screen = outputs["screen"]
        cam = screen.settings
        radius = np.asarray(screen.rings["radius"], float)
        st = settings_dict(cam.to_attrs() if hasattr(cam, "to_attrs") else cam)
        ts = screen.rings["test_speed"]
    return {"radius_m": radius, "gain": float(st.get("gain", 1.0)),
            "offset_m": (float(st.get("offset_x", 0.0)), float(st.get("offset_y", 0.0))),
            "test_speed_rad_s": None if ts is None else float(ts)}


def undersampled(t, speed):
    """Where the record samples the rotation too slowly: ``None``, or ``{"index", "t_s",
    "sample_rate_hz", "speed_hz"}`` -- the first sample whose rotor speed ``speed`` [rad/s]
    reaches half the sample rate (half a revolution or more per sample: the sampled angle
    and orbit alias, no 1X), the sample rate [Hz] and the highest speed [rev/s] from there."""
    if speed is None or t.size < 2:
        return None
    fs = 1.0 / float(np.median(np.diff(t)))
    f = np.abs(np.asarray(speed, float)) / TWO_PI
    bad = np.flatnonzero(f >= 0.5 * fs)
    if not bad.size:
        return None
    i = int(bad[0])
    return {"index": i, "t_s": float(t[i]), "sample_rate_hz": fs, "speed_hz": float(np.max(f[i:]))}


def undersampled_words(u, what: str) -> str:
    """The note of :func:`undersampled`: ``what`` (e.g. ``"1X"``) and the numbers."""
    from stand.io.numbers import plain

    return (f"{what}: the record samples {plain(u['sample_rate_hz'], 'Hz', 4)}, below twice the "
            f"{plain(u['speed_hz'], 'rev/s', 4)} speed (from {plain(u['t_s'], 's', 6)} on)")


def no_weights(scene) -> bool:
    """The rigid-rotor model of the run-up fit applies: a planar rotor without weights (a
    rotor of the family is left to its own model)."""
    bal = getattr(scene, "balancer", None)
    return getattr(scene, "kind", None) == "planar" and not getattr(bal, "count", 0)


def weightless_scene(scene) -> bool:
    """The recording's scene is known and has no weights at all (no balls nor pendulums, no
    body weights, in any plane; unlike :func:`no_weights`, any structure)."""
    return scene is not None and not (getattr(scene, "n_weights", 0)
                                      or getattr(scene, "bodies", None))


def c_over_ccrit(scene) -> float:
    """A planar scene's damping ratio c / (2 sqrt(k M)) (the supports' mean of x and y)."""
    s = scene.supports
    k, c = 0.5 * (s.stiffness_x + s.stiffness_y), 0.5 * (s.damping_x + s.damping_y)
    return float(c / (2.0 * math.sqrt(k * scene.total_mass))) if k > 0 else float("nan")


def whirls(t, x, y) -> bool:
    """Without a speed channel: the shaft whirls when the phase of x + i y (mean removed)
    advances steadily by ten turns or more."""
    z = (x - np.mean(x)) + 1j * (y - np.mean(y))
    if t.size < 16 or not np.any(np.abs(z) > 0):
        return False
    th = np.unwrap(np.angle(z))
    turns = abs(th[-1] - th[0]) / TWO_PI
    steps = np.diff(th)
    return bool(turns >= 10 and np.mean(np.sign(steps) == np.sign(th[-1] - th[0])) > 0.9)

