"""The record a scene is fitted to: the channels ``stand analyze`` reads, and the rotor angle
that drives the simulation as the recording was driven.

:func:`fit_record` reads anything :func:`stand.analysis.sources.read_source` reads (a lab
table with its map, a stand recording with probes, a Run in memory) into a
:class:`FitRecord`: the sample times, the sensors' complex signal ``x + i y`` in the
channel's own quantity (displacement, velocity or acceleration, SI), the rotor angle with
what its source leaves open (:class:`dsp.speed.RotorAngle`), and the drive that reproduces
that angle: a piecewise-linear speed programme whose integral matches the measured angle at
every node (:func:`angle_programme`).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Optional

import numpy as np

from stand.fitting.paths import FitError

__all__ = ["FitRecord", "RecordedDrive", "fit_record", "angle_programme", "corner_times",
           "with_corners_at"]

TWO_PI = 2.0 * math.pi
#: what each channel quantity is, as a derivative order of the displacement
ORDERS = {"length": 0, "velocity": 1, "acceleration": 2}
#: units of the channel quantities in SI
SI_UNITS = {"length": "m", "velocity": "m/s", "acceleration": "m/s^2"}


@dataclass
class FitRecord:
    """A record to fit (module docstring).

    Attributes
    ----------
    t : ndarray (N,)            sample times [s] (those with a rotor angle)
    t_start : float             the record's first sample [s]: the simulation starts there,
                                from the scene's initial state
    z : ndarray (N,) complex    x + i y of the sensors [SI unit of ``quantity``]
    quantity : str              ``"length"``, ``"velocity"`` or ``"acceleration"``
    angle : RotorAngle or None  the measured rotor angle (None: no speed channel)
    drive : RecordedDrive or None
        The speed programme that reproduces the angle (None: no speed channel).
    angle_misfit_rad : float    the largest |programme angle - measured angle| [rad]
    plane : str or None         the plane the sensors look at (None: the scene's main plane)
    label : str                 the file (or the run) it came from
    notes : list of str         what the reader and the fit set-up say
    weights : ndarray (N, n) or None
        Weight angles relative to the rotor [rad] where the record has them.
    mass_kg : float or None     the map's vibrating mass
    runout_m : float or None    the map's declared probe runout [m] (None: not declared)
    """

    t: np.ndarray
    t_start: float
    z: np.ndarray
    quantity: str
    angle: Optional[object]
    drive: Optional[RecordedDrive]
    angle_misfit_rad: float
    plane: Optional[str]
    label: str
    notes: list = field(default_factory=list)
    weights: Optional[np.ndarray] = None
    mass_kg: Optional[float] = None
    runout_m: Optional[float] = None

    @property
    def order(self) -> int:
        return ORDERS[self.quantity]

    @property
    def unit(self) -> str:
        return SI_UNITS[self.quantity]

    @property
    def duration(self) -> float:
        return float(self.t[-1] - self.t[0])

    @property
    def referenced(self) -> bool:
        return self.angle is not None and bool(self.angle.referenced)

    def phi(self) -> Optional[np.ndarray]:
        """The measured rotor angle at the samples [rad] (None without a speed channel)."""
        return None if self.angle is None else np.asarray(self.angle.angle_rad, float)

    def speed(self) -> Optional[np.ndarray]:
        return None if self.angle is None else np.asarray(self.angle.speed_rad_s, float)


def fit_record(source, recording_map=None) -> FitRecord:
    """Read ``source`` (a path, a Run or a Recording) into a :class:`FitRecord`."""
    from stand.analysis.sources import read_source

    d = read_source(source, recording_map)
    if "bode" in d:
        raise FitError(f"{source}: a Bode table (speed, amplitude, phase) has no time history; "
                       "stand fit needs the sampled signals (time, x, y and a speed channel)")
    t = np.asarray(d["t"], float)
    x, y = np.asarray(d["x"], float), np.asarray(d["y"], float)
    ok = np.isfinite(t) & np.isfinite(x) & np.isfinite(y)
    angle = d.get("angle")
    if angle is not None:
        ok &= np.asarray(angle.covered, bool) & np.isfinite(angle.angle_rad)
    if ok.sum() < 64:
        raise FitError(f"{_label(source, d)}: {int(ok.sum())} usable samples; a fit needs at "
                       "least 64")
    notes = list(d.get("notes") or [])
    if not ok.all():
        notes.append(f"{int((~ok).sum())} samples without a finite signal or rotor angle "
                     "left out of the fit")
        first, last = np.flatnonzero(ok)[[0, -1]]
        ok = np.zeros_like(ok)
        ok[first:last + 1] = True       # one contiguous stretch: the simulation runs through
        if not (np.isfinite(x[ok]).all() and np.isfinite(y[ok]).all()):
            raise FitError(f"{_label(source, d)}: gaps inside the record; fit one clean stretch")
    t, z = t[ok], x[ok] + 1j * y[ok]
    angle = _with_corners(angle, t, notes) if angle is not None else None
    if angle is not None:
        from dataclasses import replace

        angle = replace(angle, angle_rad=np.asarray(angle.angle_rad)[ok],
                        speed_rad_s=np.asarray(angle.speed_rad_s)[ok],
                        acceleration_rad_s2=np.asarray(angle.acceleration_rad_s2)[ok],
                        covered=np.ones(int(ok.sum()), bool))
    w = d.get("weights")
    if w is not None and d.get("phi") is not None and np.shape(w)[0] == ok.size:
        w = np.asarray(w, float)[ok] - np.asarray(d["phi"], float)[ok, None]
    else:
        w = None
    tab = d.get("table")
    rmap = getattr(tab, "recording_map", None) if tab is not None else recording_map
    probes = d.get("probes")
    t_start = float(min(t[0], np.min(tab.t) if tab is not None else t[0]))
    drive, misfit = None, 0.0
    if angle is not None:
        drive, misfit = angle_programme(t, angle.angle_rad, angle.speed_rad_s,
                                        angle.acceleration_rad_s2, t_start)
        if t_start < t[0]:
            notes.append(f"before the first measured angle ({t[0] - t_start:.4g} s of the "
                         "record) the rotor is taken to accelerate steadily from rest to the "
                         "speed it has there, the start of that fitted when the record begins "
                         "near rest (nuisance drive.rest_until); the simulation starts at the "
                         "record's first sample from the scene's initial state, the fit uses "
                         "the samples with a measured angle")
    else:
        notes.append("no speed channel: the simulation runs the scene's own speed programme "
                     "from the record's first sample; phases are not referenced")
    return FitRecord(t=t, t_start=t_start, z=z, quantity=d.get("quantity") or "length", angle=angle,
                     drive=drive, angle_misfit_rad=misfit,
                     plane=(probes or {}).get("plane") or None, label=_label(source, d),
                     notes=notes, weights=w,
                     mass_kg=getattr(rmap, "mass_kg", None) or d.get("mass_kg"),
                     runout_m=getattr(rmap, "probe_runout_m", None))


def corner_times(angle) -> list:
    """The times [s] of the double knots of a keyphasor angle's spline (its corners)."""
    knots = getattr(getattr(angle, "angle_error", None), "knots", None)
    if knots is None:
        return []
    vals, counts = np.unique(np.asarray(knots, float)[4:-4], return_counts=True)
    return [float(v) for v in vals[counts >= 2]]


def with_corners_at(rec: FitRecord, times) -> Optional[FitRecord]:
    """``rec`` with its keyphasor angle's corners moved to ``times`` [s] (the angle, its drive
    and its error modes made again from the same pulses); None when that fails."""
    from dataclasses import replace

    from dsp.errors import SignalError
    from dsp.speed import angle_from_pulses

    a = rec.angle
    try:
        new = angle_from_pulses(rec.t, a.pulses_s, timing_std_s=a.pulse_timing_std_s,
                                corners=list(times))
    except (SignalError, ValueError, np.linalg.LinAlgError):
        return None
    if not np.all(new.covered):
        return None
    drive, misfit = angle_programme(rec.t, new.angle_rad, new.speed_rad_s,
                                    new.acceleration_rad_s2, rec.t_start)
    return replace(rec, angle=new, drive=replace(drive, rest_until=rec.drive.rest_until),
                   angle_misfit_rad=misfit)


def _with_corners(angle, t, notes):
    """A keyphasor's angle again, with double knots where the speed's slope jumps (a run-up
    that turns into a hold): the spline ``stand analyze`` uses rounds such a corner over its
    knot interval and misses the angle there by several times its own std, which the fit's
    model of the angle's error could not absorb (:func:`dsp.speed.angle_from_pulses`,
    ``corners=True``)."""
    from dsp.errors import SignalError
    from dsp.speed import angle_from_pulses

    p = getattr(angle, "pulses_s", None)
    if p is None or angle.pulse_timing_std_s is None or angle.source != "keyphasor":
        return angle
    try:
        new = angle_from_pulses(t, p, timing_std_s=angle.pulse_timing_std_s, corners=True)
    except (SignalError, ValueError, np.linalg.LinAlgError):
        return angle
    knots = getattr(getattr(new.angle_error, "knots", None), "size", 0)
    old = getattr(getattr(angle.angle_error, "knots", None), "size", 0)
    if knots > old:
        notes.append(f"keyphasor angle: {(knots - old) // 2} corner(s) of the speed programme "
                     "given a double knot (the run-up's end; dsp.speed.angle_from_pulses "
                     "corners=True)")
    if not np.all(new.covered):
        return angle
    return new


def _label(source, d) -> str:
    lab = getattr(source, "path", None)
    if lab:
        return str(lab)
    if hasattr(source, "scene") and not isinstance(source, (str, bytes)):
        return f"<run of {getattr(source.scene, 'name', '')}>"
    return str(source)


@dataclass(frozen=True)
class RecordedDrive:
    """The drive of a record: the measured rotor angle as a speed programme, and the stretch
    before the first measured angle (a keyphasor's first pulse comes after the record
    starts) as a constant acceleration from rest.

    Attributes
    ----------
    programme : ndarray (K, 2)  measured nodes [s from the record's first sample, rad/s]
    angle : float               the measured angle at the first node [rad]
    lead : float                the first node's time [s] (0: the angle is measured from
                                the first sample on)
    rest_until : float          where the lead-in's constant acceleration starts from rest
                                [s]; negative: the rotor already turns at the first sample
                                (at the speed the same acceleration gives there)
    """

    programme: np.ndarray
    angle: float
    lead: float = 0.0
    rest_until: float = 0.0

    def full(self, rest_until: Optional[float] = None):
        """``(programme (K', 2), angle at the first sample)`` with the lead-in starting from
        rest at ``rest_until`` (default: this drive's)."""
        prog = np.asarray(self.programme, float)
        if self.lead <= 0.0:
            return prog, float(self.angle)
        tz = self.rest_until if rest_until is None else float(rest_until)
        tz = min(tz, self.lead * (1.0 - 1e-9))
        w0 = float(prog[0, 1])
        if tz >= 0.0:
            head = [[0.0, 0.0]] + ([[tz, 0.0]] if tz > 0.0 else [])
            gained = 0.5 * w0 * (self.lead - tz)
        else:
            ws = w0 * (-tz) / (self.lead - tz)
            head = [[0.0, ws]]
            gained = 0.5 * (ws + w0) * self.lead
        return np.vstack([np.array(head), prog]), float(self.angle - gained)


def angle_programme(t, phi, w, a, t_start: float, spacing_rev: float = 0.25,
                    max_spacing_s: float = 0.02):
    """The :class:`RecordedDrive` that reproduces a measured rotor angle.

    Nodes every ``spacing_rev`` revolutions of the top speed (at most ``max_spacing_s``, at
    least one sample interval) with speeds chosen by least squares so that the programme's
    angle -- the integral of the speed, the trapezoid of each step -- matches the measured
    angle at every node (weight 1) while staying near the measured speed (weight 1e-3:
    fixes the alternating mode the node angles leave free; weight 1 at the first node).
    Before the first measured sample (``t_start < t[0]``) the rotor accelerates from rest
    at the acceleration the angle has at ``t[0]`` (or turns at a constant speed when it does
    not accelerate there); :meth:`RecordedDrive.full` moves that start.

    Parameters
    ----------
    t : ndarray (N,)   sample times with a measured angle [s]
    phi : ndarray (N,) unwrapped rotor angle [rad]
    w, a : ndarray (N,) its speed [rad/s] and acceleration [rad/s^2]
    t_start : float    where the programme starts [s] (<= t[0])

    Returns
    -------
    (RecordedDrive, largest angle misfit over the samples [rad])
    """
    import scipy.sparse as sps
    from scipy.sparse.linalg import spsolve

    from stand.model.programme import build_table, programme_kinematics_many

    t = np.asarray(t, float)
    phi = np.asarray(phi, float)
    w = np.asarray(w, float)
    tt = t - t[0]
    top = max(float(np.max(np.abs(w))), 1e-9)
    dt = float(np.median(np.diff(t)))
    step = min(max_spacing_s, max(dt, TWO_PI * spacing_rev / top))
    n_int = max(1, int(round(tt[-1] / step)))
    nodes = np.linspace(0.0, tt[-1], n_int + 1)
    ph = np.interp(nodes, tt, phi)
    wk = np.interp(nodes, tt, w)
    h = np.diff(nodes)
    m = nodes.size
    lam = np.full(m, 1e-3)
    lam[0] = 1.0           # the first node keeps the measured speed: the lead-in starts there
    rows = np.concatenate([np.arange(m - 1), np.arange(m - 1), m - 1 + np.arange(m)])
    cols = np.concatenate([np.arange(m - 1), np.arange(1, m), np.arange(m)])
    vals = np.concatenate([0.5 * h, 0.5 * h, lam * step])
    A = sps.csr_matrix((vals, (rows, cols)), shape=(2 * m - 1, m))
    b = np.concatenate([np.diff(ph), lam * step * wk])
    speeds = spsolve((A.T @ A).tocsc(), A.T @ b)
    table = build_table(nodes, speeds)
    table[:, 2] += phi[0]
    misfit = float(np.max(np.abs(programme_kinematics_many(tt, table)[:, 0] - phi)))
    lead = float(t[0] - t_start)
    w0, a0 = float(speeds[0]), float(np.asarray(a, float)[0])
    rest = lead - w0 / a0 if a0 > 0 and w0 > 0 else -1e6 * max(lead, 1.0)
    return RecordedDrive(np.column_stack([nodes + lead, speeds]), float(phi[0]), lead,
                         rest), misfit
