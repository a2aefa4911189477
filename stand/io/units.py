"""Units: one table per quantity, and the one parser of ``"<number> <unit>"`` strings.

Every input that takes a unit goes through :func:`parse_quantity` (a lab's columns and
job files, :mod:`stand.lab.units`; a scene file's angles given as ``"0.7 rad"``,
:func:`stand.io.validate.angle`): the value is converted to SI once, here.  Spellings are
case-sensitive where SI needs it (only the listed spellings are accepted) and ``u``
stands for micro.
"""
from __future__ import annotations

import math
import re

__all__ = ["QUANTITIES", "UnitError", "factor", "parse_quantity", "G_N"]


class UnitError(ValueError):
    """An unknown or misplaced unit; the message names the field, the value and what fits."""


_MICRO = ("um", "µm", "μm")
G_N = 9.80665           #: standard gravity [m/s²] (the "g" of accelerometers)
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


def _a(quantity: str) -> str:
    return f"{'an' if quantity[:1] in 'aeiou' else 'a'} {quantity}"


def factor(quantity: str, unit: str, field: str) -> float:
    """SI factor of ``unit`` for ``quantity``; :class:`UnitError` naming ``field`` otherwise."""
    table = QUANTITIES[quantity]
    u = unit.strip()
    if u in table:
        return table[u]
    for q, t in QUANTITIES.items():          # a known unit of another quantity
        if u in t:
            raise UnitError(f"{field}: unit {unit!r} is {_a(q)} unit; {_a(quantity)} needs one "
                            f"of {', '.join(table)}")
    raise UnitError(f"{field}: unknown unit {unit!r} ({_a(quantity)}: one of {', '.join(table)})")


_NUM_UNIT = re.compile(r"^\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*(.*?)\s*$")


def parse_quantity(value, quantity: str, field: str, default_unit: str | None = None) -> float:
    """``"12 kg"``, ``"3000 rpm"``, ``"7.87 V/mm"`` or a bare number (in ``default_unit``) -> SI."""
    if isinstance(value, bool):
        raise UnitError(f"{field} = {value!r}: {_a(quantity)} with its unit, e.g. "
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
