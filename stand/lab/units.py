"""Units of lab columns: one table per quantity, converted to SI once, here.

The tables and the parser of ``"<number> <unit>"`` strings are :mod:`stand.io.units` (shared
with the scene files); this module adds what a lab's channels need: vibration quantities,
amplitude conventions, sensitivities and units carried by column names.  Spellings are
case-sensitive where SI needs it (``ms`` vs ``Ms`` is not an issue here: only the listed
spellings are accepted) and ``u`` stands for micro.
"""
from __future__ import annotations

import math
import re

from stand.io.units import _NUM_UNIT, G_N, QUANTITIES, UnitError, factor, parse_quantity  # noqa: F401

__all__ = ["QUANTITIES", "factor", "parse_quantity", "unit_from_name", "UnitError",
           "vibration_quantity", "split_convention", "sensitivity_of", "VIBRATION", "AMPLITUDE"]


#: what a vibration channel measures, by its unit; the time derivative of displacement
VIBRATION = {"length": 0, "velocity": 1, "acceleration": 2}
#: the sensitivity table of each vibration quantity
SENSITIVITY = {"length": "sensitivity", "velocity": "velocity_sensitivity",
               "acceleration": "acceleration_sensitivity"}
#: amplitude conventions a channel's unit may carry: factor to the peak (a sine's)
AMPLITUDE = {"pk": 1.0, "peak": 1.0, "0-pk": 1.0, "pk-pk": 0.5, "p-p": 0.5, "pp": 0.5,
             "rms": math.sqrt(2.0)}
#: the quantity each signal role is measured in (a displacement may also be a voltage)
ROLE_QUANTITY = {"time": "time", "x": "length", "y": "length", "speed": "speed",
                 "angle": "angle", "keyphasor": "voltage", "photogate": "voltage",
                 "amplitude": "length", "phase": "angle"}


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
