"""A field-balancing job file (``stand balance JOB.toml``): readings as a balancer shows them.

The contract (README, "Field balancing"): ``[job]`` units and method, ``[planes.NAME]``
(radius, max_mass, holes), ``[sensors.NAME]`` (weight, max_vibration, machine_class), ``[[run]]`` tables
(``kind = "slow_roll" | "reference" | "trial" | "check"``, ``speed``, ``trial``, a check
run's ``corrections`` (installed, left on), ``removed``, ``readings``) and ``[[influence]]`` tables (a known influence matrix per speed).

A reading is ``"amplitude @ angle"`` (the job's vibration unit and amplitude convention,
degrees), or a list of them (repeated readings: their mean, and the scatter of the mean as
the reading's standard uncertainty).  A reading without ``@ angle`` (``"170"``) is
amplitude-only (a plain vibration meter): a job whose readings all are is solved by the
four-run method (:mod:`stand.analysis.field_amplitude`); a job mixing both is refused.  Everything is converted here, once: vibration to SI
peak (m, m/s or m/s^2), masses to kg, speeds to rad/s, angles to radians.  The angular sense
is the weights' (trial masses, corrections, ``[[influence]]``); the readings' angles are in the
same sense (``phase = "lead"``, the default) or against it (``phase = "lag"``: a phase lag, as
proximity-probe systems show it).
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from typing import Optional

import numpy as np

from stand.lab.units import AMPLITUDE, QUANTITIES, UnitError, parse_quantity

__all__ = ["FieldJob", "FieldRun", "read_job", "parse_job", "VIBRATION_UNITS", "MASS_UNITS",
           "AMPLITUDES", "METHODS"]

#: vibration units of the readings by quantity (the lab's one unit table, stand.lab.units)
VIBRATION_UNITS = {"displacement": QUANTITIES["length"], "velocity": QUANTITIES["velocity"],
                   "acceleration": QUANTITIES["acceleration"]}
MASS_UNITS = QUANTITIES["mass"]
#: amplitude conventions -> factor to peak
AMPLITUDES = AMPLITUDE
METHODS = ("least_squares", "weighted", "min_max")
_KINDS = ("slow_roll", "reference", "trial", "check")
_NUM = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"
_POLAR = re.compile(rf"^\s*({_NUM})\s*([^@\s]*)\s*@\s*({_NUM})\s*(?:deg|°)?\s*$")
_AMPLITUDE = re.compile(rf"^\s*({_NUM})\s*([^@\s\d.+-][^@\s]*)?\s*$")   # a reading without phase


def _vibration_quantity(unit: str, field_: str) -> tuple:
    for q, t in VIBRATION_UNITS.items():
        if unit in t:
            return q, t[unit]
    known = ", ".join(u for t in VIBRATION_UNITS.values() for u in t)
    raise UnitError(f"{field_} = {unit!r}: unknown vibration unit (one of {known})")


@dataclass
class FieldRun:
    """One run of the job: kind, speed [rad/s] (NaN: not given), trial masses [kg, complex]
    (a ``check`` run's: the corrections installed, on for the runs after it),
    ``removed``, readings (sensor -> SI peak complex) and their standard uncertainties
    (sensor -> std of each of Re and Im, SI); ``trial_std``: plane -> std of each of Re and
    Im of the trial mass [kg] (its written digits)."""

    index: int
    kind: str
    speed: float
    trial: dict
    removed: bool
    readings: dict
    std: dict
    trial_std: dict = field(default_factory=dict)

    @property
    def label(self) -> str:
        return f"run[{self.index}] ({self.kind})"


@dataclass
class FieldJob:
    """A parsed job: SI values and the display units to answer in (see the module docstring)."""

    vibration_unit: str
    quantity: str
    vib_factor: float            # SI per display unit
    amplitude: str
    amp_factor: float            # peak per display amplitude
    mass_unit: str
    mass_factor: float           # kg per display mass unit
    method: str
    planes: list
    sensors: list
    radius: dict = field(default_factory=dict)       # plane -> m
    max_mass: dict = field(default_factory=dict)     # plane -> kg
    holes: dict = field(default_factory=dict)        # plane -> int
    weights: dict = field(default_factory=dict)      # plane -> [kg] masses at hand
    max_pieces: dict = field(default_factory=dict)   # plane -> int
    weight: dict = field(default_factory=dict)       # sensor -> float
    cap: dict = field(default_factory=dict)          # sensor -> SI peak
    zone_class: dict = field(default_factory=dict)   # sensor -> ISO 20816 machine class
    runs: list = field(default_factory=list)
    influence: list = field(default_factory=list)    # [(speed, {sensor: {plane: SI/kg}})]
    influence_std: list = field(default_factory=list)  # per table {sensor: {plane: SI/kg}}
    influence_source: str = ""                       # the job that measured a saved influence
    source: str = ""
    phase: str = "lead"
    rotor_mass: float = math.nan                     # kg (ISO 21940-11 grade)
    service_speed: float = math.nan                  # rad/s (default: the highest run speed)
    grade: float = math.nan                          # target grade G [mm/s]
    centre_of_mass: float = math.nan                 # m, axial (with the planes' position)
    position: dict = field(default_factory=dict)     # plane -> axial position [m]
    amplitude_only: bool = False                     # readings without phase: four-run

    def to_display(self, v) -> np.ndarray:
        """SI peak vibration -> the job's unit and amplitude convention."""
        return np.asarray(v) / (self.vib_factor * self.amp_factor)

    def from_display(self, v) -> np.ndarray:
        return np.asarray(v) * self.vib_factor * self.amp_factor


def _polar(text, field_: str, unit_ok) -> tuple:
    """``"170 @ 112"`` -> (amplitude in the given unit, angle [rad]); a unit after the amplitude
    must be ``unit_ok``'s."""
    if isinstance(text, (int, float)) and not isinstance(text, bool):
        raise ValueError(f"{field_} = {text!r}: give 'amplitude @ angle_deg', e.g. \"170 @ 112\"")
    m = _POLAR.match(str(text))
    if not m:
        raise ValueError(f"{field_} = {text!r}: expected 'amplitude @ angle_deg', e.g. \"170 @ 112\"")
    amp, unit, ang = float(m.group(1)), m.group(2), float(m.group(3))
    if not (math.isfinite(amp) and math.isfinite(ang)) or amp < 0:
        raise ValueError(f"{field_} = {text!r}: the amplitude must be finite and >= 0, the angle "
                         f"finite (deg)")
    if abs(ang) > 360.0 or amp > 1e12:
        raise ValueError(f"{field_} = {text!r}: " + (f"angle {ang:g} deg outside -360 .. 360 deg"
                         if abs(ang) > 360.0 else f"amplitude {amp:g} above 1e12: not a reading"))
    if unit:
        unit_ok(unit, field_)
    return amp, math.radians(ang)


def _amplitude_reading(vals, where, job, unit_ok) -> tuple:
    """Amplitude-only readings (``"170"`` or a list of them) -> (mean amplitude, SI peak, as a
    real complex; its standard uncertainty): the meter's rounding to the last written digit
    (q / sqrt 12, averaged over n readings), or for repeated readings the scatter of the
    mean if larger."""
    a, res = [], []
    for k, x in enumerate(vals):
        f_ = where if len(vals) == 1 else f"{where}[{k}]"
        m = _AMPLITUDE.match(str(x))
        amp = float(m.group(1))
        if not (math.isfinite(amp) and amp >= 0):
            raise ValueError(f"{f_} = {x!r}: the amplitude must be finite and >= 0")
        if m.group(2):
            unit_ok(m.group(2), f_)
        a.append(float(job.from_display(amp)))
        res.append(_last_digit(m.group(1)) * float(job.from_display(1.0)) / math.sqrt(12.0))
    a = np.array(a)
    s = math.sqrt(float(np.mean(np.square(res))) / a.size)
    if a.size > 1:
        s = max(s, float(np.std(a, ddof=1)) / math.sqrt(a.size))
    return complex(a.mean()), s


def _last_digit(number: str) -> float:
    """The unit of a written number's last digit: ``"170"`` -> 1, ``"1.15"`` -> 0.01,
    ``"2.5e3"`` -> 100 (a display rounds to it)."""
    mant, _, exp = number.strip().lstrip("+-").lower().partition("e")
    decimals = len(mant.partition(".")[2])
    return 10.0 ** ((int(exp) if exp else 0) - decimals)


def _resolution_std(text, amplitude_si: float, display_to_si: float) -> float:
    """Std of each of Re and Im of one ``"amplitude @ angle"`` reading from its resolution:
    the amplitude and the angle rounded to their last written digits (uniform, q / sqrt 12
    each), the angle's across the vector (|z| q_angle), pooled over Re and Im."""
    m = _POLAR.match(str(text))
    if not m:
        return 0.0
    qa = _last_digit(m.group(1)) * display_to_si
    qp = math.radians(_last_digit(m.group(3)))
    return math.hypot(qa, amplitude_si * qp) / math.sqrt(24.0)


def _weighing_std(text, mass_factor: float) -> float:
    """Std of each of Re and Im of a trial mass [kg]: a mass written with decimals
    (``"1.15 @ 0"``) was weighed to its last digit (uniform, q / sqrt 12, along the mass);
    a whole number (``"10 @ 0"``) is taken as the nominal, exact mass, and the angle as
    the hole or mark it sits at (exact)."""
    m = _POLAR.match(str(text))
    if not m or "." not in m.group(1).lower().partition("e")[0]:
        return 0.0
    return _last_digit(m.group(1)) * mass_factor / math.sqrt(12.0) / math.sqrt(2.0)


def _check_keys(table, allowed, where):
    if not isinstance(table, dict):
        raise ValueError(f"{where}: expected a table, got {table!r}")
    for k in table:
        if k not in allowed:
            raise ValueError(f"{where}.{k}: unknown key (known: {', '.join(allowed)})")


def _mass(value, job_unit: str, field_: str) -> float:
    """``"5 g"`` or a bare number (in the job's mass unit) -> kg."""
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        x, unit = float(value), job_unit
    else:
        m = re.match(rf"^\s*({_NUM})\s*(\S*)\s*$", str(value))
        if not m:
            raise ValueError(f"{field_} = {value!r}: expected a mass, e.g. \"5 {job_unit}\"")
        x, unit = float(m.group(1)), m.group(2) or job_unit
    if unit not in MASS_UNITS:
        raise UnitError(f"{field_} = {value!r}: unknown mass unit {unit!r} (one of "
                        f"{', '.join(MASS_UNITS)})")
    if not (math.isfinite(x) and x > 0):
        raise ValueError(f"{field_} = {value!r}: must be > 0 {unit}")
    return x * MASS_UNITS[unit]


def parse_job(doc: dict, source: str = "", influence_doc: Optional[dict] = None) -> FieldJob:
    """A :class:`FieldJob` from a parsed TOML document (``influence_doc``: a saved influence
    file whose ``[[influence]]`` replaces the job's; its own ``[job]`` units apply to it)."""
    _check_keys(doc, ("job", "planes", "sensors", "run", "influence"), "job file")
    j = doc.get("job", {})
    _check_keys(j, ("vibration_unit", "amplitude", "mass_unit", "method", "rotor_mass",
                    "service_speed", "grade", "phase", "centre_of_mass"), "[job]")
    vu = str(j.get("vibration_unit", "um"))
    quantity, vf = _vibration_quantity(vu, "job.vibration_unit")
    amp = str(j.get("amplitude", "pk"))
    if amp not in AMPLITUDES:
        raise ValueError(f"job.amplitude = {amp!r}: one of {', '.join(AMPLITUDES)}")
    mu = str(j.get("mass_unit", "g"))
    if mu not in MASS_UNITS:
        raise UnitError(f"job.mass_unit = {mu!r}: one of {', '.join(MASS_UNITS)}")
    phase = str(j.get("phase", "lead"))
    if phase not in ("lead", "lag"):
        raise ValueError(f"job.phase = {phase!r}: \"lead\" (readings' angles in the sense of the "
                         f"weights' angles, default) or \"lag\" (readings' angles against it)")
    sense = -1.0 if phase == "lag" else 1.0
    method = str(j.get("method", "least_squares"))
    if method not in METHODS:
        raise ValueError(f"job.method = {method!r}: one of {', '.join(METHODS)}")
    job = FieldJob(vibration_unit=vu, quantity=quantity, vib_factor=vf, amplitude=amp,
                   amp_factor=AMPLITUDES[amp], mass_unit=mu, mass_factor=MASS_UNITS[mu],
                   method=method, planes=[], sensors=[], source=source)
    job.phase = phase
    if "rotor_mass" in j:
        job.rotor_mass = parse_quantity(j["rotor_mass"], "mass", "job.rotor_mass")
        if not job.rotor_mass > 0:
            raise ValueError(f"job.rotor_mass = {j['rotor_mass']!r}: must be > 0 kg")
    if "service_speed" in j:
        job.service_speed = parse_quantity(j["service_speed"], "speed", "job.service_speed",
                                           default_unit="rpm")
        if not job.service_speed > 0:
            raise ValueError(f"job.service_speed = {j['service_speed']!r}: must be > 0 rpm")
    if "centre_of_mass" in j:
        job.centre_of_mass = parse_quantity(j["centre_of_mass"], "length", "job.centre_of_mass")
    if "grade" in j:
        g = str(j["grade"]).strip().upper()
        try:
            job.grade = float(g[1:] if g.startswith("G") else g)
        except ValueError:
            raise ValueError(f"job.grade = {j['grade']!r}: an ISO 21940-11 grade such as "
                             f"\"G6.3\" (mm/s)") from None
        from dsp.unbalance import ISO_GRADES_MM_S

        if not any(abs(job.grade - x) <= 1e-9 * x for x in ISO_GRADES_MM_S):
            raise ValueError(f"job.grade = {j['grade']!r}: not an ISO 21940-11 grade (one of "
                             f"{', '.join(f'G{x:g}' for x in ISO_GRADES_MM_S)})")

    def unit_ok(unit, field_):
        q, _ = _vibration_quantity(unit, field_)
        if unit != vu:
            raise UnitError(f"{field_}: unit {unit!r}; readings are in job.vibration_unit = {vu!r}")

    def mass_unit_ok(unit, field_):
        if unit != mu:
            raise UnitError(f"{field_}: unit {unit!r}; trial masses are in job.mass_unit = {mu!r}")

    def add(names, name):
        if name not in names:
            names.append(str(name))

    for name, t in (doc.get("planes") or {}).items():
        _check_keys(t, ("radius", "max_mass", "holes", "weights", "max_pieces", "position"),
                    f"planes.{name}")
        add(job.planes, name)
        if "position" in t:
            job.position[name] = parse_quantity(t["position"], "length", f"planes.{name}.position")
        if "radius" in t:
            r = parse_quantity(t["radius"], "length", f"planes.{name}.radius")
            if not r > 0:
                raise ValueError(f"planes.{name}.radius = {t['radius']!r}: must be > 0 m")
            job.radius[name] = r
        if "max_mass" in t:
            job.max_mass[name] = _mass(t["max_mass"], mu, f"planes.{name}.max_mass")
        if "holes" in t:
            h = t["holes"]
            if isinstance(h, bool) or not isinstance(h, int) or h < 3:
                raise ValueError(f"planes.{name}.holes = {h!r}: an integer >= 3 (holes every "
                                 f"360/holes deg)")
            job.holes[name] = h
        if "weights" in t:
            ws = t["weights"]
            if not isinstance(ws, list) or not ws:
                raise ValueError(f"planes.{name}.weights = {ws!r}: a list of the masses at hand, "
                                 f"e.g. [\"0.5 {mu}\", \"1 {mu}\"]")
            job.weights[name] = [_mass(w, mu, f"planes.{name}.weights[{k}]")
                                 for k, w in enumerate(ws)]
        if "max_pieces" in t:
            n = t["max_pieces"]
            if isinstance(n, bool) or not isinstance(n, int) or not 1 <= n <= 6:
                raise ValueError(f"planes.{name}.max_pieces = {n!r}: an integer 1 .. 6 (pieces "
                                 f"stacked at one position)")
            job.max_pieces[name] = n
    for name, t in (doc.get("sensors") or {}).items():
        _check_keys(t, ("weight", "max_vibration", "machine_class"), f"sensors.{name}")
        add(job.sensors, name)
        if "machine_class" in t:
            from .field_verdict import ZONES

            if str(t["machine_class"]) not in ZONES:
                raise ValueError(f"sensors.{name}.machine_class = {t['machine_class']!r}: one of "
                                 f"{', '.join(ZONES)} (ISO 10816-1 classes, ISO 10816-3 groups)")
            job.zone_class[name] = str(t["machine_class"])
        if "weight" in t:
            w = t["weight"]
            if isinstance(w, bool) or not isinstance(w, (int, float)) or not (math.isfinite(w)
                                                                              and w >= 0):
                raise ValueError(f"sensors.{name}.weight = {w!r}: a number >= 0 (dimensionless)")
            job.weight[name] = float(w)
        if "max_vibration" in t:
            c = t["max_vibration"]
            f_ = f"sensors.{name}.max_vibration"
            if isinstance(c, (int, float)) and not isinstance(c, bool):
                x = float(c)
            else:
                m = re.match(rf"^\s*({_NUM})\s*(\S*)\s*$", str(c))
                if not m:
                    raise ValueError(f"{f_} = {c!r}: expected e.g. \"76 {vu}\"")
                x = float(m.group(1))
                if m.group(2):
                    unit_ok(m.group(2), f"{f_} = {c!r}")
            if not (math.isfinite(x) and x > 0):
                raise ValueError(f"{f_} = {c!r}: must be > 0 {vu}")
            job.cap[name] = job.from_display(x)

    def speed_of(t, where):
        if "speed" not in t:
            return math.nan
        w = parse_quantity(t["speed"], "speed", f"{where}.speed", default_unit="rpm")
        if not w > 0:
            raise ValueError(f"{where}.speed = {t['speed']!r}: must be > 0 rpm")
        return w

    def reading(v, where):
        vals = v if isinstance(v, list) else [v]
        if not vals:
            raise ValueError(f"{where}: an empty list of readings")
        if all(_AMPLITUDE.match(str(x)) for x in vals):
            phase_free.append(where)
            return _amplitude_reading(vals, where, job, unit_ok)
        phased.append(where)
        z, res = [], []
        for k, x in enumerate(vals):
            a, ph = _polar(x, where if len(vals) == 1 else f"{where}[{k}]", unit_ok)
            a_si = float(job.from_display(a))
            z.append(complex(a_si) * complex(math.cos(ph), sense * math.sin(ph)))
            res.append(_resolution_std(x, a_si, float(job.from_display(1.0))))
        z = np.array(z)
        n = z.size
        # what the written digits leave open (the display's rounding, averaged over n
        # readings), and for repeated readings the scatter of their mean, pooled over Re
        # and Im (one standard uncertainty per component): the larger of the two
        s = math.sqrt(float(np.mean(np.square(res))) / n)
        if n > 1:
            s = max(s, math.sqrt((np.var(z.real, ddof=1) + np.var(z.imag, ddof=1)) / 2.0 / n))
        return complex(z.mean()), s

    phase_free, phased = [], []       # readings written without / with '@ angle'
    runs = doc.get("run") or []
    if not isinstance(runs, list):
        raise ValueError("run: use [[run]] tables (an array of tables)")
    for i, t in enumerate(runs):
        where = f"run[{i}]"
        _check_keys(t, ("kind", "speed", "trial", "removed", "readings", "name", "recording",
                        "sensors", "t_start", "corrections"), where)
        kind = str(t.get("kind", ""))
        if kind not in _KINDS:
            raise ValueError(f"{where}.kind = {t.get('kind')!r}: one of {', '.join(_KINDS)}")
        trial, trial_std = {}, {}
        key = "corrections" if kind == "check" else "trial"    # masses put on in the run
        if kind in ("trial", "check"):
            tt = t.get(key)
            if not isinstance(tt, dict) or not tt:
                raise ValueError(f"{where}.{key}: a {kind} run needs e.g. {key} = "
                                 f"{{ P1 = \"1.15 @ 0\" }} (mass in {mu} @ angle deg"
                                 + (", the corrections installed before it)" if key != "trial"
                                    else ")"))
            for p, x in tt.items():
                a, ph = _polar(x, f"{where}.{key}.{p}", mass_unit_ok)
                if not a > 0:
                    raise ValueError(f"{where}.{key}.{p} = {x!r}: the mass must be > 0 {mu}")
                add(job.planes, p)
                trial[p] = a * job.mass_factor * complex(math.cos(ph), math.sin(ph))
                trial_std[p] = _weighing_std(x, job.mass_factor)
        for k_, owner in (("trial", "trial"), ("corrections", "check")):
            if k_ in t and kind != owner:
                raise ValueError(f"{where}.{k_}: only a run of kind = \"{owner}\" carries {k_}")
        removed = t.get("removed", kind != "check")     # corrections stay on
        if not isinstance(removed, bool):
            raise ValueError(f"{where}.removed = {removed!r}: true or false")
        if "recording" in t:
            if "readings" in t:
                raise ValueError(f"{where}: give readings or a recording, not both")
            if quantity != "displacement":
                raise ValueError(f"{where}.recording: a recording's 1X phasors are "
                                 f"displacements; job.vibration_unit = {vu!r} is a {quantity}")
            vals, stds, w_rec = _recorded(t, where, source, job.sensors)
            for s in vals:
                add(job.sensors, s)
            phased.append(f"{where}.recording")
            speed = speed_of(t, where)
            job.runs.append(FieldRun(i, kind, w_rec if math.isnan(speed) else speed, trial,
                                     removed, vals, stds, trial_std))
            continue
        rd = t.get("readings")
        if not isinstance(rd, dict) or not rd:
            raise ValueError(f"{where}.readings: e.g. readings = {{ S1 = \"170 @ 112\" }} "
                             f"({vu} {amp} @ deg)")
        vals, stds = {}, {}
        for s, v in rd.items():
            add(job.sensors, s)
            vals[s], stds[s] = reading(v, f"{where}.readings.{s}")
        job.runs.append(FieldRun(i, kind, speed_of(t, where), trial, removed, vals, stds,
                                 trial_std))
    if phase_free and phased:
        raise ValueError(f"{phase_free[0]}: an amplitude-only reading, but {phased[0]} has a phase: "
                         f"write every reading as \"amplitude @ angle\" or every one as "
                         f"\"amplitude\" (amplitude-only balancing)")
    job.amplitude_only = bool(phase_free)

    if influence_doc is not None:
        if not influence_doc.get("influence"):
            raise ValueError("influence file: no [[influence]] table")
        src = parse_job({"job": influence_doc.get("job", {}),
                         "influence": influence_doc.get("influence")}, source)
        for s in src.sensors:
            add(job.sensors, s)
        for p in src.planes:
            add(job.planes, p)
        job.influence, job.influence_std = src.influence, src.influence_std
        job.influence_source = str(influence_doc["influence"][0].get("measured_by", ""))
        return job
    scale = vf * AMPLITUDES[amp] / job.mass_factor
    tables = doc.get("influence") or []
    if not isinstance(tables, list):
        raise ValueError("influence: use [[influence]] tables (an array of tables)")
    for i, t in enumerate(tables):
        where = f"influence[{i}]"
        if not isinstance(t, dict):
            raise ValueError(f"{where}: expected a table")
        m = {}
        for s, row in t.items():
            if s in ("speed", "std", "measured_by"):
                continue
            if not isinstance(row, dict):
                raise ValueError(f"{where}.{s}: e.g. {s} = {{ P1 = \"78.4 @ 58.4\" }}")
            add(job.sensors, s)
            m[s] = {}
            for p, x in row.items():
                a, ph = _polar(x, f"{where}.{s}.{p}", lambda u, f_: None)
                add(job.planes, p)
                m[s][p] = a * scale * complex(math.cos(ph), math.sin(ph))
        job.influence.append((speed_of(t, where), m))
        job.influence_std.append(_influence_std(t.get("std", {}), m, scale, where))
    return job


def _influence_std(table, m, scale, where) -> dict:
    """``std = { S1 = { P1 = 0.51 } }`` of an ``[[influence]]`` table (each of Re and Im, the
    coefficient's unit: vibration per mass) -> {sensor: {plane: SI}}; missing: exact (0)."""
    if not isinstance(table, dict):
        raise ValueError(f"{where}.std = {table!r}: e.g. std = {{ S1 = {{ P1 = 0.5 }} }}")
    out = {}
    for s, row in table.items():
        if s not in m or not isinstance(row, dict):
            raise ValueError(f"{where}.std.{s}: a table of the planes of sensor {s}'s coefficients")
        for p, v in row.items():
            if (p not in m[s] or isinstance(v, bool) or not isinstance(v, (int, float))
                    or not (math.isfinite(v) and v >= 0)):
                raise ValueError(f"{where}.std.{s}.{p} = {v!r}: a number >= 0 (the coefficient's "
                                 f"standard uncertainty, its unit) for a coefficient of the table")
            out.setdefault(s, {})[p] = float(v) * scale
    return out


def _recorded(t, where, source, declared):
    """Readings of a run taken from a recording (``stand influence``'s path): the 1X phasor
    of each sensor plane over the steady part (or from ``t_start`` [s]) -> (readings [m],
    their standard uncertainties [m], the run's mean speed [rad/s])."""
    from pathlib import Path

    from .influence import run_phasors

    path = Path(str(t["recording"]))
    if not path.is_absolute() and source:
        path = Path(source).parent / path
    sens = t.get("sensors", declared)
    if isinstance(sens, list):
        sens = {str(s): str(s) for s in sens}
    if not isinstance(sens, dict) or not sens:
        raise ValueError(f"{where}.sensors: name the recording's planes to read, e.g. "
                         f"sensors = [\"probe1\", \"probe2\"] or {{ S1 = \"probe1\" }}")
    t0 = t.get("t_start")
    if t0 is not None:
        t0 = parse_quantity(t0, "time", f"{where}.t_start", default_unit="s")
    comps = run_phasors(str(path), list(sens.values()), t_start=t0, name=f"{where} ({path})")
    vals = {s: complex(c.vector_m) for s, c in zip(sens, comps)}
    stds = {s: float(c.vector_std_m) for s, c in zip(sens, comps)}
    return vals, stds, float(np.mean([c.speed_rad_s for c in comps]))


def reference_sensors(runs, order, at: str = "",
                      need: str = "give exactly one kind = \"reference\" per speed"):
    """``(reference run, sensors)`` of a set of runs at one speed: exactly one reference run,
    and every other run reads every sensor the reference reads (else a one-line error naming
    the run and the sensors; ``order``: the job's sensors, in their order; ``at``: " at N rpm"
    or ""; ``need``: what to do about the count)."""
    refs = [r for r in runs if r.kind == "reference"]
    if len(refs) != 1:
        raise ValueError(f"run: {len(refs)} reference run(s){at}; {need}")
    sensors = [s for s in order if s in refs[0].readings]
    for r in runs:
        miss = [s for s in sensors if s not in r.readings]
        if miss:
            raise ValueError(f"{r.label}.readings: no reading of {', '.join(miss)} "
                             f"(the reference run{at} has them)")
    return refs[0], sensors


def read_job(path, influence: Optional[str] = None) -> FieldJob:
    """Read a job file (and, with ``influence``, a saved influence file) -> :class:`FieldJob`."""
    from stand.io.tomlfile import read_toml

    doc, _, label = read_toml(path, what="job file", error=ValueError)
    inf = None
    if influence is not None:
        from .field_influence_file import linked_runs

        inf, _, _ = read_toml(influence, what="influence file", error=ValueError)
        runs = linked_runs(doc, inf)
        if runs is not None:          # the measuring job's own reference: that job, its ±
            job = parse_job({**doc, "run": runs}, str(path))
            job.influence_source = str((inf.get("influence") or [{}])[0].get("measured_by", ""))
            return job
    return parse_job(doc, str(path), inf)
