"""Units of lab columns: one table per quantity, converted to SI once, here.

Spellings are case-sensitive where SI needs it (``ms`` vs ``Ms`` is not an issue
here: only the listed spellings are accepted) and ``u`` stands for micro.
"""
from __future__ import annotations

import math
import re

__all__ = ["QUANTITIES", "factor", "parse_quantity", "unit_from_name", "UnitError"]


class UnitError(ValueError):
    """An unknown or misplaced unit; the message names the field, the value and what fits."""


_MICRO = ("um", "µm", "μm")
QUANTITIES = {
    "time": {"s": 1.0, "ms": 1e-3, "us": 1e-6, "µs": 1e-6, "μs": 1e-6, "min": 60.0, "h": 3600.0},
    "length": {"m": 1.0, "mm": 1e-3, **{u: 1e-6 for u in _MICRO}, "nm": 1e-9,
               "mil": 25.4e-6, "mils": 25.4e-6, "in": 25.4e-3},
    "speed": {"rad/s": 1.0, "rpm": 2 * math.pi / 60, "r/min": 2 * math.pi / 60,
              "Hz": 2 * math.pi, "rev/s": 2 * math.pi, "rps": 2 * math.pi},
    "angle": {"rad": 1.0, "deg": math.pi / 180, "°": math.pi / 180, "rev": 2 * math.pi},
    "voltage": {"V": 1.0, "mV": 1e-3},
    "mass": {"kg": 1.0, "g": 1e-3},
    "sensitivity": {"V/m": 1.0, "V/mm": 1e3, "mV/mm": 1.0, "mV/um": 1e3, "mV/µm": 1e3,
                    "mV/mil": 1e-3 / 25.4e-6, "V/mil": 1.0 / 25.4e-6},
    "unbalance": {"g mm": 1e-6, "g*mm": 1e-6, "g·mm": 1e-6, "kg m": 1.0, "kg*m": 1.0},
}
#: the quantity each signal role is measured in (a displacement may also be a voltage)
ROLE_QUANTITY = {"time": "time", "x": "length", "y": "length", "speed": "speed",
                 "angle": "angle", "keyphasor": "voltage", "photogate": "voltage"}


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
