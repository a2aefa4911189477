"""Which column of a lab table is what, in which unit: the recording map.

Two spellings of one map:

* on the command line, ``--columns time=time_s,x=disp_x_um[um],y=disp_y_um[um],speed=tacho_rpm[rpm]``
  (a role, ``=``, the column's name, and optionally ``[unit]`` or
  ``[unit, 7.87 V/mm]`` for a probe read in volts, ``[V, threshold=2.5]`` for a
  pulse channel);
* a TOML file (reusable for every export of a lab's DAQ)::

      [table]                 # all optional: found from the file
      delimiter = ";"
      decimal = ","
      header_row = 5          # 1-based line of the column names
      key = "vibration"       # HDF5 / Parquet: the table's key
      [columns]
      time = {column = "time_ms", unit = "ms"}
      x = {column = "disp_x_um", unit = "um"}
      y = {column = "probe_y", unit = "V", sensitivity = "7.87 V/mm"}
      keyphasor = {column = "kp_V", unit = "V"}       # threshold: default by Otsu's rule
      # a vibration channel's DAQ: its anti-alias filter (or a converter's group delay,
      # filter = {group_delay = "2.4 ms"}; a sensor's resonance = "2000 Hz", q = 30, highpass =
      # "0.5 Hz" in the same table) and its ADC range (at or beyond: censored)
      # x = {column = "disp_x_um", unit = "um", range = ["-400 um", "400 um"],
      #      filter = {type = "butterworth", order = 4, cutoff = "100 Hz"}}
      speed = "tacho_rpm [rpm]"                       # the short form works too
      [rotor]
      mass = "6 kg"               # vibrating mass: unbalance in g mm (else per kg)
      service_speed = "1560 rpm"  # ISO 21940-11 grade at this speed
      natural_frequency = "12 Hz" # optional: when the record cannot identify them
      damping_ratio = 0.04

Roles: ``time`` (required), ``x``, ``y`` (shaft displacement), ``speed``
(tachometer), ``angle`` (encoder), ``keyphasor`` (once-per-revolution pulses),
``photogate`` (the book's photo-gate on the laser beam).  A Bode / polar table
(:mod:`stand.lab.bode_table`) has ``speed``, ``amplitude`` and ``phase`` instead
(no time).  Without a map, the
well-known names are recognised (:func:`recognise`) and the choice is reported.
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass, field, replace
from typing import Optional

from stand.lab.units import (QUANTITIES, ROLE_QUANTITY, UnitError, factor, is_sensitivity, parse_quantity,
                             sensitivity_of, split_convention, unit_from_name, vibration_quantity)

__all__ = ["ColumnSpec", "RecordingMap", "parse_columns", "read_map", "map_from_options", "recognise", "ROLES",
           "MapError"]

ROLES = ("time", "x", "y", "speed", "angle", "keyphasor", "photogate", "amplitude", "phase")
#: roles whose unit says a vibration quantity (displacement, velocity, acceleration)
VIBRATION_ROLES = ("x", "y", "amplitude")


class MapError(ValueError):
    """A recording map that cannot be used; the message names the field."""


@dataclass(frozen=True)
class ColumnSpec:
    """One role's column.

    Attributes
    ----------
    role : str
        One of :data:`ROLES`.
    column : str
        The column's name in the table.
    unit : str or None
        Its unit (None: to be taken from the column's name, or the default).
    sensitivity_v_per_m : float or None
        A sensor read in volts: volts per SI unit of what it measures (V/m of
        displacement, V/(m/s) of velocity, V/(m/s²) of acceleration).
    threshold : float or None
        A pulse channel's level between its two states (in its own unit).
    sensitivity_quantity : str or None
        What the sensitivity is per: ``length``, ``velocity`` or ``acceleration``.
    filter : dsp.artefacts.ChannelFilter or None
        The channel's declared filter (the analysis takes it out of the 1X and the fit).
    rail : (float, float) or None
        The channel's ADC range in its own unit: samples at or beyond it are censored.
    """

    role: str
    column: str
    unit: Optional[str] = None
    sensitivity_v_per_m: Optional[float] = None
    threshold: Optional[float] = None
    sensitivity_quantity: Optional[str] = None
    filter: Optional[object] = None
    rail: Optional[tuple] = None

    def quantity(self, field: str = "") -> str:
        """What the channel measures: a vibration channel's ``length`` (displacement),
        ``velocity`` or ``acceleration`` (by its unit, or its sensitivity for volts); else the
        role's quantity."""
        if self.role not in VIBRATION_ROLES:
            return ROLE_QUANTITY[self.role]
        unit, _ = split_convention(self.unit or "m")
        if unit in QUANTITIES["voltage"]:
            return self.sensitivity_quantity or "length"
        try:
            return vibration_quantity(unit, field or f"{self.role} = column {self.column!r}")
        except UnitError as exc:
            raise MapError(str(exc)) from None

    def convention(self) -> Optional[str]:
        """The amplitude convention the unit carries (``pk``, ``pk-pk``, ``rms``) or None."""
        return split_convention(self.unit or "")[1]

    def si_factor(self, field: str) -> float:
        """Multiply the column by this to get SI (m, m/s, m/s², s, rad/s, rad; volts stay volts)."""
        q = ROLE_QUANTITY[self.role]
        unit = self.unit
        if self.role in VIBRATION_ROLES:
            unit, _ = split_convention(unit)
            if unit in QUANTITIES["voltage"]:
                if not self.sensitivity_v_per_m:
                    raise MapError(f"{field}: a sensor in {unit} needs its sensitivity, e.g. "
                                   f"[{unit}, 7.87 V/mm], [{unit}, 100 mV/g] or "
                                   f"[{unit}, 4 mV/(mm/s)]")
                return factor("voltage", unit, field) / self.sensitivity_v_per_m
            return factor(self.quantity(field), unit, field)
        return factor(q, unit, field)

    def describe(self) -> str:
        s = f"{self.role}={self.column}[{self.unit}]"
        if self.sensitivity_v_per_m:
            if (self.sensitivity_quantity or "length") == "length":
                s += f" at {self.sensitivity_v_per_m * 1e-3:g} V/mm"
            else:
                s += f" at {self.sensitivity_v_per_m:g} V per SI {self.sensitivity_quantity} unit"
        return s


@dataclass(frozen=True)
class RecordingMap:
    """Columns by role, the table's layout, and the machine's data (SI)."""

    columns: dict = field(default_factory=dict)
    delimiter: Optional[str] = None
    decimal: Optional[str] = None
    header_row: Optional[int] = None
    key: Optional[str] = None
    mass_kg: Optional[float] = None
    service_speed_rad_s: Optional[float] = None
    natural_frequency_hz: Optional[float] = None
    damping_ratio: Optional[float] = None
    probe_runout_m: Optional[float] = None
    source: str = "--columns"

    def merged(self, other: "RecordingMap") -> "RecordingMap":
        """``other``'s entries over this map's (``--columns`` over a map file)."""
        kw = {k: v for k, v in other.__dict__.items()
              if k not in ("columns", "source") and v is not None}
        return replace(self, columns={**self.columns, **other.columns}, **kw,
                       source=f"{self.source} + {other.source}")


_BRACKET = re.compile(r"^(.*?)\s*\[([^\]]*)\]\s*$")


def _spec(role: str, text: str, where: str) -> ColumnSpec:
    """``NAME``, ``NAME[unit]``, ``NAME[unit, 7.87 V/mm]``, ``NAME[V, threshold=2.5]``."""
    if role not in ROLES:
        raise MapError(f"{where}: unknown role {role!r} (one of {', '.join(ROLES)})")
    m = _BRACKET.match(text)
    name, unit, sens, thr, sq = text.strip(), None, None, None, None
    if m:
        name = m.group(1).strip()
        parts = [p.strip() for p in re.split(r"[,;]", m.group(2)) if p.strip()]
        for p in parts:
            if p.startswith("threshold"):
                try:
                    thr = float(p.split("=", 1)[1])
                except (IndexError, ValueError):
                    raise MapError(f"{where}: {p!r}: expected threshold=NUMBER") from None
            elif is_sensitivity(p):
                try:
                    sens, sq = sensitivity_of(p, f"{where} sensitivity")
                except UnitError as exc:
                    raise MapError(str(exc)) from None
            elif unit is None:
                unit = p
            else:
                raise MapError(f"{where}: {p!r} not understood (a unit, a sensitivity such as "
                               "'7.87 V/mm', or threshold=LEVEL)")
    if not name:
        raise MapError(f"{where}: no column name")
    return ColumnSpec(role, name, unit, sens, thr, sq)


def parse_columns(text: str) -> RecordingMap:
    """The ``--columns`` form: ``role=column[unit],...``."""
    cols = {}
    # split on commas that are not inside brackets
    items, depth, cur = [], 0, ""
    for ch in str(text):
        depth += ch == "["
        depth -= ch == "]"
        if ch == "," and depth == 0:
            items.append(cur)
            cur = ""
        else:
            cur += ch
    items.append(cur)
    for item in items:
        if not item.strip():
            continue
        if "=" not in item:
            raise MapError(f"--columns: {item.strip()!r}: expected ROLE=COLUMN[unit] "
                           f"(roles: {', '.join(ROLES)})")
        role, spec = item.split("=", 1)
        role = role.strip()
        if role in cols:
            raise MapError(f"--columns: role {role!r} given twice")
        cols[role] = _spec(role, spec, f"--columns {role}")
    return RecordingMap(columns=cols, source="--columns")


def _allow(data, where, keys, label) -> None:
    """Unknown keys of a map table: one line with a "did you mean" (stand.io.validate)."""
    from stand.errors import SceneError
    from stand.io.validate import Table

    try:
        Table(data, where).allow(keys)
    except SceneError as exc:
        raise MapError(f"{label}{exc}") from None


def read_map(path) -> RecordingMap:
    """A TOML recording map (module docstring); errors name the file and the key."""
    from stand.io.tomlfile import read_toml

    data, _, label = read_toml(path, "recording map", MapError)
    unknown = set(data) - {"table", "columns", "rotor", "probes"}
    if unknown:
        raise MapError(f"{label}unknown table(s) {sorted(unknown)} (expected [table], [columns], "
                       "[rotor], [probes])")
    cols = {}
    for role, v in (data.get("columns") or {}).items():
        where = f"{label}columns.{role}"
        if isinstance(v, str):
            cols[role] = _spec(role, v, where)
        elif isinstance(v, dict):
            bad = set(v) - {"column", "unit", "sensitivity", "threshold", "filter", "range"}
            if bad or "column" not in v:
                raise MapError(f"{where}: expected {{column = NAME, unit = UNIT[, sensitivity = "
                               f"\"7.87 V/mm\", threshold = LEVEL]}}, got keys {sorted(v)}")
            if role not in ROLES:
                raise MapError(f"{where}: unknown role {role!r} (one of {', '.join(ROLES)})")
            sens, sq = v.get("sensitivity"), None
            if sens is not None:
                try:
                    sens, sq = sensitivity_of(sens, f"{where}.sensitivity")
                except UnitError as exc:
                    raise MapError(str(exc)) from None
            cols[role] = ColumnSpec(role, str(v["column"]), v.get("unit"), sens,
                                    None if v.get("threshold") is None else float(v["threshold"]),
                                    sq, _filter(v.get("filter"), f"{where}.filter"),
                                    _rail(v.get("range"), v.get("unit"), f"{where}.range"))
        else:
            raise MapError(f"{where} = {v!r}: a column name (\"NAME [unit]\") or a table")
    tab = data.get("table") or {}
    _allow(tab, "table", ("delimiter", "decimal", "header_row", "key"), label)
    hr = tab.get("header_row")
    if hr is not None and (not isinstance(hr, int) or hr < 1):
        raise MapError(f"{label}table.header_row = {hr!r}: a line number >= 1")
    rot = data.get("rotor") or {}
    _allow(rot, "rotor", ("mass", "service_speed", "natural_frequency", "damping_ratio"), label)

    def q(key, quantity):
        if key not in rot:
            return None
        val = parse_quantity(rot[key], quantity, f"{label}rotor.{key}")
        if not val > 0:
            raise MapError(f"{label}rotor.{key} = {rot[key]!r}: must be > 0")
        return val

    zeta = rot.get("damping_ratio")
    if zeta is not None and (isinstance(zeta, bool) or not isinstance(zeta, (int, float))
                             or not 0 <= zeta < 1):
        raise MapError(f"{label}rotor.damping_ratio = {zeta!r}: a number in [0, 1)")
    f0 = q("natural_frequency", "speed")
    probes = data.get("probes") or {}
    _allow(probes, "probes", ("runout",), label)
    runout = None
    if "runout" in probes:
        runout = parse_quantity(probes["runout"], "length", f"{label}probes.runout")
        if not runout >= 0:
            raise MapError(f"{label}probes.runout = {probes['runout']!r}: must be >= 0 (the "
                           "probes' 1X runout, e.g. \"2 um\"; 0 when it is compensated)")
    try:
        return RecordingMap(columns=cols, delimiter=tab.get("delimiter"), decimal=tab.get("decimal"),
                            header_row=hr, key=tab.get("key"), mass_kg=q("mass", "mass"),
                            service_speed_rad_s=q("service_speed", "speed"),
                            natural_frequency_hz=None if f0 is None else f0 / (2 * math.pi),
                            damping_ratio=None if zeta is None else float(zeta),
                            probe_runout_m=runout, source=str(path))
    except UnitError as exc:
        raise MapError(str(exc)) from None


def _filter(v, where):
    """``{type = "butterworth"|"bessel", order = N, cutoff = "100 Hz"}``, ``{group_delay =
    "2.4 ms"}``, the sensor's ``{resonance = "2000 Hz", q = 30, highpass = "0.5 Hz"}`` (any of
    them together) -> :class:`dsp.artefacts.ChannelFilter`."""
    from dsp.artefacts import ChannelFilter
    from dsp.errors import SignalError

    if v is None:
        return None
    keys = {"type", "order", "cutoff", "group_delay", "resonance", "q", "highpass"}
    if not isinstance(v, dict) or set(v) - keys or not ({"type", "group_delay", "resonance",
                                                          "highpass"} & set(v)):
        raise MapError(f"{where} = {v!r}: expected {{type = \"butterworth\" or \"bessel\", order = 4, "
                       f"cutoff = \"100 Hz\"}} and/or {{group_delay = \"2.4 ms\"}} and/or the "
                       f"sensor's {{resonance = \"2000 Hz\", q = 30, highpass = \"0.5 Hz\"}}")

    def hz(key):
        return parse_quantity(v[key], "speed", f"{where}.{key}") / (2 * math.pi) if key in v else 0.0

    try:
        delay = parse_quantity(v["group_delay"], "time", f"{where}.group_delay") \
            if "group_delay" in v else 0.0
        kind = str(v.get("type", "delay" if "group_delay" in v else "none"))
        return ChannelFilter(kind, v.get("order", 0), hz("cutoff"), delay, hz("resonance"),
                             float(v.get("q", 30.0)), hz("highpass"))
    except (UnitError, SignalError, TypeError, ValueError) as exc:
        raise MapError(f"{where}: {exc}") from None


def _rail(v, unit, where):
    """``range = ["-400 um", "400 um"]`` -> (low, high) in the channel's own ``unit``."""
    if v is None:
        return None
    try:
        lo, hi = (parse_quantity(q, "length", where) / factor("length", unit, where)
                  if isinstance(q, str) else float(q) for q in v)
    except (TypeError, ValueError, UnitError):
        raise MapError(f"{where} = {v!r}: the ADC range as [LOW, HIGH], e.g. [\"-400 um\", "
                       "\"400 um\"] (numbers: the channel's unit)") from None
    if not lo < hi:
        raise MapError(f"{where} = {v!r}: LOW must be below HIGH")
    return (lo, hi)


# ------------------------------------------------------------------ recognition
_KNOWN = {
    "time": ("t", "time", "zeit", "timestamp", "elapsed", "elapsed_time"),
    "x": ("x", "disp_x", "x_disp", "probe_x", "shaft_x", "displacement_x", "dx", "vib_x"),
    "y": ("y", "disp_y", "y_disp", "probe_y", "shaft_y", "displacement_y", "dy", "vib_y"),
    "speed": ("speed", "rpm", "tacho", "tach", "tacho_speed", "rotor_speed", "omega", "n",
              "shaft_speed", "tachometer"),
    "angle": ("rotor_angle", "angle", "phi", "encoder", "encoder_angle"),
    "keyphasor": ("keyphasor", "kp", "key", "once_per_rev", "opr", "1x_ref", "trigger",
                  "keyphasor_pulse", "tacho_pulse"),
    "photogate": ("photogate", "photo_gate", "gate", "photo"),
}
#: unit assumed when a recognised column's name carries none
DEFAULT_UNIT = {"time": "s", "x": "m", "y": "m", "speed": "rad/s", "angle": "rad",
                "keyphasor": "V", "photogate": "V", "amplitude": "um", "phase": "deg"}


def _base(name: str) -> str:
    s = re.sub(r"\s*[\[(][^\])]*[\])]\s*$", "", str(name)).strip().lower()
    s = re.sub(r"[\s\-.]+", "_", s)
    for tail in ("_rad_s", "_rev_s"):
        if s.endswith(tail):
            return s[: -len(tail)]
    units = {u.lower() for t in QUANTITIES.values() for u in t} | {"sec"}
    parts = s.split("_")
    if len(parts) > 1 and parts[-1] in units:
        s = "_".join(parts[:-1])
    return s


def recognise(columns) -> tuple[dict, list]:
    """Roles of well-known column names.

    When several columns fit a role, the one whose name carries its unit wins over one
    whose unit would be assumed, and among those the SI one (a track's ``x_m``, the
    shaft, over its ``x_mm``, the screen; ``t_s`` over a bare ``time``).

    Returns
    -------
    (dict, list of str)
        ``{role: ColumnSpec}`` with the unit from the name (or the role's SI
        default) and one line per choice (what was taken, and where a unit was
        assumed) for the user.
    """
    cands = {}
    for order, col in enumerate(columns):
        b = _base(col)
        for role, names in _KNOWN.items():
            if b not in names:
                continue
            unit = unit_from_name(col, ROLE_QUANTITY[role])
            if role in ("x", "y") and unit is None:
                unit = unit_from_name(col, "voltage")
            if role == "speed" and unit is None and b == "rpm":
                unit = "rpm"
            assumed = unit is None
            unit = unit or DEFAULT_UNIT[role]
            q = ROLE_QUANTITY[role]
            si = unit in QUANTITIES[q] and QUANTITIES[q][unit] == 1.0
            rank = (assumed, not si, order)
            if role not in cands or rank < cands[role][0]:
                cands[role] = (rank, ColumnSpec(role, str(col), unit), assumed)
            break
    found, lines = {}, []
    for role in _KNOWN:
        if role in cands:
            _, spec, assumed = cands[role]
            found[role] = spec
            lines.append(f"{role} = column {spec.column!r} [{spec.unit}]"
                         + (" (no unit in the name: assumed)" if assumed else ""))
    return found, lines


def map_from_options(columns: Optional[str] = None, map_path=None) -> Optional[RecordingMap]:
    """The recording map of ``--map FILE`` and ``--columns SPEC`` (the latter wins per role);
    None when neither is given."""
    m = read_map(map_path) if map_path else None
    if columns:
        c = parse_columns(columns)
        m = c if m is None else m.merged(c)
    return m
