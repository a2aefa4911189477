"""A recording's displacement probes read back: ``instruments/probes`` of a stand
recording, or ``run.instruments["probes"]`` of a Run in memory, and the shaft's x, y
solved from the probes' projections (what ``stand analyze`` and the DAQ export read).
"""
from __future__ import annotations

import math

import numpy as np

from stand.recording.layout import PROBES, instrument_key

__all__ = ["probe_channels", "probes_xy"]


def probe_channels(rec):
    """The displacement probes of a Run or Recording: ``{"time": (M,) [s], "signal": (M, p)
    [m], "angles": (p,) [rad], "plane": str or None, "runout_1x_m": the stated 1X runout [m]
    or None}``, or None without probes.  Read from the file
    (``instruments/probes/{time,signal,angles}`` and the group's settings) or, for a Run in
    memory, from ``run.instruments["probes"]``."""
    shape = getattr(rec, "shape", None)
    if callable(shape) and getattr(rec, "path", ""):
        try:
            if shape(instrument_key(PROBES, "signal")) is not None:
                sig = np.asarray(rec.dataset(instrument_key(PROBES, "signal")), float)
                at = rec.dataset_attrs(instrument_key(PROBES))
                return {"time": np.asarray(rec.dataset(instrument_key(PROBES, "time")), float),
                        "signal": sig.reshape(sig.shape[0], -1),
                        "angles": np.atleast_1d(np.asarray(
                            rec.dataset(instrument_key(PROBES, "angles")), float)),
                        "plane": at.get("plane"), "runout_1x_m": _runout_1x(at.get("settings"))}
        except (OSError, ValueError):
            return None
    ins = getattr(rec, "instruments", None)
    try:
        out = ins[PROBES] if ins is not None and PROBES in ins else None
    except (KeyError, TypeError):
        out = None
    if out is None:
        return None
    r = out.readings
    sig = np.asarray(r["signal"], float)
    return {"time": np.asarray(r["time"], float), "signal": sig.reshape(sig.shape[0], -1),
            "angles": np.atleast_1d(np.asarray(r["angles"], float)),
            "plane": getattr(out, "plane", None) if getattr(rec.scene, "kind", None) == "rotor"
            else None, "runout_1x_m": _runout_1x(getattr(out, "settings", None))}


def _runout_1x(settings):
    """The probes' stated 1X runout amplitude [m] (their settings: a dataclass, a mapping or
    the recording's JSON text), or None when not stated."""
    import json

    if isinstance(settings, (str, bytes)):
        try:
            settings = json.loads(settings)
        except ValueError:
            return None
    r = settings.get("runout") if isinstance(settings, dict) else getattr(settings, "runout", None)
    try:
        r = np.atleast_1d(np.asarray(r, float))
        return float(r[0]) if r.size and np.isfinite(r[0]) else 0.0
    except (TypeError, ValueError):
        return None


def probes_xy(signal, angles, notes=None):
    """``(x, y)`` [m] from probes reading ``s_i = x cos a_i + y sin a_i`` (``signal`` (M, p),
    ``angles`` (p,) [rad]): two probes -- the 2x2 solve (at 0 and 90 deg the columns
    themselves); more -- least squares.  None (with the reason in ``notes``) when the
    directions do not span the plane (one probe, or parallel probes)."""
    a = np.asarray(angles, float)
    A = np.column_stack([np.cos(a), np.sin(a)])
    sv = np.linalg.svd(A, compute_uv=False) if a.size >= 2 else np.zeros(1)
    if a.size < 2 or sv[-1] < 1e-3 * sv[0] or signal.shape[1] != a.size:
        if notes is not None:
            notes.append(f"{instrument_key(PROBES)} at {np.degrees(a).round(3).tolist()} deg: "
                         "the directions do not span the plane (x and y cannot be solved); "
                         "the simulator's shaft state (shaft/x, shaft/y) is analysed instead, "
                         "noise-free: its ± are numerical only")
        return None
    if a.size == 2 and abs(a[0]) < 1e-12 and abs(a[1] - math.pi / 2) < 1e-12:
        return signal[:, 0].copy(), signal[:, 1].copy()
    sol = np.linalg.lstsq(A, signal.T, rcond=None)[0]
    return sol[0], sol[1]
