"""Units of lab columns: one table per quantity, converted to SI once, here.

Spellings are case-sensitive where SI needs it (``ms`` vs ``Ms`` is not an issue
here: only the listed spellings are accepted) and ``u`` stands for micro.
"""
from __future__ import annotations

import math
import re

__all__ = ["QUANTITIES", "factor", "parse_quantity", "unit_from_name", "UnitError",
           "vibration_quantity", "split_convention", "sensitivity_of", "VIBRATION", "AMPLITUDE"]


class UnitError(ValueError):
    """An unknown or misplaced unit; the message names the field, the value and what fits."""


_MICRO = ("um", "µm", "μm")
G_N = 9.80665           #: standard gravity [m/s²] (the "g" of accelerometers)
#: what a vibration channel measures, by its unit; the time derivative of displacement
VIBRATION = {"length": 0, "velocity": 1, "acceleration": 2}
#: the sensitivity table of each vibration quantity
SENSITIVITY = {"length": "sensitivity", "velocity": "velocity_sensitivity",
               "acceleration": "acceleration_sensitivity"}
#: amplitude conventions a channel's unit may carry: factor to the peak (a sine's)
AMPLITUDE = {"pk": 1.0, "peak": 1.0, "0-pk": 1.0, "pk-pk": 0.5, "p-p": 0.5, "pp": 0.5,
             "rms": math.sqrt(2.0)}
QUANTITIES = {
    "time": {"s": 1.0, "ms": 1e-3, "us": 1e-6, "µs": 1e-6, "μs": 1e-6, "min": 60.0, "h": 3600.0},
    "length": {"m": 1.0, "mm": 1e-3, **{u: 1e-6 for u in _MICRO}, "nm": 1e-9,
               "mil": 25.4e-6, "mils": 25.4e-6, "in": 25.4e-3},
    "speed": {"rad/s": 1.0, "rpm": 2 * math.pi / 60, "r/min": 2 * math.pi / 60,
              "Hz": 2 * math.pi, "rev/s": 2 * math.pi, "rps": 2 * math.pi},
    "angle": {"rad": 1.0, "deg": math.pi / 180, "°": math.pi / 180, "rev": 2 * math.pi},
    "velocity": {"m/s": 1.0, "mm/s": 1e-3, "um/s": 1e-6, "µm/s": 1e-6, "in/s": 25.4e-3,
                 "ips": 25.4e-3},
    "acceleration": {"m/s²": 1.0, "m/s^2": 1.0, "m/s2": 1.0, "mm/s²": 1e-3, "mm/s^2": 1e-3,
                     "mm/s2": 1e-3, "g": G_N, "gn": G_N},
    "voltage": {"V": 1.0, "mV": 1e-3},
    "mass": {"kg": 1.0, "g": 1e-3, "mg": 1e-6, "oz": 0.028349523125, "lb": 0.45359237},
    "sensitivity": {"V/m": 1.0, "V/mm": 1e3, "mV/mm": 1.0, "mV/um": 1e3, "mV/µm": 1e3,
                    "mV/mil": 1e-3 / 25.4e-6, "V/mil": 1.0 / 25.4e-6},
    # volts per unit of velocity / acceleration, to V per SI unit (V/(m/s), V/(m/s²))
    "velocity_sensitivity": {"V/(m/s)": 1.0, "mV/(m/s)": 1e-3, "mV/(mm/s)": 1.0, "V/(mm/s)": 1e3,
                             "mV/(in/s)": 1e-3 / 25.4e-3, "V/(in/s)": 1.0 / 25.4e-3,
                             "mV/ips": 1e-3 / 25.4e-3, "V/ips": 1.0 / 25.4e-3},
    "acceleration_sensitivity": {"V/(m/s²)": 1.0, "mV/(m/s²)": 1e-3, "V/(m/s^2)": 1.0,
                                 "mV/(m/s^2)": 1e-3, "V/(m/s2)": 1.0, "mV/(m/s2)": 1e-3,
                                 "mV/g": 1e-3 / G_N, "V/g": 1.0 / G_N},
    "unbalance": {"g mm": 1e-6, "g*mm": 1e-6, "g·mm": 1e-6, "kg m": 1.0, "kg*m": 1.0},
}
#: the quantity each signal role is measured in (a displacement may also be a voltage)
ROLE_QUANTITY = {"time": "time", "x": "length", "y": "length", "speed": "speed",
                 "angle": "angle", "keyphasor": "voltage", "photogate": "voltage",
                 "amplitude": "length", "phase": "angle"}


def factor(quantity: str, unit: str, field: str) -> float:
    """SI factor of ``unit`` for ``quantity``; :class:`UnitError` naming ``field`` otherwise."""
    table = QUANTITIES[quantity]
    u = unit.strip()
    if u in table:
        return table[u]
    for q, t in QUANTITIES.items():          # a known unit of another quantity
        if u in t:
            raise UnitError(f"{field}: unit {unit!r} is a {q} unit; a {quantity} needs one of "
                            f"{', '.join(table)}")
    raise UnitError(f"{field}: unknown unit {unit!r} (a {quantity}: one of {', '.join(table)})")


def split_convention(unit: str):
    """``"g pk"`` -> ``("g", "pk")``, ``"mm/s rms"`` -> ``("mm/s", "rms")``, ``"um"`` -> ``("um", None)``."""
    u = str(unit).strip()
    for conv in sorted(AMPLITUDE, key=len, reverse=True):
        for sep in (" ", "_", ","):
            if u.lower().endswith(sep + conv):
                return u[: -len(conv) - 1].strip(), conv
    return u, None


def vibration_quantity(unit: str, field: str) -> str:
    """``length``, ``velocity`` or ``acceleration`` of a vibration channel's unit (volts:
    by its sensitivity, see :func:`sensitivity_of`)."""
    u, _ = split_convention(unit)
    for q in VIBRATION:
        if u in QUANTITIES[q]:
            return q
    known = [k for q in VIBRATION for k in QUANTITIES[q]]
    for q, t in QUANTITIES.items():
        if u in t:
            raise UnitError(f"{field}: unit {unit!r} is a {q} unit; a vibration channel needs a "
                            f"displacement, velocity or acceleration unit ({', '.join(known)}), "
                            "or V/mV with a sensitivity")
    raise UnitError(f"{field}: unknown unit {unit!r} (a vibration channel: one of "
                    f"{', '.join(known)}, or V/mV with a sensitivity)")


def sensitivity_of(text: str, field: str):
    """``"7.87 V/mm"`` / ``"100 mV/g"`` / ``"4 mV/(mm/s)"`` -> (V per SI unit, quantity)."""
    m = _NUM_UNIT.match(str(text))
    unit = m.group(2).replace(" ", "") if m else ""
    for q, table in SENSITIVITY.items():
        if unit in QUANTITIES[table]:
            return parse_quantity(str(text).replace(m.group(2), unit), table, field), q
    raise UnitError(f"{field} = {text!r}: a sensitivity such as '7.87 V/mm', '100 mV/g' or "
                    "'4 mV/(mm/s)'")


def is_sensitivity(text: str) -> bool:
    m = _NUM_UNIT.match(str(text))
    unit = m.group(2).replace(" ", "") if m else ""
    return bool(m) and any(unit in QUANTITIES[t] for t in SENSITIVITY.values())


_NUM_UNIT = re.compile(r"^\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*(.*?)\s*$")


def parse_quantity(value, quantity: str, field: str, default_unit: str | None = None) -> float:
    """``"12 kg"``, ``"3000 rpm"``, ``"7.87 V/mm"`` or a bare number (in ``default_unit``) -> SI."""
    if isinstance(value, bool):
        raise UnitError(f"{field} = {value!r}: a {quantity} with its unit, e.g. "
                        f"\"1.0 {next(iter(QUANTITIES[quantity]))}\"")
    if isinstance(value, (int, float)):
        if default_unit is None:
            raise UnitError(f"{field} = {value!r}: give the unit, e.g. \"{value} "
                            f"{next(iter(QUANTITIES[quantity]))}\"")
        x, unit = float(value), default_unit
    else:
        m = _NUM_UNIT.match(str(value))
        if not m:
            raise UnitError(f"{field} = {value!r}: expected a number and a unit, e.g. "
                            f"\"1.0 {next(iter(QUANTITIES[quantity]))}\"")
        x, unit = float(m.group(1)), m.group(2) or default_unit
        if not unit:
            raise UnitError(f"{field} = {value!r}: give the unit ({', '.join(QUANTITIES[quantity])})")
    if not math.isfinite(x):
        raise UnitError(f"{field} = {value!r}: not finite")
    return x * factor(quantity, unit, f"{field} = {value!r}")


_SUFFIX = re.compile(r"(?:[\s_]*[\[(]\s*([^\])]+?)\s*[\])]\s*$)|(?:_([A-Za-zµμ°/]+)$)")


def unit_from_name(name: str, quantity: str) -> str | None:
    """The unit a column's name carries: ``disp_x_um``, ``Time [ms]``, ``speed (rpm)`` -> the
    unit if it is one of ``quantity``'s, else None."""
    low = str(name).strip().lower()
    for tail, unit in (("_rad_s", "rad/s"), ("_rev_s", "rev/s"), ("_v_m", "V/m")):
        if low.endswith(tail):
            return unit if unit in QUANTITIES[quantity] else None
    m = _SUFFIX.search(str(name))
    if not m:
        return None
    u = (m.group(1) or m.group(2) or "").strip()
    aliases = {"rad_s": "rad/s", "rev_s": "rev/s", "hz": "Hz", "v": "V", "mv": "mV",
               "deg": "deg", "sec": "s"}
    u = aliases.get(u, aliases.get(u.lower(), u))
    return u if u in QUANTITIES[quantity] else None
