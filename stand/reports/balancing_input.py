"""Input of the balancing report: one recording (HDF5 or CSV) as arrays and metadata.

HDF5 files are read by the one recording reader
(:func:`stand.recording.hdf5.read_recording`, every layout it accepts); a CSV has
the columns ``stand analyze`` accepts.  :func:`read_input` checks what the
report needs (3 finite samples at least, increasing time) and names the file
and the field in every error; :func:`load_record` adds the rotor speed and
the final constant-speed stretch (:class:`Record`, what every section uses).
"""
from __future__ import annotations

import dataclasses
import json
import math
from pathlib import Path
from typing import Any, Optional

import numpy as np

from stand.analysis.signals import steady_start
from stand.io.jsonable import to_jsonable

__all__ = ["read_input", "load_record", "Record", "source_name"]

TWO_PI = 2.0 * math.pi


def _read_table(p: Path, recording_map=None) -> dict:
    """A lab table (:func:`stand.analysis.sources.from_table`: the one table reader and speed
    source).  A tachometer's speed or, with no speed channel, the whirl's own phase gives
    the rotor angle the report's order tracking needs (flagged: no phase reference)."""
    from stand.analysis.sources import from_table, whirls

    d = from_table(p, recording_map)
    angle = d["angle"]
    notes = list(d["notes"])
    phi, referenced = d["phi"], True
    t, x, y = d["t"], d["x"], d["y"]
    if phi is None and angle is not None:
        phi, referenced = angle.angle_rad, False
        notes.append(f"rotor angle from the {angle.source} (no reference mark: 1X phases are "
                     "relative)")
    elif phi is None and whirls(t, x, y):
        from dsp.errors import SignalError
        from dsp.speed import angle_from_1x

        try:
            a = angle_from_1x(t, (x - x.mean()) + 1j * (y - y.mean()))
            c = a.covered
            t, x, y, phi, referenced = t[c], x[c], y[c], a.angle_rad[c], False
            notes.append("no speed channel: the rotor angle is estimated from the whirl's phase")
        except SignalError as exc:
            notes.append(f"no speed channel and no usable 1X line ({exc})")
    fmt = {".parquet": "parquet", ".pq": "parquet"}.get(p.suffix.lower(),
                                                        "hdf5-table" if p.suffix.lower() in
                                                        (".h5", ".hdf5", ".hdf") else "csv")
    return dict(t=t, x=x, y=y, phi=phi, weights=None, scene=None, scene_error=None,
                attrs={}, notes=notes, solver={}, inst={}, truth={}, fmt=fmt,
                table=d["table"], phase_referenced=referenced,
                speed_measured_exactly=angle is not None and angle.source == "angle")


def _read_h5(p: Path) -> dict:
    """The HDF5 form, through the one reader :func:`stand.recording.hdf5.read_recording`."""
    from stand.recording.hdf5 import read_recording

    return _read_run(read_recording(p))  # RecordingError (a ValueError) names file and dataset


def _read_run(rec) -> dict:
    """A :class:`stand.Recording`, or a :class:`stand.Run` in memory (``fmt`` ``"run"``: its
    instruments' output read from ``run.instruments``, no file)."""
    scene, scene_error = rec.scene, None
    if scene is None and getattr(rec, "scene_text", "").strip():
        scene_error = next((n for n in rec.notes if "stored scene" in n), "scene not readable")
    elif scene is not None and scene.kind != "planar":
        scene_error = (f"the recorded scene's structure is {scene.structure_type}: the model-based "
                       "parts (chapter-5 planar rotor) are skipped")
        scene = None
    phi = np.asarray(rec.rotor_angle) if np.all(np.isfinite(rec.rotor_angle)) else None
    wa = np.asarray(rec.weight_angle)
    weights = wa if wa.size and np.all(np.isfinite(wa)) else None
    rel = np.asarray(rec.relative_angle) if weights is not None else None
    in_memory = not hasattr(rec, "dataset")
    if in_memory:
        inst, truth = _instruments_in_memory(rec)
        attrs = {"scene_name": str(getattr(rec.scene, "name", "") or "")}
        solver = to_jsonable(dict(rec.stats or {}))
    else:
        inst, truth = _instruments(rec)
        attrs, solver = rec.attrs, rec.solver
    return dict(t=np.asarray(rec.t), x=np.asarray(rec.x), y=np.asarray(rec.y), phi=phi,
                weights=weights, rel=rel, scene=scene, scene_error=scene_error,
                attrs=attrs, notes=list(rec.notes), solver=solver, inst=inst,
                truth=truth, fmt="run" if in_memory else "hdf5")


def _instruments(rec) -> tuple:
    """``(inst, truth)``: the screen's ring radii and settings, the last screen and strobe
    frames, and the truth's residual unbalance of a recording (``rec.shape``,
    ``rec.dataset``, ``rec.dataset_attrs`` as :class:`stand.Recording` has them)."""
    inst, truth = {}, {}
    if rec.shape("instruments/screen/ring_radius") is not None:
        inst["ring_radius"] = np.asarray(rec.dataset("instruments/screen/ring_radius"), float)
        attrs = rec.dataset_attrs("instruments/screen")
        try:
            inst["screen_settings"] = json.loads(attrs.get("settings", "{}"))
        except (TypeError, ValueError):
            inst["screen_settings"] = {}
        ts = attrs.get("ring_test_speed_rad_s", None)
        inst["ring_test_speed_rad_s"] = None if ts is None else float(ts)
    for key, name in (("instruments/screen/frames", "screen"),
                      ("instruments/stroboscope/frames", "strobe")):
        shape = rec.shape(key)
        if shape is not None and len(shape) == 3 and shape[0] > 0:
            inst[name + "_frame"] = np.asarray(rec.dataset(key, shape[0] - 1))
    shape = rec.shape("truth/residual_unbalance")
    if shape is not None and len(shape) == 2 and shape[0] == rec.t.size:
        truth["residual_unbalance"] = np.asarray(rec.dataset("truth/residual_unbalance"), float)
    return inst, truth


def _instruments_in_memory(run) -> tuple:
    """:func:`_instruments` of a Run in memory, read from ``run.instruments``
    (:class:`stand.instruments.outputs.InstrumentOutputs`: the outputs a recording stores,
    nothing written): the same keys, the same values."""
    from stand.instruments.pipeline import settings_dict

    outputs = getattr(run, "instruments", None)
    if not outputs:               # no instruments: a recording of this run has no truth group
        return {}, {}
    inst, truth = {}, {}
    if "screen" in outputs:
        screen = outputs["screen"]
        rings = screen.rings
        if rings is not None:
            cam = screen.settings
            inst["ring_radius"] = np.asarray(rings["radius"], float)
            inst["screen_settings"] = settings_dict(cam.to_attrs() if hasattr(cam, "to_attrs")
                                                    else cam)
            inst["ring_test_speed_rad_s"] = float(rings["test_speed"])
    for name, key in (("screen", "screen_frame"), ("stroboscope", "strobe_frame")):
        if name in outputs and outputs[name].n_frames > 0:
            out = outputs[name]
            inst[key] = np.asarray(out.frame(out.n_frames - 1))
    psi = np.asarray(outputs.traj.residual_unbalance())
    if psi.shape == np.shape(run.t):
        truth["residual_unbalance"] = np.column_stack([psi.real, psi.imag])
    return inst, truth


def read_input(path, recording_map=None) -> dict:
    """Read a recording for the balancing report.

    Parameters
    ----------
    path : str, Path, Recording or Run
        HDF5 recording (any layout :func:`stand.recording.hdf5.read_recording`
        reads) or CSV (``t_s`` [s], ``x_m``, ``y_m`` [m], optionally
        ``rotor_angle_rad`` [rad] or ``keyphasor`` (1 on a once-per-revolution
        pulse)); or a recording already read, or a run in memory (nothing written).

    Returns
    -------
    dict
        ``t`` [s], ``x``, ``y`` [m], ``phi`` (rotor angle [rad] or None),
        ``weights`` (weight angles [rad], samples x weights, or None), ``rel``
        (weight angles relative to the rotor [rad] or None), ``scene`` (the
        planar scene or None) and ``scene_error`` (why not), ``attrs``,
        ``notes``, ``solver``, ``inst`` (ring radii [m], screen settings, ring
        test speed [rad/s], last camera frames), ``truth`` (residual
        unbalance [kg m] per sample), ``fmt`` ("hdf5", "csv", ... or "run").

    Raises
    ------
    FileNotFoundError
        The file does not exist.
    ValueError
        Unreadable input (not HDF5/CSV, missing dataset or column, NaN samples,
        time not increasing): the message names the file and the field.
    """
    from stand.integrate.result import Run

    if isinstance(path, Run):        # a Recording already read, or a run in memory
        d = _read_run(path)
        p = source_name(path)
    else:
        p = Path(path)
        if not p.exists():
            raise FileNotFoundError(2, "recording not found", str(p))
        if p.is_dir():
            raise ValueError(f"{p}: is a directory, not a recording")
        from stand.lab.table import is_table

        d = _read_table(p, recording_map) if is_table(p) else _read_h5(p)
    t, x, y = d["t"], d["x"], d["y"]
    if t.size < 3:
        raise ValueError(f"{p}: 'time' has {t.size} samples; at least 3 are needed")
    for name, a in (("time", t), ("shaft/x", x), ("shaft/y", y)):
        if not np.all(np.isfinite(a)):
            raise ValueError(f"{p}: dataset {name!r} contains NaN or inf")
    if np.any(np.diff(t) <= 0):
        raise ValueError(f"{p}: dataset 'time' must be strictly increasing")
    return d


def source_name(source) -> str:
    """The name a report gives its input: a file's name, a Recording's file name, or
    ``<run of SCENE>`` for a run in memory."""
    path = getattr(source, "path", None) if not isinstance(source, (str, Path)) else source
    if path:
        return Path(path).name
    return f"<run of {getattr(getattr(source, 'scene', None), 'name', '') or 'a scene'}>"


@dataclasses.dataclass(frozen=True)
class Record:
    """One recording prepared for the report's sections.

    Attributes
    ----------
    data : dict
        What :func:`read_input` returned (weights, instruments, truth, solver
        status, attributes, notes).
    t : ndarray
        Sample times [s].
    x, y : ndarray
        Shaft displacements [m].
    phi : ndarray or None
        Unwrapped rotor angle [rad].
    speed : ndarray or None
        Rotor speed d phi / dt [rad/s].
    rotating : bool
        The rotor turns (|speed| > 1e-6 rad/s somewhere).
    steady : int
        First sample of the final constant-speed stretch (0 when not rotating).
    scene : Scene or None
        The recording's planar scene (masses, capacity, supports, drive).
    """

    data: dict
    t: np.ndarray
    x: np.ndarray
    y: np.ndarray
    phi: Optional[np.ndarray]
    speed: Optional[np.ndarray]
    rotating: bool
    steady: int
    scene: Any


def load_record(path, recording_map=None) -> Record:
    """Read a recording (:func:`read_input`) and derive the rotor speed and steady stretch.

    Raises
    ------
    FileNotFoundError, ValueError
        As :func:`read_input`.
    """
    d = read_input(path, recording_map)
    t, phi, speed = d["t"], d["phi"], None
    if phi is not None:
        phi = np.unwrap(phi)
        speed = np.gradient(phi, t)
    rotating = speed is not None and float(np.max(np.abs(speed))) > 1e-6
    steady = steady_start(t, speed) if rotating else 0
    if rotating and d.get("table") is not None and not d.get("speed_measured_exactly"):
        # a speed from pulses or a tachometer wobbles: the programme's last constant stretch
        from dsp.speed import speed_programme

        last = speed_programme(t, speed).stretches[-1]
        if last.kind == "constant":
            steady = last.i_start
    return Record(data=d, t=t, x=d["x"], y=d["y"], phi=phi, speed=speed, rotating=rotating,
                  steady=steady, scene=d["scene"])
