"""The values a fit may change: scene keys named by their dotted TOML path.

``--free supports.stiffness,rotor.unbalance_angle=0..360,balancer.drag=0.01..1`` names
values of a scene file by their path in the TOML document (``table.key``, ``table.key[i]``
for one element of a list, ``weights[0].drag`` for an array of tables), each with optional
bounds ``LO..HI`` in the file's own units.  A path to a list frees every element.  The
fit reads and writes the values in the scene file's units (angles in degrees, speeds in
rev/s); the scene parser converts them, once, as for any scene file.

:func:`parse_free` turns the option into :class:`FreeValue` objects, :func:`get_value` /
:func:`set_value` read and write a parsed TOML document, :func:`scene_with` builds the
:class:`stand.scene.model.Scene` of a document with some values replaced.
"""
from __future__ import annotations

import copy
import math
import re
from dataclasses import dataclass
from typing import Any, Optional

from stand.errors import SceneError

__all__ = ["FreeValue", "parse_free", "get_value", "set_value", "unit_of", "scene_with",
           "FitError"]


class FitError(ValueError):
    """A fit that cannot be set up: a free path that names no number, bounds that exclude
    the start, a record without what the fit needs.  One line naming the path or file."""


#: units of the keys of the scene files (docs/scene.md), by table and key; per-weight keys
#: of ``[balancer]`` and of ball/pendulum ``[[weights]]`` share theirs
_UNITS = {
    "rotor": {"mass": "kg", "eccentricity": "m", "unbalance_angle": "deg", "inertia": "kg*m^2"},
    "supports": {"stiffness": "N/m", "stiffness_x": "N/m", "stiffness_y": "N/m",
                 "damping": "N*s/m", "damping_x": "N*s/m", "damping_y": "N*s/m"},
    "balancer": {"mass": "kg", "radius": "m", "drag": "N*s/m", "inertia": "kg*m^2",
                 "initial_angles": "deg", "initial_speeds": "rev/s", "friction": "1",
                 "static_friction": "1", "slip_speed": "rad/s", "dwell_time": "s",
                 "release_time": "s"},
    "initial": {"x": "m", "y": "m", "vx": "m/s", "vy": "m/s"},
    "drive": {"torque": "N*m", "c1": "N*m*s", "c2": "N*m", "target_speed": "rev/s",
              "rotor_drag": "N*m*s", "initial_speed": "rev/s", "inertia": "kg*m^2"},
}
#: keys that are >= 0 by the scene's rules (others: > 0, or any sign where the unit says so)
_NON_NEGATIVE = {"eccentricity", "damping", "damping_x", "damping_y", "drag", "friction",
                 "static_friction", "rotor_drag", "unbalance", "couple_unbalance",
                 "damping_ratio", "stiffness_damping"}
#: keys with any sign
_ANY_SIGN = {"unbalance_angle", "initial_angles", "initial_speeds", "x", "y", "vx", "vy", "alpha",
             "torque", "initial_speed"}

_STEP = re.compile(r"([A-Za-z_][A-Za-z0-9_]*)(?:\[(\d+)\])?$")


def _steps(path: str) -> list:
    """``"weights[0].drag"`` -> ``[("weights", 0), ("drag", None)]``."""
    out = []
    for part in path.split("."):
        m = _STEP.match(part.strip())
        if not m:
            raise FitError(f"--free {path!r}: {part!r} is not a key name (write table.key, "
                           "table.key[i] or weights[i].key)")
        out.append((m.group(1), None if m.group(2) is None else int(m.group(2))))
    return out


def _walk(doc, path: str, create: bool = False):
    """The container holding the last step of ``path`` and that step's (key, index)."""
    steps = _steps(path)
    node = doc
    for i, (key, idx) in enumerate(steps[:-1]):
        if not isinstance(node, dict) or key not in node:
            raise FitError(f"--free {path!r}: the scene has no table "
                           f"[{'.'.join(k for k, _ in steps[:i + 1])}]")
        node = node[key]
        if idx is not None:
            if not isinstance(node, list) or idx >= len(node):
                raise FitError(f"--free {path!r}: {key}[{idx}] does not exist "
                               f"({len(node) if isinstance(node, list) else 0} entries)")
            node = node[idx]
    if not isinstance(node, dict):
        raise FitError(f"--free {path!r}: {'.'.join(k for k, _ in steps[:-1])} is not a table")
    return node, steps[-1]


def get_value(doc, path: str) -> Any:
    """The value at ``path`` in a parsed TOML document (KeyError-free: FitError)."""
    node, (key, idx) = _walk(doc, path)
    if key not in node:
        raise FitError(f"--free {path!r}: the scene file does not give "
                       f"{path.rpartition('.')[2]}; write its start value in the scene first")
    v = node[key]
    if idx is not None:
        if not isinstance(v, list) or idx >= len(v):
            raise FitError(f"--free {path!r}: index {idx} out of range")
        v = v[idx]
    return v


def set_value(doc, path: str, value: float) -> None:
    """Write ``value`` at ``path`` (in place)."""
    node, (key, idx) = _walk(doc, path)
    if idx is None:
        node[key] = value
    else:
        node[key][idx] = value


def _table_key(path: str) -> tuple:
    steps = _steps(path)
    table = steps[0][0]
    if table == "weights":
        table = "balancer"
    return table, steps[-1][0]


def unit_of(doc, path: str) -> str:
    """The unit of a scene key, as its file gives it (docs/scene.md, docs/rotors.md)."""
    table, key = _table_key(path)
    if key.endswith("_angle") or key.endswith("_angles") or key == "alpha":
        return "deg"
    if table == "balancer" and key == "drag":
        t = (doc.get("balancer") or {}) if _steps(path)[0][0] != "weights" else {}
        if _steps(path)[0][0] == "weights":
            t = get_value(doc, path.rpartition(".")[0]) if "." in path else {}
        return "N*m*s" if isinstance(t, dict) and t.get("type") == "pendulums" else "N*s/m"
    if table == "structure":
        return {"mass": "kg", "unbalance": "kg*m", "couple_unbalance": "kg*m",
                "damping_ratio": "1"}.get(key, "SI")
    return _UNITS.get(table, {}).get(key, "SI")


@dataclass(frozen=True)
class FreeValue:
    """One scene value the fit changes.

    Attributes
    ----------
    path : str            dotted TOML path, e.g. ``"supports.stiffness"``
    start : float         the template's value [``unit``]
    lower, upper : float  bounds [``unit``] (the key's own rule, or the user's ``LO..HI``)
    unit : str            the scene file's unit of the key
    angle : bool          an angle [deg] (no positivity; wraps)
    """

    path: str
    start: float
    lower: float
    upper: float
    unit: str
    angle: bool = False

    @property
    def scale(self) -> float:
        """A typical size of a change [unit]: the start's magnitude, or the bounds' width."""
        if self.angle:
            return 10.0
        if self.start != 0.0:
            return abs(self.start)
        if math.isfinite(self.upper - self.lower):
            return 0.1 * (self.upper - self.lower)
        return 1.0


def _bounds(text: str, path: str) -> tuple:
    lo, sep, hi = text.partition("..")
    if not sep:
        raise FitError(f"--free {path}={text}: bounds are written LO..HI (e.g. 0..1e4)")
    try:
        a = -math.inf if lo.strip() == "" else float(lo)
        b = math.inf if hi.strip() == "" else float(hi)
    except ValueError:
        raise FitError(f"--free {path}={text}: LO and HI must be numbers in the scene "
                       "file's unit of the key") from None
    if math.isnan(a) or math.isnan(b) or not a < b:
        raise FitError(f"--free {path}={text}: needs LO < HI")
    return a, b


def parse_free(spec, doc) -> list:
    """:class:`FreeValue` objects of a ``--free`` option (a string ``"p1[=LO..HI],p2"`` or a
    list of such strings / of ``(path, (lo, hi))`` tuples) against a parsed scene document."""
    items = []
    if isinstance(spec, str):
        spec = [s for s in spec.split(",") if s.strip()]
    for s in spec or ():
        if isinstance(s, (tuple, list)):
            path, bounds = s[0], (tuple(map(float, s[1])) if s[1] is not None else None)
        else:
            path, sep, b = str(s).partition("=")
            bounds = _bounds(b, path.strip()) if sep else None
        items.append((path.strip(), bounds))
    if not items:
        raise FitError("--free: name at least one scene value to fit (e.g. supports.stiffness)")
    out, seen = [], set()
    for path, bounds in items:
        value = get_value(doc, path)
        paths = ([f"{path}[{i}]" for i in range(len(value))] if isinstance(value, list)
                 else [path])
        for p in paths:
            v = get_value(doc, p)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
                raise FitError(f"--free {p}: the scene gives {v!r}; only a number can be "
                               "fitted (write the start value as a plain number in the file's "
                               "unit)")
            if p in seen:
                raise FitError(f"--free {p}: named twice")
            seen.add(p)
            unit = unit_of(doc, p)
            key = _table_key(p)[1]
            angle = unit == "deg"
            lo, hi = (-math.inf, math.inf) if angle or key in _ANY_SIGN else (
                (0.0, math.inf) if key in _NON_NEGATIVE else (0.0, math.inf))
            if bounds is not None:
                lo, hi = max(lo, bounds[0]), min(hi, bounds[1])
                if not lo < hi:
                    raise FitError(f"--free {p}: the bounds {bounds[0]:g}..{bounds[1]:g} leave "
                                   f"nothing the key allows ({unit})")
            start = float(v)
            if not lo <= start <= hi:
                raise FitError(f"--free {p}: the start value {start:g} {unit} lies outside "
                               f"the bounds {lo:g}..{hi:g}")
            out.append(FreeValue(p, start, lo, hi, unit, angle))
    return out


def scene_with(doc, values: dict, stem: str = ""):
    """The Scene of the document ``doc`` with ``values`` ({path: number}) written in."""
    from stand.scene.parse import parse

    d = dict(doc)                        # a copy of the tables written in, the rest shared
    d.update({k: copy.deepcopy(doc[k]) for k in {_steps(p)[0][0] for p in values} if k in doc})
    for path, v in values.items():
        set_value(d, path, float(v))
    try:
        return parse(d, text="", stem=stem)
    except SceneError as exc:
        raise FitError(f"the scene with {', '.join(f'{k} = {v:.6g}' for k, v in values.items())}"
                       f" is not valid: {exc}") from None


def document_text(doc, values: dict, text: str) -> Optional[str]:
    """``text`` (the template's TOML) with ``values`` written over the keys' values in place,
    comments and layout kept; None when a key's line cannot be found (e.g. an inline table)."""
    lines = text.splitlines()
    for path, v in values.items():
        steps = _steps(path)
        table = ".".join(k for k, _ in steps[:-1])
        key, idx = steps[-1]
        if any(i is not None for _, i in steps[:-1]):
            return None
        section, done = "", False
        for n, line in enumerate(lines):
            s = line.strip()
            if s.startswith("["):
                section = s.strip("[] ").split("]")[0].strip()
                continue
            m = re.match(rf"(\s*{re.escape(key)}\s*=\s*)([^#]*?)(\s*(#.*)?)$", line)
            if section == table and m:
                old = m.group(2).strip()
                if idx is None:
                    new = _toml_number(v)
                else:
                    items = old.strip("[]").split(",")
                    if old[:1] != "[" or old[-1:] != "]" or idx >= len(items):
                        return None
                    items[idx] = " " + _toml_number(v) if idx else _toml_number(v)
                    new = "[" + ",".join(items).strip() + "]"
                lines[n] = m.group(1) + new + m.group(3)
                done = True
                break
        if not done:
            return None
    return "\n".join(lines) + "\n"


def _toml_number(v: float) -> str:
    """A float as TOML writes it, to 12 significant digits."""
    s = f"{float(v):.12g}"
    return s if any(c in s for c in ".en") else s + ".0"
